"""The dry certificate: where joints only crush, a dry collapse state within the caps is
a collapse state of the structure with crushing.

With crushing only (finite f_c, no cohesion c0, no tensile strength f_t) every joint's
domain lies inside the dry one — in the plane |M| <= |N| (d - |N| / (2 f_c b)) <= |N| d,
in space 0 <= p_i <= f_c A_i inside p_i >= 0 — and the fictitious system keeps those
limits, so for the same cohesions c = -mu N the capped fictitious optimum is at most the
dry one: alpha_K^cap(c) <= alpha_K^dry(c). A certified dry collapse state (alpha, N) whose
forces lie within the caps is admissible in the capped fictitious program, so
alpha_K^cap(c) >= alpha = alpha_K^dry(c): the capped mechanism for its cohesions has the
same multiplier, and the capped certificate (held rows, min alpha, the residual test with
the caps) accepts it. With c0 > 0 or f_t > 0 the capped domain is not inside the dry one
and the step does not run.

The step runs the dry search's gap alternation (eq. 4's LPs in the plane, the dry cone
programs in space: cheaper than the capped ones, and its gap closes where the capped one
may not) on an engine of its own, under the search's time cap and the dry search's own
first-certificate bound, until it certifies a state (the descent and the rest of its rho
ladder are the capped search's to do), its work merged into the search's. That state,
if its forces are within the caps (:func:`within_caps`, to DRY_WITHIN_CAPS), gives the
cohesions of one capped fictitious program; that mechanism is certified and descended in
the capped model as any other (path ``dry certificate``), and the search goes on from
there. Otherwise the search goes on as without the step.
"""
from __future__ import annotations

import logging
import time
from dataclasses import replace

import numpy as np

from ..budget import Budget
from ..options import Deadline, Stopped
from ..tuning import DRY_WITHIN_CAPS

log = logging.getLogger(__name__)


def crushing_only(structure) -> bool:
    """Every joint dry but for a finite compressive strength somewhere (no cohesion, no
    tensile strength): where the dry certificate applies."""
    return (structure.has_materials and not np.any(structure.ft > 0) and not np.any(structure.cohesion > 0)
            and bool(np.isfinite(structure.fc).any()))


def within_caps(problem, state, tol=DRY_WITHIN_CAPS) -> bool:
    """The forces of a (dry) state within the crushing caps of ``problem`` (scaled units),
    to ``tol`` of each joint's capacity: in the plane every joint's N and M under the
    stress block's parabola, in space every point's compression at most f_c A_i."""
    n = np.maximum(-state.N, 0.0)
    if not hasattr(state, "M"):  # in space: N >= N_c (-inf where no cap)
        crush = problem.caps[0]
        return bool(np.all(n <= -crush * (1.0 + tol)))
    s = problem.s
    fb = s.fc * s.thickness
    room = n * (s.d - n / (2.0 * fb))  # the parabola's moment capacity at N (n d where f_c is infinite)
    return bool(np.all(n <= 2.0 * s.d * fb * (1.0 + tol)) and np.all(np.abs(state.M) <= room + tol * n * s.d))


def dry_first(engine):
    """The step (module doc) on ``engine`` (a :class:`~lamodel.search.gap.GapSearch` whose
    joints only crush): the least certified state it gives, or None."""
    from . import GapSearch
    from .phases import associative, merge_counts

    t = time.perf_counter()
    p = engine.problem
    budget = engine.budget
    lps0, work0 = p.n_lps(), p.work()
    found = []  # the dry engine's record, once made: its first certified state ends its run
    cap = Deadline(budget.cap.at, lambda: budget.cap.expired() or (bool(found) and found[0].best is not None))
    dry = GapSearch(replace(p.user, fc=None, ft=None, cohesion=None), Budget(cap, budget.rule, budget.seconds))
    found.append(dry.record)
    try:
        kind, _, x0 = associative(dry)
        if kind == "ok":
            dry.budget.first(lambda: dry.alternation.alternate(x0, source="dry"),
                             lambda: dry.record.best is not None)
    except Stopped:
        if budget.expired():  # the search's time cap or a stop, not the dry certificate found
            raise
    finally:
        merge_counts(p, dry.problem)
        if budget.first_bound is not None:  # the gap alternation after the step: the room it had without it
            budget.first_bound += dry.problem.work()
    best = dry.record.best
    state = None
    if best is None:
        log.info("dry certificate: the dry alternation certified nothing")
    elif not within_caps(p, best):
        log.info("dry certificate: the dry state (alpha %.6f) is beyond the caps", best.alpha)
    else:
        status, alpha_k, _, u, xi = p.mechanism(-p.mu * best.N)
        log.info("dry certificate: dry alpha %.6f within the caps, capped alpha_K %.6f (%s)", best.alpha, alpha_k,
                 status)
        if status == "optimal":
            state = engine.certifier.certify(u, xi, "dry")
        if state is not None:
            state = engine.descent.descend(state)
        else:
            # within the caps to DRY_WITHIN_CAPS only (a dry hinge is on the joint's edge,
            # beyond the polygon of the plane by CRUSHING_FLOOR of its moment): the capped
            # statics holding that mechanism's rows moves by as much, and a held slide may
            # not follow; the capped alternation from the dry statics closes that gap
            state = engine.alternation.alternate(capped_statics(p, best), source="dry")[0]
    if state is None:  # the rest of the search as without the step (its work still counted)
        budget.aside = (p.n_lps() - lps0, p.work() - work0)
    engine.record.phase("dry certificate", t)
    return state


def capped_statics(problem, state):
    """The dry ``state``'s forces as a statics of the capped ``problem``'s columns (in the
    plane a facet's slack column sigma >= 0, 0 where the state is beyond the facet; in space
    the same columns): where the capped alternation starts from."""
    if not hasattr(state, "M"):
        return np.concatenate([state.N, state.T1, state.T2, [state.alpha]])
    s_f = np.concatenate([state.N, state.V, state.M])
    slack = (problem.b - problem.Y @ s_f)[problem.kept]
    return np.concatenate([np.maximum(slack, 0.0) / problem.w_kept, s_f, [state.alpha]])


class DryCertificate:
    """The step before the gap alternation (:mod:`lamodel.search.plan`): :func:`dry_first`
    where every joint only crushes (:func:`crushing_only`), else nothing."""

    name = "dry certificate"
    once = None

    def applies(self, engine) -> bool:
        return crushing_only(engine.problem.user)

    def run(self, engine, start):
        return dry_first(engine) if self.applies(engine) else None
