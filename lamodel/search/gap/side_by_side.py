"""Independent starts side by side: pure evaluations on engines of their own, in threads.

A pure evaluation (:class:`.fitness.Fitness`: ``evaluate_pure``, ``starts_pure``) depends on
its arguments alone (a snapshot of the search, what to run, its share of the work
bounds), so the outcomes, taken in call order, are the same with any number of threads.
HiGHS releases the GIL while it solves: two starts take about the time of the longer one
on two cores.
"""
from __future__ import annotations

import queue
from concurrent.futures import ThreadPoolExecutor


class Engines:
    """Engines of one structure for pure evaluations, made by ``new_engine()`` on first need
    and reused (a HiGHS model is built once; each evaluation only re-warms it from its
    snapshot): one per evaluation running at a time. ``running`` (a dict), if given, holds
    each engine at work and its LP work when it began (for a progress display)."""

    def __init__(self, new_engine, running=None):
        self.new_engine, self.running = new_engine, running
        self.idle = queue.SimpleQueue()

    def run(self, method, *args):
        """``engine.fitness.<method>(*args)`` on an idle engine; the engine is reused
        unless the evaluation was stopped (an engine is unusable after a stop)."""
        try:
            engine = self.idle.get_nowait()
        except queue.Empty:
            engine = self.new_engine()
        if self.running is not None:
            self.running[id(engine)] = (engine, engine.problem.work())
        try:
            outcome = getattr(engine.fitness, method)(*args)
        finally:
            if self.running is not None:
                self.running.pop(id(engine), None)
        if not engine.fitness.stopped:
            self.idle.put(engine)
        return outcome


def side_by_side(new_engine, calls, workers: int, running=None):
    """The outcomes of ``calls`` (each ``(method, args)`` of an engine's ``fitness``), in
    call order, run in up to ``workers`` threads (1: one after the other in this thread)
    on :class:`Engines` made by ``new_engine()``. Each evaluation stops at the deadline
    among its arguments (a Ctrl-C reaches it there); this waits for them all. ``running``:
    see :class:`Engines`."""
    engines = Engines(new_engine, running)
    workers = max(1, min(int(workers), len(calls)))
    if workers == 1:
        return [engines.run(method, *args) for method, args in calls]
    with ThreadPoolExecutor(workers, thread_name_prefix="lamodel-start") as pool:
        futures = [pool.submit(engines.run, method, *args) for method, args in calls]
        return [future.result() for future in futures]


def alongside(here, new_engine, calls, workers: int, running=None):
    """``here()`` in this thread (on the search's own engine) while the pure ``calls`` run
    in up to ``workers - 1`` other threads (one worker: after it); the calls' outcomes in
    call order, once ``here()`` and they have all ended, whatever ``here()`` raised (it is
    raised after them). ``running``: see :class:`Engines`."""
    if int(workers) <= 1:
        try:
            here()
        finally:
            outcomes = side_by_side(new_engine, calls, 1, running)
        return outcomes
    with ThreadPoolExecutor(1, thread_name_prefix="lamodel-lanes") as pool:
        future = pool.submit(side_by_side, new_engine, calls, int(workers) - 1, running)
        try:
            here()
        finally:
            outcomes = future.result()
    return outcomes
