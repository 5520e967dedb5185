"""The certificate of a mechanism, and its cache.

With the rows a mechanism (u, xi) flows on held at equality, min alpha over S (eq. 1-4).
Feasible means an exact collapse state (the seed's second theorem): statics admissible,
mechanism compatible with ``fbar^T u = 1``, flow only on held rows, ``alpha = alpha_K``.
The formulation solves the held statics (:meth:`~.program.GapProgram.certificates`: two
LPs in the plane, a held cone program and an exact LP on fixed cones in space); every
candidate is then re-checked by the residual test (:meth:`~.program.GapProgram.state`).
"""
from __future__ import annotations

import logging

from ..tuning import RESIDUAL_TOLERANCE
from .program import CAPPED, GapProgram
from .record import Record

log = logging.getLogger(__name__)

_CAPPED = object()  # a certification cut short by its iteration cap: not an answer to remember


class Certifier:
    """Certifies mechanisms on a problem; every certified state goes to the record."""

    def __init__(self, problem: GapProgram, record: Record):
        self.problem = problem
        self.record = record
        self.cache = {}   # flow pattern -> certified state (or None)

    def certify(self, u, xi, source):
        """Statics with the rows xi flows on held, min alpha: an exact collapse state or None."""
        flow = xi > 0
        if not flow.any():
            return None
        # The answer depends on the flow pattern alone (hold its rows, min alpha; any
        # mechanism with that pattern is then compatible with the statics): searches meet
        # the same patterns again and again (wall55: 169 certifications, 33 patterns).
        key = self.problem.pattern(u, flow)
        if key in self.cache:
            return self.cache[key]
        state = self.held(u, xi, flow, source)
        if state is not _CAPPED:
            self.cache[key] = state
            return state
        return None

    def held(self, u, xi, flow, source):
        """The certificate itself (uncached): None, a state, or _CAPPED. The formulation
        gives the candidates (:meth:`~.program.GapProgram.certificates`: in the plane the
        two LPs of :meth:`~.problem.ScaledProblem.certificates`); the first that passes
        the residual check is the certificate."""
        for cand in self.problem.certificates(u, xi, flow, self.cap()):
            if cand is CAPPED:
                return _CAPPED
            x, u_c, xi_c, flow_c, tag = cand
            state = self.accept(x, u_c, xi_c, flow_c, source + tag)
            if state is not None:
                return state
        return None

    def cap(self):
        """Iteration cap of a statics solve that may be hard (certification, hold step, the
        first gap step of a perturbation): the formulation's
        (:meth:`~.program.GapProgram.iteration_cap`)."""
        return self.problem.iteration_cap()

    def accept(self, x, u, xi, flow, source):
        """The state of statics x and mechanism (u, xi) if it passes the residual check
        (kept, with its lambdas, for warm descents; told to the record), else None."""
        p = self.problem
        state = p.state(x, u, xi, flow, source)
        if max(state.residual.values()) > RESIDUAL_TOLERANCE:
            if log.isEnabledFor(logging.DEBUG):
                bad = {k: f"{v:.1e}" for k, v in state.residual.items() if v > RESIDUAL_TOLERANCE}
                log.debug("%8.2f   rejected alpha %.7f: %s", p.elapsed(), state.alpha, bad)
            return None
        state.lam = x  # kept for warm descents (not part of the user state)
        if self.record.on_state is not None:  # every certified state (scaled units), e.g. an archive
            self.record.on_state(state)
        self.record.take(state)
        return state
