"""The one HiGHS wrapper: stops within a slice, iteration caps that give back the
starting basis, a time backstop on capped solves, the primal exact from the basis."""
import time

import numpy as np
import pytest

import lamodel.search.highs as highs
from lamodel.io import read
from lamodel.search.gap.problem import ScaledProblem
from lamodel.search.options import Deadline, Stopped

from conftest import INSTANCES
from gap.helpers import bond


def _stopping_at(fire):
    return Deadline.after(None, lambda: bool(fire) and time.monotonic() >= fire[0])


@pytest.mark.slow
def test_stop_during_the_first_cold_lp():
    """A stop asked for during the first (cold, interior point + crossover) LP of a
    medium wall takes effect within a slice, not when HiGHS finishes; the LP then
    raises Stopped on any further use."""
    fire = []
    p = ScaledProblem(bond(20), _stopping_at(fire))  # 510 blocks: the cold LP takes seconds
    fire.append(time.monotonic() + 0.3)
    t = time.perf_counter()
    with pytest.raises(Stopped):
        p.statics(maximize=True)
    assert time.perf_counter() - t < 5.0
    with pytest.raises(Stopped):
        p.statics(maximize=True)


@pytest.mark.slow
def test_stop_where_highs_calls_no_callback():
    """HiGHS's crossover calls no interrupt callback; the worker thread makes that not
    matter: with HiGHS's callbacks off, a stop still returns at once."""
    fire = []
    p = ScaledProblem(bond(20), _stopping_at(fire))
    p.stat.h.cbSimplexInterrupt.unsubscribe(p.stat._interrupt)
    p.stat.h.cbIpmInterrupt.unsubscribe(p.stat._interrupt)
    fire.append(time.monotonic() + 0.3)
    t = time.perf_counter()
    with pytest.raises(Stopped):
        p.statics(maximize=True)
    assert time.perf_counter() - t < 5.0
    assert p.stat.abandoned


def test_exact_primal_from_the_basis():
    """The statics recomputed from HiGHS's final basis satisfies equilibrium to round-off
    (HiGHS's own solution only to its tolerance on its scaled model), keeps the bounds,
    and has the same alpha."""
    p = ScaledProblem(bond(10))
    status, x = p.statics(maximize=True)
    assert status == "optimal"
    xe = p.stat.exact_x()
    scale = max(1.0, np.abs(xe).max())
    assert np.abs(p.stat.A @ xe - p.stat.b).max() <= 1e-12 * scale
    assert (xe >= 0).all()
    assert xe[-1] == pytest.approx(x[-1], abs=1e-8)


def test_a_capped_solve_returns_to_its_starting_basis():
    p = ScaledProblem(read(INSTANCES / "wall55.dat"))
    p.statics(maximize=True)  # max alpha: a basis far from min alpha's
    before = p.stat.portable_basis()
    status, x = p.statics(cap=1)  # min alpha needs many more iterations than 1
    assert status == "iteration limit" and x is None
    after = p.stat.portable_basis()
    assert all(np.array_equal(a, b) for a, b in zip(before, after))
    assert p.statics()[0] == "optimal"  # uncapped, the same LP solves


@pytest.mark.slow
def test_a_capped_solve_that_crawls_stops_at_its_backstop_as_if_capped(monkeypatch):
    """HiGHS's dual simplex on near-singular bases once took 25 s for 241 iterations of a
    capped certification LP (1020 blocks): a capped solve also stops after a time backstop,
    and that counts as its cap (back at its starting basis, the search goes on), not as
    the deadline."""
    p = ScaledProblem(bond(10))
    assert p.stat.n > highs.INLINE_COLUMNS  # solved in a worker thread
    p.statics(maximize=True)  # max alpha: min alpha from here takes many iterations
    before = p.stat.portable_basis()
    p.stat.warm_iterations, p.stat.warm_seconds = 10 ** 9, 1e-12  # "iterations are fast"
    monkeypatch.setattr(highs, "CAP_BACKSTOP_MIN", 0.0)  # so the backstop is HiGHS's least time limit, 1 ms
    status, x = p.statics(cap=10 ** 6)
    monkeypatch.undo()
    assert status == "iteration limit" and x is None
    assert all(np.array_equal(a, b) for a, b in zip(before, p.stat.portable_basis()))
    assert p.statics()[0] == "optimal" and not p.deadline.expired()


@pytest.mark.slow
def test_before_its_speed_is_known_a_capped_solve_may_take_twice_the_cold_solve(monkeypatch):
    """Before an LP has a sample of warm iterations, the backstop of a capped solve is twice
    its longest cold solve (a fixed few seconds cut every certification of a 2,040-block
    wall at a fifth of its cap); a solve cut by the backstop joins the speed sample (else
    the sample never grows where every capped solve meets it)."""
    monkeypatch.setattr(highs, "CAP_BACKSTOP_MIN", 0.0)
    p = ScaledProblem(bond(20))  # 510 blocks: cold max alpha ~1 s, then min alpha ~1,500 iterations
    p.statics(maximize=True)
    assert p.stat.cold_seconds > 0 and p.stat.warm_iterations == 0
    assert p.statics(cap=10 ** 6)[0] == "optimal"

    q = ScaledProblem(bond(20))
    q.statics(maximize=True)
    q.stat.cold_seconds = 0.02 * p.stat.cold_seconds  # as if the cold solve had been fast
    status, x = q.statics(cap=10 ** 6)
    assert status == "iteration limit" and x is None
    assert 0 < q.stat.warm_iterations < p.stat.warm_iterations
    assert q.statics()[0] == "optimal" and not q.deadline.expired()


