"""Certification in space: turn a candidate into an exact collapse state on the cone, or reject it.

A collapse state is a statics in S (equilibrium, ``||T|| <= -mu N`` at every point) and a
mechanism u of the fictitious cohesive system (``fbar^T u = 1``) whose strains
``q = -A^T u`` open only at points with ``N = 0`` and slip only at points on the cone with
``T`` along the slip; by virtual work its multiplier is then exactly ``alpha = alpha_K``
(the seed's second theorem). A candidate (a conic solution, which is exact only to its
tolerance) suggests which points open and which slide, and in which direction; then

1. :func:`statics_lp` (HiGHS) finds the least alpha with those points held, where the cone
   is fixed: an opening point carries nothing, a sliding point ``T = -mu N s_hat`` along
   its slip (one generator), a stuck point lies in a pyramid inscribed in its cone with an
   edge along a reference force (so the candidate's own force is inside). Its answer is in
   S exactly (to HiGHS's round-off), not to a conic tolerance;
2. :func:`mechanism_lp` finds a mechanism compatible with that statics: no motion at points
   inside the cone, slip along T (no opening) on the cone, opening only where N = 0;
3. :func:`residuals` checks every condition with plain numpy, each measured with one
   dimension (moments as forces and rotations as lengths, by the structure's size).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.linalg import qr, svd
from scipy.sparse.linalg import splu
from threadpoolctl import threadpool_limits

from ..formulation.space import Formulation3D
from . import caps3d
from .highs import INF, HighsLP
from .tuning import (ALIGN_DONE, ALIGN_FACETS, ALIGN_ROUND_OFF, ALIGN_STEPS, ALIGN_TURN, CONTACT_TOL, FAN, FAN_COST,
                     FLOW_TOL, MECHANISM_POLISH_COLUMNS, POLISH_NEWTON_STEPS, PROJECTION_REFINEMENTS, PYRAMID_FACETS,
                     RESIDUAL_TOLERANCE)

MODES = ("stuck", "opening", "sliding", "crushing", "crushing+sliding")


@dataclass
class CollapseState3D:
    """An exact collapse state in space: point forces, multiplier, mechanism, point modes."""

    alpha: float
    N: np.ndarray          # (np,) normal forces (<= 0 compression)
    T1: np.ndarray         # (np,) tangential force along t1
    T2: np.ndarray         # (np,) tangential force along t2
    u: np.ndarray          # (6 nb) block motions (ux, uy, uz, rx, ry, rz) at the centroids
    q: np.ndarray          # (3 np) openings, slips1, slips2: q = -A^T u
    source: str = ""
    residual: dict = field(default_factory=dict)
    crushable: np.ndarray | None = None   # (np,) points with a crushing cap (None: none)

    @property
    def forces(self) -> np.ndarray:
        return np.concatenate([self.N, self.T1, self.T2, [self.alpha]])

    @property
    def motions(self) -> np.ndarray:
        """(nb, 6): ux, uy, uz, rx, ry, rz per block."""
        return self.u.reshape(-1, 6)

    @property
    def modes(self) -> np.ndarray:
        """Per point: 'stuck', 'opening' or 'sliding' (see :func:`point_modes`)."""
        return point_modes(self.q, crushable=self.crushable)


def point_modes(q, tol=FLOW_TOL, crushable=None) -> np.ndarray:
    """'opening' where the point opens, 'sliding' where it slips without opening, else
    'stuck'; motions below ``tol`` of the largest strain are none. Opening comes first,
    whatever the tangential motion: an open point has left its contact (N = T = 0), so
    its tangential motion is no frictional slip. The plane's rule is the same (a contact
    whose two ends separate is ``open``, not ``sliding``); its ``sliding+hinging`` is a
    contact turning about one end that stays in touch, which a point has not. A closing
    point of those ``crushable`` (with a crushing cap): 'crushing' (or 'crushing+sliding')."""
    npt = len(q) // 3
    qn, slip = q[:npt], np.hypot(q[npt:2 * npt], q[2 * npt:])
    U = max(np.abs(q).max() if q.size else 0.0, 1e-300)
    out = np.full(npt, MODES[0], dtype=object)
    out[slip > tol * U] = MODES[2]
    out[qn > tol * U] = MODES[1]
    if crushable is not None:
        down = (qn < -tol * U) & crushable
        out[down] = np.where(slip > tol * U, MODES[4], MODES[3])[down]
    return out


def _per_block(v, scale):
    v = np.asarray(v, float).reshape(-1, 6)
    return np.concatenate([v[:, :3].ravel(), scale * v[:, 3:].ravel()])


def residuals(form: Formulation3D, N, T1, T2, alpha, u, q) -> dict:
    """Violations of every condition of a collapse state (0 is exact), each with one dimension.

    equilibrium (eq. 2), the cone (``||T|| <= -mu N``), compatibility ``q = -A^T u``, the
    normalisation ``fbar^T u = 1``, openings >= 0, opening only where ``N = 0``, slip only
    on the cone and along T (the cohesive flow rule: ``c ||slip|| - T.slip = 0`` with
    ``c = -mu N``; 0 exactly when both hold) and ``alpha = alpha_K`` (eq. 5). With the
    joints' strengths: :func:`lamodel.search.caps3d.residuals`.
    """
    if form.caps is not None:
        return caps3d.residuals(form, N, T1, T2, alpha, u, q)
    L = form.structure.size()
    mu = form.mu
    npt = len(N)
    F = max(np.abs(_per_block(form.f0, 1 / L)).max(), np.abs(_per_block(form.fbar, 1 / L)).max(), 1e-300)
    U = max(np.abs(_per_block(u, L)).max(), np.abs(q).max(), 1e-300)
    s = np.concatenate([N, T1, T2])
    eq = _per_block(form.A @ s + form.f0 + alpha * form.fbar, 1 / L)
    Tn = np.hypot(T1, T2)
    qn, s1, s2 = q[:npt], q[npt:2 * npt], q[2 * npt:]
    slip = np.hypot(s1, s2)
    flow = -mu * N * slip - (T1 * s1 + T2 * s2)
    return {
        "equilibrium": float(np.abs(eq).max() / F),
        "cone": float(max((Tn + mu * N).max(), N.max(), 0.0) / F),
        "compatibility": float(np.abs(q - form.strains(u)).max() / U),
        "normalisation": float(abs(form.fbar @ u - 1.0)),
        "opening_sign": float(max(-qn.min(), 0.0) / U),
        "opening_complementarity": float(np.abs(N * qn).max() / (F * U)),
        "slip_flow_rule": float(np.abs(flow).max() / (F * U)),
        "slip_alignment": float(np.abs(T1 * s2 - T2 * s1).max() / (F * U)),
        "virtual_work": float(abs(form.kinematic_multiplier(u, q, N) - alpha) / max(abs(alpha), 1.0)),
    }


def passes(res: dict) -> bool:
    return max(res.values()) <= RESIDUAL_TOLERANCE


def statics_lp(form: Formulation3D, opening, sliding, slide_dir, ref=None, facets=PYRAMID_FACETS):
    """Least alpha with the cone fixed (see the module doc). ``opening``, ``sliding``
    (bool, np), ``slide_dir`` (np, 2) unit slips in the points' frames, ``ref`` (np, 2)
    reference tangential forces of the stuck points (a pyramid edge along each).

    A sliding point carries ``-n + mu s_hat`` and, at a small cost, the two forces of the
    cone at ``+/- FAN`` radians from it: slips from a conic mechanism are exact to its
    tolerance only, and directions 1e-8 apart on one face can leave no exact statics.
    Their mixtures lie within ``FAN^2 / 2`` of the cone. Returns the statics (3 np + 1) or None."""
    npt = form.np
    opening = np.asarray(opening, bool)
    sliding = np.asarray(sliding, bool) & ~opening
    stuck = ~(opening | sliding)
    mu = form.mu
    isl = np.flatnonzero(sliding)
    d = np.asarray(slide_dir, float).reshape(-1, 2)
    th_s = np.arctan2(d[isl, 1], d[isl, 0])
    ist = np.flatnonzero(stuck)
    th_0 = np.zeros(ist.size) if ref is None else np.arctan2(ref[ist, 1], ref[ist, 0])
    gens = [(isl, th_s + off, w) for off, w in ((0.0, 0.0), (FAN, FAN_COST), (-FAN, FAN_COST))]
    gens += [(ist, th_0 + 2 * np.pi * j / facets, 0.0) for j in range(facets)]
    p = np.concatenate([g[0] for g in gens])
    th = np.concatenate([g[1] for g in gens])
    m = p.size
    c = np.arange(m)
    # generator: unit compression -n plus mu times a unit tangential direction
    Tg = sp.csr_matrix((np.concatenate([-np.ones(m), mu[p] * np.cos(th), mu[p] * np.sin(th)]),
                        (np.concatenate([p, npt + p, 2 * npt + p]), np.concatenate([c, c, c]))), shape=(3 * npt, m))
    E = sp.hstack([form.A @ Tg, sp.csr_matrix(form.fbar.reshape(-1, 1))])
    cost = np.append(np.concatenate([np.full(g[0].size, g[2]) for g in gens]), 1.0)
    lp = HighsLP(E, -form.f0, cost, np.zeros(m + 1), np.full(m + 1, INF), name="certify3d")
    if lp.solve() != "optimal":
        return None
    x = lp.x()
    lam = np.maximum(x, 0.0)
    return np.concatenate([Tg @ lam[:m], [lam[-1]]])


def mechanism_lp(form: Formulation3D, N, T1, T2, tol=CONTACT_TOL):
    """A mechanism (u, q) compatible with the statics (N, T): q = 0 inside the cone, slip
    along T (within FAN radians) without opening on it, opening >= 0 (any slip) where
    N = 0; ``fbar^T u = 1``; the one of least alpha_K. None if there is none. With the
    joints' strengths: :func:`lamodel.search.caps3d.mechanism_lp`."""
    if form.caps is not None:
        return caps3d.mechanism_lp(form, N, T1, T2, tol)
    npt, nb = form.np, form.nb
    mu = form.mu
    scale = max(np.abs(N).max(), 1e-300)
    Tn = np.hypot(T1, T2)
    zero = -N <= tol * scale
    cone = ~zero & (-mu * N - Tn <= tol * scale)
    stuck = ~(zero | cone)
    At = form.A.T.tocsr()
    Q1, Q2 = -At[npt:2 * npt], -At[2 * npt:]
    Qn, along, across = form.slip_rows(T1, T2, cone)
    iz, ic, ist = np.flatnonzero(zero), np.flatnonzero(cone), np.flatnonzero(stuck)
    t = np.tan(FAN)
    rows = sp.vstack([Qn[iz], Qn[ic], (across - t * along)[ic], (across + t * along)[ic], along[ic],
                      Qn[ist], Q1[ist], Q2[ist], sp.csr_matrix(form.fbar.reshape(1, -1))])
    k, j = ic.size, ist.size
    lo = np.concatenate([np.zeros(iz.size), np.zeros(k), np.full(k, -INF), np.zeros(2 * k), np.zeros(3 * j), [1.0]])
    hi = np.concatenate([np.full(iz.size, INF), np.zeros(k), np.zeros(k), np.full(2 * k, INF), np.zeros(3 * j), [1.0]])
    cost = -form.f0 + along.T @ (-mu * N * cone)  # alpha_K = -f0^T u + sum c (slip . T_hat)
    lp = HighsLP(rows, lo, cost, np.full(6 * nb, -INF), np.full(6 * nb, INF), name="mechanism3d", b_hi=hi)
    if lp.solve() != "optimal":
        return None
    u = lp.x()
    return u, form.strains(u)


