"""Gilbert, Casapulla & Ahmed (2006), Comput. Struct. 84:873-887: LP after LP from the
associative solution, each joint with a modified Mohr-Coulomb surface through the Coulomb
point of the previous (relaxed) normal force: a fictitious cohesion and a small *negative*
fictitious friction, driven towards zero, until the normal forces stop changing.

What is followed, and where it comes from. The paper's abstract: "a specially modified
Mohr-Coulomb failure surface is adopted at each contact interface, with all failure
surfaces updated at each iteration until a converged solution is obtained", starting from
the associative LP. The details are those of the public implementation of the procedure by
Q. Wang & K. Beyer (github.com/qianqing-wanggg/Image2Block,
source/Kinematics/solve/finitefc_nonassociative.py, which cites the paper): at LP k every
contact has

    |V| <= c0 + (1 + a_k) mu |N_hat| - a_k mu |N|

i.e. a negative fictitious friction -a_k mu and a fictitious cohesion c0 + (1 + a_k) mu
|N_hat|, so that the surface passes through the Coulomb point (|N_hat|, mu |N_hat|) (plus
c0) and any extra compression lowers, not raises, the shear capacity; a_k = max(SLP_ALPHA0
SLP_ALPHA_FACTOR^(k-1), SLP_ALPHA_MIN); N_hat_k = SLP_BETA N_k + (1 - SLP_BETA) N_{k-1};
c0, "required to avoid uncontrollable penetration potentially resulting when the normal
force at a contact is zero", is SLP_COHESION times the largest |N| of the associative LP.

Ours, not the paper's: the stop is max |N_k - N_{k-1}| <= SLP_TOLERANCE of the largest
block load once a_k = a_min, at most SLP_MAX_ITERATIONS LPs; an infeasible LP is retried
with a_k halved (then 0) from the same N_hat. SLP_ALPHA0 = SLP_COHESION = 0 and SLP_BETA = 1
give the basic iteration (cohesion mu |N_prev|, zero fictitious friction).

The raw answer is the last LP's statics and the mechanism of its duals: a collapse state of
the modified surfaces, not exactly of the frictional assembly; the certification says which.
"""
from __future__ import annotations

import copy
import time
from dataclasses import dataclass

import numpy as np

from ..options import Stopped
from ..state import FAILED, Run
from ..tuning import (ACTIVE_TOLERANCES, SLP_ALPHA0, SLP_ALPHA_FACTOR, SLP_ALPHA_MIN, SLP_BETA, SLP_COHESION,
                      SLP_MAX_ITERATIONS, SLP_TOLERANCE)
from .result import MethodResult, finish


@dataclass
class Iteration:
    """Where the iteration ended: the last LP's raw answer (N, V, M, alpha, u, xi; None:
    none), LPs run, whether it converged, the last change of N, infeasible LPs retried, the
    last fictitious friction factor a, the cohesion c0 and the last LP's status."""

    raw: tuple | None
    lps: int
    converged: bool
    change: float
    retries: int
    a: float
    c0: float
    status: str

    def words(self) -> str:
        text = (f"converged after {self.lps} LPs" if self.converged
                else f"not converged: max |dN| {self.change:.1e} after {self.lps} LPs"
                + ("" if self.status == "optimal" else f" (last LP {self.status})"))
        if self.retries:
            text += f" ({self.retries} infeasible LPs retried with a smaller fictitious friction)"
        return text + f"; final fictitious friction -{self.a:g} mu, cohesion {self.c0:.1e}"


