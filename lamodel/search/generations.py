"""The GA's generations evaluated in parallel, with the same answer for any number of
workers (issue 12): in threads of this process, or as tasks on a dask.distributed cluster.

A serial GA evaluates each genome on the search's warm engine, so an evaluation depends
on every one before it (the LPs' bases, the caches of certifications and descents, the
best state so far that centres the cohesions). Here every evaluation of a generation is
instead a pure function of

* the **snapshot** taken at the generation's start (:meth:`.gap.fitness.Fitness.snapshot`: the warm
  bases of the statics and cohesive LPs, the reference normal forces, the caches), and
* its **genome**,

run by :func:`.gap.fitness.evaluate_pure` on an engine of its own. Caps on hard LPs are
counted in simplex iterations, never seconds, so an evaluation gives the same states on
any machine and under any load. The search then takes the outcomes in task order
(:mod:`.genetic`), the stopping rule counted in that order too: the certified
alpha, the tables and the LP count are the same with 1, 2 or 8 threads and on Dask.
"""
from __future__ import annotations

import math
import threading
import uuid

import numpy as np

from .options import Deadline, Stopped
from .tuning import EVALUATION_SLICE
from .workers import threads


def parallel(opt) -> bool:
    """Are the GA's evaluations pure (``opt.ga_workers`` or ``opt.scheduler`` given)?"""
    return opt.ga_workers is not None or opt.scheduler is not None


class Evaluators:
    """Engines of one structure for pure evaluations (:class:`.gap.lanes.Engines`).
    It is also what a Dask worker keeps per structure
    (:func:`lamodel.search.executor.context`), so its threads share the engines."""

    def __init__(self, structure):
        from .gap import GapSearch
        from .gap.lanes import Engines
        self.structure = structure
        self.engines = Engines(lambda: GapSearch(structure))

    def evaluate(self, snap: dict, genome, chain: int, deadline: Deadline):
        """(alpha, states, LP solves, learned) of one genome; raises Stopped at the deadline."""
        from .gap.fitness import evaluate_pure
        return self.engines.run(evaluate_pure, snap, genome, chain, deadline)


def _on_dask_worker(key, structure, snap, genome, chain, deadline):
    """A Dask task: one pure evaluation on this worker's engines of the structure.
    Stopped (the time limit: the deadline travels as the seconds the search had left when
    it submitted) comes back as None, never raised: Dask would retry a task that raises."""
    from .executor import context
    try:
        return context(key, structure, Evaluators).evaluate(snap, genome, chain, deadline)
    except Stopped:
        return None


class _Now:
    """A future computed when asked for, in the calling thread (one worker)."""

    def __init__(self, fn, *args):
        self.fn, self.args = fn, args

    def result(self, timeout=None):
        return self.fn(*self.args)

    def cancel(self):
        return True


class _Threads:
    def __init__(self, structure, workers: int, deadline: Deadline, chain: int):
        self.evaluators, self.deadline, self.chain = Evaluators(structure), deadline, chain
        self.pool = threads(workers, "ga") if workers > 1 else None

    def submit(self, snap, X):
        if self.pool is None:
            return [_Now(self.evaluators.evaluate, snap, z, self.chain, self.deadline) for z in X]
        return [self.pool.submit(self.evaluators.evaluate, snap, z, self.chain, self.deadline) for z in X]

    def close(self):
        if self.pool is not None:
            self.pool.shutdown(wait=True, cancel_futures=True)


class _Dask:
    """Evaluations as tasks on a dask.distributed cluster: the structure is sent once,
    each generation's snapshot once (the workers fetch it), each task carries a genome."""

    def __init__(self, structure, scheduler: str | None, client, deadline: Deadline, chain: int):
        from .executor import Executor, fingerprint, share
        self.executor = None
        if client is None:  # a connection of its own (closed with it)
            self.executor = Executor(scheduler=scheduler)
            client = self.executor.client
        self.client, self.deadline, self.chain = client, deadline, chain
        self.key = "ga-" + fingerprint(structure)
        self.structure = share(client, structure, self.key)
        self.run, self.generation, self.snapshot = uuid.uuid4().hex[:12], 0, None

    def submit(self, snap, X):
        from .executor import share
        g, self.generation = self.generation, self.generation + 1
        self.snapshot = share(self.client, snap, f"{self.run}-{g}")
        return [_DaskOutcome(self.client.submit(_on_dask_worker, self.key, self.structure, self.snapshot, z,
                                                self.chain, self.deadline, key=f"lamodel-ga-{self.run}-{g}-{i}",
                                                retries=1, pure=False))
                for i, z in enumerate(X)]

    def close(self):
        self.snapshot = self.structure = None
        if self.executor is not None:
            self.executor.close()


class _DaskOutcome:
    """A Dask future waited for in slices. (Not ``future.result(timeout)``: distributed
    2026.8 can lose the result of a call whose timeout races the answer.)"""

    def __init__(self, future):
        self.future, self.done = future, threading.Event()
        future.add_done_callback(lambda _: self.done.set())

    def result(self, timeout=None):
        if not self.done.wait(timeout):
            raise TimeoutError()
        value = self.future.result()
        if value is None:
            raise Stopped()
        return value

    def cancel(self):
        self.future.cancel()


class Generations:
    """How the GA evaluates a generation (``batch_fitness`` of :func:`.ga.genetic_search`).

    ``parallel`` is False by default: the GA then evaluates genome after genome on the
    search's own warm engine (a serial run's answer, the fewest LPs). With
    ``opt.ga_workers = W`` the evaluations are pure and run in W threads (W = 1: in this
    thread, one after the other); with ``opt.scheduler`` they are Dask tasks (on
    ``client`` when given, e.g. the Ipopt starts' connection). ``take(outcome, left)``
    merges an outcome into the search (in task order); ``stalled()`` is the stopping rule,
    asked before each outcome is taken: the rest of the generation is discarded.
    """

    def __init__(self, engine, opt, take, stalled, client=None):
        self.engine, self.opt, self.take, self.stalled, self.client = engine, opt, take, stalled, client
        self.parallel = parallel(opt)
        self.backend = None

    def __enter__(self):
        if self.opt.scheduler is not None:
            self.backend = _Dask(self.engine.problem.user, self.opt.scheduler, self.client, self.engine.deadline,
                                 self.opt.chain)
        elif self.parallel:
            self.backend = _Threads(self.engine.problem.user, self.opt.ga_workers, self.engine.deadline, self.opt.chain)
        return self

    def __exit__(self, *exc):
        if self.backend is not None:
            self.backend.close()

    def evaluate(self, X):
        """The fitness of each row of X, the outcomes taken in row order."""
        futures = self.backend.submit(self.engine.fitness.snapshot(), np.asarray(X, float))
        out = np.full(len(X), math.inf)
        try:
            for i, fut in enumerate(futures):
                if self.stalled():  # the GA stops after this generation; the rest is discarded
                    break
                out[i] = self.take(self._wait(fut), len(X) - 1 - i)
        finally:
            for fut in futures:
                fut.cancel()
        return out

    def _wait(self, fut):
        """The outcome, the search's deadline (Ctrl-C) checked while it is computed."""
        while True:
            try:
                return fut.result(timeout=EVALUATION_SLICE)
            except TimeoutError:
                self.engine.deadline.check()