def project_mechanism(form: Formulation3D, u, stuck, sliding, refinements=PROJECTION_REFINEMENTS):
    """The motion nearest to u with no motion at the ``stuck`` points, no opening at the
    ``sliding`` ones and ``fbar^T u = 1`` (C u = e), exact to round-off; None if there is
    none near u. Least squares ``(C^T C + eps I) d = C^T r`` with iterative refinement: one
    sparse factorisation of a 6 nb matrix (LSQR took seconds on these ill-conditioned C)."""
    npt = form.np
    At = form.A.T.tocsr()
    ist, isl = np.flatnonzero(stuck), np.flatnonzero(sliding)
    C = sp.vstack([At[ist], At[npt + ist], At[2 * npt + ist], At[isl], sp.csr_matrix(form.fbar.reshape(1, -1))]).tocsr()
    target = np.zeros(C.shape[0])
    target[-1] = 1.0
    v = np.asarray(u, float).copy()
    scale = max(np.abs(v).max(), 1.0)
    CtC = (C.T @ C).tocsc()
    eps = 1e-12 * max(abs(CtC).max(), 1e-300)
    try:
        lu = splu((CtC + eps * sp.identity(CtC.shape[0], format="csc")).tocsc())
    except RuntimeError:
        return None
    for _ in range(refinements):
        r = target - C @ v
        if np.abs(r).max() <= 1e-14 * scale:
            break
        v = v + lu.solve(C.T @ r)
    if np.abs(C @ v - target).max() > 1e-11 * scale:
        return None
    return v


