"""Methods side by side: the published ways of computing a frictional collapse multiplier,
run on the same model and put through the same certification.

* ``associative`` — the LP of max alpha over S (eq. 1-4) with associative (dilatant) flow:
  an upper bound on every collapse multiplier, exact when the mechanism only hinges.
* ``successive-lp`` — Gilbert, Casapulla & Ahmed (2006), Comput. Struct. 84:873-887: LP
  after LP from the associative solution, each joint with a modified Mohr-Coulomb surface
  through the Coulomb point of the previous (relaxed) normal force: a fictitious cohesion
  and a small *negative* fictitious friction, driven towards zero, until the normal forces
  stop changing (details and sources in :func:`successive_lp`).
* ``mpec`` — Ferris & Tin-Loi (2001), Int. J. Mech. Sci. 43:209-224: the complementarity
  of flow and yield relaxed to xi^T slack <= rho, rho driven to zero through a sequence of
  NLPs (Ipopt, warm-started), from the associative solution. In eq. (5)
  alpha_K - alpha = xi^T slack, so the relaxation is the model's ``epsilon``.
* ``seed`` — the seed paper's method as it describes it: a genetic algorithm on eq. (5);
  each individual starts an Ipopt solve of eq. (5) (the bilinear condition exact, no
  relaxation) and its fitness is the multiplier Ipopt returns.
* ``lamodel`` — the certified search (:func:`lamodel.search.driver.solve`).

In space (:func:`lamodel.search.search3d.solve3d`) the same search runs on the cone
formulation; beside it the associative cone program and :func:`successive_cone`
(successive cone programming: Portioli et al.; Wang & Beyer's public code), each raw
answer certified by the search's certifier.

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
from .state import CERTIFIED, FAILED, NO_COLLAPSE, NOT_CERTIFIED, UNSTABLE, CollapseState, Run, unstable_message
from .tuning import (MPEC_LADDER, SEED_FEASIBILITY, SEED_GENE_MAX, SEED_GENERATIONS, SEED_LADDER, SEED_POP_SIZE,
                     SEED_SPREAD, SLP_ALPHA0,
                     SLP_ALPHA_FACTOR, SLP_ALPHA_MIN, SLP_BETA, SLP_COHESION, SLP_MAX_ITERATIONS, SLP_TOLERANCE,
                     STABLE_ALPHA)

#: the methods, in the order of ``methods.csv``
METHODS = ("associative", "successive-lp", "mpec", "seed", "lamodel")
#: what ``--method`` accepts
CHOICES = METHODS + ("all",)



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
    status: str = NOT_CERTIFIED           # one of lamodel.search.state.STATUSES (all but interrupted)
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
    if at_rest.status == "infeasible" or (at_rest.ok and at_rest.alpha > STABLE_ALPHA):
        return UNSTABLE, unstable_message(at_rest.alpha if at_rest.ok else None), None
    assoc = lps.associative()
    if assoc.ok:
        return "ok", "", assoc
    if assoc.status.startswith("unbounded"):
        return NO_COLLAPSE, ("the associative LP is unbounded: no dilatant collapse for this live load "
                               "(use --method lamodel for a frictional one)"), None
    return FAILED, f"the associative LP failed ({assoc.status})", None


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
    result.status = CERTIFIED if state is not None else NOT_CERTIFIED
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
    from ..solvers.bridge import QuadraticNLP
    m = create_model(structure, xi_factor=options.xi_factor)
    return m, (QuadraticNLP(m) if options.solver == "lamodel_ipopt" else None)


# --------------------------------------------------------------------------- methods
def associative(structure, options, lps, assoc, t0):
    result = MethodResult("associative", structure, alpha_associative=assoc.alpha, iterations=1, seed=options.seed)
    N, V, M, alpha = lps.split(assoc.x)
    u, lam = _associative_mechanism(lps, assoc)
    result.runs = [Run(0, "associative LP", alpha, "optimal", np.nan, 1, time.perf_counter() - t0)]
    return _finish(result, lps, (N, V, M, alpha, u, lam), t0, "upper bound (dilatant flow)")


def _gilbert_lp(lps, a):
    """LP of one iteration of Gilbert et al. (2006): max alpha, equilibrium, the hinge rows
    of eq. 4, and at each contact the modified sliding rows ``+-V - a mu N <= cap`` (N <= 0
    is compression), i.e. ``|V| <= cap - a mu |N|``: a fictitious friction coefficient
    ``-a mu`` (negative) and a fictitious cohesion ``cap``, set per iteration (row bounds)."""
    import scipy.sparse as sp
    from .lp import INF, methods_lp
    nc = lps.nc
    E = sp.hstack([lps.A, sp.csr_matrix(lps.fbar.reshape(-1, 1))])
    I, Z, z = sp.identity(nc, format="csr"), sp.csr_matrix((nc, nc)), sp.csr_matrix((nc, 1))
    aMu = sp.diags(-a * np.asarray(lps.structure.mu, dtype=float) * np.ones(nc))
    slide = sp.bmat([[aMu, I, Z, z], [aMu, -I, Z, z]])
    hinge = sp.hstack([lps.Y[2 * nc:], sp.csr_matrix((2 * nc, 1))])
    cost = np.zeros(lps.nvar)
    cost[-1] = -1.0
    return methods_lp(cost, sp.vstack([E, slide, hinge]),
                      np.concatenate([-lps.f0, np.full(4 * nc, -INF)]), np.concatenate([-lps.f0, np.zeros(4 * nc)]),
                      np.append(np.full(3 * nc, -INF), 0.0), np.full(3 * nc + 1, INF))


def successive_lp(structure, options, lps, assoc, t0):
    """Gilbert, Casapulla & Ahmed (2006), Comput. Struct. 84:873-887: LP after LP, each joint
    with a modified Mohr-Coulomb surface through the Coulomb point of the normal force
    carried over from the previous LP.

    What is followed, and where it comes from. The paper's abstract: "a specially modified
    Mohr-Coulomb failure surface is adopted at each contact interface, with all failure
    surfaces updated at each iteration until a converged solution is obtained", starting
    from the associative LP. The details are those of the public implementation of the
    procedure by Q. Wang & K. Beyer (github.com/qianqing-wanggg/Image2Block,
    source/Kinematics/solve/finitefc_nonassociative.py, which cites the paper): at LP k
    every contact has

        |V| <= c0 + (1 + a_k) mu |N_hat| - a_k mu |N|

    i.e. a *negative* fictitious friction coefficient -a_k mu and a fictitious cohesion
    c0 + (1 + a_k) mu |N_hat|, so that the surface passes through the Coulomb point
    (|N_hat|, mu |N_hat|) (plus c0) and any extra compression lowers, not raises, the shear
    capacity; a_k = max(SLP_ALPHA0 * SLP_ALPHA_FACTOR^(k-1), SLP_ALPHA_MIN) (0.3, halved each
    LP, down to 0.001); the normal forces carried over are relaxed,
    N_hat_k = SLP_BETA N_k + (1 - SLP_BETA) N_{k-1} (0.6), N_k the LP's own; c0 is a small
    cohesion "required to avoid uncontrollable penetration potentially resulting when the
    normal force at a contact is zero" (the comment there, citing the paper), here
    SLP_COHESION times the largest |N| of the associative LP (1e-5, as there).

    What differs (ours, not the paper's or that implementation's): the stop is
    max |N_k - N_{k-1}| <= SLP_TOLERANCE of the largest block load once a_k = a_min (there:
    a relative change of the multiplier below 1e-4, at most 10 LPs), at most
    SLP_MAX_ITERATIONS LPs; an infeasible LP (a contact whose N_hat is ~0 cannot carry the
    compression equilibrium needs once a_k > 0) is retried with a_k halved (then 0) from the
    same N_hat, where that implementation returns the previous LP's answer. Setting
    SLP_ALPHA0 = SLP_COHESION = 0 and SLP_BETA = 1 gives the basic iteration (cohesion
    mu |N_prev|, zero fictitious friction).

    The raw answer is the last LP's statics and the mechanism of its duals: a collapse state
    of the modified surfaces (a_min = 0.001, cohesion c0), not exactly of the frictional
    assembly (its compatibility residual is ~a_min mu); the certification says which."""
    from .certify import force_scale
    from .lp import INF
    result = MethodResult("successive-lp", structure, alpha_associative=assoc.alpha, seed=options.seed)
    nb, nc, mu = lps.nb, lps.nc, np.asarray(structure.mu, dtype=float)
    N_prev = N_hat = lps.split(assoc.x)[0]
    c0 = SLP_COHESION * float(np.abs(N_prev).max())
    tol = SLP_TOLERANCE * force_scale(lps)
    a, lp, lp_a = SLP_ALPHA0, None, None
    raw, change, converged, retries, k, res = None, np.inf, False, 0, 0, None
    rows = np.arange(3 * nb, 3 * nb + 2 * nc)
    while k < SLP_MAX_ITERATIONS:
        k += 1
        if lp is None or lp_a != a:
            lp, lp_a = _gilbert_lp(lps, a), a
        cap = c0 - (1.0 + a) * mu * np.minimum(N_hat, 0.0)
        lp.set_row_bounds(np.full(2 * nc, -INF), np.concatenate([cap, cap]), rows)
        res = lps._run(lp)
        if not res.ok:
            if res.status == "infeasible" and a > 0:
                a = a / 2 if a / 2 >= SLP_ALPHA_MIN else 0.0
                retries += 1
                continue
            break
        N, V, M, alpha = lps.split(res.x)
        u = -res.row_dual[:3 * nb]
        xi = np.maximum(-res.row_dual[3 * nb:], 0.0)  # slide+, slide-, hinge+, hinge-
        raw = (N, V, M, alpha, u, xi)
        change = float(np.abs(N - N_prev).max())
        N_hat = SLP_BETA * N + (1.0 - SLP_BETA) * N_prev
        N_prev = N
        if change <= tol and a <= SLP_ALPHA_MIN:
            converged = True
            break
        a = max(a * SLP_ALPHA_FACTOR, SLP_ALPHA_MIN) if a > 0 else 0.0
    result.iterations = 1 + k
    if raw is None:
        result.notes, result.status = f"LP 1 failed ({res.status})", FAILED
        result.seconds = time.perf_counter() - t0
        return result
    status = (f"converged after {k} LPs" if converged
              else f"not converged: max |dN| {change:.1e} after {k} LPs"
              + ("" if res is None or res.ok else f" (last LP {res.status})"))
    if retries:
        status += f" ({retries} infeasible LPs retried with a smaller fictitious friction)"
    status += f"; final fictitious friction -{a:g} mu, cohesion {c0:.1e}"
    result.runs = [Run(0, "successive LP (Gilbert et al. 2006) from the associative solution", raw[3], status,
                       np.nan, result.iterations, time.perf_counter() - t0)]
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
        raw, message, iterations = ipopt_ladder(model, nlp, structure, start, SEED_LADDER, options.ipopt_options,
                                                deadline)
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
    initial = np.exp(rng.normal(0.0, SEED_SPREAD, size=(pop_size, structure.n_contacts)))
    initial[0] = 1.0  # the associative cohesions
    genetic_search(fitness, structure.n_contacts, initial=initial, upper=SEED_GENE_MAX, pop_size=pop_size,
                   generations=generations, seed=options.seed, out_of_time=deadline.expired)
    n = len(result.runs)
    if best["raw"] is None:
        result.notes, result.status = f"none of {n} Ipopt solves ran", FAILED
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


def successive_cone(engine, x, source="successive"):
    """Successive cone programming (Portioli et al.; Wang & Beyer's public code: a fixed
    friction capacity from the previous normal forces, relaxed, at most
    SUCCESSIVE_CONE_STEPS programs) from the statics x, on a search ``engine``
    (:class:`lamodel.search.gap.GapSearch`): each step the cohesive program for
    capacities ``c = -mu N``, its mechanism certified by the engine's certifier (held
    statics, residual test). Returns (least certified state or None, last raw alpha)."""
    from .tuning import (SUCCESSIVE_CONE_ALPHA_TOL, SUCCESSIVE_CONE_C_TOL, SUCCESSIVE_CONE_RELAXATION,
                         SUCCESSIVE_CONE_STEPS)
    p = engine.problem
    best, raw, prev = None, np.nan, np.inf
    c = -p.mu * p.N_of(x)
    for _ in range(SUCCESSIVE_CONE_STEPS):
        status, raw_k, xc, u, xi = p.mechanism(c)
        if status != "optimal":
            break
        raw = raw_k
        st = engine.certifier.certify(u, xi, source)
        if st is not None and (best is None or st.alpha < best.alpha):
            best = st
        c_new = -p.mu * p.cohesive_N(xc)
        # converged: the capacities reproduce themselves, or alpha no longer moves
        if np.abs(c_new - c).max() <= SUCCESSIVE_CONE_C_TOL * max(np.abs(c).max(), 1e-300) or \
                abs(raw - prev) <= SUCCESSIVE_CONE_ALPHA_TOL * max(1.0, abs(raw)):
            break
        prev = raw
        c = (1 - SUCCESSIVE_CONE_RELAXATION) * c + SUCCESSIVE_CONE_RELAXATION * c_new
    return best, raw


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
    if name != "lamodel" and getattr(structure, "has_materials", False):
        raise InputError(f"method '{name}' knows dry joints only; the joints' strengths (fc, ft, cohesion) "
                         "are solved by --method lamodel")
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
    pop, gens = seed_budget or (None, None)  # either may be unset (None): the seed's own
    return seed_ga(structure, opt, lps, assoc, t0, deadline, pop or SEED_POP_SIZE, gens or SEED_GENERATIONS)


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
