"""Certification from the rows a statics nearly holds: where an alternation stalls below
the best certified alpha with flows left on slack rows."""
from __future__ import annotations

import numpy as np

from ..tuning import BELOW_BEST, SEARCH_ACTIVE
from .alternation import Alternation
from .certify import Certifier
from .descent import Descent
from .program import GapProgram
from .record import least


class Near:
    """Certifies from near-active rows on a problem."""

    def __init__(self, problem: GapProgram, certifier: Certifier, descent: Descent, alternation: Alternation):
        self.problem, self.certifier, self.descent, self.alternation = problem, certifier, descent, alternation

    def stalled_below(self, x, best) -> bool:
        """The statics x, where the last alternation ended, stalled below the certified state
        ``best`` (or nothing is certified). An alternation that ended at a certified mechanism
        did not stall: its statics' alpha is that state's less a round-off gap."""
        if self.alternation.converged:
            return False
        return best is None or x[-1] < best.alpha - BELOW_BEST * max(1.0, best.alpha)

    def certify(self, x, source, first=False):
        """Certification from the rows the statics x holds nearly active, at several
        tolerances (``first``: stop at the first tolerance that certifies)."""
        p = self.problem
        return self.certify_slack(p.slack(x), max(1.0, np.abs(x).max()), p.N_of(x), source, first=first)

    def certify_slack(self, slack, scale, N, source, tols=SEARCH_ACTIVE, first=False):
        """For each tolerance: the rows with slack <= tol * scale may flow; the least-alpha_K
        mechanism on them for cohesions -mu N, certified and descended. The least alpha
        certified (``first``: at the first tolerance that certifies), or None."""
        best = None
        c = -self.problem.mu * N
        tried = set()
        for tol in tols:
            allowed = slack <= tol * scale
            key = allowed.tobytes()
            if key in tried or not allowed.any():
                continue
            tried.add(key)
            status, _, _, u, xi = self.problem.mechanism(c, allowed)
            if status != "optimal":
                continue
            st = self.certifier.certify(u, xi, source)
            if st is not None:
                best = least(best, self.descent.descend(st))
                if first:
                    break
        return best
