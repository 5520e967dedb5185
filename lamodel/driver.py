"""The solver driver: GA-seeded multistart of Ipopt on eq. (5), certified minimum alpha.

1. The associative LP gives an upper bound on every collapse multiplier and the
   reference cohesions c_ref = -mu N.
2. A genetic algorithm (:mod:`lamodel.ga`) searches cohesions c = g * c_ref. Each genome
   is scored by the LP of the fictitious system (its duals are a mechanism) and that
   mechanism's certification (:mod:`lamodel.certify`): the fitness is a certified
   collapse multiplier whenever one exists, and every certified state is archived.
3. The best distinct archived states, descended with the alternating certification LPs,
   start Ipopt solves of eq. (5) with the bilinear condition relaxed to
   0 <= alpha_K - alpha <= epsilon and epsilon driven to 0 with warm starts, in worker
   processes (each builds its own Pyomo model). Every Ipopt point is certified.
4. The least certified alpha wins. Nothing uncertified is reported as a multiplier.
"""
from __future__ import annotations

import multiprocessing
import os
import signal
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field

import numpy as np

from .certify import CollapseState, certify, certify_flow, descend
from .lp import LimitLPs
from .structure import Structure

#: epsilon ladder for the relaxed bilinear condition, as fractions of max(1, alpha)
EPSILON_LADDER = (1e-3, 1e-5, 0.0)
#: Ipopt options for the warm-started ladder (start points are nearly feasible)
IPOPT_OPTIONS = {"tol": 1e-8, "acceptable_tol": 1e-6, "constr_viol_tol": 1e-9, "mu_init": 1e-6,
                 "bound_push": 1e-8, "bound_frac": 1e-8, "max_iter": 150, "mumps_pivot_order": 0,
                 # Ipopt relaxes bounds by 1e-8 by default: a tension N = +1e-8 on an open joint
                 # times xi at its bound makes a fake, lower alpha_K (measured on wall55: 4.5e-5).
                 "bound_relax_factor": 0.0}


#: Ipopt's return codes in a word or two (runs.csv's status column)
IPOPT_STATUS = {0: "optimal", 1: "acceptable", 2: "infeasible", 3: "step too small", 4: "diverging",
                5: "user stop", 6: "feasible point", -1: "iteration limit", -2: "restoration failed",
                -3: "step error", -4: "time limit", -10: "too few degrees of freedom", -11: "invalid problem",
                -12: "invalid option", -13: "invalid number", -199: "internal error"}


@dataclass
class SolveOptions:
    seed: int = 0
    starts: int = 2                # Ipopt solves of eq. (5)
    workers: int | None = None     # worker processes (default: all cores)
    time_limit: float | None = None
    pop_size: int = 10
    generations: int = 5
    chain: int = 4                 # fixed-point LP steps per fitness evaluation
    xi_factor: float = 100.0
    ipopt_options: dict = field(default_factory=dict)
    solver: str = "lamodel_ipopt"  # or "ipopt": Pyomo's interface to an ipopt executable on PATH
    progress: bool = False


@dataclass
class Run:
    start: int
    source: str
    alpha_ipopt: float = np.nan
    status: str = ""
    alpha_certified: float = np.nan
    iterations: int = 0
    seconds: float = 0.0


@dataclass
class Outcome:
    """What the driver found; :mod:`lamodel.report` turns it into tables."""

    structure: Structure
    best: CollapseState | None
    alpha_associative: float
    runs: list
    status: str                # certified, unstable, no_collapse, not_certified, interrupted
    message: str
    wall_time_s: float
    seed: int

    @property
    def certified(self) -> bool:
        return self.best is not None


class _Archive:
    """Certified states, one per distinct flow pattern, best first."""

    def __init__(self):
        self.states = {}

    def add(self, state: CollapseState | None):
        if state is None:
            return
        key = state.flow.tobytes()
        old = self.states.get(key)
        if old is None or state.alpha < old.alpha:
            self.states[key] = state

    def best(self, n=None):
        ranked = sorted(self.states.values(), key=lambda s: s.alpha)
        return ranked if n is None else ranked[:n]


def reference_cohesion(structure: Structure, N_assoc) -> np.ndarray:
    """c_ref = -mu N of the associative solution.

    Contacts it leaves unloaded keep no cohesion: a cohesion on a contact without
    compression lets the fictitious system carry shear across an open joint, which no
    real state can (measured: such genomes almost never certify).
    """
    return structure.mu * -np.minimum(N_assoc, 0.0)


