"""The published methods' lane of the default search (lamodel/search/plan.py: PUBLISHED):
where Gilbert et al.'s successive LP lands lower than the rest of the search, the default
run reports that state, named in runs.csv; elsewhere the lane leaves alpha as it was."""
import json
import os
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from conftest import INSTANCES, ROOT
from lamodel.geometry import stone_wall
from lamodel.io.datfile import read_dat
from lamodel.io.jsonspec import structure_from_json
from lamodel.search import plan
from lamodel.search.driver import SolveOptions, solve
from lamodel.search.gap.lanes import Lane
from lamodel.search.methods import run_method

OPTIONS = SolveOptions(workers=1)


def stones(n, seed, mu):
    """The families benchmark's stone panel (benchmarks/families.py: stones of about the same
    size whatever their number)."""
    width = 2.0 * np.sqrt(n / 10.0)
    return stone_wall(n, width=width, height=width / 2, seed=seed, mu=mu, name=f"stones{n}_s{seed}")


def solved(structure, lane_on, monkeypatch):
    with monkeypatch.context() as m:
        if not lane_on:
            m.setattr(plan, "PUBLISHED", Lane(()))
        return solve(structure, OPTIONS)


@pytest.mark.slow
def test_the_successive_lp_lane_gives_the_best_where_it_lands_lower(tmp_path):
    # measured (benchmarks/lanes.py): on this 50-stone panel at mu 0.6 the default run
    # without the lane certifies 0.409561 (GA), Gilbert et al.'s method alone 0.372565
    spec = tmp_path / "stones.json"
    spec.write_text(json.dumps(stones(50, 0, 0.6)))
    alone = run_method("successive-lp", structure_from_json(stones(50, 0, 0.6)))
    out = tmp_path / "out"
    res = subprocess.run([sys.executable, "-m", "lamodel.cli", "solve", str(spec), "--out", str(out), "--no-plot",
                          "--quiet"], capture_output=True, text=True, cwd=ROOT, timeout=300,
                         env=dict(os.environ, PYTHONPATH=str(ROOT)))
    assert res.returncode == 0, res.stderr
    summary, runs = pd.read_csv(out / "summary.csv"), pd.read_csv(out / "runs.csv")
    assert alone.certified
    assert summary.alpha[0] <= alone.alpha_certified + 1e-9
    assert runs.path[0] == "successive LP"


@pytest.mark.slow
@pytest.mark.parametrize("make", [lambda: read_dat(INSTANCES / "wall33.dat"),
                                  lambda: structure_from_json(stones(40, 1, 0.65)),
                                  lambda: structure_from_json(stones(30, 5, 0.6))],
                         ids=["wall33", "stones40_s1", "stones30_s5"])
def test_the_lane_never_raises_alpha_and_its_work_is_counted(make, monkeypatch):
    s = make()
    off, on = solved(s, False, monkeypatch), solved(s, True, monkeypatch)
    assert on.best.alpha <= off.best.alpha + 1e-12
    assert on.work > off.work  # its LPs count in the search's work
    phases = on.phases
    assert "published methods" in phases and "published methods" not in off.phases


def test_the_lane_steps_aside_in_space_and_the_cone_lane_in_the_plane():
    from lamodel.search.published.successive_cone import SuccessiveCone
    from lamodel.search.published.successive_lp import SuccessiveLP
    assert [type(s) for s in plan.PUBLISHED.strategies] == [SuccessiveLP, SuccessiveCone]
