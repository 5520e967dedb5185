"""The backstop of a capped cold solve's simplex (:class:`lamodel.search.highs.HighsLP`)."""
from __future__ import annotations

import time

from .tuning import CAP_BACKSTOP, CAP_BACKSTOP_MIN, CAP_BACKSTOP_SAMPLE


class Pace:
    """The backstop of a capped cold solve's simplex, which has no warm speed of this LP to
    go by: CAP_BACKSTOP times the time its cap takes at the speed of its own first
    CAP_BACKSTOP_SAMPLE iterations (CAP_BACKSTOP_MIN s at least). A barrel vault's
    alignment LP went on after its interior point run at 2,000 iterations a second, then
    at 5 (each in a proof of primal infeasibility) and would have taken hours to its cap."""

    def __init__(self, cap: int):
        self.cap, self.start, self.limit, self.cut = cap, None, None, False

    def slow(self, iterations: int) -> bool:
        """At a simplex iteration: past the backstop (then ``cut``)."""
        if iterations < 0:  # HiGHS calls it in its interior point run too, with no iteration count
            return False
        now = time.perf_counter()
        if self.start is None:
            self.start = (now, iterations)
            return False
        t0, i0 = self.start
        if self.limit is None:
            if iterations - i0 < CAP_BACKSTOP_SAMPLE:
                return False
            self.limit = CAP_BACKSTOP * max(CAP_BACKSTOP_MIN, self.cap * (now - t0) / (iterations - i0))
        self.cut = self.cut or now - t0 > self.limit
        return self.cut
