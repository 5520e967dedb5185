"""The driver (lamodel.search.driver.solve): the seed's values, statuses, stops, and
solve.py's output contract."""
import numpy as np
import pandas as pd
import pytest

from oracle import check_folder
from lamodel.search.driver import SolveOptions, solve
from lamodel.search.state import NOT_CERTIFIED
from lamodel.geometry import running_bond_wall
from lamodel.io.jsonspec import structure_from_json

from conftest import INSTANCES, run_script, stack_spec


def small_wall():
    """A 3-course running-bond wall (8 blocks): quick, yet with sliding and hinging."""
    return structure_from_json(running_bond_wall([[0.5, 1, 1, 0.5], [1, 1, 1], [0.5, 1, 1, 0.5]], name="wall8"))


def bond(courses, width=25):
    rows = [[0.5] + [1] * (width - 1) + [0.5] if r % 2 == 0 else [1] * width for r in range(courses)]
    return structure_from_json(running_bond_wall(rows, name=f"bond{courses}"))


def test_same_seed_same_alpha_and_tables():
    s = small_wall()
    a = solve(s, SolveOptions(starts=0, seed=3))
    b = solve(s, SolveOptions(starts=0, seed=3))
    assert a.best.alpha == b.best.alpha
    assert np.array_equal(a.best.u, b.best.u) and np.array_equal(a.best.N, b.best.N)


def test_wall33_reaches_ferris_and_tin_loi(wall33):
    o = solve(wall33, SolveOptions(starts=0))
    assert o.certified
    assert o.best.alpha <= 0.63900  # Ferris & Tin-Loi 0.63898; the seed 0.63911
    assert o.best.alpha <= o.alpha_associative


@pytest.mark.slow
def test_ipopt_start_is_certified():
    s = structure_from_json(stack_spec(n=3, width=1.0, height=1.0))
    o = solve(s, SolveOptions(starts=1, workers=1))
    assert o.certified and o.best.alpha == pytest.approx(1 / 3, abs=1e-9)
    ipopt = [r for r in o.runs if r.source.startswith("ipopt")]
    assert len(ipopt) == 1 and ipopt[0].alpha_certified == pytest.approx(1 / 3, abs=1e-9)


@pytest.mark.slow
def test_solve_script_output_contract(tmp_path):
    out = tmp_path / "res"
    p = run_script("solve.py", INSTANCES / "wall33.dat", "--out", out, "--starts", "1", "--quiet")
    assert p.returncode == 0, p.stderr
    summary = pd.read_csv(out / "summary.csv")
    assert list(summary.columns[:9]) == ["instance", "alpha", "certified", "alpha_associative", "n_blocks",
                                         "n_contacts", "n_starts", "n_certified", "wall_time_s"]
    assert bool(summary.certified[0]) and summary.n_blocks[0] == 33 and summary.n_contacts[0] == 83
    # the contract's columns first, in order (extra columns, e.g. the load moments dead_m and
    # live_m of point loads, may follow them)
    assert list(pd.read_csv(out / "blocks.csv").columns[:10]) == ["block", "x", "y", "dead_x", "dead_y", "live_x",
                                                                  "live_y", "ux", "uy", "theta"]
    contacts = pd.read_csv(out / "contacts.csv")
    assert list(contacts.columns) == ["contact", "block_a", "block_b", "cx", "cy", "nx", "ny", "d", "mu", "N", "V",
                                      "M", "mode"]
    assert set(contacts["mode"]) <= {"closed", "sliding", "hinging", "sliding+hinging", "open"}
    runs = pd.read_csv(out / "runs.csv")
    assert list(runs.columns) == ["start", "source", "alpha_ipopt", "status", "alpha_certified", "iterations",
                                  "seconds", "path"]
    # the search's row says which path certified its answer
    assert runs["path"][0] in ("gap alternation", "rescue", "fixed-point fallback", "chain from zero cohesion",
                               "continuation", "GA")
    assert len(runs) == summary.n_starts[0]
    alpha = check_folder(out)
    assert alpha == pytest.approx(summary.alpha[0]) and alpha <= 0.63900
    assert (out / "mechanism.png").stat().st_size > 0
    assert "alpha = 0.6389" in p.stdout


