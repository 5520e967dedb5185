"""The two-LP certificate of a mechanism, and its cache.

With the rows a mechanism (u, xi) flows on held at equality, min alpha over S (eq. 1-4).
Feasible means an exact collapse state (the seed's second theorem): statics admissible,
mechanism compatible with ``fbar^T u = 1``, flow only on held rows, ``alpha = alpha_K``.
Every state is then re-checked by :func:`lamodel.search.certify.residuals`.
"""
from __future__ import annotations

import numpy as np

from ..tuning import CERTIFY_CAP_ROWS, LP_TOLERANCE, RESIDUAL_TOLERANCE
from .problem import ScaledProblem
from .record import Record

_CAPPED = object()  # a certification cut short by its iteration cap: not an answer to remember


class Certifier:
    """Certifies mechanisms on a problem; every certified state goes to the record."""

    def __init__(self, problem: ScaledProblem, record: Record):
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
        key = flow.tobytes()
        if key in self.cache:
            return self.cache[key]
        state = self.held(u, xi, flow, source)
        if state is not _CAPPED:
            self.cache[key] = state
            return state
        return None

    def held(self, u, xi, flow, source):
        """The certificate itself (uncached): None, a state, or _CAPPED."""
        # Holding the rows by bounds makes the warm basis infeasible, and the primal phase 1
        # took minutes at 2040 blocks. Instead: (1) min of the sum of the lambdas the held
        # rows set to zero, from the current (feasible) basis; zero means the rows can be
        # held; (2) then those lambdas are zero, so bounding them keeps the basis feasible,
        # and min alpha is a warm primal solve. Each is capped (iterations, see cap): a
        # certification that hard is not worth it now. Unit weights, not the gap's
        # virtual-work weights w: a row flowing 1e-9 of the largest flow weighs its lambdas
        # so little that w^T lambda ~ 1e-10 left them at 0.1 (1020 blocks), and the held LP
        # then started infeasible (primal phase 1 gave up, HiGHS's dual simplex ran on
        # singular bases for minutes).
        p = self.problem
        cap = self.cap()
        zeroed = p.zeroed(flow)
        status, x = p.statics(cost_lam=zeroed.astype(float), alpha_cost=0.0, cap=cap)
        if status == "iteration limit":
            return _CAPPED
        if status != "optimal" or x[:p.nl][zeroed].max() > LP_TOLERANCE * max(1.0, np.abs(x).max()):
            return None
        status, x = p.statics(held=flow, cap=cap)
        if status == "iteration limit":
            return _CAPPED
        if status != "optimal":
            return None
        x = p.stat.exact_x()  # equilibrium to round-off, not to HiGHS's tolerance
        return self.accept(x, u, xi, flow, source)

    def cap(self):
        """Iteration cap of a statics LP that may be hard (certification, hold step, the
        first gap step of a perturbation): CERTIFY_CAP_ROWS simplex iterations a row of
        the statics (3 nb rows)."""
        return int(CERTIFY_CAP_ROWS * self.problem.stat.m)

    def accept(self, x, u, xi, flow, source):
        """The state of statics x and mechanism (u, xi) if it passes the residual check
        (kept, with its lambdas, for warm descents; told to the record), else None."""
        p = self.problem
        state = p.state(x, u, xi, flow, source)
        if max(state.residual.values()) > RESIDUAL_TOLERANCE:
            if p.verbose > 1:
                bad = {k: f"{v:.1e}" for k, v in state.residual.items() if v > RESIDUAL_TOLERANCE}
                print(f"{p.elapsed():8.2f}   rejected alpha {state.alpha:.7f}: {bad}", flush=True)
            return None
        state.lam = x  # kept for warm descents (not part of the user state)
        if self.record.on_state is not None:  # every certified state (scaled units), e.g. an archive
            self.record.on_state(state)
        self.record.take(state)
        return state