def _null_space(C: np.ndarray) -> np.ndarray:
    """Orthonormal basis of the null space of a tall dense C: a QR first, so that the SVD
    is of a square matrix of its columns (scipy's null_space forms the rows x rows U)."""
    R = qr(C, mode="r")[0] if C.shape[0] > C.shape[1] else C
    R = np.vstack([R, np.zeros((max(C.shape[1] - R.shape[0], 0), C.shape[1]))])
    _, sv, Vt = svd(R)
    rank = int((sv > 1e-10 * max(sv.max() if sv.size else 0.0, 1e-300)).sum())
    return Vt[rank:].T


def polish_mechanism(form: Formulation3D, u, stuck, sliding, c, max_columns=MECHANISM_POLISH_COLUMNS,
                     steps=POLISH_NEWTON_STEPS):
    """The mechanism of least ``alpha_K = -f0^T u + sum c ||slip||`` among those with the
    same stuck and sliding points (no motion, no opening) as the exact motion u, by Newton's
    method on the null space of those conditions (dense: the blocks u moves, at most
    ``max_columns`` motions). A conic program leaves the motion off its optimum by about the
    square root of its tolerance along flat directions (a spurious turn of 6e-6 of a sliding
    block), and the sliding directions with it; here they are exact to round-off. None if
    the problem is too large or a slip vanishes (then that point is not sliding)."""
    # one BLAS thread: on a loaded machine a threaded LAPACK took 40x longer (0.6 s for
    # seven 90 x 90 SVDs, 0.016 s on one thread)
    with threadpool_limits(1):
        return _polish(form, u, stuck, sliding, c, max_columns, steps)


