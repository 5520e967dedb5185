"""The solver: least certified collapse multiplier of a frictional block assembly (eq. 5).

The seed's frame — a genetic algorithm over the fictitious cohesions whose individuals
become points of eq. (5), polished by Ipopt — on the LP search of :mod:`.gap`:

1. **Scale.** Forces by the mean dead load of a block, lengths by the size of the
   structure (:mod:`lamodel.formulation.scaling`): every LP and NLP is unit-free; states
   come back in the user's units (:class:`.gap.problem.ScaledProblem`).
2. **The plan** (:mod:`.plan`: phases and lanes in the order they run): the associative
   bound; the first certificate (the gap alternation, and where it stalls the lanes
   [single block, chain from zero cohesion, rescue, fixed-point fallback] beside [dilatancy
   continuation]); stability; the continuation lanes; the GA (:mod:`.genetic`: no
   improvement for a while, counted in evaluations and LP solves against those of the
   first certificate, at most ``generations`` generations, or the time limit); the lane
   of the published fixed-point methods (:mod:`.published`, PUBLISHED_SHARE times the work
   before it, within the work bound). The search
   runs under one budget (:mod:`.budget`), made once here: the time limit as a hard cap
   and, without one, counted work, not time: the first certificate at FIRST_WORK times the
   formulation's work bound, the whole search at TOTAL_WORK times the first certificate's
   LP solves and WORK_PER_BLOCK LP work a block.
3. **Ipopt polish.** The best distinct certified states start Ipopt on eq. (5) (the bilinear
   condition relaxed to ``0 <= alpha_K - alpha <= eps``, eps -> 0) in worker processes,
   when the model is small enough: a start is skipped, with the reason in runs.csv, when
   its estimated time does not fit the budget. Every Ipopt point is certified again.

The same steps solve a structure in space: :mod:`.gap` is written against a formulation
interface (:class:`.gap.program.GapProgram`), implemented by the planar LPs and by the
cone programs of :class:`.gap.problem3d.ConeProblem` (no Ipopt polish there).

Nothing uncertified is ever reported as a multiplier. Ctrl-C and the time limit reach
inside every LP (HiGHS's interrupt callback); the best certified state so far is kept.
Every tuned constant is in :mod:`.tuning`.
"""
from __future__ import annotations

import logging
import math
import threading
import time
from concurrent.futures import FIRST_COMPLETED, wait
from concurrent.futures.process import BrokenProcessPool

import numpy as np
from threadpoolctl import threadpool_limits

from ..loads import one_live_load
from ..signals import catch_sigint, restore_sigint
from ..structure import Structure
from ..structure3d import Structure3D
from . import ipopt as _ipopt  # its task looked up at submit time (tests replace it)
from .budget import Budget
from .canonical import canonical, mechanism_from_user, rows_to_user, to_user
from .ipopt import start_pool
from .options import SolveOptions, Stopped
from .plan import phase, run as run_plan
from .outcome import Outcome
from .progress import Progress
from .state import (CERTIFIED, INTERRUPTED, NO_COLLAPSE, NOT_CERTIFIED, UNSTABLE, Run,
                    unstable_message)
from .tuning import (ACTIVE_TOLERANCES, BLAS_THREADS, DEFAULT_STARTS, EPSILON_LADDER, FIRST_WORK, IPOPT_GROWTH,
                     IPOPT_ITERATIONS, IPOPT_SECONDS_1020, POLISH_SECONDS, STALL_WORK)
from .workers import count as count_workers

log = logging.getLogger(__name__)

__all__ = ["Outcome", "Run", "SolveOptions", "solve", "ipopt_seconds"]

def ipopt_seconds(n_blocks: int) -> float:
    """Estimated seconds of one Ipopt start on eq. (5) (the model of :mod:`.tuning`)."""
    return IPOPT_ITERATIONS * IPOPT_SECONDS_1020 * (n_blocks / 1020.0) ** IPOPT_GROWTH


