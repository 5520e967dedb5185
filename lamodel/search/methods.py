"""Methods side by side: the published ways of computing a frictional collapse multiplier,
run on the same model and put through the same certification.

* ``associative`` — the LP of max alpha over S (eq. 1-4) with associative (dilatant) flow:
  an upper bound on every collapse multiplier, exact when the mechanism only hinges.
* ``successive-lp`` — Gilbert, Casapulla & Ahmed (2006), Comput. Struct. 84:873-887: each
  joint gets a fictitious cohesion from the normal force of the previous LP and a
  zero-dilatancy fictitious friction (shear capacity mu |N_prev|, independent of N); LP
  after LP, from the associative solution, until the normal forces stop changing.
* ``mpec`` — Ferris & Tin-Loi (2001), Int. J. Mech. Sci. 43:209-224: the complementarity
  of flow and yield relaxed to xi^T slack <= rho, rho driven to zero through a sequence of
  NLPs (Ipopt, warm-started), from the associative solution. In eq. (5)
  alpha_K - alpha = xi^T slack, so the relaxation is the model's ``epsilon``.
* ``seed`` — the seed paper's method as it describes it: a genetic algorithm on eq. (5);
  each individual starts an Ipopt solve of eq. (5) (the bilinear condition exact, no
  relaxation) and its fitness is the multiplier Ipopt returns.
* ``lamodel`` — the certified search (:func:`lamodel.search.driver.solve`).

Solver libraries load inside the methods (``lamodel --help`` lists :data:`CHOICES` at once).

Every method returns a *raw* answer (its own forces, multiplier and mechanism), reported as
it is, with the largest residual of the conditions of a collapse state
(:func:`lamodel.search.certify.residuals`). The raw answer is then certified
(:func:`lamodel.search.certify.certify`, never :func:`~lamodel.search.certify.descend`: the
certification reads the raw answer's active rows, it does not search further). A raw
answer that yields no collapse state is reported as not certified, never replaced.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..structure import Structure
from .options import Deadline, SolveOptions
from .state import CollapseState, Run

#: the methods, in the order of ``methods.csv``
METHODS = ("associative", "successive-lp", "mpec", "seed", "lamodel")
#: what ``--method`` accepts
CHOICES = METHODS + ("all",)

#: successive LP: stop when max |N_k - N_{k-1}| <= this fraction of the largest block load
SLP_TOLERANCE = 1e-8
#: successive LP: at most this many LPs after the associative one
SLP_MAX_ITERATIONS = 200
#: MPEC: the relaxation rho (as a fraction of max(1, alpha)), divided by 10 from stage to
#: stage as Ferris & Tin-Loi do, then 0 (eq. 5 exactly)
MPEC_LADDER = (1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 0.0)
#: seed: default GA budget (population, generations); each individual is one Ipopt solve
SEED_POP_SIZE, SEED_GENERATIONS = 4, 2
#: seed: an Ipopt point whose largest residual exceeds this is infeasible for eq. (5): its
#: fitness is penalised (the GA needs a number for every individual)
SEED_FEASIBILITY = 1e-5


@dataclass
class MethodResult:
    """One method on one structure: its raw answer, and that answer certified."""

    method: str
    structure: Structure
    alpha_raw: float = np.nan
    raw_residual: float = np.nan          # largest residual of the raw answer (0: exact)
    state: CollapseState | None = None    # the certified state, or None
    alpha_associative: float = np.nan
    seconds: float = 0.0
    iterations: int = 0                   # LPs (associative, successive-lp) or Ipopt iterations
    notes: str = ""
    status: str = "not_certified"         # certified, not_certified, unstable, no_collapse, failed
    runs: list = field(default_factory=list)
    seed: int = 0

    @property
    def alpha_certified(self) -> float:
        return self.state.alpha if self.state is not None else np.nan

    @property
    def certified(self) -> bool:
        return self.state is not None

    def outcome(self):
        """The method's answer as a driver :class:`~lamodel.search.driver.Outcome` (for the
        result folder: summary, blocks, contacts, runs)."""
        from .driver import Outcome
        return Outcome(self.structure, self.state, self.alpha_associative, self.runs, self.status, self.notes,
                       self.seconds, self.seed)


# --------------------------------------------------------------------------- helpers
def _associative(structure, lps):
    """(status, message, LP result): the associative LP, or why no method can start."""
    at_rest = lps.statics(None, minimize=True)
    if at_rest.status == "infeasible" or (at_rest.ok and at_rest.alpha > 1e-9):
        return "unstable", "unstable under dead load: no statically admissible state at alpha = 0", None
    assoc = lps.associative()
    if assoc.ok:
        return "ok", "", assoc
    if assoc.status.startswith("unbounded"):
        return "no_collapse", ("the associative LP is unbounded: no dilatant collapse for this live load "
                               "(use --method lamodel for a frictional one)"), None
    return "failed", f"the associative LP failed ({assoc.status})", None


def _associative_mechanism(lps, assoc):
    """The associative flow of the LP's duals: u and lambda >= 0 on the yield rows of eq. 4
    (q = Y^T lambda, with the dilatancy mu lambda_slide on the opening)."""
    u = -assoc.row_dual[:3 * lps.nb]
    lam = np.maximum(-assoc.row_dual[3 * lps.nb:], 0.0)
    return u, lam


def _start_state(lps, assoc, source="associative"):
    """A complete start point of eq. (5): the associative statics and the mechanism of the
    fictitious system with cohesion -mu N of those statics (the cohesive LP's duals)."""
    N, V, M, alpha = lps.split(assoc.x)
    res, u, xi = lps.cohesive(-lps.structure.mu * N)
    return CollapseState(alpha=alpha, N=N, V=V, M=M, u=u, xi=xi, flow=xi > 0, source=source)


def _finish(result: MethodResult, lps, raw, t0, extra="", run=0):
    """Put the raw answer (N, V, M, alpha, u, xi) through the certification; fill notes
    and the certified alpha of the run (``result.runs[run]``) that gave the raw answer."""
    from .certify import RESIDUAL_TOLERANCE, certify, residuals
    N, V, M, alpha, u, xi = raw
    result.alpha_raw = float(alpha)
    r = residuals(lps, N, V, M, alpha, u, np.asarray(xi, dtype=float))
    worst = max(r, key=r.get)
    result.raw_residual = r[worst]
    state = certify(lps, N, V, M, alpha, u, xi, source=result.method)
    result.state = state
    result.status = "certified" if state is not None else "not_certified"
    if state is not None and result.runs:
        result.runs[run].alpha_certified = state.alpha
    if r[worst] <= RESIDUAL_TOLERANCE:
        what = f"raw answer is a collapse state (largest residual {r[worst]:.1e})"
    else:
        what = f"raw answer is not a collapse state ({worst} residual {r[worst]:.1e})"
    if state is None:
        what += "; no collapse state from its active rows: not certified"
    elif abs(state.alpha - alpha) > 1e-8 * max(1.0, abs(alpha)):
        what += f"; certified (least alpha on its active rows): {state.alpha:.6f}"
    result.notes = "; ".join(x for x in (extra, what) if x)
    result.seconds = time.perf_counter() - t0
    return result


def _ipopt_model(structure, options: SolveOptions):
    """The Pyomo model of eq. (5) compiled once for Ipopt (None: Pyomo's ipopt executable)."""
    from ..formulation.model import create_model
    from .bridge import QuadraticNLP
    m = create_model(structure, xi_factor=options.xi_factor)
    return m, (QuadraticNLP(m) if options.solver == "lamodel_ipopt" else None)


# --------------------------------------------------------------------------- methods
def associative(structure, options, lps, assoc, t0):
    result = MethodResult("associative", structure, alpha_associative=assoc.alpha, iterations=1, seed=options.seed)
    N, V, M, alpha = lps.split(assoc.x)
    u, lam = _associative_mechanism(lps, assoc)
    result.runs = [Run(0, "associative LP", alpha, "optimal", np.nan, 1, time.perf_counter() - t0)]
    return _finish(result, lps, (N, V, M, alpha, u, lam), t0, "upper bound (dilatant flow)")


def successive_lp(structure, options, lps, assoc, t0):
    """Gilbert, Casapulla & Ahmed (2006). Reading of their procedure: LP k has, at every
    joint, the shear capacity |V| <= mu |N_{k-1}| (a cohesion from the previous normal
    force, friction angle zero: no dilatancy), the no-tension/eccentricity rows of eq. 4
    unchanged; N_0 from the associative LP; stop when max |N_k - N_{k-1}| is below
    SLP_TOLERANCE of the largest load. A converged LP is a collapse state by the seed's
    second theorem (cohesion -mu N of its own normal forces)."""
    from .certify import force_scale
    result = MethodResult("successive-lp", structure, alpha_associative=assoc.alpha, seed=options.seed)
    N = lps.split(assoc.x)[0]
    tol = SLP_TOLERANCE * force_scale(lps)
    raw, change, converged, k = None, np.inf, False, 0
    for k in range(1, SLP_MAX_ITERATIONS + 1):
        res, u, xi = lps.cohesive(-structure.mu * N)
        if not res.ok:
            break
        N_new, V, M, alpha = lps.split(res.x)
        change = float(np.abs(N_new - N).max())
        N, raw = N_new, (N_new, V, M, alpha, u, xi)
        if change <= tol:
            converged = True
            break
    result.iterations = 1 + k
    if raw is None:
        result.notes, result.status = f"LP 1 failed ({res.status})", "failed"
        result.seconds = time.perf_counter() - t0
        return result
    status = (f"converged after {k} LPs" if converged
              else f"not converged: max |dN| {change:.1e} after {k} LPs")
    result.runs = [Run(0, "successive LP from the associative solution", raw[3], status, np.nan, result.iterations,
                       time.perf_counter() - t0)]
    return _finish(result, lps, raw, t0, status)


def mpec(structure, options, lps, assoc, t0, deadline=Deadline()):
    """Ferris & Tin-Loi (2001): min alpha with 0 <= xi^T slack <= rho, rho -> 0 (MPEC_LADDER),
    each NLP warm-started from the previous one, the first from the associative solution.
    Ipopt with bound_relax_factor 0 (its default relaxation of N <= 0 makes fake, low alphas)."""
    from .ipopt import ipopt_ladder
    result = MethodResult("mpec", structure, alpha_associative=assoc.alpha, seed=options.seed)
    model, nlp = _ipopt_model(structure, options)
    start = _start_state(lps, assoc)
    raw, message, iterations = ipopt_ladder(model, nlp, structure, start, MPEC_LADDER, options.ipopt_options,
                                            deadline)
    result.iterations = iterations
    result.runs = [Run(0, "relaxed MPEC from the associative solution", raw[3], message, np.nan, iterations,
                       time.perf_counter() - t0)]
    return _finish(result, lps, raw, t0, f"{len(MPEC_LADDER)} NLPs, last: {message}")


def seed_ga(structure, options, lps, assoc, t0, deadline=Deadline(), pop_size=SEED_POP_SIZE,
            generations=SEED_GENERATIONS):
    """The seed's GA on eq. (5). A genome g (one gene per contact) is turned into a start
    point of eq. (5) by the fictitious cohesive LP with cohesions g * (-mu N_assoc) (its
    primal a statics, its duals a mechanism); Ipopt solves eq. (5) from it with the bilinear
    condition exact; the fitness is Ipopt's alpha (penalised when its point is infeasible
    beyond SEED_FEASIBILITY). The raw answer is the fittest individual's point."""
    from .certify import residuals
    from .ga import genetic_search
    from .ipopt import ipopt_ladder
    result = MethodResult("seed", structure, alpha_associative=assoc.alpha, seed=options.seed)
    model, nlp = _ipopt_model(structure, options)
    c_ref = structure.mu * -np.minimum(lps.split(assoc.x)[0], 0.0)
    best = {"fitness": np.inf, "raw": None, "run": 0}
    penalty = assoc.alpha + 1.0

    def fitness(g):
        t = time.perf_counter()
        if deadline.expired():
            return penalty
        res, u, xi = lps.cohesive(g * c_ref)
        if not res.ok:
            return penalty
        N, V, M, alpha = lps.split(res.x)
        start = CollapseState(alpha=alpha, N=N, V=V, M=M, u=u, xi=xi, flow=xi > 0)
        raw, message, iterations = ipopt_ladder(model, nlp, structure, start, (0.0,), options.ipopt_options, deadline)
        result.iterations += iterations
        worst = max(residuals(lps, *raw).values())
        value = raw[3] if worst <= SEED_FEASIBILITY else penalty + raw[3]
        result.runs.append(Run(len(result.runs), f"GA individual {len(result.runs) + 1}", raw[3],
                               f"{message}, largest residual {worst:.1e}", np.nan, iterations,
                               time.perf_counter() - t))
        if value < best["fitness"]:
            best.update(fitness=value, raw=raw, run=len(result.runs) - 1)
        return value

    rng = np.random.default_rng(options.seed)
    initial = np.exp(rng.normal(0.0, 0.3, size=(pop_size, structure.n_contacts)))
    initial[0] = 1.0  # the associative cohesions
    genetic_search(fitness, structure.n_contacts, initial=initial, upper=3.0, pop_size=pop_size,
                   generations=generations, seed=options.seed, out_of_time=deadline.expired)
    n = len(result.runs)
    if best["raw"] is None:
        result.notes, result.status = f"none of {n} Ipopt solves ran", "failed"
        result.seconds = time.perf_counter() - t0
        return result
    feasible = best["fitness"] < penalty
    extra = f"GA {pop_size} x {generations}, {n} Ipopt solves of eq. 5" + (
        "" if feasible else f"; no Ipopt point feasible within {SEED_FEASIBILITY:g}: the least alpha is reported")
    return _finish(result, lps, best["raw"], t0, extra, best["run"])


def lamodel_search(structure, options, lps, t0):
    """The default certified search; its answer is certified again like every method's."""
    from .driver import solve
    outcome = solve(structure, options)
    result = MethodResult("lamodel", structure, alpha_associative=outcome.alpha_associative, runs=outcome.runs,
                          iterations=int(sum(r.iterations for r in outcome.runs)), seed=options.seed)
    if outcome.best is None:
        result.notes, result.status = outcome.message, outcome.status
        result.seconds = time.perf_counter() - t0
        return result
    b = outcome.best
    run = next((i for i, r in enumerate(outcome.runs) if r.alpha_certified == b.alpha), 0)
    return _finish(result, lps, (b.N, b.V, b.M, b.alpha, b.u, b.xi), t0, "certified search", run)


# --------------------------------------------------------------------------- entry points
def run_method(name: str, structure: Structure, options: SolveOptions | None = None,
               seed_budget: tuple[int, int] | None = None) -> MethodResult:
    """Run one method (one of :data:`METHODS`) on the structure; ``options.time_limit``
    bounds this method alone. ``seed_budget`` = (population, generations) of the seed's GA."""
    from ..errors import InputError
    from .lp import LimitLPs
    if name not in METHODS:
        raise InputError(f"method '{name}' is unknown; expected one of {', '.join(CHOICES)}")
    opt = options or SolveOptions()
    structure.validate()
    opt.validate()
    t0 = time.perf_counter()
    deadline = Deadline.after(opt.time_limit)
    lps = LimitLPs(structure)
    lps.deadline = deadline
    if name == "lamodel":
        return lamodel_search(structure, opt, lps, t0)
    status, message, assoc = _associative(structure, lps)
    if assoc is None:
        return MethodResult(name, structure, notes=message, status=status, seconds=time.perf_counter() - t0,
                            iterations=lps.n_solves, seed=opt.seed)
    if name == "associative":
        return associative(structure, opt, lps, assoc, t0)
    if name == "successive-lp":
        return successive_lp(structure, opt, lps, assoc, t0)
    if name == "mpec":
        return mpec(structure, opt, lps, assoc, t0, deadline)
    pop, gens = seed_budget or (SEED_POP_SIZE, SEED_GENERATIONS)
    return seed_ga(structure, opt, lps, assoc, t0, deadline, pop, gens)


def run_methods(name: str, structure: Structure, options: SolveOptions | None = None,
                seed_budget: tuple[int, int] | None = None, progress=None) -> list:
    """``name`` one of :data:`CHOICES`: that method, or (``all``) every method in turn.
    ``progress(result)`` is called after each."""
    out = []
    for m in (METHODS if name == "all" else (name,)):
        out.append(run_method(m, structure, options, seed_budget))
        if progress is not None:
            progress(out[-1])
    return out


def best_of(results: list) -> MethodResult:
    """The method with the least certified alpha (the first listed on a tie), or the first
    method when none is certified."""
    certified = [r for r in results if r.certified]
    return min(certified, key=lambda r: r.alpha_certified) if certified else results[0]
