"""The conic programs of the 3D search, solved with Clarabel (second-order cones).

Columns are the statics ``x = (N, T1, T2, alpha)`` of :mod:`lamodel.formulation.space`
(3 np + 1), on the non-dimensional structure. Every program shares the equilibrium rows
``A s_f + alpha fbar = -f0``; they differ in the cone each point lives in and the cost:

* :meth:`ConePrograms.associative` — max alpha over the admissible set S (the Coulomb cone
  ``||T|| <= -mu N`` at every point): the associative bound, an upper bound on alpha_c.
* :meth:`ConePrograms.cohesive` — max alpha of the fictitious cohesive system with
  cohesions c (``||T|| <= c``, ``N <= 0``): alpha_as(c) of the seed. The duals of the
  equilibrium rows are its mechanism u (``fbar^T u = 1``), with strains ``q = -A^T u``.
* :meth:`ConePrograms.statics` — min ``alpha + w^T s_f`` over S, with chosen points held:
  opening points at ``N = T = 0``, sliding points at ``T = -mu N s_hat`` (on the cone,
  along the slip). With ``w`` the gap weights of a mechanism it is the gap step; with the
  flowing points held and ``w = 0`` it is the statics half of the certification.

With the joints' strengths (:attr:`~lamodel.formulation.space.Formulation3D.caps`) every
point's N lies between its crushing and tensile forces ``N_c <= N <= N_t`` (linear rows)
and its cone's radius gains the cohesion force k (``||T|| <= k - mu N``); held points:
opening at ``N = N_t``, crushing at ``N = N_c``, sliding at ``T = (k - mu N) s_hat``.
"""
from __future__ import annotations

from dataclasses import dataclass

import clarabel
import numpy as np
import scipy.sparse as sp

from ..formulation.space import Formulation3D
from .tuning import CONE_KTRATIO, CONE_TOLERANCE


@dataclass
class ConeResult:
    """One conic solve: status ('optimal', 'infeasible', 'unbounded' or Clarabel's word),
    the statics x (3 np + 1), alpha, and the mechanism u from the equilibrium duals."""

    status: str
    x: np.ndarray | None = None
    u: np.ndarray | None = None
    iterations: int = 0
    seconds: float = 0.0

    @property
    def ok(self) -> bool:
        return self.status == "optimal"

    @property
    def alpha(self) -> float:
        return float(self.x[-1]) if self.x is not None else np.nan


_STATUS = {"Solved": "optimal", "AlmostSolved": "optimal", "PrimalInfeasible": "infeasible",
           "AlmostPrimalInfeasible": "infeasible", "DualInfeasible": "unbounded",
           "AlmostDualInfeasible": "unbounded"}


def _cone_scaled(rows, b):
    """Each point's three cone rows (and their right-hand side) divided by their largest
    coefficient where it passes 1: the same cone (w s is in it with s, w > 0), but a huge
    mu's rows ``(mu N, T1, T2)`` become ``(N, T1 / mu, T2 / mu)``, so the solver's
    tolerances, relative to the data's size, stay those of an ordinary structure."""
    if rows.shape[0] == 0:
        return rows, b
    top = abs(rows).max(axis=1).toarray().ravel().reshape(-1, 3).max(axis=1)
    w = np.repeat(1.0 / np.maximum(top, 1.0), 3)
    return sp.diags(w) @ rows, np.asarray(b, float) * w


