"""Successive cone programming in space (Portioli et al.; Wang & Beyer's public code): a
fixed friction capacity from the previous normal forces, relaxed, at most
SUCCESSIVE_CONE_STEPS programs, each the search's cohesive cone program."""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .successive_lp import own
from ..tuning import (SUCCESSIVE_CONE_ALPHA_TOL, SUCCESSIVE_CONE_C_TOL, SUCCESSIVE_CONE_RELAXATION,
                      SUCCESSIVE_CONE_STEPS)


def successive_cone(engine, x, source="successive"):
    """From the statics x, on a search ``engine`` (:class:`lamodel.search.gap.GapSearch`):
    each step the cohesive program for capacities ``c = -mu N``, its mechanism certified by
    the engine's certifier (held statics, residual test). Returns (least certified state or
    None, last raw alpha)."""
    p = engine.problem
    best, raw, prev = None, np.nan, np.inf
    c = -p.mu * p.N_of(x)
    for _ in range(SUCCESSIVE_CONE_STEPS):
        status, raw_k, xc, u, xi = p.mechanism(c)
        if status != "optimal":
            break
        raw = raw_k
        st = engine.certifier.certify(u, xi, source)
        if st is not None and (best is None or st.alpha < best.alpha):
            best = st
        c_new = -p.mu * p.cohesive_N(xc)
        # converged: the capacities reproduce themselves, or alpha no longer moves
        if np.abs(c_new - c).max() <= SUCCESSIVE_CONE_C_TOL * max(np.abs(c).max(), 1e-300) or \
                abs(raw - prev) <= SUCCESSIVE_CONE_ALPHA_TOL * max(1.0, abs(raw)):
            break
        prev = raw
        c = (1 - SUCCESSIVE_CONE_RELAXATION) * c + SUCCESSIVE_CONE_RELAXATION * c_new
    return best, raw


@dataclass(frozen=True)
class SuccessiveCone:
    """Successive cone programming as a lane of the search in space: from the associative
    statics, every certified state descended; it ends at the work bounds."""

    name = "successive cone"
    once = "successive cone"

    def run(self, engine, start):
        from ..gap.problem3d import ConeProblem
        p, ran = engine.problem, engine.lanes.ran
        if self.once in ran or not isinstance(p, ConeProblem) or start.x_assoc is None:
            return ran.get(self.once, (None,))[0]  # in the plane: the successive LP's
        t = time.perf_counter()
        best = None
        try:
            with engine.budget.lane():
                best, _ = successive_cone(engine, start.x_assoc, "scp")
                if best is not None:
                    best = own(engine, engine.descent.descend(best), "scp")
        finally:
            ran[self.once] = (best,)
            engine.record.phase("successive cone", t)
        return best