def solve(structure: Structure | Structure3D, options: SolveOptions | None = None, stop=None,
          on_associative=None, mechanisms=(), work_scale=1.0) -> Outcome:
    """Find the least certified collapse multiplier of the structure (see module doc), planar
    or in space: the same steps on the formulation of :func:`.gap.formulation_of` (in
    space: cone programs, no Ipopt polish).

    ``stop``: a callable returning True to stop early (e.g. ``event.is_set`` of an event set
    by another thread), as Ctrl-C does: the best certified state so far is reported, with
    the status ``interrupted``. ``on_associative(alpha)``: called with the associative
    multiplier as soon as it is known (finite; e.g. to start the lower bound beside the
    search, :mod:`lamodel.bound.beside`). ``mechanisms``: certified collapse states (the
    user's units and order) of the same blocks and contacts under other loads, e.g. a
    study's other load positions (planar): their mechanisms are certified here first
    (:func:`.gap.phases.given_mechanisms`). ``work_scale``: the default run's work bounds
    times this (no effect under a time limit).
    """
    from .gap import GapSearch

    opt = options or SolveOptions()
    t0 = time.perf_counter()
    structure.validate()
    one_live_load(structure, "solve")
    opt.validate()
    _check_solver(opt)
    # the search works on the blocks and contacts in their canonical order (the LPs are
    # degenerate: the file's order would decide which state they reach); answers told back
    user, (structure, order) = structure, canonical(structure)
    sigint = threading.Event()  # Ctrl-C
    asked = sigint.is_set if stop is None else (lambda: sigint.is_set() or bool(stop()))
    budget = Budget.for_solve(opt.time_limit, asked, work_scale)
    workers = count_workers(opt.workers)
    plan = _polish_plan(structure, opt, budget, workers)
    # the search leaves the polish its share of a time limit
    search_budget = budget.reserve(plan["reserve"] if plan["run"] else 0.0)
    progress = Progress(opt.progress, budget.seconds)
    archive = {}  # every certified state (scaled units), the least alpha per flow pattern

    def on_state(state):
        key = state.flow.tobytes()
        if key not in archive or state.alpha < archive[key].alpha:
            archive[key] = state

    def on_certified(user_state):
        progress.best(user_state.alpha)

    # from here a stop signal only asks the search to stop: the workers started below end with it
    old_handler = catch_sigint(sigint.set)
    pool = blas = engine = None
    runs: list[Run] = []
    status, message, alpha_assoc, lps_first = NOT_CERTIFIED, "", np.nan, 0
    try:
        # Ipopt works on the scaled structure too; its workers fork now, before HiGHS starts
        # threads here, and build their models while the LPs run.
        pool = start_pool(_scaled(structure), opt, workers, plan["n"]) if plan["run"] else None
        # BLAS_THREADS while the search runs (the Ipopt workers keep the setting they forked with)
        blas = threadpool_limits(BLAS_THREADS, user_api="blas")
        engine = GapSearch(structure, search_budget, on_certified=on_certified, on_state=on_state)
        progress.follow(engine.share)
        t_search = time.perf_counter()
        # the GA's Dask tasks share the Ipopt starts' connection when there is one
        what, alpha_assoc, lps_first = run_plan(engine, opt, progress, getattr(pool, "client", None), on_associative,
                                                stall_work=STALL_WORK, workers=workers,
                                                given=_given(engine.problem, mechanisms, order))
        search_budget.end()
        status, message = _verdict(engine, what, alpha_assoc)
        runs.append(Run(0, "ga+lp", np.nan, _run_status(engine, status, budget),
                        engine.record.best.alpha if engine.record.best is not None else np.nan, engine.n_lps(),
                        time.perf_counter() - t_search, path_of(engine.record.best)))
        if status == CERTIFIED or (status == NOT_CERTIFIED and engine.record.best is not None):
            _polish(engine, pool, plan, archive, runs, opt, budget, progress)
    finally:
        if blas is not None:
            blas.restore_original_limits()
        progress.close()
        restore_sigint(old_handler)
        if pool is not None:
            _shutdown(pool, kill=budget.expired())
    record = engine.record if engine is not None else None
    if record is not None and record.best_user is not None and status in (NOT_CERTIFIED, CERTIFIED):
        status = CERTIFIED
    if budget.asked():
        status, message = INTERRUPTED, ("interrupted: the best certified state so far is reported"
                                        if record is not None and record.best_user is not None
                                        else "interrupted before any state was certified")
    elif status == CERTIFIED:
        message = "certified collapse state"
    if status in (CERTIFIED, INTERRUPTED, NOT_CERTIFIED) and budget.expired() and not budget.asked():
        message += " (the time limit stopped the search)"
    runs.sort(key=lambda r: r.start)
    best = to_user(record.best_user, order) if record is not None and status in (CERTIFIED, INTERRUPTED) else None
    found = f"alpha {best.alpha:.6f} ({path_of(best)})" if best is not None else message
    log.info("%s: %s after %.2f s", status, found, time.perf_counter() - t0)
    stall = record.stall if record is not None and best is None and status != UNSTABLE else None
    return Outcome(user, best, alpha_assoc, runs, status, message, time.perf_counter() - t0, opt.seed,
                   first=record.first if record is not None and record.first else (np.nan, np.nan),
                   phases=dict(record.phases) if record is not None else {},
                   history=list(record.history) if record is not None else [],
                   lps_first=lps_first, work=engine.problem.work() if engine is not None else 0,
                   certification_lps=getattr(engine.problem, "n_lp", 0) if engine is not None else 0,
                   stalled=stall[:3] + (rows_to_user(stall[3], order),) if stall is not None else None)