def gilbert_lp(lps, a):
    """LP of one iteration: max alpha, equilibrium, the hinge rows of eq. 4 (with the joints'
    strengths: their N-M facets), and at each contact the modified sliding rows
    ``+-V - a mu N <= cap`` (N <= 0 is compression), i.e. ``|V| <= cap - a mu |N|``; ``cap``
    is set per iteration (row bounds)."""
    import scipy.sparse as sp
    from ..highs import INF
    from ..lp import methods_lp
    nc = lps.nc
    E = sp.hstack([lps.A, sp.csr_matrix(lps.fbar.reshape(-1, 1))])
    I, Z, z = sp.identity(nc, format="csr"), sp.csr_matrix((nc, nc)), sp.csr_matrix((nc, 1))
    aMu = sp.diags(-a * np.asarray(lps.structure.mu, dtype=float) * np.ones(nc))
    slide = sp.bmat([[aMu, I, Z, z], [aMu, -I, Z, z]])
    hinge = sp.hstack([lps.Y[2 * nc:], sp.csr_matrix((lps.nr - 2 * nc, 1))])
    cost = np.zeros(lps.nvar)
    cost[-1] = -1.0
    return methods_lp(cost, sp.vstack([E, slide, hinge]), np.concatenate([-lps.f0, np.full(lps.nr, -INF)]),
                      np.concatenate([-lps.f0, np.zeros(2 * nc), lps.b_lp[2 * nc:]]),
                      np.append(np.full(3 * nc, -INF), 0.0), np.full(3 * nc + 1, INF))


def iterate(lps, N_assoc, stop=None) -> Iteration:
    """Gilbert et al.'s iteration on ``lps`` (:class:`lamodel.search.lp.LimitLPs`) from the
    associative normal forces; ``stop()`` true ends it between two LPs."""
    from ..certify import force_scale
    from ..highs import INF
    nb, nc, mu = lps.nb, lps.nc, np.asarray(lps.structure.mu, dtype=float)
    N_prev = N_hat = np.asarray(N_assoc, dtype=float)
    c0 = SLP_COHESION * float(np.abs(N_prev).max())
    tol = SLP_TOLERANCE * force_scale(lps)
    a, lp, lp_a = SLP_ALPHA0, None, None
    out = Iteration(None, 0, False, np.inf, 0, a, c0, "optimal")
    rows = np.arange(3 * nb, 3 * nb + 2 * nc)
    while out.lps < SLP_MAX_ITERATIONS and not (stop is not None and stop()):
        out.lps += 1
        if lp is None or lp_a != a:
            # a new fictitious friction: a new LP of the same shape, warm from the last basis
            basis = None if lp is None else lp.portable_basis()
            lp, lp_a = gilbert_lp(lps, a), a
            if basis is not None:
                lp.restart(basis)
        cap = c0 + lps.b_lp[:nc] - (1.0 + a) * mu * np.minimum(N_hat, 0.0)  # and the joints' own cohesion
        lp.set_row_bounds(np.full(2 * nc, -INF), np.concatenate([cap, cap]), rows)
        res = lps.run(lp)
        out.status = res.status
        if not res.ok:
            if res.status == "infeasible" and a > 0:
                a = out.a = a / 2 if a / 2 >= SLP_ALPHA_MIN else 0.0
                out.retries += 1
                continue
            break
        N, V, M, alpha = lps.split(res.x)
        u = -res.row_dual[:3 * nb]
        xi = np.maximum(-res.row_dual[3 * nb:], 0.0)  # slide+, slide-, hinge+, hinge-
        out.raw = (N, V, M, alpha, u, xi)
        out.change = float(np.abs(N - N_prev).max())
        N_hat = SLP_BETA * N + (1.0 - SLP_BETA) * N_prev
        N_prev = N
        if out.change <= tol and a <= SLP_ALPHA_MIN:
            out.converged = True
            break
        a = out.a = max(a * SLP_ALPHA_FACTOR, SLP_ALPHA_MIN) if a > 0 else 0.0
    return out


