"""The dilatancy continuation: a homotopy from the associative statics, an exact solution,
down to the seed's frictional system."""
from __future__ import annotations

import time
from dataclasses import dataclass

from ..tuning import DILATANCY_STEPS, DILATANCY_TRACK, RHO_HIGH
from .record import least


@dataclass(frozen=True)
class Dilatancy:
    """The dilatancy continuation, once a search: from the associative statics (at t = 1
    the fictitious system whose sliding dilates by t mu is the associative one, whose
    optimum is a collapse state) through the systems of DILATANCY_STEPS down to the seed's
    (t = 0), the gap alternation tracking the statics at each t; at t = 0 the alternation
    certifies, and where it stalls below the best, RHO_HIGH and the rows the statics nearly
    holds, then the seed's fixed-point chain from the stall. It reaches collapse states the
    other starts miss (the 510-block running-bond wall at mu = 1.0: 0.568109, where the
    others certify 0.816327). It ends at the work bounds."""

    name = "dilatancy continuation"
    once = "dilatancy"

    def run(self, engine, start):
        ran = engine.lanes.ran
        if self.once in ran:
            return ran[self.once][0]
        t = time.perf_counter()
        near, record, budget = engine.near, engine.record, engine.budget
        alternate = engine.alternation.alternate
        best = None
        try:
            with budget.lane():
                x = start.x_assoc
                for dil in DILATANCY_STEPS:
                    _, x = alternate(x, source="dilatancy", dilatancy=dil, max_steps=DILATANCY_TRACK)
                best, x = alternate(x, source="dilatancy")
                if near.stalled_below(x, record.best):
                    st, x = alternate(x, rhos=RHO_HIGH, source="dilatancy")
                    best = least(best, st)
                    if near.stalled_below(x, record.best):
                        best = least(best, near.certify(x, "dilatancy-near"))
                if near.stalled_below(x, record.best):
                    best = least(best, engine.chains.fixed_point((x,), source="dilatancy-fixed", until=budget.spent))
        finally:
            ran[self.once] = (best,)
            record.phase("dilatancy", t)
        return best
