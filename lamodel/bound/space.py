"""The bound in space: the Coulomb cone by polygons for HiGHS, the certificates on the cone.

The same LPs as in the plane (:mod:`.lps`), on the contact points of a
:class:`~lamodel.structure3d.Structure3D` (:mod:`lamodel.formulation.space`):

* **Nmin LPs** over a *circumscribed* pyramid of each point's cone ``hypot(T1, T2) <= -mu N``:
  generators ``(N, T) = (-1, mu w_i)`` at the vertices w_i of a regular BOUND_PYRAMID-gon around
  the unit circle. The pyramid holds the cone, so its minimum is at most the cone's. The
  certificate (multipliers y of the equilibrium rows) is then checked against the cone
  itself: the dual bound uses the cone's support function ``mu |g_T|`` with ``|g_T|``
  rounded up (:class:`ExactData3D`), so it holds whatever polygon HiGHS was given.
* **alpha_coh** over an *inscribed* polygon of each cohesive disk ``|T| <= c``: the
  zonotope ``T = sum_i nu_i d_i``, ``|nu_i| <= BETA c``, of ZONES directions d_i, a regular
  2 ZONES-gon of radius ``BETA / sin(pi / (2 ZONES)) < 1`` (every column bound, no extra
  row; within ``cos(pi / (2 ZONES))`` of the disk). Its maximum is at most the disk's. The
  statics is rebuilt exactly from the basis and checked with ``T1^2 + T2^2 <= c^2`` and
  ``N <= 0`` in rationals.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import scipy.sparse as sp

from ..formulation.space import equilibrium_matrix, load_vectors, scaled, scales
from ..search.highs import INF
from ..search.tuning import BOUND_PYRAMID, ZONE_MARGIN, ZONES
from ..structure3d import Structure3D
from .exact import ExactData, _q, rebuild, weights
from .lps import BoundLPs

#: half-length of each zonotope segment (radius 1 - ZONE_MARGIN: room for the exact rebuild)
BETA = math.sin(math.pi / (2 * ZONES)) * (1.0 - ZONE_MARGIN)


def pyramid_vertices(m: int = BOUND_PYRAMID) -> np.ndarray:
    """(m, 2) vertices of a regular m-gon around the unit circle (its sides tangent to it,
    pushed out by 1e-9), one of them along t1."""
    r = (1.0 + 1e-9) / math.cos(math.pi / m)
    t = 2 * math.pi * np.arange(m) / m
    return r * np.column_stack([np.cos(t), np.sin(t)])


def zone_directions(k: int = ZONES) -> np.ndarray:
    """(k, 2) unit directions at (i + 1/2) pi / k: the zonotope's vertices lie along t1
    and t2 (the sliding directions of a course), where it meets the disk."""
    t = (np.arange(k) + 0.5) * math.pi / k
    d = np.column_stack([np.cos(t), np.sin(t)])
    # mirror images exactly (-x, y): opposite slips of a symmetric pattern cancel exactly
    d[k - 1 - np.arange(k // 2)] = d[np.arange(k // 2)] * [-1.0, 1.0]
    return d


def _point_matrix(npt, per, kinds):
    """(3 np x per np) sparse: column ``per p + i`` puts ``kinds[i]`` = (N, T1, T2) on point p."""
    rows, cols, vals = [], [], []
    p = np.arange(npt)
    for i, comps in enumerate(kinds):
        for c, v in enumerate(comps):
            if v:
                rows.append(c * npt + p)
                cols.append(per * p + i)
                vals.append(np.broadcast_to(v, (npt,)).astype(float))
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(3 * npt, per * npt))


class BoundLPs3D(BoundLPs):
    """:class:`~lamodel.bound.lps.BoundLPs` on the contact points of a structure in space.

    Cohesive columns: ``N_p <= 0`` then the ZONES zonotope coordinates of each point, then
    alpha."""

    def _setup(self):
        s = self.structure
        self.nc = s.n_points
        ss, A, f0, fb = self._scaled(scales, scaled, equilibrium_matrix, load_vectors, 3)
        self.d_shrunk = None
        npt, m, k = self.nc, BOUND_PYRAMID, ZONES
        w = pyramid_vertices(m)
        # a generator per pyramid vertex; mu differs by point: the columns carry it
        G = sp.lil_matrix((3 * npt, m * npt))
        for i in range(m):
            G[np.arange(npt), m * np.arange(npt) + i] = -1.0
            G[npt + np.arange(npt), m * np.arange(npt) + i] = s.mu * w[i, 0]
            G[2 * npt + np.arange(npt), m * np.arange(npt) + i] = s.mu * w[i, 1]
        self.zones = zone_directions(k)
        C = _point_matrix(npt, k + 1, [(1.0, 0.0, 0.0)] + [(0.0, d[0], d[1]) for d in self.zones])
        ncol = (k + 1) * npt + 1
        lo, hi = np.full(ncol, -INF), np.full(ncol, INF)
        hi[0:ncol - 1:k + 1] = 0.0  # N_p <= 0: no tension
        idx = np.flatnonzero(np.arange(ncol - 1) % (k + 1))
        self._build(A, f0, fb, sp.csr_matrix(G), m, C, lo, hi, idx, idx // (k + 1), BETA)


def _norm_up(a: Fraction, b: Fraction) -> Fraction:
    """A rational >= hypot(a, b), within a few units in the last place of a float."""
    q = a * a + b * b
    if not q:
        return Fraction(0)
    f = math.nextafter(math.sqrt(float(q)) * (1 + 4e-16), math.inf)
    while Fraction(f) ** 2 < q:
        f = math.nextafter(f * (1 + 1e-15), math.inf)
    return Fraction(f)


class ExactData3D(ExactData):
    """:class:`~lamodel.bound.exact.ExactData` on the Coulomb cone of contact points."""

    step_slack = Fraction(1) + Fraction(1, 10 ** 9)

    def __init__(self, structure: Structure3D):
        s = structure
        self.nb, self.nc = s.n_blocks, s.n_points
        self._load(equilibrium_matrix(s), *load_vectors(s), s.mu)
        self.d = None
        self.zones = [(_q(d[0]), _q(d[1])) for d in zone_directions(ZONES)]

    def _reduced(self, t, k):
        """Reduced cost of each point's ``-N`` under the cone: ``t_N + mu |t_T|`` (the
        norm rounded up, so the dual bound only loses), minus the objective's weight."""
        n = self.nc
        r = [t[p] + self.mu[p] * _norm_up(t[n + p], t[2 * n + p]) for p in range(n)]
        for j, w in weights(k).items():
            r[j] -= _q(w)
        return r

    def cohesive_bound(self, answer, limits, c, d_shrunk=None):
        """Exact lower bound on alpha_coh(c) (cohesion per point) from the cohesive LP's
        answer: its statics rebuilt exactly, then ``N <= 0`` and ``|T| <= c`` checked."""
        n, k = self.nc, len(self.zones)
        per = k + 1
        ncol = per * n + 1
        colT1 = [dict(self.cols[n + p]) for p in range(n)]
        colT2 = [dict(self.cols[2 * n + p]) for p in range(n)]

        def column(j):
            if j == ncol - 1:
                return {i: v for i, v in enumerate(self.fbar) if v}
            p, i = divmod(j, per)
            if i == 0:
                return dict(self.cols[p])
            d1, d2 = self.zones[i - 1]
            out = {r: d1 * v for r, v in colT1[p].items()}
            for r, v in colT2[p].items():
                out[r] = out.get(r, Fraction(0)) + d2 * v
            return out

        room = np.zeros(ncol, bool)
        room[:-1] = np.arange(ncol - 1) % per != 0  # the zonotope's bounds were shrunk
        room[-1] = True
        x = rebuild(column, ncol, answer, limits, [-v for v in self.f0], room)
        if x is None:
            return None
        for p in range(n):
            nu = x[per * p + 1:per * (p + 1)]
            t1 = sum((d[0] * v for d, v in zip(self.zones, nu)), Fraction(0))
            t2 = sum((d[1] * v for d, v in zip(self.zones, nu)), Fraction(0))
            if x[per * p] > 0 or t1 * t1 + t2 * t2 > c[p] * c[p]:
                return None
        return x[-1]

