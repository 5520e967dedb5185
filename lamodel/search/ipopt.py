"""Ipopt on eq. (5) in worker processes: each builds the Pyomo model once, then solves
the relaxed bilinear condition 0 <= alpha_K - alpha <= epsilon with epsilon driven to 0
(warm starts), from the states the LP search found. Every Ipopt point is certified by the
parent (:mod:`lamodel.search.certify`); nothing Ipopt says is reported unchecked.
"""
from __future__ import annotations

import multiprocessing
import os
import signal
import subprocess
import threading
import time
from concurrent.futures import Future

from ..structure import Structure
from .options import Deadline
from .state import CollapseState
from .tuning import EPSILON_LADDER, IPOPT_OPTIONS, IPOPT_WARM_OPTIONS
from .workers import processes



#: Ipopt's return codes in a word or two (runs.csv's status column)
IPOPT_STATUS = {0: "optimal", 1: "acceptable", 2: "infeasible", 3: "step too small", 4: "diverging",
                5: "user stop", 6: "feasible point", -1: "iteration limit", -2: "restoration failed",
                -3: "step error", -4: "time limit", -5: "time limit", -10: "too few degrees of freedom", -11: "invalid problem",
                -12: "invalid option", -13: "invalid number", -199: "internal error"}


# ----------------------------------------------------------------------- Ipopt workers
_WORKER = {}


def _init_worker(structure: Structure, xi_factor: float, solver: str, own_signals: bool = True):
    """Build the Pyomo model of eq. (5) and compile it for Ipopt, once per worker."""
    if own_signals:
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
        from ..process import end_with_parent
        end_with_parent()  # whatever ends the solve (even kill -9) ends this worker too
    from ..formulation.model import create_model
    from ..solvers.bridge import QuadraticNLP
    m = create_model(structure, xi_factor=xi_factor)
    _WORKER.update(model=m, nlp=QuadraticNLP(m) if solver == "lamodel_ipopt" else None, structure=structure)


def _warm(_):
    return os.getpid()


def start_pool(structure, opt, workers, n_starts=None):
    """Where the Ipopt starts run: a pool of up to ``workers`` local processes (default),
    a Dask cluster (``opt.scheduler``), or this process when it is itself a worker (a
    study's variant, a Dask task: the work is already spread, and daemonic workers cannot
    fork a pool)."""
    if opt.scheduler is not None:
        return _DaskPool(structure, opt)
    if multiprocessing.parent_process() is not None:
        return _InlinePool(structure, opt)
    workers = max(1, min(workers, n_starts or opt.starts or 1))
    # forked before any HiGHS thread exists in this process; workers build their models
    # while the GA runs here.
    pool = processes(workers, _init_worker, (structure, opt.xi_factor, opt.solver), start="fork")
    for _ in range(workers):
        pool.submit(_warm, None)
    return pool


class _InlinePool:
    """The pool interface, run in this process at submit (one start after another)."""

    def __init__(self, structure, opt):
        self.args = (structure, opt.xi_factor, opt.solver, False)

    def submit(self, fn, *args):
        if self.args is not None:  # the model of this structure, built at the first start
            _init_worker(*self.args)
            self.args = None
        fut = Future()
        try:
            fut.set_result(fn(*args))
        except Exception as exc:  # recorded by ipopt_multistart like a pool's failure
            fut.set_exception(exc)
        return fut

    def shutdown(self, wait=True, cancel_futures=False):
        pass


class _DaskPool:
    """The pool interface on a dask.distributed cluster: each worker builds the model once
    per structure (:func:`lamodel.search.executor.context`); a deadline travels as the
    seconds left (its pickled form)."""

    def __init__(self, structure, opt):
        from .executor import Executor, fingerprint, share
        self.executor = Executor(scheduler=opt.scheduler)
        client = self.client = self.executor.client  # the GA's Dask tasks use it too
        self.key = fingerprint((structure, opt.xi_factor, opt.solver))
        self.shared = share(client, (structure, opt.xi_factor, opt.solver), self.key)
        self.pool = client.get_executor(retries=1, pure=False)

    def submit(self, fn, *args):
        return self.pool.submit(_on_dask_worker, self.key, self.shared, fn, *args)

    def shutdown(self, wait=True, cancel_futures=False):
        self.pool.shutdown(wait=False)
        self.executor.close()


def _prepare_model(shared):
    structure, xi_factor, solver = shared
    _init_worker(structure, xi_factor, solver, own_signals=False)
    return dict(_WORKER)


_MODEL_LOCK = threading.Lock()  # one Pyomo model per worker: its threads take turns


def _on_dask_worker(key, shared, fn, *args):
    from .executor import context
    with _MODEL_LOCK:
        _WORKER.update(context(key, shared, _prepare_model))
        return fn(*args)


def ipopt_ladder(model, nlp, structure, start: CollapseState, ladder=EPSILON_LADDER, options=None,
                 deadline: Deadline | None = None):
    """Solve eq. (5) from a start with 0 <= alpha_K - alpha <= epsilon, epsilon -> 0.

    Each stage warm-starts from the previous one (primal and multipliers). Returns
    (state arrays, Ipopt status message, iterations).
    """
    from ..formulation.model import get_state, set_state
    deadline = deadline or Deadline()
    set_state(model, structure, start.N, start.V, start.M, start.alpha, start.u, start.xi)
    x = nlp.start_point() if nlp is not None else None
    scale = max(1.0, abs(start.alpha))
    iterations, message, mult = 0, "not run", None
    for frac in ladder:
        model.epsilon.set_value(frac * scale)
        opts = dict(IPOPT_OPTIONS)
        opts.update(options or {})
        if mult is not None:
            opts.update(IPOPT_WARM_OPTIONS)
        if deadline.at is not None and deadline.left() <= 0.5:
            message = "time limit"
            break
        if nlp is None:  # Pyomo's own interface to an ipopt executable (warm start: primal only)
            from pyomo.environ import SolverFactory
            opts = {k: v for k, v in opts.items() if not k.startswith("warm_start")}
            wall = None
            if deadline.at is not None:
                # the executable's own limit is CPU time (all 3.11 has: it ends with a point);
                # Pyomo's timelimit ends the process at the wall time left
                wall = float(deadline.left())
                opts["max_cpu_time"] = wall
            try:
                res = SolverFactory("ipopt").solve(model, options=opts, load_solutions=False, timelimit=wall)
            except subprocess.TimeoutExpired:
                message = "time limit"
                break
            message = str(res.solver.termination_condition)
            if len(res.solution) == 0:
                break
            model.solutions.load_from(res)
            continue
        # the deadline in wall time, asked at every iteration
        out = nlp.solve(x0=x, options=opts, load=True, multipliers=mult, stop=deadline.expired)
        iterations += out["iterations"]
        message = IPOPT_STATUS.get(out["status"], f"ipopt status {out['status']}")
        if out["status"] == 5 and deadline.expired():
            message = "time limit"
            break
        if out["status"] in (-3, -10, -11, -12, -13, -199):
            break
        x, mult = out["x"], (out["mult_g"], out["mult_x_L"], out["mult_x_U"])
    return get_state(model, structure), message, iterations


def _ipopt_task(start_id, start: CollapseState, ladder, options, deadline: Deadline):
    t = time.perf_counter()
    state, message, iterations = ipopt_ladder(_WORKER["model"], _WORKER["nlp"], _WORKER["structure"], start,
                                              ladder, options, deadline)
    return start_id, state, message, iterations, time.perf_counter() - t