def test_the_work_of_a_solve_is_its_iterations_times_its_rows():
    """HighsLP.work (the search's work bound) grows by the simplex iterations of a warm
    solve times the LP's rows."""
    p = ScaledProblem(bond(6))
    p.statics(maximize=True)
    before = p.stat.work
    cost = np.zeros(p.nl + 1)
    cost[-1] = 1.0
    p.stat.set_cost(cost)
    p.stat.solve()
    its = p.stat.h.getInfo().simplex_iteration_count
    assert its > 0 and p.stat.work - before == its * p.stat.m


def test_pace_cuts_a_simplex_at_twice_its_cap_at_its_first_speed(monkeypatch):
    """The pace of a capped cold solve's simplex: the interior point run's calls (no
    iteration count) are not its sample; the sample is its first CAP_BACKSTOP_SAMPLE
    iterations, and the cut comes at CAP_BACKSTOP times the cap at that speed."""
    from lamodel.search import pace
    clock = [0.0]
    monkeypatch.setattr(pace.time, "perf_counter", lambda: clock[0])
    monkeypatch.setattr(pace, "CAP_BACKSTOP", 2.0)
    monkeypatch.setattr(pace, "CAP_BACKSTOP_MIN", 0.5)
    monkeypatch.setattr(pace, "CAP_BACKSTOP_SAMPLE", 100)
    p = pace.Pace(cap=10_000)
    for t in (0.0, 5.0, 30.0):        # the interior point run: minutes, no iteration count
        clock[0] = t
        assert not p.slow(-1)
    clock[0] = 30.0
    assert not p.slow(0)              # its simplex begins
    clock[0] = 30.1
    assert not p.slow(100)            # 1 ms an iteration: the cap takes 10 s, the cut 20 s
    assert p.limit == pytest.approx(20.0)
    clock[0] = 49.9
    assert not p.slow(3_000) and not p.cut
    clock[0] = 50.1                   # crawling: 3,001 of 10,000 iterations at the cut
    assert p.slow(3_001) and p.cut


@pytest.mark.slow
def test_a_paced_cold_solve_ends_as_if_capped_not_stopped(monkeypatch):
    """A capped cold interior point solve (its simplex the clean-up's) that its pace cuts
    says it met its cap: a barrel vault's alignment LP went on for hours in HiGHS's dual
    simplex, and the search waited on it."""
    p = ScaledProblem(bond(10))
    lp = p.stat
    assert lp.n > highs.IPM_COLUMNS and lp.cold  # cold: the interior point method, then a simplex
    monkeypatch.setattr(highs.Pace, "slow", lambda self, iterations: iterations >= 0 and setattr(self, "cut", True)
                        is None)
    # two interior point iterations leave HiGHS an imprecise point its simplex cleans up
    assert lp.solve(cap=10 ** 6, deadline=p.deadline, ipm_cap=2) == "iteration limit"
    assert not p.deadline.expired() and not lp.abandoned
    monkeypatch.undo()
    assert p.statics(maximize=True)[0] == "optimal"


class _WorkLeft(Deadline):
    """A deadline whose work bound leaves ``left`` units of LP work."""

    def __init__(self, left):
        super().__init__()
        self.left_work = left

    def work_left(self):
        return self.left_work


def test_a_work_bound_cuts_a_solve_where_it_is_reached_back_at_its_basis():
    """A solve is cut where the work bound is reached, not after it: with the work left for
    one iteration the solve stops there (Stopped, as the bound stops a solve between two),
    counts its iteration and leaves the basis it started from; with room, the same solve."""
    p = ScaledProblem(read(INSTANCES / "wall55.dat"))
    p.statics(maximize=True)  # max alpha: min alpha from here takes many iterations
    before, work = p.stat.portable_basis(), p.stat.work
    p.deadline = _WorkLeft(1.5 * p.stat.m)
    with pytest.raises(Stopped):
        p.statics()
    assert 0 < p.stat.work - work <= 2 * p.stat.m
    assert all(np.array_equal(a, b) for a, b in zip(before, p.stat.portable_basis()))
    p.deadline = _WorkLeft(1e12)
    assert p.statics()[0] == "optimal"


def test_the_work_left_is_the_bound_that_applies_now():
    """A budget's deadline tells the solves the work left: the whole search's bound, and
    the first certificate's while it runs; none once the search ended."""
    from lamodel.search.budget import Budget
    b = Budget.for_solve()
    b.count(ScaledProblem(read(INSTANCES / "wall33.dat")))
    assert b.deadline.work_left() == np.inf
    b.bound(None, 1000.0)
    assert b.deadline.work_left() == 1000.0 - b.work()
    b._first, b.first_bound = True, 10.0
    assert b.deadline.work_left() == 10.0 - b.work()
    b._first = False
    b.end()
    assert b.deadline.work_left() == np.inf
