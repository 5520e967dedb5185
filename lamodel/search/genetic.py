"""The GA phase of the search: pymoo's GA (:mod:`.ga`) over the genome z (one gene a
contact: cohesions ``c = -mu N_best exp(z)`` around the best certified state), with the
engine's fitness (:class:`.gap.fitness.Fitness`) and its stopping rule, counted in
evaluations and LP solves, not timed: a seed gives the same answer on any machine."""
from __future__ import annotations

import math
import time

import numpy as np

from . import ga  # pymoo's GA, looked up at the call (tests count its evaluations)
from .generations import Generations
from .tuning import DESCENT_STEP, NO_CERTIFICATE, STALL_WORK, Z_INIT, Z_MAX


def genetic_search(engine, opt, client=None, lps_first=None, stall_work=STALL_WORK):
    """pymoo's GA over z with the engine's fitness (module doc); with ``opt.ga_workers`` or
    ``opt.scheduler`` each generation's evaluations are pure and run in parallel
    (:mod:`.generations`; ``client``: a Dask connection to use). It stops at the engine's
    work bounds (:class:`.budget.Budget`); ``stall_work``: see stalled."""
    nc, fitness_of, record = engine.problem.nc, engine.fitness, engine.record
    lps_first = max(engine.n_lps() if lps_first is None else lps_first, 1)  # the first certificate's work
    state = {"evals": 0, "since": 0, "best": record.alpha(), "lps": engine.n_lps()}

    def stalled():
        """The stopping rule: pop_size evaluations and ``stall_work`` times the LPs of the
        first certificate without improvement (LPs, not seconds: deterministic); without a
        time limit, also the search's work bounds (evaluations elsewhere merged in task
        order count theirs: the same with any number of workers)."""
        if engine.budget.spent():
            return True
        return (state["since"] >= opt.pop_size
                and engine.n_lps() - state["lps"] >= stall_work * lps_first)

    def counted(alpha, left=0):
        """The GA's fitness of an evaluation whose states the engine has taken: the
        stopping rule's counts follow, and no certificate is worth 10 + the best alpha.
        ``left``: evaluations of this generation after this one, from the same snapshot
        (they cannot use the improvement: the stall is counted after them)."""
        state["evals"] += 1
        if _better(record.alpha(), state["best"]):
            state.update(best=record.alpha(), since=-left, lps=engine.n_lps())
        else:
            state["since"] += 1
        return alpha if np.isfinite(alpha) else NO_CERTIFICATE + (state["best"] if np.isfinite(state["best"]) else 0.0)

    def fitness(z):
        if stalled():  # the rest of this generation is skipped, then the GA stops
            return math.inf
        # one evaluation (a chain of certified, descended steps) can cost a tenth of the
        # work bound at 510 blocks: it ends between two LP solves once the bound is
        # spent (what it certified is in the record already)
        alpha = math.inf
        with engine.budget.lane():
            alpha = fitness_of.evaluate(z, opt.chain, reference_N=fitness_of.reference_N())
        return counted(alpha)

    def take(outcome, left):
        """One pure evaluation's outcome (generations.py), taken in task order."""
        alpha, states, lps, learned = outcome
        fitness_of.merge(states, lps, learned)
        return counted(alpha, left)

    rng = np.random.default_rng(opt.seed)
    sigma = np.resize(Z_INIT, opt.pop_size)[:, None]  # small, medium and large perturbations
    initial = np.clip(sigma * rng.standard_normal((opt.pop_size, nc)), -Z_MAX, Z_MAX)
    initial[0] = 0.0
    t = time.perf_counter()
    try:
        with Generations(engine, opt, take, stalled, client) as generations:
            ga.genetic_search(fitness, nc, initial=initial, lower=-Z_MAX, upper=Z_MAX, pop_size=opt.pop_size,
                              generations=opt.generations, seed=opt.seed, out_of_time=stalled,
                              batch_fitness=generations.evaluate if generations.parallel else None)
    finally:
        record.phase("ga", t)


def _better(a, b):
    """a improves on b (b may be inf: nothing yet)."""
    return a < b if not math.isfinite(b) else a < b - DESCENT_STEP * max(1.0, abs(b))