def _polish(form, u, stuck, sliding, c, max_columns, steps):
    npt = form.np
    v = np.asarray(u, float).reshape(-1, 6)
    size = np.abs(v).max()
    moving = np.flatnonzero(np.abs(v).max(axis=1) > 1e-9 * size)
    cols = (6 * moving[:, None] + np.arange(6)).ravel()
    isl = np.flatnonzero(sliding)
    if isl.size == 0 or cols.size > max_columns:
        return None
    At = form.A.T.tocsr()[:, cols]
    ist = np.flatnonzero(stuck)
    C = sp.vstack([At[ist], At[npt + ist], At[2 * npt + ist], At[isl]]).toarray()
    C = np.vstack([C[np.abs(C).max(axis=1) > 0], form.fbar[cols]])
    Z = _null_space(C)
    if Z.shape[1] == 0:
        return np.asarray(u, float).copy()
    B1, B2 = -At[npt + isl].toarray() @ Z, -At[2 * npt + isl].toarray() @ Z   # slips along the null space
    u0 = np.asarray(u, float)[cols]
    s1, s2 = -At[npt + isl] @ u0, -At[2 * npt + isl] @ u0
    g0 = -form.f0[cols] @ Z
    cs = np.asarray(c, float)[isl]

    def f(y):
        return float(g0 @ y + cs @ np.hypot(s1 + B1 @ y, s2 + B2 @ y))

    y = _newton(f, np.zeros(Z.shape[1]), g0, cs, s1, s2, B1, B2, steps)
    if y is None:
        return None
    out = np.asarray(u, float).copy()
    out[cols] = u0 + Z @ y
    return out


