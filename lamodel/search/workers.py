"""Every pool of worker threads and processes a solve or a study makes, and the one
meaning of ``--workers``: that many at most, all cores when not given (:func:`count`).

* the lanes beside each other (:mod:`.gap.lanes`) and the GA's generations
  (:mod:`.generations`): threads of this process (:func:`threads`), since HiGHS releases
  the GIL while it solves;
* the Ipopt starts (:mod:`.ipopt`) and a study's variants (:mod:`.executor`): local
  processes (:func:`processes`), each ending with the process that made it.
"""
from __future__ import annotations

import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor


def count(workers: int | None = None) -> int:
    """``--workers`` as a number: ``workers``, or all cores when None."""
    return workers or os.cpu_count() or 1


def threads(workers: int, name: str) -> ThreadPoolExecutor:
    """A pool of ``workers`` threads named ``lamodel-<name>``."""
    return ThreadPoolExecutor(count(workers), thread_name_prefix=f"lamodel-{name}")


def processes(workers: int, initializer, initargs=(), start="fork", preload=()) -> ProcessPoolExecutor:
    """A pool of ``workers`` local processes, each running ``initializer(*initargs)`` once.

    ``start`` is the start method wanted: "fork" (the Ipopt pool: forked before any HiGHS
    thread exists in this process, so the workers build their models while the search
    runs) or "forkserver" (a study's pool: workers forked from a clean server process,
    never from one that already runs HiGHS or Dask threads, whose locks a fork would copy
    mid-use; the server imports the ``preload`` modules once). "spawn" where the wanted
    one is missing."""
    methods = multiprocessing.get_all_start_methods()
    ctx = multiprocessing.get_context(start if start in methods else "spawn")
    if ctx.get_start_method() == "forkserver" and preload:
        ctx.set_forkserver_preload(list(preload))
    return ProcessPoolExecutor(max_workers=count(workers), mp_context=ctx, initializer=initializer, initargs=initargs)
