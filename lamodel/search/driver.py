"""The solver driver: GA-seeded multistart of Ipopt on eq. (5), certified minimum alpha.

1. The associative LP gives an upper bound on every collapse multiplier and the
   reference cohesions c_ref = -mu N.
2. A genetic algorithm (:mod:`lamodel.search.ga`) searches cohesions c = g * c_ref. Each genome
   is scored by the LP of the fictitious system (its duals are a mechanism) and that
   mechanism's certification (:mod:`lamodel.search.certify`): the fitness is a certified
   collapse multiplier whenever one exists, and every certified state is archived.
3. The best distinct archived states, descended with the alternating certification LPs,
   start Ipopt solves of eq. (5) with the bilinear condition relaxed to
   0 <= alpha_K - alpha <= epsilon and epsilon driven to 0 with warm starts, in worker
   processes (each builds its own Pyomo model). Every Ipopt point is certified.
4. The least certified alpha wins. Nothing uncertified is reported as a multiplier.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..formulation.matrices import xi_bounds
from ..structure import Structure
from .certify import certify, certify_flow, descend
from .lp import LimitLPs
from .ipopt import ipopt_multistart, start_pool
from .options import Deadline, SolveOptions
from .state import CollapseState, Run

__all__ = ["Outcome", "Run", "SolveOptions", "reference_cohesion", "solve"]

@dataclass
class Outcome:
    """What the driver found; :mod:`lamodel.output.report` turns it into tables."""

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
    deadline = Deadline.after(opt.time_limit)
    out_of_time = deadline.expired
    structure.validate()
    opt.validate()
    _check_solver(opt)
    lps = LimitLPs(structure)                     # tight tolerances: what is reported
    screen = LimitLPs(structure, tolerance=None, formulation=lps.formulation)  # HiGHS defaults: the GA's LPs
    screen.deadline = deadline
    # the reported LPs may finish what the search found: a tenth of the limit more
    lps.deadline = deadline.extended(0.1 * (opt.time_limit or 0.0))
    runs: list[Run] = []
    final = _Archive()     # states certified with tight tolerances

    def finish(status, message, alpha_assoc=np.nan):
        best = final.best(1)[0] if final.states else None
        runs.sort(key=lambda r: r.start)
        return Outcome(structure, best, alpha_assoc, runs, status, message, time.perf_counter() - t0, opt.seed)

    # Fork the Ipopt workers before HiGHS starts threads here; they build their models
    # while the LPs and the GA run.
    pool = start_pool(structure, opt) if opt.starts > 0 else None
    ga_start, lp0, alpha_assoc = time.perf_counter(), lps.n_solves, np.nan
    try:
        status, message, assoc = _classify(structure, lps, final)
        if status in ("unstable", "no_collapse", "failed"):
            return finish("not_certified" if status == "failed" else status, message)
        alpha_assoc = assoc.alpha if assoc is not None else np.inf
        if assoc is not None:
            _lp_engine(structure, opt, deadline, final)
            _genetic_search(structure, opt, lps, screen, assoc, final, out_of_time)
        best = final.best(1)[0] if final.states else None
        runs.append(Run(0, "ga+lp", np.nan, ("certified" if best else "not_certified")
                        + (", time limit" if out_of_time() else ""), best.alpha if best else np.nan,
                        screen.n_solves + lps.n_solves - lp0, time.perf_counter() - ga_start))
        # ---- Ipopt multistart on eq. (5) from the best distinct states
        if pool is not None:
            starts = final.best(opt.starts)
            if not starts and assoc is not None:
                starts = [s for s in [_associative_start(lps, assoc)] if s is not None]
            if out_of_time():
                runs.extend(Run(i, "ipopt", status="time limit: not started") for i in range(1, opt.starts + 1))
            elif starts:
                ipopt_multistart(pool, lps, starts, final, runs, opt, deadline)
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
    mres, u, xi = lps.mechanism(allowed, np.zeros(structure.n_contacts), xi_max=xi_bounds(structure))
    if not mres.ok:
        return "no_collapse", "no collapse for this live load: no mechanism can follow it", None
    state = certify_flow(lps, u, xi, source="mechanism LP")
    if state is not None:
        final.add(descend(lps, state))
    return "ok", "", None


def _lp_engine(structure, opt, deadline, final):
    """The unit-free LP search on the complementarity gap (:mod:`.engine`), first: its
    certified state (checked in the user's units) joins the archive, so the least of it
    and the GA's wins. A failure of the engine is not fatal: the GA still runs."""
    from .engine import GapSearch
    try:
        engine = GapSearch(structure, deadline, seed=opt.seed)
        result = engine.run(explore=True)
    except (ArithmeticError, ValueError, AssertionError, RuntimeError, np.linalg.LinAlgError):
        return
    if result.best is not None and result.status == "certified":
        result.best.source = "lp engine"
        final.add(result.best)


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
    from ..errors import InputError
    if opt.solver == "ipopt" and opt.starts > 0:
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
    """The associative statics with the mechanism of its cohesive LP: an Ipopt start when
    the LPs certified nothing; None when that LP did not finish (e.g. the time limit)."""
    N, V, M, alpha = lps.split(assoc.x)
    res, u, xi = lps.cohesive(-lps.structure.mu * N)
    if not res.ok:
        return None
    return CollapseState(alpha=alpha, N=N, V=V, M=M, u=u, xi=xi, flow=xi > 0, source="associative")