# ------------------------------------------------------------------------ the search
#: The paths that certify a state, by the first word of its source (runs.csv, ``path``).
PATHS = {"gap": "gap alternation", "rescue": "rescue", "fixed": "fixed-point fallback",
         "zero": "chain from zero cohesion", "continuation": "continuation", "slow": "slow continuation",
         "dilatancy": "dilatancy continuation",
         "genome": "GA", "ipopt": "Ipopt polish", "single": "single block", "slp": "successive LP",
         "scp": "successive cone", "dry": "dry certificate", "mpec": "MPEC"}


def path_of(state) -> str:
    """Which path of the search certified ``state`` (empty for None): the gap alternation,
    its rescue, the fixed-point fallback (:mod:`.gap.chains`), the chain from zero
    cohesion, a published method's lane (:mod:`.published`), a continuation start, the GA
    or the Ipopt polish; a descent from a state
    keeps its path."""
    if state is None:
        return ""
    word = state.source.replace("-", "+").split("+")[0]
    return PATHS.get(word, word)


def _given(problem, states, order):
    """The mechanisms of ``states`` (user units and order) in the search's units and order,
    those the live load does work on (planar formulations; none in space)."""
    if not hasattr(problem, "mechanism_from_user"):
        return []
    out = []
    for st in states:
        u, xi = problem.mechanism_from_user(*mechanism_from_user(st.u, st.xi, order))
        if u is not None:
            out.append((u, xi))
    return out


def _verdict(engine, what, alpha_assoc):
    """Status and message of the search (:func:`.plan.run` said ``what``)."""
    if what == "unstable":
        return UNSTABLE, _unstable_message(engine)
    if what == "stability unknown":
        return NOT_CERTIFIED, ("no collapse state certified: the LP of the least alpha over the statics failed, "
                               "so whether the structure stands under its dead load is not known")
    if what not in ("searched", "stopped"):
        return NOT_CERTIFIED, f"the associative LP failed ({what})"
    if engine.record.best is None:
        return _nothing_certified(engine, alpha_assoc, stopped=what == "stopped")[:2]
    return CERTIFIED, ""


