"""The starts of the gap alternation."""
import numpy as np
import pytest

from lamodel.search.gap import GapSearch
from lamodel.search.options import Stopped
from lamodel.search.tuning import RHO_CONTS

from .helpers import bond, collapse_violation
from lamodel.search.gap.continuation import Continuation
from lamodel.search.gap.lanes import Start
from lamodel.search.gap.phases import associative, stable
from lamodel.search.plan import continuations, first_certificate


def test_continuation_starts_certify_and_give_the_lps_their_bases_back():
    """The continuation starts (rho raised from a low value) leave every LP with the basis
    it had (the GA after them starts where it would without them), and return certified
    states that pass the independent check, never above the associative bound."""
    s = bond(6, width=8)
    e = GapSearch(s)
    _, a_assoc, x0 = associative(e)
    first_certificate(e, x0)
    stable(e)
    lps = e.problem.lps
    before = {name: lp.portable_basis() for name, lp in lps.items()}
    continuations(e, x0)
    for name, lp in lps.items():
        after = lp.portable_basis()
        if before[name] is None:
            assert after is None
        else:
            assert all(np.array_equal(b, a) for b, a in zip(before[name], after))
    found = [Continuation(rhos).run(e, Start(x0)) for rhos in RHO_CONTS]
    assert any(st is not None for st in found)
    for st in found:
        if st is not None:
            assert st.alpha <= a_assoc + 1e-9
            assert collapse_violation(s, e.problem.to_user(st)) <= 1e-7


def test_near_active_rows_certify_a_stalled_statics():
    """From the last statics of an alternation, the mechanisms on its nearly active rows
    certify a state no lower than what the whole search can reach, and a valid one."""
    s = bond(4, width=6)
    e = GapSearch(s)
    _, a_assoc, x0 = associative(e)
    _, x = e.alternation.alternate(x0)
    st = e.near.certify(x, "near")
    assert st is not None and st.alpha <= a_assoc + 1e-9
    assert collapse_violation(s, e.problem.to_user(st)) <= 1e-7


def test_a_continuation_ends_between_two_lps_at_the_work_bound():
    """A continuation whose work bound is reached on the way ends after the LP that reached
    it (no LP is cut inside HiGHS): the LPs stay usable, and what it certified before is
    in the record."""
    s = bond(6, width=8)
    e = GapSearch(s)
    _, _, x0 = associative(e)
    first_certificate(e, x0)
    free = GapSearch(s)
    associative(free)
    first_certificate(free, x0)
    n = free.n_lps()
    Continuation().run(free, Start(x0))
    assert free.n_lps() - n > 3
    e.budget.bound(e.n_lps() + 3)
    Continuation().run(e, Start(x0))
    assert e.n_lps() == e.budget.work_limit
    assert not any(lp.abandoned for lp in e.problem.lps.values())
    with pytest.raises(Stopped):  # the spent budget stops the next solve before it starts
        e.problem.statics()
    e.budget.end()  # the search ended: its work bounds stop no later solve (a verdict's)
    assert e.problem.statics()[0] == "optimal"


def test_the_continuations_stop_at_the_work_bound():
    """With the LP work already at the driver's bound the continuation starts (and the chain
    from zero cohesion) solve no LP; the work counted is that of the LPs solved."""
    e = GapSearch(bond(6, width=8))
    _, _, x0 = associative(e)
    first_certificate(e, x0)
    work = e.budget.work()
    assert work > 0 and work == sum(lp.work for lp in e.problem.lps.values())
    e.budget.bound(None, work)
    lps = e.n_lps()
    continuations(e, x0)
    assert e.n_lps() == lps


def _with_one_and_two_threads(s, run):
    """``run(engine, x_assoc, workers)`` on a new engine with one thread, then two: each
    engine with the (alpha, source) of every state it took in the order taken."""
    outcomes = []
    for workers in (1, 2):
        e = GapSearch(s)
        _, _, x0 = associative(e)
        found = []
        e.record.on_state = lambda st: found.append((st.alpha, st.source))
        run(e, x0, workers)
        outcomes.append((e, found))
    return outcomes


def test_the_continuation_lanes_give_the_same_answer_with_any_number_of_threads():
    """The continuation lanes (a ladder each, then the chain from zero cohesion or the
    dilatancy continuation) are pure functions of the search's state and of their share of
    the work left: one thread or two, the same certified states in the same order, the same
    LP solves and work counted, the same caches learned."""
    def lanes(e, x0, workers):
        first_certificate(e, x0)
        stable(e)
        continuations(e, x0, workers=workers)

    (a, found_a), (b, found_b) = _with_one_and_two_threads(bond(6, width=8, mu=1.0), lanes)
    assert found_a and found_a == found_b
    assert a.record.alpha() == b.record.alpha() <= min(alpha for alpha, _ in found_a)
    assert (a.n_lps(), a.budget.work()) == (b.n_lps(), b.budget.work())
    assert a.certifier.cache.keys() == b.certifier.cache.keys()
    assert "from zero" in a.lanes.ran and "dilatancy" in a.lanes.ran


def test_a_stop_during_the_lanes_keeps_what_they_certified():
    """A stop (Ctrl-C, the time limit) while the lanes run side by side reaches both
    within a moment; what they certified before it is taken, then Stopped is raised, and
    the search's own LPs (never touched by the lanes) stay usable."""
    import threading
    import time

    import pytest

    from lamodel.search.budget import Budget
    from lamodel.search.options import Deadline, Stopped

    s = bond(10, width=25, mu=0.9)
    stop = threading.Event()
    e = GapSearch(s, Budget(Deadline(None, stop.is_set)))
    _, _, x0 = associative(e)
    first_certificate(e, x0)
    found = []
    e.record.on_state = found.append
    timer = threading.Timer(1.0, stop.set)
    timer.start()
    t = time.perf_counter()
    with pytest.raises(Stopped):
        continuations(e, x0, workers=2)
    assert time.perf_counter() - t < 5.0
    assert all(e.record.alpha() <= st.alpha for st in found)
    assert not any(lp.abandoned for lp in e.problem.lps.values())
    stop.clear()
    assert e.problem.statics()[0] == "optimal"


def test_the_fallback_lanes_of_the_first_certificate_give_the_same_answer_with_any_number_of_threads():
    """Where the gap alternation certifies nothing (the seed's 33-block panel at mu = 0.9),
    the first certificate's two fallback lanes (the rescue and the chains on the search's
    engine, the dilatancy continuation a pure evaluation beside them) give one thread or
    two the same states in the same order, the same LP solves and work; both then count as
    run, the least state passes the independent check, and the search's LPs are usable."""
    from lamodel.geometry import seed_wall
    from lamodel.io.jsonspec import structure_from_json
    s = structure_from_json(seed_wall(6, mu=0.9))
    (a, found_a), (b, found_b) = _with_one_and_two_threads(
        s, lambda e, x0, workers: first_certificate(e, x0, workers=workers))
    assert found_a and found_a == found_b
    assert {src.split("-")[0] for _, src in found_a} >= {"zero", "dilatancy"}
    assert (a.n_lps(), a.budget.work()) == (b.n_lps(), b.budget.work())
    assert "from zero" in a.lanes.ran and "dilatancy" in a.lanes.ran
    assert collapse_violation(s, a.record.best_user) <= 1e-7
    n = a.n_lps()
    assert stable(a) and a.n_lps() == n + 1
    assert a.record.alpha() <= 0.617365 and a.record.alpha() <= associative(a)[1] + 1e-9
