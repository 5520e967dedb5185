"""What the search has found so far: the least certified state (scaled and in the user's
units), when the first came, every improvement, and the time spent in each phase."""
from __future__ import annotations

import logging
import time

from ..state import CollapseState
from ..tuning import IMPROVEMENT, RESIDUAL_TOLERANCE
from .program import GapProgram

log = logging.getLogger(__name__)


def least(best, st):
    """The lesser of two certified states (either may be None)."""
    return st if st is not None and (best is None or st.alpha < best.alpha) else best


class Record:
    """The best certified state so far.

    ``on_state(state)`` (scaled units) hears of every certified state, e.g. to archive
    them; ``on_certified(state)`` (user units) of every new best. A new best must pass the
    residual check in the user's units too.
    """

    def __init__(self, problem: GapProgram, on_certified=None, on_state=None):
        self.problem = problem
        self.on_certified = on_certified
        self.on_state = on_state
        self.best: CollapseState | None = None      # scaled units
        self.best_user: CollapseState | None = None
        self.first = None                           # (alpha, seconds) of the first certificate
        self.history = []                           # (seconds, alpha, source, LP solves) of each improvement
        self.phases = {}                            # seconds per phase
        #: (alpha, alpha_K, relative gap, rows holding it) of the alternation step nearest a
        #: collapse state: what a search that certifies nothing reports, never as its answer
        self.stall = None

    def phase(self, name, t, step=False):
        """Add the time since ``t`` (perf_counter) to phase ``name``, a phase or lane that
        ended (logged at INFO with the work and the best alpha so far; a ``step`` of one,
        an alternation or a descent, at DEBUG)."""
        seconds = time.perf_counter() - t
        self.phases[name] = self.phases.get(name, 0.0) + seconds
        level = logging.DEBUG if step else logging.INFO
        if log.isEnabledFor(level):
            log.log(level, "%s: %.2f s, %d LP solves so far, best certified alpha %s", name, seconds,
                    self.problem.n_lps(), f"{self.best.alpha:.6f}" if self.best is not None else "none")

    def note_gap(self, alpha: float, gap: float, rows):
        """An alternation step: its statics' alpha, the gap ``alpha_K - alpha`` of its
        mechanism, the rows that hold the gap (flows on rows the statics keeps slack). The
        step with the least relative gap ``(alpha_K - alpha) / alpha_K`` is kept."""
        alpha_k = alpha + max(gap, 0.0)
        rel = max(gap, 0.0) / max(abs(alpha_k), 1e-300)
        if self.stall is None or rel < self.stall[2]:
            self.stall = (float(alpha), float(alpha_k), float(rel), rows)

    def alpha(self) -> float:
        """The best certified alpha (inf if none)."""
        return self.best.alpha if self.best is not None else float("inf")

    def forget(self, best=None, on_state=None):
        """No state found yet (a pure evaluation starts so, below ``best``, a scaled state
        or None), every certified state told to ``on_state``."""
        self.best_user = self.first = None
        self.best, self.on_state = best, on_state
        self.history = []

    def withdraw(self):
        """No certified state counts (the structure does not stand under its dead load)."""
        self.best = self.best_user = None

    def take(self, state: CollapseState):
        """A certified state (scaled units): a new best if it improves on the best."""
        a = state.alpha
        if self.best is not None and a >= self.best.alpha - IMPROVEMENT * max(1.0, abs(a)):
            return
        p = self.problem
        user = p.to_user(state)
        if max(user.residual.values()) > RESIDUAL_TOLERANCE:
            if log.isEnabledFor(logging.DEBUG):
                bad = {k: f"{v:.1e}" for k, v in user.residual.items() if v > RESIDUAL_TOLERANCE}
                log.debug("%8.2f   rejected alpha %.7f in the user's units: %s (scaled: %.1e)", p.elapsed(), a, bad,
                          max(state.residual.values()))
            return
        self.best, self.best_user = state, user
        t = p.elapsed()
        if self.first is None:
            self.first = (a, t)
        self.history.append((t, a, state.source, p.n_lps()))
        log.info("%8.2f s  certified alpha %.6f  %s (%d LP solves)", t, a, state.source, p.n_lps())
        if self.on_certified is not None:
            self.on_certified(user)
