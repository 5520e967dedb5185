"""A continuation: the gap alternation from the associative statics on another penalty
ladder, into other collapse states than the main ladder's."""
from __future__ import annotations

import time
from dataclasses import dataclass

from ..tuning import RHO_CONTS, RHO_HIGH, RHO_SLOW
from .record import least


@dataclass(frozen=True)
class Continuation:
    """A start from the associative statics on the penalty ladder ``rhos``: a low rho lets
    alpha fall far before the gap is squeezed out (the penalty method's continuation).
    Where it stalls below the best certified alpha, rho goes on up (RHO_HIGH) and the rows
    the statics nearly holds are certified. It ends early, between two LP solves, once the
    work bounds are spent. Returns the least certified state of the start (or None; what it
    certified before an early end is in the record)."""

    rhos: tuple = RHO_CONTS[0]
    name = "continuation"
    source = "continuation"  # runs.csv's path of what it certifies (driver.PATHS)
    once = None

    def run(self, engine, start):
        t = time.perf_counter()
        near, alternate, record = engine.near, engine.alternation.alternate, engine.record
        try:
            with engine.budget.lane():  # the time limit or a stop: the search's to handle
                best, x = alternate(start.x_assoc, rhos=self.rhos, source=self.source)
                if near.stalled_below(x, record.best):
                    st, x = alternate(x, rhos=RHO_HIGH, source=self.source)
                    best = least(best, st)
                    if near.stalled_below(x, record.best):
                        best = least(best, near.certify(x, f"{self.source}-near"))
                return best
            return None
        finally:
            record.phase(self.name, t)


@dataclass(frozen=True)
class SlowContinuation(Continuation):
    """The continuation on a slow ladder (RHO_SLOW: rho doubled from 1): the penalty
    method's counterpart of Ferris & Tin-Loi's relaxation xi^T slack <= rho driven to zero
    step by step. Where the statics must cross to another mechanism, the quick ladders jump
    past the states the slow one follows (docs/method/evidence.md, "The slow continuation")."""

    rhos: tuple = RHO_SLOW
    name = "slow continuation"
    source = "slow-continuation"