def _newton(f, y, g0, cs, s1, s2, B1, B2, steps):
    """Damped Newton steps on f(y) = g0 y + sum c ||s + B y|| (see polish_mechanism)."""
    for _ in range(steps):
        a1, a2 = s1 + B1 @ y, s2 + B2 @ y
        r = np.hypot(a1, a2)
        if r.min() <= 1e-12 * max(r.max(), 1e-300):
            return None
        h1, h2 = a1 / r, a2 / r
        g = g0 + (cs * h1) @ B1 + (cs * h2) @ B2
        if np.abs(g).max() <= 1e-14 * max(1.0, abs(f(y))):
            break
        # Hessian of c ||a||: c (I - h h^T) / ||a||, projected on the null space
        w = cs / r
        P1, P2 = -h2, h1   # the unit direction across the slip
        Bp = P1[:, None] * B1 + P2[:, None] * B2
        H = Bp.T @ (w[:, None] * Bp)
        d = np.linalg.lstsq(H + 1e-14 * np.trace(H) * np.eye(len(y)), -g, rcond=None)[0]
        t, f0_ = 1.0, f(y)
        while f(y + t * d) > f0_ + 1e-4 * t * (g @ d) and t > 1e-12:
            t *= 0.5
        y = y + t * d
    return y


def exact_state(form: Formulation3D, x, u=None, source="") -> CollapseState3D | None:
    """The collapse state of a statics x (3 np + 1) with the mechanism u (or, if u is None
    or fails, one fitted to x by :func:`mechanism_lp`) when every residual passes; else None."""
    N, T1, T2 = form.split(x)
    for tries in range(2):
        if tries == 1 or u is None:
            mech = mechanism_lp(form, N, T1, T2)
            if mech is None:
                return None
            u = mech[0]
        q = form.strains(u)
        st = CollapseState3D(alpha=float(x[-1]), N=N.copy(), T1=T1.copy(), T2=T2.copy(), u=u, q=q, source=source)
        st.residual = residuals(form, N, T1, T2, st.alpha, u, q)
        if passes(st.residual):
            return st
        if tries == 0 and u is None:
            break
    return None


def lp_work(lp: HighsLP) -> float:
    """The work of an LP's last solve in the cone programs' units (iterations times rows^1.5,
    :attr:`lamodel.search.cone.ConePrograms.work`): an interior-point iteration factorises
    as a cone program's does, a simplex (or crossover) iteration updates a factor of the
    rows, so it counts the rows once."""
    info = lp.h.getInfo()
    simplex = max(info.simplex_iteration_count, 0) + max(info.crossover_iteration_count, 0)
    return max(info.ipm_iteration_count, 0) * lp.m ** 1.5 + simplex * lp.m