def _nothing_certified(engine, alpha_assoc, stopped):
    """Status and message when no collapse state was certified: what is known."""
    when = " before the stop" if stopped else ""
    if alpha_assoc == np.inf:
        # Zero cohesion is the weakest fictitious system: if even it carries any multiple
        # of the live load, no mechanism of any friction can follow the load.
        try:
            status = engine.problem.mechanism(np.zeros(engine.problem.nc))[0] if not stopped else "stopped"
        except Stopped:
            status = "stopped"
        if status == "unbounded":
            glued = getattr(engine.problem, "glued_message", lambda: "")()
            return NO_COLLAPSE, ("no collapse for this live load: no mechanism can follow it"
                                 + (glued or " (even frictionless joints carry any multiple of it)")), alpha_assoc
        return NOT_CERTIFIED, (
            f"no collapse state certified{when}: the associative LP is unbounded (the statics carries any "
            "multiple of the live load with dilatant friction) and the search found no mechanism of the "
            "frictional assembly; rigid blocks with non-dilatant friction can also lock (e.g. a block wedged "
            "between piers)"), alpha_assoc
    bound = (f"; the associative multiplier {alpha_assoc:.6g} bounds alpha_c from above"
             if np.isfinite(alpha_assoc) else "")
    if engine.budget.first_spent and not stopped:
        when = (f" within the default run's work bound ({FIRST_WORK:g} times the LP work a search of "
                f"{engine.problem.nb} blocks is given; --time-limit SECONDS searches for that long instead)")
    return NOT_CERTIFIED, f"no collapse state certified{when}{bound}", alpha_assoc


def _unstable_message(engine):
    """Unstable under dead load, and what alpha it would need to stand (if any)."""
    try:
        status, x = engine.problem.statics()  # least alpha >= 0 with a statics
    except Stopped:
        return unstable_message()
    message = unstable_message(x[-1] if status == "optimal" else None)
    crushing = getattr(engine.problem, "crushing_message", None)
    return message + crushing() if crushing is not None else message


def _run_status(engine, status, budget):
    text = CERTIFIED if engine.record.best is not None else status.replace("_", " ")
    if budget.asked():
        text += ", interrupted"
    elif budget.expired():
        text += ", time limit"
    return text


# --------------------------------------------------------------------- Ipopt polish
def _scaled(structure):
    from ..formulation.scaling import scaled, scales
    return scaled(structure, *scales(structure))


def _polish_plan(structure, opt, budget, workers) -> dict:
    """How many Ipopt starts, and may they run: ``--starts K`` asks for K whatever they
    cost (within a time limit: the budget's polish share); without it, up to
    DEFAULT_STARTS when one is estimated at most POLISH_SECONDS (or half the time limit).
    None where the formulation has no Ipopt polish (in space). ``workers``: the Ipopt
    processes at most."""
    from .gap import formulation_of
    explicit = opt.starts is not None
    n = opt.starts if explicit else DEFAULT_STARTS
    polish = formulation_of(structure).polish
    if not polish and not explicit:
        n = 0
    est = ipopt_seconds(structure.n_blocks)
    workers = max(1, min(workers, n or 1))
    plan = dict(n=n, estimate=est, explicit=explicit, reserve=est * math.ceil(n / workers), why="")
    most = budget.polish_seconds()
    if n == 0:
        plan["run"] = False
    elif not polish:   # asked for: each start's row says why it did not run
        where = "in space" if getattr(structure, "dimension", 2) == 3 else "for joints with strengths"
        plan["run"], plan["reserve"], plan["why"] = False, 0.0, (f"skipped: no Ipopt polish {where} (the Pyomo "
                                                                 "model of eq. 5 has dry joints in the plane)")
    elif most is not None and est > most:
        plan["run"], plan["why"] = False, (f"skipped: Ipopt on {structure.n_blocks} blocks takes about {est:.3g} s "
                                           f"a start (estimated), over half the time limit")
    elif not explicit and most is None and est > POLISH_SECONDS:
        plan["run"], plan["why"] = False, (f"skipped: Ipopt on {structure.n_blocks} blocks takes about {est:.3g} s "
                                           f"a start (estimated); ask for it with --starts")
    else:
        plan["run"] = True
    return plan


