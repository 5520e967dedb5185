"""Eq. (1)-(5) in space, as sparse matrices: the point-contact model on the Coulomb cone.

The 3D counterpart of :mod:`lamodel.formulation.matrices` (the one place where the 3D
mechanics is written). Conventions are those of :mod:`lamodel.structure3d`:

* statics ``s = (N, T1, T2, alpha)``: per contact point p a normal force N_p (<= 0 is
  compression) and two tangential components in the point's frame ``(n, t1, t2)``; the
  force ``N n + T1 t1 + T2 t2`` acts on body a at the point, its opposite on body b;
* equilibrium ``A s_f + f0 + alpha fbar = 0`` (eq. 1-2), A of size 6 nb x 3 np, block rows
  ``(fx, fy, fz, mx, my, mz)`` with moments about the centroid (3D cross products);
* admissibility (eq. 4 on the cone): ``hypot(T1, T2) <= -mu N`` (so ``N <= 0``);
* compatibility ``q = -A^T u``: per point ``q = (opening, slip1, slip2)``, the motion of b
  relative to a at the point, in the point's frame (virtual work:
  ``alpha fbar^T u + f0^T u = s_f^T q``);
* the fictitious cohesive system: cohesion ``c_p = -mu N_p`` of the real statics,
  ``||t_p|| <= c_p``, no dilatancy; its flow rule opens only where ``N = 0`` and slips along
  the tangential force; ``alpha_K = -u^T f0 + sum_p c_p ||slip_p||`` (eq. 5).
* with the joints' strengths (:meth:`lamodel.structure3d.Structure3D.caps`: per point the
  crushing force ``N_c = -f_c A``, the tensile force ``N_t = min(f_t A, k / mu)``, the cohesion force
  ``k = c0 A``) the real domain is ``N_c <= N <= N_t``, ``||T|| <= k - mu N``; the
  fictitious system's cohesion is ``c_p = max(k - mu N_p, 0)`` (``c0 A + mu |N|`` at a
  compressed point: the real cone's radius at the real N), its caps the same and
  associative: a point opens only at ``N = N_t``, closes (crushes) only at ``N = N_c``,
  and dissipates ``N_t q_n`` opening, ``N_c q_n`` crushing and ``c_p ||slip||`` sliding.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..search.tuning import CAP_FAR
from ..structure3d import Structure3D
from .matrices import Statics


def _skew_rows(r: np.ndarray, f: np.ndarray) -> np.ndarray:
    """(k, 3): r x f row by row (the moment of a force f applied at lever arm r)."""
    return np.cross(r, f)


def equilibrium_matrix(s: Structure3D) -> sp.csr_matrix:
    """A of eq. (2) in space: block resultants (6 nb) produced by the point forces (3 np).

    Column p (N_p), np + p (T1_p), 2 np + p (T2_p): the unit force along n, t1, t2 at the
    point acts on body a and, reversed, on body b; its moment is about the body's centroid.
    """
    nb, npt = s.n_blocks, s.n_points
    ia, ib = s.point_blocks()
    rows, cols, vals = [], [], []
    for blk, sign in ((ia, 1.0), (ib, -1.0)):
        on = blk >= 0
        k = np.flatnonzero(on)
        j = blk[on]
        r = s.point[k] - s.centroid[j]  # lever arm from the centroid to the point
        for col0, vec in ((0, s.normal), (npt, s.tangent1), (2 * npt, s.tangent2)):
            f = vec[k]
            m = _skew_rows(r, f)
            for comp in range(3):
                rows += [6 * j + comp, 6 * j + 3 + comp]
                cols += [col0 + k, col0 + k]
                vals += [sign * f[:, comp], sign * m[:, comp]]
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(6 * nb, 3 * npt))


def load_vectors(s: Structure3D):
    """(f0, fbar) of eq. (2), each of length 6 nb: resultants at the centroids and, in the
    moment rows, the moments of loads applied elsewhere (``dead_m``, ``live_m``)."""
    f0 = np.column_stack([s.dead, s.dead_m]).ravel()
    fb = np.column_stack([s.live, s.live_m]).ravel()
    return f0, fb


def kinematic_multiplier(f0, mu, u, q, N, caps=None) -> float:
    """alpha_K = -u^T f0 + sum_p c_p ||slip_p|| with c_p = -mu N_p (eq. 5 on the cone):
    the work of the dead loads plus the dissipation of the fictitious cohesive system;
    with the joints' strengths ``caps`` (module doc) that of its caps too."""
    npt = len(mu)
    slip = np.hypot(q[npt:2 * npt], q[2 * npt:])
    if caps is None:
        return float(-np.dot(f0, u) - np.sum(mu * N * slip))
    crush, tension, k = caps
    c = np.maximum(_finite(k) - mu * N, 0.0)
    return float(-np.dot(f0, u) + np.sum(np.where(np.isfinite(k), c, 0.0) * slip) + cap_dissipation(caps, q[:npt]))


