"""The phases of the search that are not lanes: the associative statics, the first
certificate (the gap alternation, and lanes where it stalls), stability; and the
published methods' and the continuations' lanes. The plan (:mod:`lamodel.search.plan`) names the lanes."""
from __future__ import annotations

import time

import numpy as np

from ..highs import INF
from ..tuning import IMPROVEMENT, MPEC_SHARE, PUBLISHED_SHARE, SLOW_SHARE
from ..budget import Budget
from .lanes import Start


def associative(engine):
    """Stability and the associative bound. Returns (status, alpha_assoc, x_assoc): status
    'ok', 'unstable' (S is empty), 'unbounded' (x: a least-alpha statics, None where that
    program has no optimum either: no start for the search) or the solver's word."""
    t = time.perf_counter()
    p = engine.problem
    try:
        status, x = p.statics(maximize=True)
        if status == "infeasible":
            return "unstable", np.nan, None
        if status == "unbounded":
            least, x = p.statics()  # least alpha instead: start somewhere finite
            return "unbounded", INF, x if least == "optimal" else None
        if status != "optimal":
            return status, np.nan, None
        return "ok", float(x[-1]), x
    finally:
        engine.record.phase("associative", t)


def stable(engine) -> bool | None:
    """Some statics carries the dead load alone (min alpha over S is 0): True, False (S
    empty, or its least alpha above 0), or None when the LP ends otherwise (min alpha >= 0
    is never unbounded: at f_t = c0 = 1e12 HiGHS said so, and the stack was called unstable).

    Solved warm from the last basis (a certification LP's, near the least alpha): cheap
    after a certificate, where a cold start costs as much as the associative LP.
    """
    t = time.perf_counter()
    p = engine.problem
    before = p.save_bases(("stat",))
    try:
        status, x = p.statics()
        if status == "optimal":
            return bool(x[-1] <= p.stable_alpha)
        return False if status == "infeasible" else None
    finally:
        # Back to the basis near the collapse states: from the alpha = 0 vertex every
        # later certification LP of a 1020-block wall hit its iteration cap (6120
        # iterations, 4.4 s each) and the exploration certified nothing.
        p.load_bases(before, restart_cold=False)
        engine.record.phase("stability", t)


def first_certificate(engine, x_assoc, here, there, workers=1, before=(), given=()):
    """``given``: mechanisms (u, xi) of the same blocks under other loads
    (:func:`given_mechanisms`), then the steps ``before`` (strategies, in turn, until one
    certifies), then, if nothing is certified, the gap alternation from the associative
    statics and, if it certifies nothing, lane ``here`` on this engine beside the ``there``
    lanes (:meth:`.lanes.Lanes.alongside`). Within the budget's first bound
    (:meth:`~lamodel.search.budget.Budget.first`; the side lanes stop at the time cap, not there)."""

    def run():
        given_mechanisms(engine, given)
        for step in before:
            if engine.record.best is None:
                step.run(engine, Start(x_assoc))
        if engine.record.best is not None:
            return
        _, x = engine.alternation.alternate(x_assoc, source="gap")
        if engine.record.best is None:
            engine.lanes.alongside(here, there, Start(x_assoc, x), workers)

    engine.budget.first(run, lambda: engine.record.best is not None)


def given_mechanisms(engine, given):
    """Each mechanism (u, xi) of ``given`` certified on this structure (its flow rows held,
    min alpha: one statics each; a mechanism of another load of the same blocks is
    compatible here, only its normalisation changes) and descended, on an engine of its
    own (the search's LPs keep their bases: where none certifies, the search runs as
    without them; the solves are counted). Returns the least certified state, or None."""
    if not given:
        return None
    from . import GapSearch
    t = time.perf_counter()
    side = GapSearch(engine.problem.user, Budget(engine.budget.cap, None, engine.budget.seconds))
    best = None
    try:
        for u, xi in given:
            st = side.certifier.certify(u, xi, "given")
            if st is not None:
                st = side.descent.descend(st)
                if best is None or st.alpha < best.alpha:
                    best = st
    finally:
        merge_counts(engine.problem, side.problem)
        engine.record.phase("given mechanisms", t)
    if best is not None:
        if engine.record.on_state is not None:
            engine.record.on_state(best)
        engine.record.take(best)
    return best