def _polish(engine, pool, plan, archive, runs, opt, budget, progress):
    """Step 3: Ipopt from the best distinct certified states; each point certified in the
    engine (its rows held, min alpha, descended), so a better one becomes the best. Under
    the solve's ``budget``: the whole time limit (the search had less)."""
    n = plan["n"]
    if n == 0:
        return
    starts = sorted(archive.values(), key=lambda s: s.alpha)[:n]
    rows = {}
    if not plan["run"] or pool is None:
        for i in range(1, n + 1):
            runs.append(Run(i, "ipopt", status=plan["why"] or "skipped"))
        return
    for i in range(len(starts) + 1, n + 1):
        rows[i] = Run(i, "ipopt", status=f"skipped: only {len(starts)} distinct certified state"
                                         f"{'s' if len(starts) != 1 else ''} to start from")
    phase(progress, "Ipopt on eq. 5")
    engine.budget.release()  # Ipopt's points certified within the whole limit (the search had less)
    futures = {}
    for i, st in enumerate(starts, start=1):
        if budget.left() < plan["estimate"]:
            rows[i] = Run(i, f"ipopt from {st.source} (alpha {st.alpha:.6f})",
                          status=f"skipped: time limit ({budget.left():.3g} s left, about "
                                 f"{plan['estimate']:.3g} s needed)")
            continue
        futures[pool.submit(_ipopt._ipopt_task, i, st, EPSILON_LADDER, opt.ipopt_options, budget.cap)] = (i, st)
    pending = set(futures)
    try:
        while pending:
            if budget.expired():
                break
            done, pending = wait(pending, timeout=0.1, return_when=FIRST_COMPLETED)
            for fut in done:
                i, st = futures[fut]
                rows[i] = _certify_ipopt(engine, fut, i, st)
    except Stopped:
        pass
    for fut, (i, st) in futures.items():  # pending: left to _shutdown (cancelled, or their workers
        if i not in rows:                 # killed); done: its point's certification was stopped
            rows[i] = Run(i, f"ipopt from {st.source} (alpha {st.alpha:.6f})",
                          status="interrupted" if budget.asked() else "time limit")
    runs.extend(rows[i] for i in sorted(rows))
    for i in sorted(rows):
        log.info("Ipopt start %d (%s): %s, certified alpha %.6f", i, rows[i].source, rows[i].status,
                 rows[i].alpha_certified)


def _certify_ipopt(engine, fut, i, st) -> Run:
    source = f"ipopt from {st.source} (alpha {st.alpha:.6f})"
    try:
        _, (N, V, M, alpha, u, xi), message, iterations, seconds = fut.result()
    except BrokenProcessPool:
        return Run(i, source, status="worker died")
    except Exception as exc:  # a failed solve is recorded, never fatal
        return Run(i, source, status=f"failed: {type(exc).__name__}: {exc}")
    state = _certify_point(engine, N, V, M, "ipopt")
    return Run(i, source, alpha, message, state.alpha if state is not None else np.nan, iterations, seconds,
               path_of(state))


def _certify_point(engine, N, V, M, source):
    """An Ipopt point (scaled units) as a collapse state: the rows it holds within a
    tolerance may flow (:meth:`.gap.near.Near.certify_slack`). The least certified alpha
    at the first tolerance that certifies, or None."""
    s = np.concatenate([N, V, M])
    return engine.near.certify_slack(-(engine.problem.Y @ s), max(float(np.abs(s).max()), 1.0), np.minimum(N, 0.0),
                                       source, tols=ACTIVE_TOLERANCES, first=True)


def _shutdown(pool, kill):
    """Stop the Ipopt workers; on Ctrl-C or the time limit, kill them (a running start
    would otherwise hold the exit for its whole solve)."""
    live = getattr(pool, "_processes", None)
    procs = list(live.values()) if kill and isinstance(live, dict) else []
    # Killed workers make the pool mark its pending futures broken; a future cancelled
    # before that makes its manager thread raise (InvalidStateError, printed on stderr).
    pool.shutdown(wait=False, cancel_futures=not procs)
    for p in procs:
        try:
            p.kill()
        except (OSError, AttributeError):
            pass


# -------------------------------------------------------------------------- helpers
def _check_solver(opt):
    from ..errors import InputError
    if opt.solver == "ipopt" and opt.starts != 0:
        from pyomo.environ import SolverFactory
        if not SolverFactory("ipopt").available(exception_flag=False):
            raise InputError("solver 'ipopt' asks for an ipopt executable on PATH and none was found; "
                             "expected the default 'lamodel_ipopt' (Debian's libipopt through cyipopt)")
