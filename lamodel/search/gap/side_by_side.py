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


def side_by_side(new_engine, calls, workers: int, running=None):
    """The outcomes of ``calls`` (each ``(method, args)`` of an engine's ``fitness``), in
    call order, run in up to ``workers`` threads (1: one after the other in this thread)
    on engines made by ``new_engine()``, an engine reused by the next call once its
    evaluation ends unstopped. Each evaluation stops at the deadline among its arguments
    (a Ctrl-C reaches it there); this waits for them all. ``running`` (a dict), if given,
    holds each engine at work and its LP work when it began (for a progress display)."""
    idle = queue.SimpleQueue()

    def run(method, args):
        try:
            engine = idle.get_nowait()
        except queue.Empty:
            engine = new_engine()
        if running is not None:
            running[id(engine)] = (engine, engine.problem.work())
        try:
            outcome = getattr(engine.fitness, method)(*args)
        finally:
            if running is not None:
                running.pop(id(engine), None)
        if not engine.fitness.stopped:
            idle.put(engine)  # not after a stop: an engine is unusable after it
        return outcome

    workers = max(1, min(int(workers), len(calls)))
    if workers == 1:
        return [run(method, args) for method, args in calls]
    with ThreadPoolExecutor(workers, thread_name_prefix="lamodel-start") as pool:
        futures = [pool.submit(run, method, args) for method, args in calls]
        return [future.result() for future in futures]
