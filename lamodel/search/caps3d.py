"""Certification in space with the joints' strengths: the residual test, the held statics
and the mechanism of a statics, where points have caps (crushing ``N_c``, tension
``N_t``) and cohesion forces k (:mod:`lamodel.formulation.space`).

The conditions of a collapse state (:func:`residuals`): equilibrium; the real domain
``N_c <= N <= N_t``, ``||T|| <= k - mu N``; compatibility and ``fbar^T u = 1``; the caps'
flow rule (a point opens only at ``N = N_t``, closes only at ``N = N_c``: a point without
a crushing cap never closes); the slips' rule on the cone of radius
``c = k - mu N`` (``c ||slip|| = T . slip`` and T along the slip); and ``alpha = alpha_K``
(eq. 5 with the caps' dissipation). The held statics (:func:`statics_lp`) is an exact LP
(HiGHS) on the points' own variables: held caps as equalities, a sliding point's force on
its cone along its slip, every other point in a pyramid of PYRAMID_FACETS facets inscribed
in its cone (an edge along a reference force), the caps as column bounds.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..formulation.space import Formulation3D
from .highs import INF, HighsLP
from .tuning import CONTACT_TOL, PYRAMID_FACETS


def _per_block(v, scale):
    v = np.asarray(v, float).reshape(-1, 6)
    return np.concatenate([v[:, :3].ravel(), scale * v[:, 3:].ravel()])


def residuals(form: Formulation3D, N, T1, T2, alpha, u, q) -> dict:
    """Violations of every condition of a collapse state with caps (module doc; 0 is
    exact), each with one dimension, under the names of the dry test. The domain is the
    real one (every cap, however far); the flow rules the programs': a point never opens
    where its tensile cap is infinite (CAP_FAR), nor slips where its cohesion force is."""
    crush, tension, k = form.structure.caps()
    _, opens, slides = np.isfinite(form.caps)
    L = form.structure.size()
    mu = form.mu
    npt = len(N)
    F = max(np.abs(_per_block(form.f0, 1 / L)).max(), np.abs(_per_block(form.fbar, 1 / L)).max(), 1e-300)
    U = max(np.abs(_per_block(u, L)).max(), np.abs(q).max(), 1e-300)
    eq = _per_block(form.A @ np.concatenate([N, T1, T2]) + form.f0 + alpha * form.fbar, 1 / L)
    qn, s1, s2 = q[:npt], q[npt:2 * npt], q[2 * npt:]
    slip = np.hypot(s1, s2)
    c = k - mu * N
    below = np.where(np.isfinite(crush), crush - N, -np.inf)
    crushable = np.isfinite(form.caps[0])
    closing = np.maximum(-qn, 0.0)
    off_top = np.where(opens, np.minimum(np.abs(tension - N) / F, 1.0), 1.0)
    off_bottom = np.where(crushable, np.minimum(np.abs(N - np.where(crushable, crush, 0.0)) / F, 1.0), 0.0)
    return {
        "equilibrium": float(np.abs(eq).max() / F),
        "cone": float(max((np.hypot(T1, T2) - c).max(), (N - tension).max(), below.max(), 0.0) / F),
        "compatibility": float(np.abs(q - form.strains(u)).max() / U),
        "normalisation": float(abs(form.fbar @ u - 1.0)),
        # a point closes only where it may crush, opens only where it may open
        "opening_sign": float(max(closing[~crushable].max(initial=0.0), np.max(qn, where=~opens, initial=0.0)) / U),
        # a motion at a point off its cap: the smaller of its size and its work there
        # (a cap far away times a round-off closing is no violation)
        "opening_complementarity": float(max(np.max(off_top * np.maximum(qn, 0.0), initial=0.0),
                                             np.max(off_bottom * closing, initial=0.0)) / U),
        # on the cone along T, or (a point of infinite cohesion force) no slip at all
        "slip_flow_rule": float(max(np.max(np.abs(c * slip - (T1 * s1 + T2 * s2)), where=slides, initial=0.0) / F,
                                    np.max(slip, where=~slides, initial=0.0)) / U),
        "slip_alignment": float(np.abs(T1 * s2 - T2 * s1).max() / (F * U)),
        "virtual_work": float(abs(form.kinematic_multiplier(u, q, N) - alpha) / max(abs(alpha), 1.0)),
    }


def statics_lp(form: Formulation3D, opening, sliding, slide_dir, ref=None, crushing=None, facets=PYRAMID_FACETS,
               deadline=None):
    """Least alpha with the points held (module doc), exact: columns ``(N, T1, T2, alpha)``.
    ``ref`` (np, 2): reference tangential forces (a pyramid edge along each). Returns the
    statics (3 np + 1) or None; ``deadline`` (a search's) stops it inside HiGHS (Stopped):
    on thousands of points its cold solve takes minutes."""
    crush, tension, k = form.caps
    n = form.np
    mu = form.mu
    opening = np.asarray(opening, bool) & np.isfinite(tension)   # infinite: the point never opens
    crushing = np.zeros(n, bool) if crushing is None else np.asarray(crushing, bool) & ~opening
    sliding = np.asarray(sliding, bool) & np.isfinite(k)         # ... nor slides (its T free)
    other = np.flatnonzero(~sliding & np.isfinite(k))
    nx = 3 * n + 1
    rows, lo, hi = [sp.hstack([form.A, sp.csr_matrix(form.fbar.reshape(-1, 1))])], [-form.f0], [-form.f0]
    isl = np.flatnonzero(sliding)
    d = np.asarray(slide_dir, float).reshape(-1, 2)[isl]
    r = np.arange(isl.size)
    for j in (0, 1):  # T_j + mu d_j N = k d_j
        rows.append(sp.csr_matrix((np.r_[np.ones(isl.size), mu[isl] * d[:, j]], (np.r_[r, r], np.r_[(1 + j) * n + isl, isl])),
                                  shape=(isl.size, nx)))
        lo.append(k[isl] * d[:, j])
        hi.append(k[isl] * d[:, j])
    th0 = np.zeros(other.size) if ref is None else np.arctan2(ref[other, 1], ref[other, 0])
    p = np.repeat(other, facets)
    th = (th0[:, None] + 2 * np.pi * np.arange(facets)[None, :] / facets).ravel()
    cos = np.cos(np.pi / facets)
    m = np.arange(p.size)  # e.T <= (k - mu N) cos(pi / facets): the inscribed pyramid
    rows.append(sp.csr_matrix((np.r_[np.cos(th), np.sin(th), mu[p] * cos], (np.r_[m, m, m], np.r_[n + p, 2 * n + p, p])),
                              shape=(p.size, nx)))
    lo.append(np.full(p.size, -INF))
    hi.append(k[p] * cos)
    c_lo = np.r_[np.where(np.isfinite(crush), crush, -INF), np.full(2 * n, -INF), 0.0]
    c_hi = np.r_[np.where(np.isfinite(tension), tension, INF), np.full(2 * n, INF), INF]
    c_lo[:n][opening] = tension[opening]
    c_hi[:n][crushing] = c_lo[:n][crushing] = crush[crushing]
    cost = np.zeros(nx)
    cost[-1] = 1.0
    lp = HighsLP(sp.vstack(rows).tocsr(), np.concatenate(lo), cost, c_lo, c_hi, name="certify3d-caps",
                 b_hi=np.concatenate(hi))
    if lp.solve(deadline=deadline) != "optimal":
        return None
    x = lp.x()
    x[:n] = np.clip(x[:n], c_lo[:n], c_hi[:n])
    return x


def mechanism_lp(form: Formulation3D, N, T1, T2, tol=CONTACT_TOL):
    """A mechanism (u, q) compatible with the statics (N, T) with caps: a point may open
    where ``N = N_t``, close where ``N = N_c``, slip along T where T is on its cone (at
    the same time, as the fictitious domain's corners allow), else it is still;
    ``fbar^T u = 1``; the one of least alpha_K. None if there is none."""
    crush, tension, k = form.caps
    npt, nb = form.np, form.nb
    mu = form.mu
    scale = max(np.abs(N).max(), np.abs(k[np.isfinite(k)]).max(initial=0.0), 1e-300)
    Tn = np.hypot(T1, T2)
    c = k - mu * N   # inf where the point never slides: neither at the apex nor on the cone
    at_top = tension - N <= tol * scale
    at_bottom = np.isfinite(crush) & (N - np.where(np.isfinite(crush), crush, -INF) <= tol * scale)
    apex = c <= tol * scale  # the cone's apex (T = 0): any slip, no dissipation
    on_cone = (c - Tn <= tol * scale) & ~apex
    At = form.A.T.tocsr()
    Q1, Q2 = -At[npt:2 * npt], -At[2 * npt:]
    Qn, along, across = form.slip_rows(T1, T2, on_cone)
    still = np.flatnonzero(~on_cone & ~apex)
    ic = np.flatnonzero(on_cone)
    n_lo = np.where(at_bottom, -INF, 0.0)
    n_hi = np.where(at_top, INF, 0.0)
    rows = sp.vstack([Qn, across[ic], along[ic], Q1[still], Q2[still], sp.csr_matrix(form.fbar.reshape(1, -1))])
    lo = np.r_[n_lo, np.zeros(ic.size), np.zeros(ic.size), np.zeros(2 * still.size), 1.0]
    hi = np.r_[n_hi, np.zeros(ic.size), np.full(ic.size, INF), np.zeros(2 * still.size), 1.0]
    # alpha_K = -f0 u + sum N_t qn (opening) + N_c qn (closing) + c (slip . T_hat): the
    # caps' terms at the statics' own N, which the flow rule makes equal to them
    cost = -form.f0 + Qn.T @ N + along.T @ np.where(on_cone, c, 0.0)
    lp = HighsLP(rows.tocsr(), lo, cost, np.full(6 * nb, -INF), np.full(6 * nb, INF), name="mechanism3d-caps", b_hi=hi)
    if lp.solve() != "optimal":
        return None
    u = lp.x()
    return u, form.strains(u)