@pytest.mark.slow
def test_exit_codes(tmp_path):
    assert run_script("solve.py", tmp_path / "missing.dat").returncode == 2
    bad = tmp_path / "bad.dat"
    bad.write_text("set BLOCKS := ;\n")
    p = run_script("solve.py", bad, "--out", tmp_path / "o")
    assert p.returncode == 2 and "Traceback" not in p.stderr and len(p.stderr.strip().splitlines()) == 1
    # a block on a narrow ledge that overhangs: it cannot stand under its own weight
    spec = {"name": "ledge", "mu": 0.6, "blocks": [
        {"id": "ground", "vertices": [[-1, -1], [0.2, -1], [0.2, 0], [-1, 0]], "support": True},
        {"id": "b1", "vertices": [[0, 0], [2, 0], [2, 1], [0, 1]]}]}
    import json
    path = tmp_path / "ledge.json"
    path.write_text(json.dumps(spec))
    p = run_script("solve.py", path, "--out", tmp_path / "o2", "--quiet")
    assert p.returncode == 3 and "unstable under dead load" in p.stdout


@pytest.mark.slow
@pytest.mark.parametrize("name", ["wall33", "wall55", "arch", "portal", "portal_columns"])
def test_every_instance_certifies_from_dat_and_json_alike(name):
    from lamodel.io.datfile import read_dat
    a = solve(read_dat(INSTANCES / f"{name}.dat"), SolveOptions(starts=0))
    b = solve(structure_from_json(INSTANCES / f"{name}.json"), SolveOptions(starts=0))
    assert a.certified and b.certified
    assert a.best.alpha == pytest.approx(b.best.alpha, abs=1e-9)
    assert a.best.alpha <= a.alpha_associative + 1e-9


@pytest.mark.slow
def test_time_limit_is_honoured_on_a_larger_wall():
    """A 255-block wall (its search takes far longer than the limit): the driver stops within
    max(10 %, 2 s) of --time-limit (measured: well under), with a certified state or an
    honest status, never a crash."""
    import time
    rows = [[0.5] + [1] * 24 + [0.5] if r % 2 == 0 else [1] * 25 for r in range(10)]
    s = structure_from_json(running_bond_wall(rows, name="bond10"))
    for limit in (0.3, 2.0):
        t = time.perf_counter()
        o = solve(s, SolveOptions(time_limit=limit, progress=False))
        elapsed = time.perf_counter() - t
        assert elapsed < limit + 2.0 + 1.0, elapsed  # +1 s of slack for a loaded test machine
        assert o.status in ("certified", "not_certified"), o.message
        assert "time limit" in o.message
        if o.certified:
            assert o.best.alpha <= o.alpha_associative + 1e-9


# ---------------------------------------------------------------- seed values
@pytest.mark.parametrize("courses, expected", [(6, 0.638982), (10, 0.557416)])
def test_seed_walls_exact(courses, expected):
    """Ferris & Tin-Loi's exact values; every improvement lower than the one before, and
    the reported state a collapse state by the independent check."""
    from gap.helpers import collapse_violation, wall
    s = wall(courses)
    o = solve(s, SolveOptions(starts=0))
    assert o.status == "certified"
    assert o.best.alpha == pytest.approx(expected, abs=1e-6)
    assert o.best.alpha <= o.alpha_associative
    alphas = [a for _, a, _, _ in o.history]
    assert alphas and alphas[-1] == o.best.alpha
    assert alphas == sorted(alphas, reverse=True) and len(set(alphas)) == len(alphas)  # each a new best
    assert collapse_violation(s, o.best) <= 1e-7
    assert max(o.best.residual.values()) <= 1e-7


