"""What the search has found so far: the least certified state (scaled and in the user's
units), when the first came, every improvement, and the time spent in each phase."""
from __future__ import annotations

import time

from ..state import CollapseState
from ..tuning import IMPROVEMENT, RESIDUAL_TOLERANCE
from .program import GapProgram


class Record:
    """The best certified state so far.

    ``on_state(state)`` (scaled units) hears of every certified state, e.g. to archive
    them; ``on_certified(state)`` (user units) of every new best. A new best must pass the
    residual check in the user's units too.
    """

    def __init__(self, problem: GapProgram, on_certified=None):
        self.problem = problem
        self.on_certified = on_certified
        self.on_state = None
        self.best: CollapseState | None = None      # scaled units
        self.best_user: CollapseState | None = None
        self.first = None                           # (alpha, seconds) of the first certificate
        self.history = []                           # (seconds, alpha, source, LP solves) of each improvement
        self.phases = {}                            # seconds per phase

    def phase(self, name, t):
        """Add the time since ``t`` (perf_counter) to phase ``name``."""
        self.phases[name] = self.phases.get(name, 0.0) + time.perf_counter() - t

    def alpha(self) -> float:
        """The best certified alpha (inf if none)."""
        return self.best.alpha if self.best is not None else float("inf")

    def forget(self):
        """No state found yet (a pure evaluation starts so)."""
        self.best = self.best_user = self.first = None
        self.history = []

    def take(self, state: CollapseState):
        """A certified state (scaled units): a new best if it improves on the best."""
        a = state.alpha
        if self.best is not None and a >= self.best.alpha - IMPROVEMENT * max(1.0, abs(a)):
            return
        p = self.problem
        user = p.to_user(state)
        if max(user.residual.values()) > RESIDUAL_TOLERANCE:
            if p.verbose > 1:
                bad = {k: f"{v:.1e}" for k, v in user.residual.items() if v > RESIDUAL_TOLERANCE}
                print(f"{p.elapsed():8.2f}   rejected alpha {a:.7f} in the user's units: {bad} "
                      f"(scaled: {max(state.residual.values()):.1e})", flush=True)
            return
        self.best, self.best_user = state, user
        t = p.elapsed()
        if self.first is None:
            self.first = (a, t)
        self.history.append((t, a, state.source, p.n_lps()))
        if p.verbose:
            print(f"  {t:8.2f} s  alpha {a:.6f}  {state.source}", flush=True)
        if self.on_certified is not None:
            self.on_certified(user)
