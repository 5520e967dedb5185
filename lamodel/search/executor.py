"""Map a pure task function over inputs: in this process, in local worker processes, or
on a ``dask.distributed`` cluster — with the same results everywhere.

A task is ``fn(context, item, seed)``:

* ``context`` is what the worker builds once from the shared object (``prepare(shared)``,
  e.g. a structure's LPs or Pyomo model) and caches per worker, keyed by a hash of the
  shared object, so a worker running many tasks of one structure builds it once;
* ``item`` is the task's own input (a variant's parameters, a restart's index...);
* ``seed`` is the task's child of one ``numpy.random.SeedSequence(seed)``, spawned in
  task order: it depends on the task's index only, never on which worker runs it or when.

So ``fn`` must be a pure function of (context, item, seed) and importable by name (the
local processes unpickle it by reference; Dask workers need lamodel on their
``PYTHONPATH``). Results come back in task order.

Faults: a task whose worker dies (or that raises) is retried ``retries`` times (default
once), elsewhere when the cluster has another worker; every attempt is counted and the
workers lost are recorded in :class:`TaskResult`. A task that fails every attempt is
returned with its error, never raised: the rest of the map goes on.

On Dask the retry of a task whose worker died is the scheduler's own: it reruns the task
on another worker up to its ``distributed.scheduler.allowed-failures`` times (default 3;
set it to 1 for "retried once"), then reports KilledWorker; a task that raises is retried
``retries`` times. lamodel counts attempts from the events each task logs when it starts.
"""
from __future__ import annotations

import hashlib
import os
import pickle
import socket
import threading
import time
import uuid
from collections import deque
from concurrent.futures import FIRST_COMPLETED, wait
from dataclasses import dataclass, field
from typing import Any, Callable
from urllib.parse import urlsplit

import numpy as np

from ..errors import InputError
from .tuning import CONTEXTS_KEPT, SCHEDULER_TIMEOUT
from .workers import count, processes

#: topic of the events tasks log on Dask workers when they start (attempts, worker)
EVENT_TOPIC = "lamodel-task-start"


@dataclass
class TaskResult:
    """One task's outcome: its value (None if every attempt failed) and its history."""

    index: int
    value: Any = None
    error: str = ""              # the last failure, "" on success
    attempts: int = 0            # 1 unless the task was retried
    worker: str = ""             # where the value was computed
    lost: list = field(default_factory=list)  # workers that died (or failed) while running it
    seconds: float = 0.0         # inside the task function

    @property
    def ok(self) -> bool:
        return not self.error


# ------------------------------------------------------------------------ worker side
_CONTEXTS: dict = {}            # key -> prepare(shared), per worker process
_SHARED: dict = {}              # key -> shared (local pools: installed once per process)
_LOCK = threading.Lock()        # a Dask worker may run tasks in threads


def _identity(x):
    return x


def context(key: str, shared, prepare: Callable | None):
    """``prepare(shared)``, built once per worker process and key."""
    with _LOCK:
        if key in _CONTEXTS:
            return _CONTEXTS[key]
    value = (prepare or _identity)(shared)
    with _LOCK:
        while len(_CONTEXTS) >= CONTEXTS_KEPT:
            _CONTEXTS.pop(next(iter(_CONTEXTS)))
        _CONTEXTS[key] = value
    return value


def _install(key, shared, prepare):
    """Local pool initializer: the shared object travels once per worker process, which
    ends when the map's process does, whatever ends it."""
    from ..process import end_with_parent
    end_with_parent()  # its parent is the forkserver, which ends with the map's process
    _SHARED[key] = (shared, prepare)


def _local_call(fn, key, item, seed):
    shared, prepare = _SHARED[key]
    t = time.perf_counter()
    value = fn(context(key, shared, prepare), item, seed)
    return value, f"local pid {os.getpid()}", time.perf_counter() - t


def _dask_call(fn, key, shared, prepare, run, index, item, seed):
    from distributed import get_worker
    worker = get_worker()
    worker.log_event(EVENT_TOPIC, {"run": run, "index": index, "worker": worker.address})
    t = time.perf_counter()
    value = fn(context(key, shared, prepare), item, seed)
    return value, worker.address, time.perf_counter() - t


# ------------------------------------------------------------------------ parent side
def fingerprint(obj) -> str:
    """A content hash of a picklable object (the per-worker cache key)."""
    return hashlib.sha1(pickle.dumps(obj, protocol=4)).hexdigest()[:16]