@pytest.mark.slow
def test_medium_wall_certified_and_checked():
    """A 255-block running-bond wall: a certified state whose statics and mechanism pass
    the independent check (the gap alternation with its hold step, then descents)."""
    from gap.helpers import collapse_violation
    s = bond(10)
    o = solve(s, SolveOptions(starts=0, time_limit=60))
    assert o.status == "certified"
    assert o.best.alpha <= o.alpha_associative
    assert collapse_violation(s, o.best) <= 1e-7


# -------------------------------------------------------------- interruption
@pytest.mark.slow
def test_stop_flag_from_another_thread():
    import threading
    import time
    stop = threading.Event()
    timer = threading.Timer(1.0, stop.set)
    timer.start()
    t = time.perf_counter()
    o = solve(bond(10), SolveOptions(starts=0), stop=stop.is_set)
    took = time.perf_counter() - t
    timer.cancel()
    assert o.status == "interrupted" and "interrupted" in o.runs[0].status
    assert took < 1.0 + 4.0


@pytest.mark.slow
def test_sigint_stops_the_search_with_the_best_so_far():
    """Ctrl-C (SIGINT in the main thread) stops the search and returns the best so far."""
    import os
    import signal
    import threading
    import time
    # as from a terminal: pytest may have been started with SIGINT ignored, which the
    # search rightly leaves alone
    default = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        t = time.perf_counter()
        o = solve(bond(10), SolveOptions(starts=0))
        took = time.perf_counter() - t
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, default)
    assert o.status == "interrupted" and took < 1.0 + 4.0


def test_a_time_limit_before_the_first_lp_does_not_crash(wall33):
    o = solve(wall33, SolveOptions(starts=0, time_limit=1e-9))
    assert o.status == "not_certified" and o.best is None
    assert "time limit" in o.message


# ------------------------------------------------------------------ statuses
def _spec(bodies, live=(1.0, 0.0), mu=0.6):
    return {"name": "t", "mu": mu, "live_load": list(live), "blocks": bodies}


def test_no_collapse_when_the_live_load_presses_down():
    from conftest import rect
    spec = _spec([{"id": "ground", "vertices": rect(-2, -1, 2, 0), "support": True},
                  {"id": "b", "vertices": rect(-0.5, 0, 0.5, 1)}], live=(0.0, -1.0))
    o = solve(structure_from_json(spec), SolveOptions(starts=0))
    assert o.status == "no_collapse" and o.best is None


def test_unstable_under_dead_load():
    """A block held only by friction on a vertical face stands only under a push."""
    from conftest import rect
    spec = _spec([{"id": "pier", "vertices": rect(-1, 0, 0, 3), "support": True},
                  {"id": "b", "vertices": rect(0, 1, 1, 2)}], live=(-1.0, 0.0))
    o = solve(structure_from_json(spec), SolveOptions(starts=0))
    assert o.status == "unstable" and o.best is None
    assert o.message.startswith("unstable under dead load")


def test_without_a_time_limit_the_work_is_bounded_by_the_first_certificate(monkeypatch):
    """Without a time limit the search stops once it has solved TOTAL_WORK times the LPs
    of its first certificate (an evaluation of the GA may end past it); a time limit
    replaces that bound (the search then runs to its own stopping rule)."""
    from lamodel.search import budget
    s = structure_from_json(running_bond_wall([[0.5, 1, 1, 1, 1, 0.5], [1] * 5] * 3, mu=0.9, name="wall33"))
    free = solve(s, SolveOptions(starts=0))
    first = free.history[0][3]
    monkeypatch.setattr(budget, "TOTAL_WORK", 1.0)
    bounded = solve(s, SolveOptions(starts=0))
    timed = solve(s, SolveOptions(starts=0, time_limit=600))
    assert bounded.certified and bounded.best.alpha <= bounded.alpha_associative
    assert bounded.runs[0].iterations < free.runs[0].iterations
    assert timed.runs[0].iterations == free.runs[0].iterations
    assert bounded.history[0][3] == first  # the same first certificate