def solve(structure: Structure, options: SolveOptions | None = None) -> Outcome:
    """Find the least certified collapse multiplier of the structure (see module doc)."""
    opt = options or SolveOptions()
    t0 = time.perf_counter()
    deadline = None if opt.time_limit is None else t0 + opt.time_limit
    out_of_time = (lambda: False) if deadline is None else (lambda: time.perf_counter() > deadline)
    structure.validate()
    _check_solver(opt)
    lps = LimitLPs(structure)                     # tight tolerances: what is reported
    screen = LimitLPs(structure, tolerance=None)  # HiGHS defaults: the GA's many LPs
    screen.deadline = deadline
    # the reported LPs may finish what the search found: a tenth of the limit more
    lps.deadline = None if deadline is None else deadline + 0.1 * opt.time_limit
    runs: list[Run] = []
    final = _Archive()     # states certified with tight tolerances

    def finish(status, message, alpha_assoc=np.nan):
        best = final.best(1)[0] if final.states else None
        runs.sort(key=lambda r: r.start)
        return Outcome(structure, best, alpha_assoc, runs, status, message, time.perf_counter() - t0, opt.seed)

    # Fork the Ipopt workers before HiGHS starts threads here; they build their models
    # while the LPs and the GA run.
    pool = _start_pool(structure, opt) if opt.starts > 0 else None
    ga_start, lp0, alpha_assoc = time.perf_counter(), lps.n_solves, np.nan
    try:
        status, message, assoc = _classify(structure, lps, final)
        if status in ("unstable", "no_collapse", "failed"):
            return finish("not_certified" if status == "failed" else status, message)
        alpha_assoc = assoc.alpha if assoc is not None else np.inf
        if assoc is not None:
            _genetic_search(structure, opt, lps, screen, assoc, final, out_of_time)
        best = final.best(1)[0] if final.states else None
        runs.append(Run(0, "ga+lp", np.nan, ("certified" if best else "not_certified")
                        + (", time limit" if out_of_time() else ""), best.alpha if best else np.nan,
                        screen.n_solves + lps.n_solves - lp0, time.perf_counter() - ga_start))
        # ---- Ipopt multistart on eq. (5) from the best distinct states
        if pool is not None:
            starts = final.best(opt.starts) or ([_associative_start(lps, assoc)] if assoc is not None else [])
            if out_of_time():
                runs.extend(Run(i, "ipopt", status="time limit: not started") for i in range(1, opt.starts + 1))
            elif starts:
                _ipopt_multistart(pool, structure, lps, starts, final, runs, opt, deadline)
    except KeyboardInterrupt:
        if not any(r.start == 0 for r in runs):
            best = final.best(1)[0] if final.states else None
            runs.append(Run(0, "ga+lp", np.nan, "interrupted", best.alpha if best else np.nan,
                            screen.n_solves + lps.n_solves - lp0, time.perf_counter() - ga_start))
        return finish("interrupted", "interrupted: the best certified state so far is reported", alpha_assoc)
    finally:
        if pool is not None:
            pool.shutdown(wait=False, cancel_futures=True)
    limit = " (the time limit stopped the search)" if out_of_time() else ""
    if not final.states:
        return finish("not_certified", "no start reached a certified collapse state" + limit, alpha_assoc)
    return finish("certified", "certified collapse state" + limit, alpha_assoc)


def _classify(structure, lps, final):
    """Can the structure stand, and can it collapse? Returns (status, message, assoc LP).

    * no statically admissible state at alpha = 0: unstable under dead load;
    * max alpha over S unbounded: the associative assembly never collapses, but a
      frictional one still may (e.g. lifting off joints squeezed by friction), so look
      for a mechanism directly; none at all means no collapse for this live load.
    """
    at_rest = lps.statics(None, minimize=True)  # least alpha >= 0 with a statics
    if at_rest.status == "infeasible" or (at_rest.ok and at_rest.alpha > 1e-9):
        need = f" (it needs alpha >= {at_rest.alpha:.6g} to stand)" if at_rest.ok else ""
        return "unstable", "unstable under dead load: no statically admissible state at alpha = 0" + need, None
    if not at_rest.ok:
        return "failed", f"the statics LP failed ({at_rest.status})", None
    assoc = lps.associative()
    if assoc.ok:
        return "ok", "", assoc
    if not assoc.status.startswith("unbounded"):
        return "failed", f"the associative LP failed ({assoc.status})", None
    allowed = np.ones(4 * structure.n_contacts, dtype=bool)
    mres, u, xi = lps.mechanism(allowed, np.zeros(structure.n_contacts), xi_max=structure.xi_bounds())
    if not mres.ok:
        return "no_collapse", "no collapse for this live load: no mechanism can follow it", None
    state = certify_flow(lps, u, xi, source="mechanism LP")
    if state is not None:
        final.add(descend(lps, state))
    return "ok", "", None