def _finite(v):
    """``v`` with its infinite entries (caps no state reaches) 0."""
    return np.where(np.isfinite(v), v, 0.0)


def cap_dissipation(caps, qn) -> float:
    """The caps' dissipation ``sum N_t q_n+ + N_c q_n-`` (q_n- = min(q_n, 0); a point
    without a crushing cap closes by nothing, one without a tensile cap opens by nothing, and
    contributes nothing: the residual test rejects such a motion)."""
    crush, tension, _ = caps
    closing = np.minimum(qn, 0.0)
    return float(np.sum(_finite(tension) * np.maximum(qn, 0.0)) + np.sum(_finite(crush) * closing))


def gap_weights(mu, q) -> np.ndarray:
    """w (3 np) with ``w^T s_f = alpha_K(N) - alpha`` for every statics in equilibrium and a
    mechanism with strains q (virtual work): per point ``-N open - mu N ||slip|| - T.slip``,
    which is >= 0 on the cone and 0 exactly when the point obeys the cohesive flow rule."""
    npt = len(mu)
    slip = np.hypot(q[npt:2 * npt], q[2 * npt:])
    return np.concatenate([-q[:npt] - mu * slip, -q[npt:2 * npt], -q[2 * npt:]])


def gap_constant(caps, mu, q) -> float:
    """With the joints' strengths, ``alpha_K(N) - alpha = w^T s_f + this`` (w of
    :func:`gap_weights`): the caps' dissipation and the cohesion forces' ``k ||slip||``."""
    npt = len(mu)
    if caps is None:
        return 0.0
    slip = np.hypot(q[npt:2 * npt], q[2 * npt:])
    return float(np.sum(_finite(caps[2]) * slip)) + cap_dissipation(caps, q[:npt])


def scales(s: Structure3D):
    """(force, length) units of the non-dimensional problem: the mean dead load of a block
    (the largest live load if there is none) and the size of the structure."""
    F = float(np.linalg.norm(s.dead, axis=1).sum() / s.n_blocks)
    if not F > 0:
        F = float(max(np.linalg.norm(s.live, axis=1).max(), np.linalg.norm(s.live_m, axis=1).max() / s.size()))
    return F, float(s.size())


