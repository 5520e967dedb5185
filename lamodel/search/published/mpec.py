"""Ferris & Tin-Loi (2001), Int. J. Mech. Sci. 43:209-224: the complementarity of flow and
yield relaxed to xi^T slack <= rho, rho driven to zero through a sequence of NLPs (Ipopt,
warm-started), from the associative solution. In eq. (5) alpha_K - alpha = xi^T slack, so
the relaxation is the model's ``epsilon``."""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..options import Deadline
from ..state import Run
from ..tuning import MPEC_LADDER
from .result import MethodResult, finish, ipopt_model, start_state


@dataclass(frozen=True)
class MPEC:
    """min alpha with 0 <= xi^T slack <= rho, rho -> 0 (MPEC_LADDER), each NLP warm-started
    from the previous one. Ipopt with bound_relax_factor 0 (its default relaxation of
    N <= 0 makes fake, low alphas)."""

    name = "mpec"

    def method(self, structure, options, lps, assoc, t0, deadline=None):
        from ..ipopt import ipopt_ladder
        result = MethodResult(self.name, structure, alpha_associative=assoc.alpha, seed=options.seed)
        start = start_state(lps, assoc)
        if start is None:  # the cohesive LP of the start stopped (the time limit) or failed
            return result.failed("no start point: the cohesive LP of the associative statics ended without an "
                                 f"optimum{' (time limit)' if lps.deadline.expired() else ''}", t0)
        model, nlp = ipopt_model(structure, options)
        raw, message, iterations = ipopt_ladder(model, nlp, structure, start, MPEC_LADDER, options.ipopt_options,
                                                deadline or Deadline())
        result.iterations = iterations
        result.runs = [Run(0, "relaxed MPEC from the associative solution", raw[3], message, np.nan, iterations,
                           time.perf_counter() - t0)]
        return finish(result, lps, raw, t0, f"{len(MPEC_LADDER)} NLPs, last: {message}")
