"""The search, as phases and lanes in the order they run (the names of the log and of
runs.csv's ``path``; how each works: docs/method/search.md):

1. **associative** — max alpha over the statics: the upper bound, and the first statics;
2. **first certificate** — given mechanisms (a study's other loads); where joints only crush,
   the **dry certificate** (:mod:`.gap.dry`); if none certifies, the gap alternation from there;
   if it stalls, lane [single block, chain from zero cohesion, rescue, fixed-point fallback]
   (on the search's engine, until one certifies) beside lane [dilatancy continuation];
3. **stability** — some statics carries the dead load alone;
4. **continuation** — lane [continuation (rho from 10), chain from zero cohesion] beside lane
   [continuation (rho from 30), dilatancy continuation] (once-a-search strategies run once);
5. **GA** — pymoo's GA over the cohesions around the best state (:mod:`.genetic`);
6. **published methods** — lane [successive LP (Gilbert et al. 2006; in the plane), successive
   cone (in space)], each raw answer certified and descended (:func:`.gap.phases.published`);
7. **slow continuation** — rho doubled from 1 (RHO_SLOW), up to SLOW_BLOCKS blocks (:func:`.gap.phases.slow`);
8. **MPEC** — Ferris & Tin-Loi's where the slow continuation went lower (:func:`.gap.phases.mpec`);
9. **Ipopt polish** — from the best distinct certified states (the driver, in the plane).

Lanes side by side are pure evaluations on engines of their own, merged in the order
written: the same answer with any number of workers (:mod:`.gap.lanes`).
"""
from __future__ import annotations

import logging

import numpy as np

from .gap.chains import FixedPoint, FromZero
from .gap.continuation import Continuation, SlowContinuation
from .gap.dilatancy import Dilatancy
from .gap.dry import DryCertificate
from .gap.lanes import Lane
from .gap import phases
from .gap.phases import associative, stable, below
from .gap.rescue import Rescue
from .gap.single import SingleBlocks
from .genetic import genetic_search
from .options import Stopped
from .published.mpec import MPEC
from .published.successive_cone import SuccessiveCone
from .published.successive_lp import SuccessiveLP
from .tuning import RHO_CONTS, SLOW_BLOCKS

log = logging.getLogger(__name__)

BEFORE_ALTERNATION = (DryCertificate(),)  # where every joint only crushes
#: Where the gap alternation stalls: here, then beside it. The chain from zero cohesion before the
#: rescue, whose ladders stay at a partial optimum (docs/method/evidence.md, "The lanes where ...").
IF_STALLED = Lane((SingleBlocks(), FromZero(cold=True), Rescue(), FixedPoint()), until_certified=True)
BESIDE_STALLED = (Lane((Dilatancy(),)),)
#: After stability: the continuation lanes.
CONTINUATIONS = (Lane((Continuation(RHO_CONTS[0]), FromZero())), Lane((Continuation(RHO_CONTS[1]), Dilatancy())))
#: After the GA: the published fixed-point methods (each skips the formulation not its own).
PUBLISHED = Lane((SuccessiveLP(), SuccessiveCone()))
#: Last: the slow continuation, alone, so that every phase before it runs as without it;
#: after it, where it went lower, the MPEC.
SLOW, MPEC_LANE = Lane((SlowContinuation(),)), Lane((MPEC(),))


def first_certificate(engine, x_assoc, workers=1, given=()):
    """Phase 2 (:func:`.gap.phases.first_certificate`) with the lanes above."""
    phases.first_certificate(engine, x_assoc, IF_STALLED, BESIDE_STALLED, workers, BEFORE_ALTERNATION, given)


def continuations(engine, x_assoc, workers=1):
    """Phase 4 (:func:`.gap.phases.continuations`) with the lanes above."""
    return phases.continuations(engine, x_assoc, CONTINUATIONS, workers)


def run(engine, opt, progress, client=None, on_associative=None, stall_work=None, workers=1, given=()):
    """Phases 1-8 on ``engine`` (a :class:`.gap.GapSearch`, under its budget: :mod:`.budget`).
    ``stall_work``: the GA's stall rule (:mod:`.genetic`); ``workers``: the lanes' threads
    (:mod:`.workers`); ``given``: mechanisms (u, xi, scaled) of other loads (phase 2). Returns
    (what, alpha_assoc, LP solves of the first certificate): what is 'searched', 'stopped' (a stop
    or the time limit), 'unstable', 'stability unknown' (its LP failed) or the associative LP's word."""
    alpha_assoc, lps_first = np.nan, 0
    try:
        kind, alpha_assoc, x0 = associative(engine)
        engine.fitness.associative(x0)
        if kind == "unstable" or kind not in ("ok", "unbounded"):
            return kind, alpha_assoc, 0
        if x0 is None:  # unbounded, and no statics to start from: the verdict asks the weakest system
            return "searched", alpha_assoc, 0
        if on_associative is not None and kind == "ok":
            on_associative(alpha_assoc)
        progress.bound(alpha_assoc)
        log.info("associative bound %.6f (%d LP solves)", alpha_assoc, engine.n_lps())
        phase(progress, "first certificate")
        first_certificate(engine, x0, workers, given)
        # (stability gives the statics LP back its basis near the collapse states: the GA starts there)
        if not (standing := stable(engine)):
            engine.record.withdraw()
            return ("unstable" if standing is False else "stability unknown"), alpha_assoc, 0
        lps_first = engine.n_lps()  # the work of the first certificate (the stopping rules' unit)
        engine.budget.after_first(lps_first)  # the bounds of the rest of the search (none under a time limit)
        if x0 is not None and np.isfinite(alpha_assoc):
            phase(progress, "continuation")
            continuations(engine, x0, workers)
        # the GA also runs when the first phases stalled: its perturbations of the
        # associative cohesions are the next way to a certificate
        phase(progress, "GA + LP")
        genetic_search(engine, opt, client, lps_first, stall_work)
        if x0 is not None and np.isfinite(alpha_assoc) and PUBLISHED.strategies:
            phase(progress, "published methods")
            phases.published(engine, x0, PUBLISHED, workers)
        if x0 is not None and np.isfinite(alpha_assoc) and SLOW.strategies and engine.problem.nb <= SLOW_BLOCKS:
            phase(progress, "slow continuation")
            best = engine.record.best  # before the slow continuation
            if below(phases.slow(engine, x0, SLOW, workers), best) and MPEC_LANE.strategies:
                phase(progress, "MPEC")
                phases.mpec(engine, x0, MPEC_LANE, workers)
    except Stopped:
        return "stopped", alpha_assoc, lps_first
    return "searched", alpha_assoc, lps_first


def phase(progress, name):
    """A phase begins: on the progress line and in the log."""
    log.info("phase: %s", name)
    progress.phase(name)