@dataclass(frozen=True)
class SuccessiveLP:
    """Gilbert et al.'s successive LP: ``method`` alone (``--method successive-lp``), or
    ``run`` as a lane of the search (in the plane, dry joints): the iteration on the
    search's scaled structure from its associative statics, its raw answer certified by
    the search (the mechanism's flow rows, then the rows its statics holds) and descended.
    Its LPs count in the search's work; it ends between two LPs at the work bounds."""

    name = "successive LP"
    once = "successive LP"

    def method(self, structure, options, lps, assoc, t0, deadline=None):
        result = MethodResult("successive-lp", structure, alpha_associative=assoc.alpha, seed=options.seed)
        it = iterate(lps, lps.split(assoc.x)[0])
        result.iterations = 1 + it.lps
        if it.raw is None:
            return result.failed(f"LP 1 failed ({it.status})", t0, FAILED)
        result.runs = [Run(0, "successive LP (Gilbert et al. 2006) from the associative solution", it.raw[3],
                           it.words(), np.nan, result.iterations, time.perf_counter() - t0)]
        return finish(result, lps, it.raw, t0, it.words())

    def run(self, engine, start):
        from ..lp import LimitLPs
        p, ran = engine.problem, engine.lanes.ran
        s = getattr(p, "s", None)
        if self.once in ran or s is None or s.has_materials or start.x_assoc is None:
            # in space: not this method's; with the joints' strengths it gave no alpha the search
            # did not (docs/method/evidence.md, "The successive LP's lane with the joints' strengths")
            return ran.get(self.once, (None,))[0]
        t = time.perf_counter()
        lps = LimitLPs(s)
        lps.deadline = p.deadline
        counted = [0, 0]  # the solves and work of lps already added to the search's

        def spent():
            n, work = lps.n_solves, lps.work
            p.lps_elsewhere += n - counted[0]
            p.work_elsewhere += work - counted[1]
            counted[:] = n, work
            return engine.budget.stopping()

        def lane():
            it = iterate(lps, p.N_of(start.x_assoc), spent)
            spent()
            return certified(engine, it.raw, "slp") if it.raw is not None and not engine.budget.over() else None

        return run_once(engine, self.once, "successive LP", t, lane)


def run_once(engine, name, phase, t, lane):
    """``lane()`` (a published method's lane: its least certified state, or None) run once a
    search: what a work bound ended is None, the time cap or a stop go on up; the answer
    kept under ``name`` (:attr:`~lamodel.search.gap.lanes.Lanes.ran`), the seconds since
    ``t`` under ``phase``."""
    best = None
    try:
        best = lane()
    except Stopped:
        if engine.budget.over():
            raise
    finally:
        engine.lanes.ran[name] = (best,)
        engine.record.phase(phase, t)
    return best


def certified(engine, raw, source):
    """A raw answer (N, V, M, alpha, u, xi) of the search's scaled structure certified by
    the search: its mechanism's flow rows held, and the rows its statics holds (as an Ipopt
    point is, :func:`lamodel.search.driver.solve`), each descended; the least, or None."""
    N, V, M, _, u, xi = raw
    best = engine.certifier.certify(u, np.asarray(xi, dtype=float), source)
    if best is not None:
        best = engine.descent.descend(best)
    s = np.concatenate([N, V, M])
    near = engine.near.certify_slack(-(engine.problem.Y @ s), max(float(np.abs(s).max()), 1.0),
                                     np.minimum(N, 0.0), source + "-near", tols=ACTIVE_TOLERANCES, first=True)
    best = near if near is not None and (best is None or near.alpha < best.alpha) else best
    return own(engine, best, source)


def own(engine, state, source):
    """``state`` as this lane's answer: one the caches gave (a certification or descent
    another path made first, and did not keep) is named after the lane and told to the
    record like a new one (runs.csv's ``path`` says which lane reached it)."""
    if state is None or state.source.startswith(source):
        return state
    state = copy.copy(state)
    state.source = f"{source}+{state.source}"
    if engine.record.on_state is not None:
        engine.record.on_state(state)
    engine.record.take(state)
    return state
