"""The genetic algorithm that seeds the search (the seed solves eq. 5 with a GA).

The genome is the vector of fictitious cohesions, one gene per contact, as multiples of a
reference cohesion: c_k = g_k * c_ref_k. For a fixed c, eq. (5)'s fictitious system is an
LP (:meth:`lamodel.search.lp.LimitLPs.cohesive`) whose primal is a statics and whose duals are a
mechanism — a complete point of eq. (5), which the fitness function certifies.

The GA itself is pymoo's single-objective GA (tournament selection, simulated binary
crossover, polynomial mutation, (mu + lambda) survival that keeps the best — elitism —
and removal of duplicate genomes), driven by a seeded generator: a well-kept library
instead of a hand-written loop, and the same seed gives the same population history.
"""
from __future__ import annotations

import numpy as np
from pymoo.algorithms.soo.nonconvex.ga import GA
from pymoo.core.duplicate import DefaultDuplicateElimination
from pymoo.core.problem import Problem
from pymoo.core.termination import Termination
from pymoo.operators.crossover.sbx import SBX
from pymoo.operators.mutation.pm import PM
from pymoo.optimize import minimize


class _CohesionProblem(Problem):
    """min fitness(g) over g in [lower, upper]^n (one gene per contact)."""

    def __init__(self, fitness, lower, upper, batch_fitness=None):
        super().__init__(n_var=len(lower), n_obj=1, xl=np.asarray(lower, float), xu=np.asarray(upper, float))
        self.fitness, self.batch_fitness = fitness, batch_fitness

    def _evaluate(self, X, out, *args, **kwargs):
        if self.batch_fitness is not None:  # a generation at once (evaluated in parallel)
            out["F"] = np.asarray(self.batch_fitness(np.asarray(X, float)), float).reshape(-1, 1)
        else:
            out["F"] = np.array([[self.fitness(x)] for x in X])


class _ExactDuplicates(DefaultDuplicateElimination):
    """pymoo's default rule (a genome within 1e-16 of an earlier one, or of one already in
    the population, is dropped) by exact comparison of the rows: the same verdicts without
    loading scipy.spatial for a distance matrix (0.17 s, a tenth of a seed wall's run)."""

    def _do(self, pop, other, is_duplicate):
        seen = set() if other is None else {r.tobytes() for r in np.asarray(self.func(other), float) + 0.0}
        for i, row in enumerate(np.asarray(self.func(pop), float) + 0.0):  # + 0.0: -0.0 is 0.0
            key = row.tobytes()
            if key in seen:
                is_duplicate[i] = True
            elif other is None:
                seen.add(key)
        return is_duplicate


class _Budget(Termination):
    """Stop after n generations, or earlier when the caller says time is up."""

    def __init__(self, generations, out_of_time):
        super().__init__()
        self.generations, self.out_of_time = generations, out_of_time

    def _update(self, algorithm):
        if self.out_of_time():
            return 1.0
        return algorithm.n_gen / self.generations


def genetic_search(fitness, n_genes: int, initial=None, lower=0.0, upper=2.0, pop_size: int = 16,
                   generations: int = 8, seed: int = 0, out_of_time=lambda: False, batch_fitness=None):
    """Minimise fitness(genome) with a GA; returns (best genome, best fitness, n_evaluations).

    ``initial`` rows (e.g. the genome of the associative solution) seed the first
    population; the rest of it is drawn uniformly from the box by the seeded generator.
    ``batch_fitness(X)``, when given, evaluates a whole generation (rows of X) at once.
    """
    lower = np.full(n_genes, lower, dtype=float)
    upper = np.full(n_genes, upper, dtype=float)
    rng = np.random.default_rng(seed)
    pop = rng.uniform(lower, upper, size=(pop_size, n_genes))
    if initial is not None:
        initial = np.atleast_2d(np.asarray(initial, dtype=float))[:pop_size]
        pop[:len(initial)] = np.clip(initial, lower, upper)
    algorithm = GA(pop_size=pop_size, sampling=pop, crossover=SBX(prob=0.9, eta=15),
                   mutation=PM(eta=20), eliminate_duplicates=_ExactDuplicates())
    problem = _CohesionProblem(fitness, lower, upper, batch_fitness)
    res = minimize(problem, algorithm, _Budget(generations, out_of_time), seed=seed, verbose=False)
    n_eval = int(res.algorithm.evaluator.n_eval)
    if res.X is None:
        return None, np.inf, n_eval
    return np.asarray(res.X, dtype=float), float(np.atleast_1d(res.F)[0]), n_eval