def test_without_a_time_limit_the_lp_work_is_bounded_by_the_size(monkeypatch):
    """Without a time limit the search also stops at WORK_PER_BLOCK LP work a block,
    continuations included, and its first certificate only at FIRST_WORK times that: with
    no work left after it, the search solves no LP past its first phase."""
    from lamodel.search import budget
    from lamodel.search.gap import problem
    s = structure_from_json(running_bond_wall([[0.5, 1, 1, 1, 1, 0.5], [1] * 5] * 3, mu=0.9, name="wall33"))
    monkeypatch.setattr(problem, "WORK_PER_BLOCK", 1e-9)
    monkeypatch.setattr(budget, "FIRST_WORK", 1e18)  # the first certificate's bound out of the way
    o = solve(s, SolveOptions(starts=0))
    assert o.certified and o.best.alpha <= o.alpha_associative
    assert o.runs[0].iterations == o.lps_first
    timed = solve(s, SolveOptions(starts=0, time_limit=600))
    assert timed.runs[0].iterations > o.lps_first


def test_without_a_time_limit_the_first_certificate_ends_at_its_work_bound(monkeypatch):
    """Without a time limit a structure no start certifies ends at FIRST_WORK times the work
    bound (here 0: at once), with exit status 3 and a message that names the bound and
    --time-limit; with a time limit the same search runs on and certifies (the 33-block
    panel at mu = 0.9 needs the chain from zero cohesion, past the alternation)."""
    from lamodel.search.gap import problem
    s = structure_from_json(running_bond_wall([[0.5, 1, 1, 1, 1, 0.5], [1] * 5] * 3, mu=0.9, name="wall33"))
    monkeypatch.setattr(problem, "WORK_PER_BLOCK", 0.0)
    o = solve(s, SolveOptions(starts=0))
    assert not o.certified and o.status == NOT_CERTIFIED and o.best is None
    assert "work bound" in o.message and "--time-limit" in o.message
    assert "associative multiplier" in o.message
    timed = solve(s, SolveOptions(starts=0, time_limit=600))
    assert timed.certified and timed.best.alpha <= 0.617365


def test_runs_csv_says_which_path_certified_the_answer():
    """The chain from zero cohesion certifies the 33-block panel at mu = 0.9 first, where
    the gap alternation and its rescue stall, and it is the least state (0.617364 for every
    seed, before the GA: a GA of one generation of two)."""
    from lamodel.search.driver import path_of
    s = structure_from_json(running_bond_wall([[0.5, 1, 1, 1, 1, 0.5], [1] * 5] * 3, mu=0.9, name="wall33"))
    o = solve(s, SolveOptions(starts=0, pop_size=2, generations=1))
    assert o.certified and o.history[0][2].startswith("zero-cohesion")
    assert path_of(o.best) == "chain from zero cohesion" and o.best.alpha <= 0.617365
    assert o.runs[0].path == path_of(o.best)


def _blas_threads():
    """Threads of each BLAS library loaded (numpy's and scipy's may differ), by file."""
    from threadpoolctl import threadpool_info
    return {d["filepath"]: d["num_threads"] for d in threadpool_info() if d["user_api"] == "blas"}


def test_the_search_runs_on_one_blas_thread_and_gives_the_others_back():
    """numpy's BLAS on one thread while the search runs (BLAS_THREADS: a threaded dot
    product spins its threads after each of the search's LP-sized products), the caller's
    setting back afterwards, also after a stop."""
    from threadpoolctl import threadpool_limits
    from lamodel.search.tuning import BLAS_THREADS
    s = small_wall()
    with threadpool_limits(2, user_api="blas"):
        before = _blas_threads()
        if not before or min(before.values()) < 2:
            pytest.skip("no BLAS here that threadpoolctl can set to two threads")
        during = []
        o = solve(s, SolveOptions(starts=0), on_associative=lambda a: during.append(_blas_threads()))
        assert o.certified and during and set(during[0].values()) == {BLAS_THREADS}
        after = _blas_threads()
        assert {f: after[f] for f in before} == before
        stopped = solve(s, SolveOptions(starts=0), stop=lambda: True)
        after = _blas_threads()
        assert not stopped.certified and {f: after[f] for f in before} == before