def scaled(s: Structure3D, F: float, L: float) -> Structure3D:
    """The structure with forces divided by F and lengths by L (alpha is unchanged)."""
    return Structure3D(
        name=s.name, blocks=s.blocks, centroid=s.centroid / L, dead=s.dead / F, live=s.live / F,
        supports=s.supports, interfaces=s.interfaces, iface_a=s.iface_a, iface_b=s.iface_b,
        iface_polygon=[p / L for p in s.iface_polygon], iface_holes=[[h / L for h in hs] for hs in s.iface_holes],
        point_interface=s.point_interface, point=s.point / L,
        normal=s.normal, tangent1=s.tangent1, tangent2=s.tangent2, mu=s.mu, dead_m=s.dead_m / (F * L),
        live_m=s.live_m / (F * L), volume=s.volume / L ** 3,
        polyhedra={k: (np.asarray(v) / L, f) for k, (v, f) in s.polyhedra.items()}, units={}, meta=dict(s.meta),
        **({} if not s.has_materials else {  # stresses in F / L^2, areas in L^2
            "fc": s.fc * (L * L / F), "ft": s.ft * (L * L / F), "cohesion": s.cohesion * (L * L / F),
            "area": s.areas() / (L * L)}))


@dataclass
class Formulation3D(Statics):
    """The matrices of one 3D structure, built once (every solver of it shares them)."""

    @classmethod
    def of(cls, s: Structure3D) -> "Formulation3D":
        f0, fbar = load_vectors(s)
        return cls(s, equilibrium_matrix(s), f0, fbar)

    @property
    def nb(self) -> int:
        return self.structure.n_blocks

    @property
    def np(self) -> int:
        return self.structure.n_points

    @property
    def mu(self) -> np.ndarray:
        return self.structure.mu

    @property
    def caps(self):
        """``(N_c, N_t, k)`` per point with the joints' strengths (module doc), else None.
        A cap or cohesion force beyond CAP_FAR times the loads is infinite (-inf, inf, inf):
        no state reaches it, and its rows would only spoil the programs' scale. A point of
        infinite k has no cone (it never slides), one of infinite N_t never opens."""
        if not self.structure.has_materials:
            return None
        if getattr(self, "_caps", None) is None:
            far = CAP_FAR * (np.abs(self.f0).sum() + np.abs(self.fbar).sum())
            crush, tension, k = self.structure.caps()
            self._caps = (np.where(crush < -far, -np.inf, crush), np.where(tension > far, np.inf, tension),
                          np.where(k > far, np.inf, k))
        return self._caps

    def split(self, s_f):
        """(N, T1, T2) of a statics vector (3 np, or 3 np + 1 with alpha last)."""
        n = self.np
        return s_f[:n], s_f[n:2 * n], s_f[2 * n:3 * n]

    def slip_rows(self, T1, T2, on):
        """The strain rows ``(Q_n, along, across)`` (``q = Q u``): openings, and at the points
        ``on`` the slips along and across the tangential force (T1, T2) (0 elsewhere)."""
        n = self.np
        At = self.A.T.tocsr()
        Qn, Q1, Q2 = -At[:n], -At[n:2 * n], -At[2 * n:]
        Tn = np.hypot(T1, T2)
        safe = np.where(Tn > 0, Tn, 1.0)
        h1, h2 = np.where(on, T1 / safe, 0.0), np.where(on, T2 / safe, 0.0)
        return Qn, sp.diags(h1) @ Q1 + sp.diags(h2) @ Q2, sp.diags(-h2) @ Q1 + sp.diags(h1) @ Q2

    def strains(self, u) -> np.ndarray:
        """q = -A^T u: (openings, slips1, slips2) of the mechanism u, stacked by kind."""
        return -(self.A.T @ u)

    def kinematic_multiplier(self, u, q, N) -> float:
        return kinematic_multiplier(self.f0, self.mu, u, q, N, self.caps)

    def gap_constant(self, q) -> float:
        return gap_constant(self.caps, self.mu, q)

    def gap_weights(self, q) -> np.ndarray:
        return gap_weights(self.mu, q)

    def cone_slack(self, s_f) -> np.ndarray:
        """-mu N - ||T|| per point (>= 0 when admissible; with cohesion ``k - mu N - ||T||``)."""
        N, T1, T2 = self.split(s_f)
        if self.caps is None:
            return -self.mu * N - np.hypot(T1, T2)
        return self.caps[2] - self.mu * N - np.hypot(T1, T2)