def task_seeds(seed, n: int) -> list:
    """n independent child seeds of one SeedSequence, in task order."""
    root = seed if isinstance(seed, np.random.SeedSequence) else np.random.SeedSequence(seed)
    return root.spawn(n)


def check_scheduler(address: str, timeout: float = SCHEDULER_TIMEOUT) -> str:
    """A dask scheduler address ``tcp://HOST:PORT`` that answers a TCP connection now;
    InputError (one line) otherwise, at once rather than after Dask's long timeouts."""
    text = str(address).strip()
    parts = urlsplit(text if "://" in text else "tcp://" + text)
    try:
        port = parts.port
    except ValueError:
        port = None
    if parts.scheme not in ("tcp", "tls") or not parts.hostname or port is None:
        raise InputError(f"scheduler '{address}': expected an address tcp://HOST:PORT")
    try:
        socket.create_connection((parts.hostname, port), timeout=timeout).close()
    except OSError as exc:
        raise InputError(f"scheduler {parts.scheme}://{parts.hostname}:{port}: cannot connect "
                         f"({exc.strerror or exc}); expected a running dask scheduler") from None
    return f"{parts.scheme}://{parts.hostname}:{port}"


class Executor:
    """Runs maps of tasks locally or on a Dask cluster; a context manager.

    ``Executor(workers=N)``: N local processes (1: in this process, no pool).
    ``Executor(scheduler="tcp://HOST:PORT")``: an existing cluster (a Client connects).
    ``Executor(client=c)``: a Client the caller owns (not closed here).
    ``preload``: modules the local worker processes import once, before forking (e.g. the
    solver's, so that each worker does not import Pyomo again).
    """

    def __init__(self, workers: int | None = None, scheduler: str | None = None, client=None,
                 retries: int = 1, preload=()):
        if workers is not None and scheduler is not None:
            raise InputError("give either a number of local workers or a scheduler address, not both")
        if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
            raise InputError(f"workers is {workers!r}; expected a whole number >= 1")
        if not isinstance(retries, int) or retries < 0:
            raise InputError(f"retries is {retries!r}; expected a whole number >= 0")
        self.retries = retries
        self.preload = tuple(preload)  # modules local workers import before their first task
        self.client, self._own_client = client, False
        self.workers = count(workers)
        if client is None and scheduler is not None:
            address = check_scheduler(scheduler)
            from distributed import Client
            try:
                self.client, self._own_client = Client(address, timeout=10), True
            except (OSError, TimeoutError) as exc:
                raise InputError(f"scheduler {address}: no dask scheduler answered ({exc})") from None

    def close(self):
        if self._own_client:
            self.client.close()
            self.client = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # -------------------------------------------------------------------------- map
    def map(self, fn: Callable, items, shared=None, prepare: Callable | None = None, seed=0,
            progress: Callable | None = None) -> list[TaskResult]:
        """``[fn(prepare(shared), item, seed_i) for each item]`` as TaskResults in task
        order; ``progress(result)`` is called in this process as each task ends (on Dask
        its attempts and lost workers are filled in when the map ends)."""
        items = list(items)
        seeds = task_seeds(seed, len(items))
        key = fingerprint((shared, prepare))
        if self.client is not None:
            return self._map_dask(fn, items, shared, prepare, seeds, key, progress)
        if self.workers == 1 or len(items) <= 1:
            return self._map_here(fn, items, shared, prepare, seeds, key, progress)
        return self._map_local(fn, items, shared, prepare, seeds, key, progress)

    def _finish(self, res: TaskResult, progress):
        if progress is not None:
            progress(res)

    def _map_here(self, fn, items, shared, prepare, seeds, key, progress):
        results = []
        for i, item in enumerate(items):
            res = TaskResult(i)
            while res.attempts <= self.retries:
                res.attempts += 1
                t = time.perf_counter()
                try:
                    res.value = fn(context(key, shared, prepare), item, seeds[i])
                except (KeyboardInterrupt, SystemExit):
                    raise
                except Exception as exc:
                    res.error = f"{type(exc).__name__}: {exc}"
                    res.lost.append(f"this process ({res.error})")
                    continue
                res.error, res.worker, res.seconds = "", "this process", time.perf_counter() - t
                break
            results.append(res)
            self._finish(res, progress)
        return results

    def _pool(self, fn, key, shared, prepare):
        # forkserver (:func:`.workers.processes`); the server imports the task's module
        # once, so workers start without importing it
        return processes(self.workers, _install, (key, shared, prepare), start="forkserver",
                         preload=(fn.__module__, *self.preload))

    def _map_local(self, fn, items, shared, prepare, seeds, key, progress):
        from concurrent.futures.process import BrokenProcessPool
        results = [TaskResult(i) for i in range(len(items))]
        pending, running = deque(range(len(items))), {}
        pool = self._pool(fn, key, shared, prepare)
        try:
            while pending or running:
                # no more tasks in flight than workers: when a process dies, the pool
                # fails every task in flight, and each of those was really running
                while pending and len(running) < self.workers:
                    i = pending.popleft()
                    results[i].attempts += 1
                    running[pool.submit(_local_call, fn, key, items[i], seeds[i])] = i
                done, _ = wait(running, return_when=FIRST_COMPLETED)
                broken = False
                for fut in done:
                    i = running.pop(fut)
                    res = results[i]
                    try:
                        res.value, res.worker, res.seconds = fut.result()
                        res.error = ""
                    except BrokenProcessPool:
                        broken = True
                        self._failed(res, "a local worker process died", "local worker (died)", pending, progress)
                    except Exception as exc:
                        self._failed(res, f"{type(exc).__name__}: {exc}", "local worker", pending, progress)
                    else:
                        self._finish(res, progress)
                if broken:  # the pool is unusable: what it still ran failed with it
                    for fut, i in running.items():
                        self._failed(results[i], "a local worker process died", "local worker (died)", pending,
                                     progress)
                    running.clear()
                    pool.shutdown(wait=False, cancel_futures=True)
                    pool = self._pool(fn, key, shared, prepare)
        except BaseException:  # a stop signal, an error: no variant runs on
            from ..process import kill_quietly
            kill_quietly(list((getattr(pool, "_processes", None) or {}).values()))
            raise
        finally:
            pool.shutdown(wait=False, cancel_futures=True)
        return results

    def _failed(self, res, error, where, pending, progress):
        res.error = error
        res.lost.append(where)
        if res.attempts <= self.retries:
            pending.appendleft(res.index)
        else:
            self._finish(res, progress)

    def _map_dask(self, fn, items, shared, prepare, seeds, key, progress):
        from distributed import as_completed
        client, run = self.client, uuid.uuid4().hex[:12]
        shared_future = share(client, shared, key)
        futures = {}
        for i, item in enumerate(items):
            fut = client.submit(_dask_call, fn, key, shared_future, prepare, run, i, item, seeds[i],
                                key=f"lamodel-{run}-{i}", retries=self.retries, pure=False)
            futures[fut] = i
        results = [TaskResult(i) for i in range(len(items))]
        for fut in as_completed(futures):
            res = results[futures[fut]]
            res.attempts = 1  # until the events are read, below
            try:
                res.value, res.worker, res.seconds = fut.result()
            except Exception as exc:  # KilledWorker (it died on every attempt), or raised each time
                res.error = f"{type(exc).__name__}: {exc}"
            self._finish(res, progress)
        del shared_future
        self._attempts(results, run)
        return results

    def _attempts(self, results, run):
        """Attempts and lost workers from the start events the tasks logged (read once)."""
        starts = {}
        for _, msg in self.client.get_events(EVENT_TOPIC):
            if isinstance(msg, dict) and msg.get("run") == run:
                starts.setdefault(msg.get("index"), []).append(msg.get("worker"))
        for res in results:
            tried = starts.get(res.index, [])
            res.attempts = max(len(tried), 1)
            res.lost = tried[:-1] if res.ok else tried


def share(client, obj, key: str):
    """``obj`` on a Dask cluster, sent once, fetched once by each worker that needs it.

    A task that returns it, not ``client.scatter``: scattered data lives only on workers,
    so a worker dying with the only copy would leave every task that needs it waiting
    forever; a task's result is recomputed from its spec, which the scheduler keeps.
    """
    return client.submit(_identity, obj, key=f"lamodel-shared-{key}", pure=True)


def run_tasks(fn, items, shared=None, prepare=None, seed=0, workers=None, scheduler=None, retries=1,
              progress=None) -> list[TaskResult]:
    """One map on a fresh :class:`Executor` (see :meth:`Executor.map`)."""
    with Executor(workers=workers, scheduler=scheduler, retries=retries) as ex:
        return ex.map(fn, items, shared=shared, prepare=prepare, seed=seed, progress=progress)