def align(form: Formulation3D, opening, sliding, u, N0, steps=ALIGN_STEPS, deadline=None, ipm_cap=None,
          cap_rows=None, tally=None):
    """Sliding directions on which a statics and a mechanism with the given points opening
    and sliding agree, by Newton's method on the flow rule; None if a step is infeasible.

    A conic program's mechanism slips off its exact directions by about the square root of
    its tolerance (3e-5 rad on a dome whose gap alternation closed its gap to 3e-11), and
    no statics holds directions that far off (the held programs are infeasible). Each step
    turns every sliding direction d by an angle dt, the statics ``T = -mu N (d + dt d_perp)``
    and the slip ``(d_perp . slip) = |slip| dt`` both linearised about the last step (N0,
    |slip|), stuck points in a pyramid of ALIGN_FACETS facets inscribed in their cone and
    still, opening points free of force and opening; one LP (HiGHS) a step, the least
    total turn. Consecutive steps' LPs have one shape: the first starts cold by the
    interior point method (at most ``ipm_cap`` iterations: it tells an infeasible pattern
    in a dozen, where the dual simplex wandered for minutes), each next one from the last
    one's basis (at most ``cap_rows`` simplex iterations a row); every solve stops at
    ``deadline``, inside HiGHS, and ``tally(work)`` is told its work (:func:`lp_work`).
    Returns (directions (np, 2), mechanism u) for :func:`statics_lp` and :func:`exact_state`
    (which decide: nothing here is a certificate)."""
    npt, nb = form.np, form.nb
    mu = form.mu
    opening = np.asarray(opening, bool)
    sliding = np.asarray(sliding, bool) & ~opening
    stuck = ~(opening | sliding)
    At = form.A.T.tocsr()
    Qn, Q1, Q2 = -At[:npt], -At[npt:2 * npt], -At[2 * npt:]
    isl, ist, io = np.flatnonzero(sliding), np.flatnonzero(stuck), np.flatnonzero(opening)
    ns, nu, nx = isl.size, 6 * nb, 3 * npt + 1
    q = form.strains(u)
    lam = np.hypot(q[npt + isl], q[2 * npt + isl])
    if ns == 0 or np.any(lam <= 0):
        return None
    d = np.column_stack([q[npt + isl], q[2 * npt + isl]]) / lam[:, None]
    N0 = np.asarray(N0, float)[isl]
    K = ALIGN_FACETS
    th = 2 * np.pi * np.arange(K) / K
    D = sp.diags
    E = sp.hstack([form.A, sp.csr_matrix(form.fbar.reshape(-1, 1))]).tocsr()
    sel = lambda idx, off: sp.csr_matrix((np.ones(idx.size), (np.arange(idx.size), off + idx)),  # noqa: E731
                                         shape=(idx.size, nx))
    # stuck points: e_k . T <= -mu N cos(pi / K), k facets
    pk, tk = np.repeat(ist, K), np.tile(th, ist.size)
    r = np.arange(pk.size)
    pyr = sp.csr_matrix((np.concatenate([np.cos(tk), np.sin(tk), mu[pk] * np.cos(np.pi / K)]),
                         (np.concatenate([r, r, r]), np.concatenate([npt + pk, 2 * npt + pk, pk]))), shape=(pk.size, nx))
    mech = sp.vstack([Qn[ist], Q1[ist], Q2[ist], Qn[isl], Qn[io], sp.csr_matrix(form.fbar.reshape(1, -1))])
    m_lo = np.concatenate([np.zeros(3 * ist.size + ns + io.size), [1.0]])
    m_hi = np.concatenate([np.zeros(3 * ist.size + ns), np.full(io.size, INF), [1.0]])
    Z = lambda r_, c_: sp.csr_matrix((r_, c_))  # noqa: E731
    basis = None
    for _ in range(steps):
        perp = np.column_stack([-d[:, 1], d[:, 0]])
        # T_k + mu N d_k + mu N0 dt perp_k = 0 (k = 1, 2)
        slide = [sp.hstack([sel(isl, (1 + k) * npt) + sp.csr_matrix((mu[isl] * d[:, k], (np.arange(ns), isl)),
                                                                     shape=(ns, nx)),
                            Z(ns, nu), D(mu[isl] * N0 * perp[:, k])]) for k in (0, 1)]
        # perp . slip - |slip| dt = 0; d . slip >= 0
        across = D(perp[:, 0]) @ Q1[isl] + D(perp[:, 1]) @ Q2[isl]
        along = D(d[:, 0]) @ Q1[isl] + D(d[:, 1]) @ Q2[isl]
        # columns: statics (nx), motions (nu), turns dt (ns), their sizes a >= |dt| (ns)
        I = sp.identity(ns, format="csr")
        rows = sp.vstack([sp.hstack([E, Z(E.shape[0], nu + 2 * ns)]),
                          sp.hstack([pyr, Z(pyr.shape[0], nu + 2 * ns)]),
                          *[sp.hstack([r_, Z(ns, ns)]) for r_ in slide],
                          sp.hstack([Z(mech.shape[0], nx), mech, Z(mech.shape[0], 2 * ns)]),
                          sp.hstack([Z(ns, nx), across, D(-lam), Z(ns, ns)]),
                          sp.hstack([Z(ns, nx), along, Z(ns, 2 * ns)]),
                          sp.hstack([Z(ns, nx + nu), -I, I]), sp.hstack([Z(ns, nx + nu), I, I])]).tocsr()
        lo = np.concatenate([-form.f0, np.full(pyr.shape[0], -INF), np.zeros(2 * ns), m_lo, np.zeros(4 * ns)])
        hi = np.concatenate([-form.f0, np.zeros(pyr.shape[0]), np.zeros(2 * ns), m_hi, np.zeros(ns), np.full(3 * ns, INF)])
        c_lo = np.concatenate([np.full(npt, -INF), np.full(2 * npt, -INF), [0.0], np.full(nu, -INF),
                               np.full(ns, -ALIGN_TURN), np.zeros(ns)])
        c_hi = np.concatenate([np.zeros(npt), np.full(2 * npt, INF), [INF], np.full(nu, INF), np.full(2 * ns, ALIGN_TURN)])
        for idx in (io, npt + io, 2 * npt + io):   # opening points carry nothing
            c_lo[idx] = c_hi[idx] = 0.0
        cost = np.zeros(nx + nu + 2 * ns)
        cost[nx + nu + ns:] = 1.0   # the least turn
        rows.data[np.abs(rows.data) < ALIGN_ROUND_OFF] = 0.0   # round-off (cos(pi / 2)), not coefficients
        rows.eliminate_zeros()
        lp = HighsLP(rows, lo, cost, c_lo, c_hi, name="align3d", b_hi=hi, ipm=True)
        cap = None if cap_rows is None else max(int(cap_rows * lp.m), 1)
        if basis is not None:
            lp.restart(basis)
        try:
            status = lp.solve(cap=cap, deadline=deadline, ipm_cap=ipm_cap)
        finally:
            if tally is not None and not lp.abandoned:
                tally(lp_work(lp))
        if status != "optimal":
            return None
        basis = lp.portable_basis()
        sol = lp.x()
        dt, u = sol[nx + nu:nx + nu + ns], sol[nx:nx + nu]
        d = d + dt[:, None] * perp
        d /= np.hypot(d[:, 0], d[:, 1])[:, None]
        N0 = sol[isl]
        q = form.strains(u)
        lam = np.maximum(d[:, 0] * q[npt + isl] + d[:, 1] * q[2 * npt + isl], 0.0)
        if np.abs(dt).max() <= ALIGN_DONE or np.any(lam <= 0):
            break
    out = np.zeros((npt, 2))
    out[isl] = d
    return out, u
