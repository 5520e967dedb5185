"""The associative method: the LP of max alpha over S (eq. 1-4) with associative (dilatant)
flow, an upper bound on every collapse multiplier, exact when the mechanism only hinges."""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..state import Run
from .result import MethodResult, finish


@dataclass(frozen=True)
class Associative:
    name = "associative"

    def method(self, structure, options, lps, assoc, t0, deadline=None):
        result = MethodResult(self.name, structure, alpha_associative=assoc.alpha, iterations=1, seed=options.seed)
        N, V, M, alpha = lps.split(assoc.x)
        # the associative flow of the LP's duals: u, and lambda >= 0 on the yield rows of eq. 4
        u = -assoc.row_dual[:3 * lps.nb]
        lam = np.maximum(-assoc.row_dual[3 * lps.nb:], 0.0)
        result.runs = [Run(0, "associative LP", alpha, "optimal", np.nan, 1, time.perf_counter() - t0)]
        return finish(result, lps, (N, V, M, alpha, u, lam), t0, "upper bound (dilatant flow)")
