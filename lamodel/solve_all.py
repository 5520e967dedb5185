"""The first pass of a load-case or rolling study: every variant solved, one after another
in this process or side by side in local worker processes, with the same outcomes either
way (a solve's answer does not depend on its number of workers: :mod:`.search.gap.lanes`).

``options.workers`` (``--workers``; all cores when not given) is the number of variants
solved at once; each of them then runs its search on one core, as a parametric study's
variants do (no pools inside pools). With a Dask ``scheduler`` the variants are solved one
after another, the cluster running each one's GA and Ipopt starts.

A stop signal (Ctrl-C, SIGTERM, SIGHUP) ends the pass as it ends one solve: each solve under
way ends at its next check with its best certified state (status ``interrupted``); the
variants not begun are not run (None). In worker processes the signal reaches every solve
under way from here, whatever sent it to this process, again each second until they have
all ended: a worker that took it before its solve began still ends.

A worker process that dies (killed, out of memory) takes the solves in flight with it:
they are solved again on new workers, once; a second death is an error naming them. The
workers start by importing what the main module imports; a script run as ``python
script.py`` is run again in each of them, so a script that starts studies must do so under
``if __name__ == "__main__":`` (Python's rule for process pools; the error says so).
"""
from __future__ import annotations

import logging
import multiprocessing
import os
import signal
import sys
import threading
from concurrent.futures import FIRST_COMPLETED, wait
from dataclasses import replace

from .search.driver import SolveOptions, solve
from .search.state import INTERRUPTED
from .search.workers import count, processes

log = logging.getLogger(__name__)

#: Seconds between two deliveries of the stop to the workers still solving.
RESEND = 1.0
#: Times a variant whose worker process died (killed, out of memory) is solved again.
RETRIES = 1


def solve_all(variants, options: SolveOptions | None = None, on_outcome=None, labels=None) -> list:
    """The outcome of every variant, in their order (None: not run, after a stop).
    ``on_outcome(i, outcome)`` is called in this process as each one ends; ``labels``
    name the variants in messages (default: their structures' names)."""
    opt = options or SolveOptions()
    workers = min(count(opt.workers), len(variants))
    # (a daemonic process, a multiprocessing pool's worker, may not start processes)
    if workers <= 1 or opt.scheduler is not None or multiprocessing.current_process().daemon:
        return _one_after_another(variants, opt, on_outcome)
    labels = [v.name for v in variants] if labels is None else [str(x) for x in labels]
    return _side_by_side(variants, replace(opt, workers=1, ga_workers=None, progress=False), workers, on_outcome,
                         labels)


def _one_after_another(variants, opt, on_outcome):
    outcomes = [None] * len(variants)
    for i, variant in enumerate(variants):
        outcomes[i] = solve(variant, opt)
        if on_outcome is not None:
            on_outcome(i, outcomes[i])
        if outcomes[i].status == INTERRUPTED:
            break
    return outcomes


def _side_by_side(variants, opt, workers, on_outcome, labels):
    from concurrent.futures.process import BrokenProcessPool

    from .process import kill_quietly
    from .signals import catch_sigint, restore_sigint, stop_signal
    outcomes, pending, running = [None] * len(variants), list(range(len(variants)))[::-1], {}
    tries = [0] * len(variants)
    stop = threading.Event()
    caught = catch_sigint(stop.set)
    pool = _pool(workers)
    try:
        while pending or running:
            if stop.is_set() or stop_signal() is not None:
                stop.set()
                pending.clear()
                _stop_workers(pool)
            # no more variants in flight than workers: each one submitted is being solved
            while pending and len(running) < workers:
                i = pending.pop()
                tries[i] += 1
                running[pool.submit(_solve_here, variants[i], opt)] = i
            done, _ = wait(running, timeout=RESEND if stop.is_set() else 0.2, return_when=FIRST_COMPLETED)
            broken = False
            for fut in done:
                i = running.pop(fut)
                try:
                    outcomes[i] = fut.result()  # a solve that raised raises here, as in one process
                except BrokenProcessPool:
                    broken = True
                    running[fut] = i
                    continue
                if on_outcome is not None:
                    on_outcome(i, outcomes[i])
            if broken:  # a worker died (killed, out of memory): the pool fails every solve in flight
                lost = sorted(running.values())
                running.clear()
                kill_quietly(list((getattr(pool, "_processes", None) or {}).values()))
                pool.shutdown(wait=False, cancel_futures=True)
                if not stop.is_set():
                    twice = [labels[i] for i in lost if tries[i] > RETRIES]
                    if twice:
                        raise RuntimeError(f"the worker processes solving {', '.join(twice)} died {RETRIES + 1} "
                                           f"times ({_why_died()}); try --workers 1 (workers=1)")
                    log.warning("a worker process died; solving %s again", ", ".join(labels[i] for i in lost))
                    pending.extend(lost[::-1])  # solved again first, on a new pool
                    pool = _pool(workers)
    except BaseException:
        kill_quietly(list((getattr(pool, "_processes", None) or {}).values()))
        raise
    finally:
        pool.shutdown(wait=False, cancel_futures=True)
        restore_sigint(caught)
    return outcomes


def _why_died() -> str:
    """The likely causes of workers dying, for the error: a script run as ``python
    script.py`` is run again by every worker (module doc)."""
    main = sys.modules.get("__main__")
    if getattr(main, "__spec__", None) is None and getattr(main, "__file__", None):
        return ("out of memory, or the script starts the study outside 'if __name__ == \"__main__\":', "
                "which each worker runs again")
    return "out of memory?"


def _pool(workers):
    return processes(workers, _worker_start, start="forkserver", preload=("lamodel.search.driver",))


def _stop_workers(pool):
    for p in list((getattr(pool, "_processes", None) or {}).values()):
        try:
            os.kill(p.pid, signal.SIGTERM)
        except (OSError, AttributeError):
            pass


def _worker_start():
    """A worker ends with this process, and a stop signal that reaches it between two
    solves is remembered, never fatal (its next solve is never begun: see above)."""
    from .process import end_with_parent
    from .signals import catch_sigint
    end_with_parent()
    catch_sigint(_remember)


def _remember():
    pass


def _solve_here(variant, opt):
    return solve(variant, opt)