def merge_counts(problem, other):
    """The solves and work of ``other`` (a problem of an engine of its own) counted as
    ``problem``'s (certification LPs as such)."""
    lps = other.n_lps()
    if hasattr(problem, "n_lp") and hasattr(other, "n_lp"):
        problem.n_lp += other.n_lp
        lps -= other.n_lp
    problem.lps_elsewhere += lps
    problem.work_elsewhere += other.work()


def published(engine, x_assoc, lane, workers=1):
    """The published methods' ``lane`` from the associative statics, after the rest of the
    search (which it leaves as it was: the same states, the same work), a pure evaluation
    (:meth:`.lanes.Lanes.beside`): its states, LP solves and work merged into the search's.
    Its bound, without a time limit: PUBLISHED_SHARE times the search's LP work so far,
    within the formulation's work bound (the default run's whole-search bound)."""
    work = engine.budget.work()
    return last_lane(engine, x_assoc, lane, min(work * (1.0 + PUBLISHED_SHARE), engine.budget.whole_bound()),
                     workers, "published methods")


def slow(engine, x_assoc, lane, workers=1):
    """The slow continuation's ``lane`` after the published methods, as they are run, on a
    share of its own beyond the whole-search bound (which the published methods may have
    spent), so that what ran before it is as without it: SLOW_SHARE times the search's LP
    work so far, at most SLOW_SHARE times that bound, in whole units of LP work (none: no LP)."""
    work = engine.budget.work()
    return last_lane(engine, x_assoc, lane, work + int(SLOW_SHARE * min(work, engine.budget.whole_bound())), workers,
                     "slow continuation")


def below(state, before) -> bool:
    """``state`` (a lane's least, or None) is below the search's best ``before`` it (or
    the first certified) by more than round-off, as a new best must be (IMPROVEMENT). Where
    the slow continuation is, its lowest state lies on a slow relaxation path the quick
    ladders jump past: there the MPEC's lane runs (docs/method/evidence.md, "The MPEC's
    lane"). A state equal to the best but for round-off started the lane's Ipopt ladder for
    10 s on a 129-block wall whose search took 1.3 s."""
    return state is not None and (before is None
                                  or state.alpha < before.alpha - IMPROVEMENT * max(1.0, abs(before.alpha)))


def mpec(engine, x_assoc, lane, workers=1):
    """The MPEC's ``lane`` last, on a share of its own as the slow continuation (its LP
    work, the start's mechanism and the certification of its answer: MPEC_SHARE times the
    search's so far, at most times the whole-search bound; its Ipopt iterations bounded by
    the lane itself), so that all before it is as without it."""
    work = engine.budget.work()
    return last_lane(engine, x_assoc, lane, work + int(MPEC_SHARE * min(work, engine.budget.whole_bound())), workers,
                     "MPEC")


def last_lane(engine, x_assoc, lane, bound, workers, phase):
    """``lane`` from the associative statics after the rest of the search, a pure evaluation
    whose states, LP solves and work are merged into the search's; without a time limit
    bounded by the LP work ``bound``. Returns its least certified state (or None)."""
    budget = engine.budget
    if budget.rule is not None:
        budget.bound(None, bound)
    return engine.lanes.beside([lane], Start(x_assoc), workers, phase=phase)[0]


def continuations(engine, x_assoc, lanes, workers=1):
    """``lanes`` side by side (:meth:`.lanes.Lanes.beside`), without the once-a-search
    strategies the first certificate ran. The LPs keep the bases they had before them (the
    lanes run on engines of their own), so that what follows starts where it would
    without them."""
    ran = engine.lanes.ran
    return engine.lanes.beside([lane.without(ran) for lane in lanes], Start(x_assoc), workers)