def _genetic_search(structure, opt, lps, screen, assoc, final, out_of_time):
    """Step 2 of the module doc: the GA over cohesions, then the best states certified
    again with tight tolerances and descended into ``final``."""
    archive = _Archive()  # states certified by the screening LPs
    alpha_assoc = assoc.alpha
    c_ref = reference_cohesion(structure, lps.split(assoc.x)[0])

    from tqdm import tqdm
    bar = tqdm(total=opt.pop_size * opt.generations, desc="GA + LP", unit="genome", leave=False,
               disable=not opt.progress)

    def fitness(g):
        """Least certified alpha along a short chain of the fixed-point map
        c -> -mu N(LP_c), started from c = g * c_ref: a fixed point is a collapse
        state (the seed's second theorem). Only the last steps are certified (measured:
        the first steps of a chain almost never are, and proving that costs most), and
        each certified state is descended. Without one: the LP value plus a penalty."""
        bar.update()
        c, best, fallback = g * c_ref, np.inf, alpha_assoc + 10.0
        if out_of_time():  # the rest of this generation is skipped, then the GA stops
            return fallback
        for step in range(opt.chain):
            res, u, xi = screen.cohesive(c)
            if not res.ok:
                break
            fallback = min(fallback, res.alpha + 1.0)  # worse than any certified state
            if step >= opt.chain - 2:
                state = certify_flow(screen, u, xi, source="ga")
                if state is not None and state.flow.tobytes() not in archive.states:
                    state = descend(screen, state)
                    archive.add(state)
                    best = min(best, state.alpha)
                elif state is not None:
                    best = min(best, archive.states[state.flow.tobytes()].alpha)
            c = -structure.mu * screen.split(res.x)[0]
        return best if np.isfinite(best) else fallback

    from .ga import genetic_search
    rng = np.random.default_rng(opt.seed)
    # the associative cohesions and log-normal perturbations of them
    initial = np.exp(rng.normal(0.0, 0.3, size=(opt.pop_size, structure.n_contacts)))
    initial[0] = 1.0
    try:
        genetic_search(fitness, structure.n_contacts, initial=initial, upper=3.0, pop_size=opt.pop_size,
                       generations=opt.generations, seed=opt.seed, out_of_time=out_of_time)
    finally:
        bar.close()
        # the best distinct states again with tight tolerances, and descended (also when
        # interrupted: what was found is kept)
        for state in archive.best(max(opt.starts, 3)):
            final.add(_recertify(lps, state))


def _check_solver(opt):
    from .errors import InputError
    if opt.solver == "lamodel_ipopt":
        return
    if opt.solver != "ipopt":
        raise InputError(f"solver '{opt.solver}' is unknown; expected 'lamodel_ipopt' or 'ipopt'")
    if opt.starts > 0:
        from pyomo.environ import SolverFactory
        if not SolverFactory("ipopt").available(exception_flag=False):
            raise InputError("solver 'ipopt' asks for an ipopt executable on PATH and none was found; "
                             "expected the default 'lamodel_ipopt' (Debian's libipopt through cyipopt)")


def _recertify(lps, state):
    """A state found with screening tolerances, certified again with tight ones and
    descended; None if it does not survive."""
    tight = certify_flow(lps, state.u, state.xi, state.source)
    if tight is None:
        tight = certify(lps, state.N, state.V, state.M, state.alpha, state.u, state.xi, state.source)
    return None if tight is None else descend(lps, tight)


def _associative_start(lps, assoc):
    N, V, M, alpha = lps.split(assoc.x)
    res, u, xi = lps.cohesive(-lps.structure.mu * N)
    return CollapseState(alpha=alpha, N=N, V=V, M=M, u=u, xi=xi, flow=xi > 0, source="associative")


# ----------------------------------------------------------------------- Ipopt workers
_WORKER = {}


