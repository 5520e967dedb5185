"""One meaning of --workers (lamodel/search/workers.py): all cores when not given, and the
same tables whatever the number (the lanes beside each other are pure evaluations merged in
lane order, the GA's generations too)."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from lamodel.geometry import running_bond_wall
from lamodel.search import workers

ROOT = Path(__file__).resolve().parents[2]
TIMING_COLUMNS = ("seconds", "wall_time_s", "alpha_lower_seconds")


def test_workers_default_to_all_cores():
    assert workers.count(None) == (os.cpu_count() or 1)
    assert workers.count(3) == 3


def test_a_pool_of_threads_has_as_many_workers_as_asked():
    with workers.threads(2, "test") as pool:
        names = set(pool.map(lambda _: __import__("threading").current_thread().name, range(8)))
    assert names and all(n.startswith("lamodel-test") for n in names)
    assert pool._max_workers == 2


@pytest.mark.slow
def test_command_line_tables_identical_for_one_two_and_four_workers(tmp_path):
    """A 5-course running-bond wall at mu = 0.9, whose gap alternation stalls: its first
    certificate runs lanes beside each other (the side lane bounded by the main lane's
    work), then the continuation lanes and the GA's generations in worker threads;
    `--workers 1`, `2` and `4` write the same tables (all of them, but for how long the
    runs took)."""
    rows = [[0.5] + [1] * 9 + [0.5] if r % 2 == 0 else [1] * 10 for r in range(5)]
    instance = tmp_path / "bond5x10.json"
    instance.write_text(json.dumps(running_bond_wall(rows, mu=0.9, name="bond5x10")))
    tables = []
    for n in ("1", "2", "4"):
        out = tmp_path / f"w{n}"
        p = subprocess.run([sys.executable, str(ROOT / "scripts" / "solve.py"), str(instance), "--workers", n,
                            "--seed", "0", "--generations", "3", "--starts", "0", "--out", str(out),
                            "--no-plot", "--quiet"], capture_output=True, text=True, timeout=300, cwd=ROOT)
        assert p.returncode == 0, p.stderr
        tables.append({f.name: pd.read_csv(f, dtype=str).drop(columns=list(TIMING_COLUMNS), errors="ignore")
                       for f in sorted(out.glob("*.csv"))})
    one, *more = tables
    assert {"summary.csv", "runs.csv", "blocks.csv", "contacts.csv"} <= set(one)
    assert "chain from zero cohesion" in one["runs.csv"]["path"].tolist()  # the stalled start's lanes ran
    for other in more:
        assert set(other) == set(one)
        for table in one:
            pd.testing.assert_frame_equal(other[table], one[table], obj=table)
