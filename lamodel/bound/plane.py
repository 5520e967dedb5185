"""A sharper node bound: two contacts' normal forces as a polygon, not a box corner.

The rounds bound alpha_coh at the ideal point (every ``-N_k`` at its own minimum). Where
the weakest cohesive mechanism slides on two contacts whose normal forces trade off (two
piers sharing a load: their sum is fixed, either may be small), that corner lies far
below every statics. Here the projection P of the node's statics onto ``(-N_i, -N_j)`` is
enclosed in a polygon Q = {n >= Nmin, w^T n >= beta} whose every side is an LP's exact
dual bound (:meth:`lamodel.bound.exact.ExactData.dual_bound` with weights w >= 0). Then
for every collapse state s in the node

    alpha_s = alpha_coh(-mu N(s)) >= alpha_coh(mu (n_i, n_j, Nmin_rest)) >= min over Q's vertices,

because alpha_coh is nondecreasing (the other contacts stay at their minima) and concave
(a concave function's minimum over a polyhedron that is closed upwards is at a vertex).
Each vertex's alpha_coh is checked like every cohesive bound. Q is refined by cutting off
its lowest vertex with the side through the two statics that support its sides, until
that vertex lies (to 1e-9) in P or BOUND_MAX_CUTS sides are added.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from ..search.tuning import BOUND_MAX_CUTS
from .exact import floor_float



def _vertices(planes):
    """The vertices of {w^T n >= beta for each plane} (all w >= 0, the first two the axes):
    the feasible intersections of two sides, exactly, each with the indices of its sides."""
    out = {}
    for p in range(len(planes)):
        for q in range(p + 1, len(planes)):
            (a0, a1), ba, _ = planes[p]
            (b0, b1), bb, _ = planes[q]
            a0, a1, b0, b1 = (Fraction(x) for x in (a0, a1, b0, b1))
            det = a0 * b1 - a1 * b0
            if det == 0:
                continue
            v = ((ba * b1 - bb * a1) / det, (a0 * bb - b0 * ba) / det)
            if v not in out and all(Fraction(w[0]) * v[0] + Fraction(w[1]) * v[1] >= beta
                                    for w, beta, _ in planes):
                out[v] = (p, q)
    return list(out.items())


def _direction(first, second):
    """The normal (>= 0, summing to 1) of the side through the statics supporting two
    sides; the bisector of the two normals when that is not available or not >= 0."""
    (w1, _, p1), (w2, _, p2) = first, second
    if p1 is not None and p2 is not None:
        w = np.array([p2[1] - p1[1], p1[0] - p2[0]])
        if w.sum() < 0:
            w = -w
        if np.all(w >= 0) and w.sum() > 0:
            return w / w.sum()
    w = np.asarray(w1, float) / np.hypot(*w1) + np.asarray(w2, float) / np.hypot(*w2)
    return w / w.sum()


def pair_bound(search, node, i, j) -> float:
    """A checked lower bound on alpha over the node's collapse states from the polygon of
    contacts i and j (see the module doc); never above what its certificates prove."""
    lps, ex = search.lps, search.exact
    base = [ex.mu[k] * Fraction(float(node.nmin[k])) for k in range(search.nc)]
    values = {}

    def alpha_at(v):
        if v not in values:
            search._check_time()
            c = list(base)
            c[i], c[j] = ex.mu[i] * v[0], ex.mu[j] * v[1]
            cf = np.array([floor_float(x) for x in c])
            ans = lps.cohesive(cf, deadline=search.deadline)
            if ans.status != "optimal":
                values[v] = -math.inf
            elif not ans.value > node.a:
                values[v] = ans.value  # at most a: it proves nothing and claims nothing
            else:
                q = ex.cohesive_bound(ans, lps.cohesive_limits(cf), c, lps.d_shrunk)
                values[v] = -math.inf if q is None else floor_float(q)
        return values[v]

    planes = [((1.0, 0.0), Fraction(float(node.nmin[i])), None), ((0.0, 1.0), Fraction(float(node.nmin[j])), None)]
    for _ in range(BOUND_MAX_CUTS):
        verts = _vertices(planes)
        low, (p, q) = min(((alpha_at(v), sides) for v, sides in verts), key=lambda t: t[0])
        v = next(v for v, sides in verts if sides == (p, q))
        if low > node.b or low == -math.inf:
            return low
        w = _direction(planes[p], planes[q])
        weights = {i: float(w[0]), j: float(w[1])}
        search._check_time()
        ans = lps.normal_force(weights, node.a, node.b, node.lo, node.hi, deadline=search.deadline)
        if ans.status != "optimal":
            return low
        beta = ex.dual_bound(ans.y, weights, node.a, node.b, node.lo, node.hi)
        at_v = Fraction(float(w[0])) * v[0] + Fraction(float(w[1])) * v[1]
        if beta is None or beta <= at_v + Fraction(1, 10 ** 9) * max(1, abs(at_v)):
            return low  # the lowest vertex is (nearly) a statics: the polygon is tight there
        planes.append(((float(w[0]), float(w[1])), beta, (ans.x[i], ans.x[j])))
    return min(alpha_at(v) for v, _ in _vertices(planes))
