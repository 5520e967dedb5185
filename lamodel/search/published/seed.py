"""The seed paper's method as it describes it: a genetic algorithm on eq. (5); each
individual starts an Ipopt solve of eq. (5) (the bilinear condition exact, no relaxation)
and its fitness is the multiplier Ipopt returns."""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..options import Deadline
from ..state import CollapseState, Run
from ..tuning import SEED_FEASIBILITY, SEED_GENE_MAX, SEED_GENERATIONS, SEED_LADDER, SEED_POP_SIZE, SEED_SPREAD
from .result import MethodResult, finish, ipopt_model


@dataclass(frozen=True)
class SeedGA:
    """A genome g (one gene per contact) is turned into a start point of eq. (5) by the
    fictitious cohesive LP with cohesions g * (-mu N_assoc) (its primal a statics, its duals
    a mechanism); Ipopt solves eq. (5) from it with the bilinear condition exact; the
    fitness is Ipopt's alpha (penalised when its point is infeasible beyond
    SEED_FEASIBILITY). The raw answer is the fittest individual's point."""

    pop_size: int = SEED_POP_SIZE
    generations: int = SEED_GENERATIONS
    name = "seed"

    def method(self, structure, options, lps, assoc, t0, deadline=None):
        from ..certify import residuals
        from ..ga import genetic_search
        from ..ipopt import ipopt_ladder
        deadline = deadline or Deadline()
        result = MethodResult(self.name, structure, alpha_associative=assoc.alpha, seed=options.seed)
        model, nlp = ipopt_model(structure, options)
        c_ref = structure.mu * -np.minimum(lps.split(assoc.x)[0], 0.0)
        best = {"fitness": np.inf, "raw": None, "run": 0}
        penalty = assoc.alpha + 1.0

        def fitness(g):
            t = time.perf_counter()
            if deadline.expired():
                return penalty
            res, u, xi = lps.cohesive(g * c_ref)
            if not res.ok:
                return penalty
            N, V, M, alpha = lps.split(res.x)
            start = CollapseState(alpha=alpha, N=N, V=V, M=M, u=u, xi=xi, flow=xi > 0)
            raw, message, iterations = ipopt_ladder(model, nlp, structure, start, SEED_LADDER,
                                                    options.ipopt_options, deadline)
            result.iterations += iterations
            worst = max(residuals(lps, *raw).values())
            value = raw[3] if worst <= SEED_FEASIBILITY else penalty + raw[3]
            result.runs.append(Run(len(result.runs), f"GA individual {len(result.runs) + 1}", raw[3],
                                   f"{message}, largest residual {worst:.1e}", np.nan, iterations,
                                   time.perf_counter() - t))
            if value < best["fitness"]:
                best.update(fitness=value, raw=raw, run=len(result.runs) - 1)
            return value

        rng = np.random.default_rng(options.seed)
        initial = np.exp(rng.normal(0.0, SEED_SPREAD, size=(self.pop_size, structure.n_contacts)))
        initial[0] = 1.0  # the associative cohesions
        genetic_search(fitness, structure.n_contacts, initial=initial, upper=SEED_GENE_MAX, pop_size=self.pop_size,
                       generations=self.generations, seed=options.seed, out_of_time=deadline.expired)
        n = len(result.runs)
        if best["raw"] is None:
            return result.failed(f"none of {n} Ipopt solves ran", t0)
        feasible = best["fitness"] < penalty
        extra = f"GA {self.pop_size} x {self.generations}, {n} Ipopt solves of eq. 5" + (
            "" if feasible else f"; no Ipopt point feasible within {SEED_FEASIBILITY:g}: the least alpha is reported")
        return finish(result, lps, best["raw"], t0, extra, best["run"])
