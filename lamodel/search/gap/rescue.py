"""The rescue: where the main ladder certifies nothing, other ladders from where it stalled
and from the associative statics."""
from __future__ import annotations

from dataclasses import dataclass

from ..tuning import RHO_HIGH, RHO_LOW, RHO_MAIN
from .record import least


@dataclass(frozen=True)
class Rescue:
    """Higher rho from where the main ladder stalled (the gap, and the flows on slack rows,
    shrink with rho: 2040 blocks), then from the associative statics with flow on slack
    rows forbidden, and a low rho ladder; each followed by certification from near-active
    rows, until one certifies."""

    name = "rescue"
    once = None

    def run(self, engine, start):
        best = None
        starts = [(start.x_assoc, dict(rhos=RHO_MAIN, forbid_slack=True)), (start.x_assoc, dict(rhos=RHO_LOW))]
        if start.x_stall is not None:
            starts.insert(0, (start.x_stall, dict(rhos=RHO_HIGH)))
        for x0, kw in starts:
            st, x = engine.alternation.alternate(x0, source="rescue", **kw)
            best = least(best, st)
            best = least(best, engine.near.certify(x, "rescue-near"))
            if best is not None:
                break
        return best
