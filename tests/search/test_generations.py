"""The GA's generations in parallel (issue 12): every evaluation a pure function of the
generation's snapshot and its genome, merged in task order, so the answer is the same
for any number of workers, in threads or on a real Dask cluster (a LocalCluster on
127.0.0.1, tests/conftest.py)."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from lamodel.geometry import running_bond_wall
from lamodel.io import read
from lamodel.io.jsonspec import structure_from_json
from lamodel.search import highs
from lamodel.search.driver import solve
from lamodel.search.gap import problem as gap_problem
from lamodel.search.options import SolveOptions

pytestmark = pytest.mark.slow  # they start processes or clusters, or take seconds

ROOT = Path(__file__).resolve().parents[2]
INSTANCES = ROOT / "instances"
#: what a run's CSV tables may differ in: how long it took
TIMING_COLUMNS = ("seconds", "wall_time_s", "alpha_lower_seconds")


def bond7x5_spec():
    """A 7-course running-bond wall (39 blocks) with mu = 1.0: its GA improves on the
    states the first phases certify, in three steps (seed 0, pure evaluations: 0.609524 to
    0.591641), so the order in which outcomes are taken matters."""
    rows = [[0.5] + [1] * 4 + [0.5] if r % 2 == 0 else [1] * 5 for r in range(7)]
    return running_bond_wall(rows, mu=1.0, name="bond7x5")


def _structure(name):
    return structure_from_json(bond7x5_spec()) if name == "bond7x5" else read(INSTANCES / name)


def _same_outcome(o, ref):
    assert o.status == ref.status == "certified"
    assert o.best.alpha == ref.best.alpha
    assert [(a, src) for _, a, src, _ in o.history] == [(a, src) for _, a, src, _ in ref.history]
    assert o.runs[0].iterations == ref.runs[0].iterations  # the same LPs, counted
    for field in ("N", "V", "M", "u", "xi"):
        assert np.array_equal(getattr(o.best, field), getattr(ref.best, field)), field


@pytest.mark.parametrize("name", ["wall33.dat", "wall55.dat", "bond7x5"])
def test_same_answer_for_any_number_of_workers(name):
    structure = _structure(name)
    outs = [solve(structure, SolveOptions(seed=0, starts=0, ga_workers=w, pop_size=6, generations=3))
            for w in (1, 2, 3)]
    for o in outs[1:]:
        _same_outcome(o, outs[0])
    if name == "bond7x5":  # the GA found something, merged in task order
        assert sum(src.startswith("genome") for _, _, src, _ in outs[0].history) >= 1


@pytest.mark.parametrize("name", ["wall33.dat", "bond7x5"])
def test_threads_and_a_dask_cluster_give_the_same_answer(name, dask_cluster):
    structure = _structure(name)
    options = dict(seed=0, starts=0, pop_size=6, generations=3)
    one = solve(structure, SolveOptions(ga_workers=1, **options))
    two = solve(structure, SolveOptions(ga_workers=2, **options))
    on_dask = solve(structure, SolveOptions(scheduler=dask_cluster.scheduler_address, **options))
    _same_outcome(two, one)
    _same_outcome(on_dask, one)


def test_same_seed_same_answer_and_the_stopping_rule_counted(monkeypatch):
    """Enough generations for the stopping rule to end the GA (not the generation count):
    it stops after the same evaluation for any number of workers, and again with the
    same seed; another seed is another search."""
    from lamodel.search import ga
    evaluations = []
    genetic_search = ga.genetic_search

    def counting(*args, **kwargs):
        out = genetic_search(*args, **kwargs)
        evaluations.append(out[2])
        return out
    monkeypatch.setattr(ga, "genetic_search", counting)
    structure = structure_from_json(bond7x5_spec())
    options = dict(starts=0, pop_size=6, generations=40)
    outs = [solve(structure, SolveOptions(seed=0, ga_workers=w, **options)) for w in (1, 2, 1)]
    for o in outs[1:]:
        _same_outcome(o, outs[0])
    assert evaluations[0] == evaluations[1] == evaluations[2] < 40 * 6  # the rule stopped it
    other = solve(structure, SolveOptions(seed=1, ga_workers=2, **options))
    assert other.runs[0].iterations != outs[0].runs[0].iterations


def test_iteration_caps_leave_the_answer_to_the_seed(monkeypatch):
    """Caps on hard statics LPs are simplex iterations: made tiny, they cut many solves
    (each back at its starting basis), and the answer is still the same for 1 and 2
    workers. (Time caps made it depend on the machine and its load.)"""
    cut = []
    lp_solve = highs.HighsLP.solve

    def counting(self, cap=None, deadline=None):
        status = lp_solve(self, cap, deadline)
        if status == "iteration limit":
            cut.append(self.name)
        return status
    monkeypatch.setattr(highs.HighsLP, "solve", counting)
    monkeypatch.setattr(gap_problem, "CERTIFY_CAP_ROWS", 0.5)  # a quarter of the default
    structure = structure_from_json(bond7x5_spec())
    outs = [solve(structure, SolveOptions(seed=0, starts=0, ga_workers=w, pop_size=6, generations=3))
            for w in (1, 2)]
    assert cut
    _same_outcome(outs[1], outs[0])


def _tables(folder):
    """Every CSV table a solve wrote, without its timing columns."""
    return {p.name: pd.read_csv(p, dtype=str).drop(columns=list(TIMING_COLUMNS), errors="ignore")
            for p in sorted(Path(folder).glob("*.csv"))}


@pytest.mark.parametrize("name", ["wall33.dat", "bond7x5"])
def test_command_line_tables_identical_for_workers_and_dask(name, tmp_path, dask_cluster):
    """What a user compares: the CSV tables of `solve --workers 1`, `--workers 2` and
    `--scheduler` (all of them, but for how long the runs took)."""
    instance = INSTANCES / name
    if name == "bond7x5":
        instance = tmp_path / "bond7x5.json"
        instance.write_text(json.dumps(bond7x5_spec()))
    tables = {}
    for where in (["--workers", "1"], ["--workers", "2"], ["--scheduler", dask_cluster.scheduler_address]):
        out = tmp_path / where[1].replace(":", "_").replace("/", "_")
        p = subprocess.run([sys.executable, str(ROOT / "scripts" / "solve.py"), str(instance), *where,
                            "--seed", "0", "--generations", "3", "--starts", "0", "--out", str(out),
                            "--no-plot", "--quiet"], capture_output=True, text=True, timeout=300, cwd=ROOT)
        assert p.returncode == 0, p.stderr
        tables[where[0] + where[1]] = _tables(out)
    first, *others = tables.values()
    assert {"summary.csv", "runs.csv", "blocks.csv", "contacts.csv"} <= set(first)
    for other in others:
        assert set(other) == set(first)
        for table in first:
            pd.testing.assert_frame_equal(other[table], first[table], obj=table)