class ConePrograms:
    """The SOCPs of one (non-dimensional) 3D structure; see the module doc."""

    def __init__(self, form: Formulation3D, threads: int = 1):
        self.form = form
        self.nb, self.np = form.nb, form.np
        self.nx = 3 * self.np + 1
        self.E = sp.hstack([form.A, sp.csr_matrix(form.fbar.reshape(-1, 1))]).tocsc()
        self.threads = threads
        self.n_solves = 0
        self.seconds = 0.0
        self.work = 0.0  # interior-point iterations times rows^1.5 (the default run's work bound)
        n = self.np
        idx = np.arange(n)
        # SOC rows of point p: (cone radius, T1, T2); s = b - Gx, so T rows carry -1.
        self._soc_T = sp.csr_matrix((np.full(2 * n, -1.0), (np.concatenate([3 * idx + 1, 3 * idx + 2]),
                                                            np.concatenate([n + idx, 2 * n + idx]))),
                                    shape=(3 * n, self.nx))
        self._soc_N = sp.csr_matrix((form.mu, (3 * idx, idx)), shape=(3 * n, self.nx))

    # ------------------------------------------------------------------ building
    def _solve(self, cost, rows_zero, b_zero, rows_nonneg, soc_rows, soc_b, n_soc, time_limit=None, b_nonneg=None):
        """min cost^T x subject to rows_zero x = b_zero, rows_nonneg x <= b_nonneg (0 if
        None; s = b - Gx >= 0) and SOC blocks of 3 rows (s = soc_b - soc_rows x in the cone)."""
        soc_rows, soc_b = _cone_scaled(soc_rows, soc_b)
        G = sp.vstack([rows_zero, rows_nonneg, soc_rows]).tocsc()
        b = np.concatenate([b_zero, np.zeros(rows_nonneg.shape[0]) if b_nonneg is None else b_nonneg, soc_b])
        cones = [clarabel.ZeroConeT(rows_zero.shape[0]), clarabel.NonnegativeConeT(rows_nonneg.shape[0])]
        cones += [clarabel.SecondOrderConeT(3)] * n_soc
        settings = clarabel.DefaultSettings()
        settings.verbose = False
        settings.max_threads = self.threads
        for name in ("tol_gap_abs", "tol_gap_rel", "tol_feas", "tol_infeas_abs", "tol_infeas_rel"):
            setattr(settings, name, CONE_TOLERANCE)
        settings.tol_ktratio = CONE_KTRATIO
        if time_limit is not None:
            settings.time_limit = max(float(time_limit), 1e-3)
        P = sp.csc_matrix((self.nx, self.nx))
        solver = clarabel.DefaultSolver(P, np.asarray(cost, float), G, b, cones, settings)
        sol = solver.solve()
        self.n_solves += 1
        self.seconds += float(sol.solve_time)
        self.work += int(sol.iterations) * G.shape[0] ** 1.5  # an iteration's factorisation fills in
        status = _STATUS.get(str(sol.status).split(".")[-1], str(sol.status).split(".")[-1])
        if status != "optimal":
            return ConeResult(status, iterations=int(sol.iterations), seconds=float(sol.solve_time))
        z = np.asarray(sol.z)
        u = z[:self.E.shape[0]]
        fu = float(self.form.fbar @ u)
        u = u / fu if abs(fu) > 1e-12 else None
        return ConeResult(status, np.asarray(sol.x), u, int(sol.iterations), float(sol.solve_time))

    def _nonneg(self, keep=None):
        """Rows -N >= 0 (every point, or those in ``keep``) and alpha >= 0."""
        n = self.np
        idx = np.arange(n) if keep is None else np.flatnonzero(keep)
        rows = sp.csr_matrix((np.ones(idx.size), (np.arange(idx.size), idx)), shape=(idx.size, self.nx))
        alpha = sp.csr_matrix(([-1.0], ([0], [self.nx - 1])), shape=(1, self.nx))
        return sp.vstack([rows, alpha])

    def _capped(self, may_open=None, may_crush=None):
        """With the joints' strengths: rows ``N <= N_t`` (the points with a tensile cap, or
        those of ``may_open``), ``-N <= -N_c`` (the points with a crushing cap, or those of
        ``may_crush``) and alpha >= 0, and their right-hand sides."""
        n = self.np
        crush, tension, _ = self.form.caps
        up = np.isfinite(tension) if may_open is None else np.isfinite(tension) & np.asarray(may_open, bool)
        up = np.flatnonzero(up)
        down = np.isfinite(crush) if may_crush is None else np.isfinite(crush) & np.asarray(may_crush, bool)
        down = np.flatnonzero(down)
        k = up.size + down.size
        rows = sp.csr_matrix((np.r_[np.ones(up.size), -np.ones(down.size), -1.0],
                              (np.arange(k + 1), np.r_[up, down, self.nx - 1])), shape=(k + 1, self.nx))
        return rows, np.r_[tension[up], -crush[down], 0.0]

    def _radius(self):
        """The cones' radii at N = 0: the cohesion forces (0 without strengths)."""
        out = np.zeros(3 * self.np)
        if self.form.caps is not None:
            out[0::3] = self.form.caps[2]
        return out

    def _coned(self):
        """The points with a cone (all but those of infinite cohesion force: T free)."""
        return np.ones(self.np, bool) if self.form.caps is None else np.isfinite(self.form.caps[2])

    def _cones(self, points, soc, b):
        """The SOC rows ``soc`` and right-hand sides ``b`` (3 np) of ``points`` (bool, np)."""
        keep = np.flatnonzero(np.repeat(points, 3))
        return soc[keep], b[keep], int(points.sum())

    # ------------------------------------------------------------------ programs
    def associative(self, time_limit=None) -> ConeResult:
        """max alpha over S (the Coulomb cone at every point)."""
        cost = np.zeros(self.nx)
        cost[-1] = -1.0
        if self.form.caps is not None:
            rows, b = self._capped()
            return self._solve(cost, self.E, -self.form.f0, rows,
                               *self._cones(self._coned(), self._soc_N + self._soc_T, self._radius()), time_limit,
                               b_nonneg=b)
        return self._solve(cost, self.E, -self.form.f0, self._nonneg(), self._soc_N + self._soc_T,
                           np.zeros(3 * self.np), self.np, time_limit)

    def cohesive(self, c, may_open=None, may_slip=None, time_limit=None, dilatancy=0.0, may_crush=None) -> ConeResult:
        """alpha_as(c): max alpha with ||T_p|| <= c_p and N_p <= 0; u is its mechanism.

        ``may_open`` / ``may_slip`` (bool, np) restrict the mechanism: a point that may not
        open has its N free (the dual then gives it no opening), one that may not slip its
        T free (no slip). ``dilatancy`` t: ``||T_p|| <= c_p - t mu N_p`` (the cone of
        friction t mu widened by the cohesion), whose mechanism's slips dilate by t mu.
        With the joints' strengths c includes the cohesion forces and N lies between the
        caps (``may_open``, ``may_crush``: the points whose cap may flow)."""
        n = self.np
        c = np.maximum(np.asarray(c, float), 0.0)
        cost = np.zeros(self.nx)
        cost[-1] = -1.0
        slip = self._coned() if may_slip is None else np.asarray(may_slip, bool) & self._coned()
        b = np.zeros(3 * n)
        b[0::3] = c
        keep = np.flatnonzero(np.repeat(slip, 3))
        soc = self._soc_T if dilatancy == 0 else self._soc_T + dilatancy * self._soc_N
        if self.form.caps is not None:
            rows, bn = self._capped(may_open, may_crush)
            return self._solve(cost, self.E, -self.form.f0, rows, soc[keep], b[keep], int(slip.sum()), time_limit,
                               b_nonneg=bn)
        return self._solve(cost, self.E, -self.form.f0, self._nonneg(may_open), soc[keep], b[keep],
                           int(slip.sum()), time_limit)

    def statics(self, w=None, opening=None, sliding=None, slide_dir=None, time_limit=None,
                crushing=None) -> ConeResult:
        """min alpha + w^T s_f over S with points held: ``opening`` (bool, np) at N = T = 0,
        ``sliding`` (bool, np) at T = -mu N s_hat with ``slide_dir`` (np, 2) the unit slip
        directions in the points' frames (with the joints' strengths: the module doc;
        ``crushing`` at N = N_c)."""
        n = self.np
        if self.form.caps is not None:
            return self._capped_statics(w, opening, sliding, slide_dir, time_limit, crushing)
        cost = np.zeros(self.nx)
        cost[-1] = 1.0
        if w is not None:
            cost[:3 * n] = w
        opening = np.zeros(n, bool) if opening is None else np.asarray(opening, bool)
        sliding = (np.zeros(n, bool) if sliding is None else np.asarray(sliding, bool)) & ~opening
        free = ~(opening | sliding)
        zero = [self.E]
        io = np.flatnonzero(opening)
        if io.size:  # N = T1 = T2 = 0
            cols = np.concatenate([io, n + io, 2 * n + io])
            zero.append(sp.csr_matrix((np.ones(cols.size), (np.arange(cols.size), cols)), shape=(cols.size, self.nx)))
        isl = np.flatnonzero(sliding)
        if isl.size:  # T_k + mu N s_k = 0, k = 1, 2
            zero += self._slide_rows(isl, slide_dir)
        Z = sp.vstack(zero)
        bz = np.concatenate([-self.form.f0, np.zeros(Z.shape[0] - self.E.shape[0])])
        keep = np.repeat(free, 3)
        soc = (self._soc_N + self._soc_T)[np.flatnonzero(keep)]
        return self._solve(cost, Z, bz, self._nonneg(~opening), soc, np.zeros(soc.shape[0]), int(free.sum()),
                           time_limit)

    def _slide_rows(self, isl, slide_dir):
        """The rows ``T_j + mu N s_j`` (j = 1, 2) of the sliding points ``isl`` along their
        unit slips ``slide_dir`` (np, 2)."""
        n = self.np
        d = np.asarray(slide_dir, float)[isl]
        mu = self.form.mu[isl]
        r = np.arange(isl.size)
        return [sp.csr_matrix((np.concatenate([np.ones(isl.size), mu * d[:, j]]),
                               (np.concatenate([r, r]), np.concatenate([(1 + j) * n + isl, isl]))),
                              shape=(isl.size, self.nx)) for j in (0, 1)]

    def _capped_statics(self, w, opening, sliding, slide_dir, time_limit, crushing):
        """:meth:`statics` with the joints' strengths: opening points at ``N = N_t``,
        crushing ones at ``N = N_c``, sliding ones at ``T = (k - mu N) s_hat``; every
        point keeps its cone and its caps (those it has: none infinite)."""
        n = self.np
        crush, tension, k = self.form.caps
        cost = np.zeros(self.nx)
        cost[-1] = 1.0
        if w is not None:
            cost[:3 * n] = w
        held = [np.zeros(n, bool) if m is None else np.asarray(m, bool) for m in (opening, crushing, sliding)]
        opening, crushing, sliding = held
        opening = opening & np.isfinite(tension)   # a point of infinite caps or k never moves so
        crushing = crushing & ~opening & np.isfinite(crush)
        sliding = sliding & np.isfinite(k)
        zero, bz = [self.E], [-self.form.f0]
        for pts, value in ((opening, tension), (crushing, crush)):
            idx = np.flatnonzero(pts)
            zero.append(sp.csr_matrix((np.ones(idx.size), (np.arange(idx.size), idx)), shape=(idx.size, self.nx)))
            bz.append(value[idx])
        isl = np.flatnonzero(sliding)
        if isl.size:  # T_j + mu N s_j = k s_j, j = 1, 2
            zero += self._slide_rows(isl, slide_dir)
            bz += [k[isl] * np.asarray(slide_dir, float)[isl, j] for j in (0, 1)]
        rows, bn = self._capped()
        return self._solve(cost, sp.vstack(zero), np.concatenate(bz), rows,
                           *self._cones(self._coned(), self._soc_N + self._soc_T, self._radius()), time_limit,
                           b_nonneg=bn)