def _init_worker(structure: Structure, xi_factor: float, solver: str):
    """Build the Pyomo model of eq. (5) and compile it for Ipopt, once per worker."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    from .bridge import QuadraticNLP
    from .model import create_model
    m = create_model(structure, xi_factor=xi_factor)
    _WORKER.update(model=m, nlp=QuadraticNLP(m) if solver == "lamodel_ipopt" else None, structure=structure)


def _warm(_):
    return os.getpid()


def _start_pool(structure, opt):
    workers = opt.workers or os.cpu_count() or 1
    workers = max(1, min(workers, opt.starts))
    # fork before any HiGHS thread exists in this process; workers build their models
    # while the GA runs here.
    ctx = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn")
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_init_worker,
                               initargs=(structure, opt.xi_factor, opt.solver))
    for _ in range(workers):
        pool.submit(_warm, None)
    return pool


def ipopt_ladder(model, nlp, structure, start: CollapseState, ladder=EPSILON_LADDER, options=None,
                 deadline=None):
    """Solve eq. (5) from a start with 0 <= alpha_K - alpha <= epsilon, epsilon -> 0.

    Each stage warm-starts from the previous one (primal and multipliers). Returns
    (state arrays, Ipopt status message, iterations).
    """
    from .model import get_state, set_state
    set_state(model, structure, start.N, start.V, start.M, start.alpha, start.u, start.xi)
    x = nlp.start_point()
    scale = max(1.0, abs(start.alpha))
    iterations, message, mult = 0, "not run", None
    for frac in ladder:
        model.epsilon.set_value(frac * scale)
        opts = dict(IPOPT_OPTIONS)
        opts.update(options or {})
        if mult is not None:
            opts.update(warm_start_init_point="yes", warm_start_bound_push=1e-9, warm_start_mult_bound_push=1e-9)
        if deadline is not None:
            left = deadline - time.perf_counter()
            if left <= 0.5:
                message = "time limit"
                break
            opts["max_cpu_time"] = float(left)
        if nlp is None:  # Pyomo's own interface to an ipopt executable (warm start: primal only)
            from pyomo.environ import SolverFactory
            opts = {k: v for k, v in opts.items() if not k.startswith("warm_start")}
            res = SolverFactory("ipopt").solve(model, options=opts, load_solutions=False)
            message = str(res.solver.termination_condition)
            if len(res.solution) == 0:
                break
            model.solutions.load_from(res)
            continue
        out = nlp.solve(x0=x, options=opts, load=True, multipliers=mult)
        iterations += out["iterations"]
        message = IPOPT_STATUS.get(out["status"], f"ipopt status {out['status']}")
        if out["status"] in (-3, -10, -11, -12, -13, -199):
            break
        x, mult = out["x"], (out["mult_g"], out["mult_x_L"], out["mult_x_U"])
    return get_state(model, structure), message, iterations


def _ipopt_task(start_id, start: CollapseState, ladder, options, deadline_left):
    t = time.perf_counter()
    deadline = None if deadline_left is None else t + deadline_left
    state, message, iterations = ipopt_ladder(_WORKER["model"], _WORKER["nlp"], _WORKER["structure"], start,
                                              ladder, options, deadline)
    return start_id, state, message, iterations, time.perf_counter() - t


def _ipopt_multistart(pool, structure, lps, starts, archive, runs, opt, deadline):
    futures = {}
    for i, st in enumerate(starts, start=1):
        left = None if deadline is None else deadline - time.perf_counter()
        fut = pool.submit(_ipopt_task, i, st, EPSILON_LADDER, opt.ipopt_options, left)
        futures[fut] = (i, st)
    from tqdm import tqdm
    bar = tqdm(total=len(futures), desc="Ipopt on eq. 5", unit="start", leave=False, disable=not opt.progress)
    try:
        for fut in as_completed(futures, timeout=None if deadline is None else max(deadline - time.perf_counter(), 0) + 30):
            bar.update()
            i, st = futures[fut]
            source = f"ipopt from {st.source} (alpha {st.alpha:.6f})"
            try:
                _, (N, V, M, alpha, u, xi), message, iterations, seconds = fut.result()
            except BrokenProcessPool:
                runs.append(Run(i, source, status="worker died"))
                continue
            except Exception as exc:  # a failed solve is recorded, never fatal
                runs.append(Run(i, source, status=f"failed: {type(exc).__name__}: {exc}"))
                continue
            state = certify(lps, N, V, M, alpha, u, xi, source="ipopt")
            if state is not None:
                state = descend(lps, state)
                archive.add(state)
            runs.append(Run(i, source, alpha, message, state.alpha if state else np.nan, iterations, seconds))
    except TimeoutError:
        pass
    except KeyboardInterrupt:
        for fut, (i, st) in futures.items():
            if not any(r.start == i for r in runs):
                runs.append(Run(i, f"ipopt from {st.source} (alpha {st.alpha:.6f})", status="interrupted"))
        raise
    finally:
        bar.close()
    for fut, (i, st) in futures.items():
        if not any(r.start == i for r in runs):
            fut.cancel()
            runs.append(Run(i, f"ipopt from {st.source} (alpha {st.alpha:.6f})", status="time limit"))
    runs.sort(key=lambda r: r.start)
