"""Ferris & Tin-Loi (2001), Int. J. Mech. Sci. 43:209-224: the complementarity of flow and
yield relaxed to xi^T slack <= rho, rho driven to zero through a sequence of NLPs (Ipopt,
warm-started), from the associative solution. In eq. (5) alpha_K - alpha = xi^T slack, so
the relaxation is the model's ``epsilon``."""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..options import Deadline, SolveOptions
from ..state import Run
from ..tuning import MPEC_LADDER, MPEC_LANE_BLOCKS, MPEC_LANE_ITERATIONS
from .result import MethodResult, finish, ipopt_model, start_state
from .successive_lp import certified, run_once


@dataclass(frozen=True)
class MPEC:
    """min alpha with 0 <= xi^T slack <= rho, rho -> 0 (MPEC_LADDER), each NLP warm-started
    from the previous one. Ipopt with bound_relax_factor 0 (its default relaxation of
    N <= 0 makes fake, low alphas). ``method`` alone (``--method mpec``), or ``run`` as the
    search's last lane (in the plane, dry joints, up to MPEC_LANE_BLOCKS blocks)."""

    name = "MPEC"
    once = "MPEC"

    def method(self, structure, options, lps, assoc, t0, deadline=None):
        from ..ipopt import ipopt_ladder
        result = MethodResult("mpec", structure, alpha_associative=assoc.alpha, seed=options.seed)
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

    def run(self, engine, start):
        """The method as ``--method mpec`` runs it (the user's units, the structure in the
        search's canonical order, its own associative LP: the same answer), each NLP at most
        MPEC_LANE_ITERATIONS Ipopt iterations (an iteration costs about as blocks^1.8: hence
        the size bound); its raw answer certified by the search and descended
        (:func:`.successive_lp.certified`). Its two LPs count in the search's work."""
        from ..ipopt import ipopt_ladder
        from ..lp import LimitLPs
        p, ran = engine.problem, engine.lanes.ran
        s = getattr(p, "s", None)
        if (self.once in ran or s is None or s.has_materials or start.x_assoc is None
                or s.n_blocks > MPEC_LANE_BLOCKS):
            return ran.get(self.once, (None,))[0]  # in space, strengths, or too large: not run
        t = time.perf_counter()
        lps = LimitLPs(p.user)
        lps.deadline = p.deadline

        def lane():
            assoc = lps.associative()
            begin = start_state(lps, assoc) if assoc.ok else None
            p.lps_elsewhere += lps.n_solves
            p.work_elsewhere += lps.work
            if begin is None or engine.budget.over():
                return None
            model, nlp = ipopt_model(p.user, SolveOptions())
            raw, _, _ = ipopt_ladder(model, nlp, p.user, begin, MPEC_LADDER, {"max_iter": int(MPEC_LANE_ITERATIONS)},
                                     p.deadline)
            return certified(engine, _scaled(p, raw), "mpec")

        return run_once(engine, self.once, "MPEC", t, lane)


def _scaled(p, raw):
    """A raw answer (N, V, M, alpha, u, xi) in the user's units in the search's scaled units
    (:meth:`lamodel.search.gap.problem.ScaledProblem.to_user`, inverted)."""
    N, V, M, alpha, u, xi = raw
    F, L, nc = p.F, p.L, p.nc
    u = np.array(u, dtype=float) * (F * L)
    u[0::3] /= L
    u[1::3] /= L
    xi = np.array(xi, dtype=float) * (F * L)
    xi[:2 * nc] /= L
    return N / F, V / F, M / (F * L), alpha, u, xi
