"""Descent from a certified state: each step a lower certified state, or the end.

Two kinds of step, each certified (:mod:`lamodel.search.gap.certify`): mechanisms for the state's own
cohesions restricted to the rows its statics holds (at the two tightest active
tolerances), then a pressure step (release the held rows whose lambdas the certification
LP would like positive). alpha never increases.
"""
from __future__ import annotations

import time

import numpy as np

from ..tuning import ACTIVE_TOLERANCES, DESCENT_MAX_STEPS, DESCENT_STEP, PRESSURE_GROUPS, PRESSURE_SINGLE
from .certify import Certifier
from .program import GapProgram
from .record import Record


class Descent:
    """Descends certified states; a descent depends on the certified state alone (cached)."""

    def __init__(self, problem: GapProgram, certifier: Certifier, record: Record):
        self.problem, self.certifier, self.record = problem, certifier, record
        self.cache = {}   # flow pattern of a certified state -> its descent

    def descend(self, state, max_steps=DESCENT_MAX_STEPS):
        """From a certified state: restricted mechanisms, then pressure steps, while alpha falls."""
        key = self.problem.pattern(state.u, state.flow)
        if key in self.cache:
            return self.cache[key]
        start = state
        t = time.perf_counter()
        try:
            for _ in range(max_steps):
                nxt = self._restricted_step(state)
                if nxt is None or nxt.alpha >= state.alpha - DESCENT_STEP * max(1.0, state.alpha):
                    nxt = self._pressure_step(state)
                if nxt is None or nxt.alpha >= state.alpha - DESCENT_STEP * max(1.0, state.alpha):
                    break
                state = nxt
            self.cache[key] = self.cache[self.problem.pattern(start.u, start.flow)] = state
        finally:
            self.record.phase("descend", t, step=True)
        return state

    def _restricted_step(self, state):
        rows = (self.problem.active_rows(state.lam, tol) for tol in ACTIVE_TOLERANCES[:2])
        return self._first_lower(state, rows, "+descend")

    def _first_lower(self, state, allowed_sets, tag):
        """Mechanisms for the state's cohesions restricted to each allowed set in turn, each
        certified; stops at the first certified state below the state's alpha. The least
        certified (or None)."""
        best = None
        c = -self.problem.mu * state.N
        for allowed in allowed_sets:
            status, _, _, u, xi = self.problem.mechanism(c, allowed)
            if status != "optimal":
                continue
            cand = self.certifier.certify(u, xi, state.source + tag)
            if cand is not None and (best is None or cand.alpha < best.alpha):
                best = cand
            if best is not None and best.alpha < state.alpha - DESCENT_STEP:
                break
        return best

    def _pressure_step(self, state):
        """Reduced costs of the held lambdas (min alpha with the flow rows held) say which
        held rows push alpha up; let the most pushing ones go (not allowed to flow)."""
        p = self.problem
        row_push = p.pushing_rows(state)
        if row_push is None:
            return None
        order = np.argsort(-row_push)
        order = order[row_push[order] > 0]
        allowed0 = p.active_rows(state.lam, ACTIVE_TOLERANCES[1])
        # the most pushing rows one at a time, then the top ones together
        trials = [order[i:i + 1] for i in range(min(PRESSURE_SINGLE, order.size))]
        trials += [order[:n] for n in PRESSURE_GROUPS if n <= order.size]

        def released(rel):
            allowed = allowed0.copy()
            allowed[rel] = False
            return allowed
        return self._first_lower(state, (released(rel) for rel in trials), "+pressure")
