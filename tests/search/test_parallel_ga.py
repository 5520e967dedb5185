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
from lamodel.search import engine as engine_module
from lamodel.search.driver import solve
from lamodel.search.engine import GapSearch
from lamodel.search.options import SolveOptions

ROOT = Path(__file__).resolve().parents[2]
INSTANCES = ROOT / "instances"
#: what a run's CSV tables may differ in: how long it took
TIMING_COLUMNS = ("seconds", "wall_time_s")


def bond5x5_spec():
    """A 5-course running-bond wall (28 blocks) with mu = 0.9: its GA improves on the
    first certificate twice (seed 0), so the order in which outcomes are taken matters."""
    rows = [[0.5] + [1] * 4 + [0.5] if r % 2 == 0 else [1] * 5 for r in range(5)]
    return running_bond_wall(rows, mu=0.9, name="bond5x5")


def _structure(name):
    return structure_from_json(bond5x5_spec()) if name == "bond5x5" else read(INSTANCES / name)


def _same_outcome(o, ref):
    assert o.status == ref.status == "certified"
    assert o.best.alpha == ref.best.alpha
    assert [(a, src) for _, a, src in o.history] == [(a, src) for _, a, src in ref.history]
    assert o.runs[0].iterations == ref.runs[0].iterations  # the same LPs, counted
    for field in ("N", "V", "M", "u", "xi"):
        assert np.array_equal(getattr(o.best, field), getattr(ref.best, field)), field


def _after_first_certificate(name):
    e = GapSearch(read(INSTANCES / name), seed=0)
    _, _, x0 = e.start()
    e.N_assoc = e.N_of(x0)
    e.alternate(x0)
    assert e.best is not None
    return e


def test_an_evaluation_does_not_depend_on_what_its_engine_did_before():
    e = _after_first_certificate("wall55.dat")
    snap = e.snapshot()
    rng = np.random.default_rng(3)
    genomes = [s * rng.standard_normal(e.nc) for s in (0.1, 0.3, 1.0, 0.3, 1.0)]
    forward, backward = e.evaluator(), e.evaluator()
    a = [forward.evaluate_pure(snap, g) for g in genomes]
    b = [backward.evaluate_pure(snap, g) for g in genomes[::-1]][::-1]
    for (alpha_a, states_a, lps_a, _), (alpha_b, states_b, lps_b, _) in zip(a, b):
        assert alpha_a == alpha_b and lps_a == lps_b
        assert [s.alpha for s in states_a] == [s.alpha for s in states_b]
        for sa, sb in zip(states_a, states_b):
            assert np.array_equal(sa.N, sb.N) and np.array_equal(sa.u, sb.u)
    # and the snapshot belongs to the search: evaluating leaves it untouched
    assert e.snapshot()["reference_N"].tobytes() == snap["reference_N"].tobytes()


def test_merged_states_are_recorded_as_if_found_here():
    e = _after_first_certificate("wall55.dat")
    before, lps = e.best.alpha, e.n_lps()
    seen = []
    e.on_state = seen.append
    alpha, states, n, learned = e.evaluator().evaluate_pure(e.snapshot(), np.zeros(e.nc))
    e.merge(states, n, learned)
    assert e.n_lps() == lps + n and len(seen) == len(states)
    assert e.best.alpha <= min([before] + [s.alpha for s in states]) + 1e-15
    assert e.best_user is not None and max(e.best_user.residual.values()) <= 1e-7


def test_a_snapshot_pickles_and_an_evaluation_from_its_copy_is_the_same():
    """What a Dask task receives: the snapshot through pickle, bases as plain arrays."""
    import pickle
    e = _after_first_certificate("wall33.dat")
    snap = e.snapshot()
    copy = pickle.loads(pickle.dumps(snap))
    genome = 0.3 * np.random.default_rng(0).standard_normal(e.nc)
    a, b = e.evaluator().evaluate_pure(snap, genome), e.evaluator().evaluate_pure(copy, genome)
    assert a[0] == b[0] and a[2] == b[2] and [s.alpha for s in a[1]] == [s.alpha for s in b[1]]


@pytest.mark.parametrize("name", ["wall33.dat", "wall55.dat", "bond5x5"])
def test_same_answer_for_any_number_of_workers(name):
    structure = _structure(name)
    outs = [solve(structure, SolveOptions(seed=0, starts=0, ga_workers=w, pop_size=6, generations=3))
            for w in (1, 2, 3)]
    for o in outs[1:]:
        _same_outcome(o, outs[0])
    if name == "bond5x5":  # the GA found something, merged in task order
        assert sum(src.startswith("genome") for _, _, src in outs[0].history) >= 1


@pytest.mark.parametrize("name", ["wall33.dat", "bond5x5"])
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
    structure = structure_from_json(bond5x5_spec())
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
    lp_solve = engine_module._LP.solve

    def counting(self, cap=None):
        status = lp_solve(self, cap)
        if status == "iteration limit":
            cut.append(self.name)
        return status
    monkeypatch.setattr(engine_module._LP, "solve", counting)
    monkeypatch.setattr(engine_module, "CERTIFY_CAP_ROWS", 0.5)  # a quarter of the default
    structure = structure_from_json(bond5x5_spec())
    outs = [solve(structure, SolveOptions(seed=0, starts=0, ga_workers=w, pop_size=6, generations=3))
            for w in (1, 2)]
    assert cut
    _same_outcome(outs[1], outs[0])


def test_a_capped_solve_returns_to_its_starting_basis():
    e = GapSearch(read(INSTANCES / "wall55.dat"), seed=0)
    e.start()  # max alpha: a basis far from min alpha's
    before = e.stat.portable_basis()
    status, x = e.statics(cap=1)  # min alpha needs many more iterations than 1
    assert status == "iteration limit" and x is None
    after = e.stat.portable_basis()
    assert all(np.array_equal(a, b) for a, b in zip(before, after))
    assert e.statics()[0] == "optimal"  # uncapped, the same LP solves


def _tables(folder):
    """Every CSV table a solve wrote, without its timing columns."""
    return {p.name: pd.read_csv(p, dtype=str).drop(columns=list(TIMING_COLUMNS), errors="ignore")
            for p in sorted(Path(folder).glob("*.csv"))}


@pytest.mark.parametrize("name", ["wall33.dat", "bond5x5"])
def test_command_line_tables_identical_for_workers_and_dask(name, tmp_path, dask_cluster):
    """What a user compares: the CSV tables of `solve --workers 1`, `--workers 2` and
    `--scheduler` (all of them, but for how long the runs took)."""
    instance = INSTANCES / name
    if name == "bond5x5":
        instance = tmp_path / "bond5x5.json"
        instance.write_text(json.dumps(bond5x5_spec()))
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


