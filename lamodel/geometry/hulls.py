"""Convex blocks in bulk: the convex hulls of many small vertex sets at once (numpy).

Blocks given by their corners (no faces) are the common case, and a building has
thousands of them, so their hulls are found together, grouped by number of corners: every
facet plane of a hull passes through three of its corners and has all corners on one side.
Blocks this cannot settle (more than ``MAX_CORNERS`` corners, repeated corners, no
volume) are left to :func:`lamodel.geometry.polyhedra.polyhedron`, which reports errors.
"""
from __future__ import annotations

from itertools import combinations

import numpy as np
import shapely

from ..structure3d import tangent_frame
from .polyhedra import Facet, Polyhedron

MAX_CORNERS = 12


def _group(ids, P, tol):
    """Polyhedra (or None) for B blocks of k corners each, P (B, k, 3)."""
    B, k, _ = P.shape
    centre = P.mean(axis=1, keepdims=True)
    Q = P - centre                                   # centred: better rounding
    size = np.linalg.norm(Q.max(axis=1) - Q.min(axis=1), axis=1)
    ok_block = size > 0
    gap = np.linalg.norm(Q[:, :, None] - Q[:, None], axis=3) + np.eye(k) * 1e300
    ok_block &= gap.min(axis=(1, 2)) > tol           # repeated corners: the general path
    T = np.array(list(combinations(range(k), 3)))
    a, b, c = Q[:, T[:, 0]], Q[:, T[:, 1]], Q[:, T[:, 2]]
    n = np.cross(b - a, c - a)                       # (B, m, 3)
    norm = np.linalg.norm(n, axis=2)
    good = norm > 1e-9 * size[:, None] ** 2
    n = n / np.where(good, norm, 1.0)[..., None]
    d = np.einsum("bki,bmi->bmk", Q, n) - np.einsum("bmi,bmi->bm", a, n)[..., None]
    out, inn = (d <= tol).all(axis=2), (d >= -tol).all(axis=2)
    flip = inn & ~out
    n[flip] *= -1
    on = np.abs(d) <= tol
    good &= (out | inn) & (on.sum(axis=2) >= 3)
    code = (on * (1 << np.arange(k))).sum(axis=2) + (np.arange(B)[:, None] << k)
    _, first = np.unique(np.where(good, code, -1), return_index=True)
    bi, mi = np.unravel_index(first, good.shape)
    keep = good[bi, mi]
    bi, mi = bi[keep], mi[keep]
    normal = n[bi, mi]                                # (F, 3)
    member = on[bi, mi]                               # (F, k)
    e1, e2 = tangent_frame(normal)
    xy = np.stack([np.einsum("fki,fi->fk", Q[bi], e1), np.einsum("fki,fi->fk", Q[bi], e2)], axis=2)
    cnt = member.sum(axis=1)
    mid = (xy * member[..., None]).sum(axis=1) / cnt[:, None]
    ang = np.where(member, np.arctan2(xy[..., 1] - mid[:, None, 1], xy[..., 0] - mid[:, None, 0]), np.inf)
    order = np.argsort(ang, axis=1)                   # members first, counter-clockwise about n
    # volume and centroid: fans of the facets, tetrahedra to the block's centre
    vol6 = np.zeros(B)
    mom = np.zeros((B, 3))
    rows = np.arange(len(bi))
    p0 = Q[bi, order[:, 0]]
    for j in range(1, k - 1):
        live = j + 1 < cnt
        pj, pk = Q[bi, order[:, j]], Q[bi, order[:, np.minimum(j + 1, k - 1)]]
        v6 = np.where(live, np.einsum("fi,fi->f", p0, np.cross(pj, pk)), 0.0)
        np.add.at(vol6, bi, v6)
        np.add.at(mom, bi, v6[:, None] * (p0 + pj + pk) / 4)
    volume = vol6 / 6
    ok_block &= volume > tol * size ** 2
    # facet polygons (origin: the first corner in order), all in one shapely call
    flat_f = np.repeat(rows, cnt)
    flat_j = np.concatenate([order[f, :cnt[f]] for f in rows]) if len(rows) else np.zeros(0, dtype=int)
    origin_xy = xy[rows, order[:, 0]]
    coords = xy[flat_f, flat_j] - origin_xy[flat_f]
    shapes = shapely.polygons(shapely.linearrings(coords, indices=flat_f))
    out_list = [None] * B
    facets = [[] for _ in range(B)]
    faces = [[] for _ in range(B)]
    start = np.concatenate([[0], np.cumsum(cnt)])
    corners = P[bi]                                                   # (F, k, 3)
    offset = (np.einsum("fki,fi->fk", corners, normal) * member).sum(axis=1) / cnt
    lo = np.where(member[..., None], corners, np.inf).min(axis=1)
    hi = np.where(member[..., None], corners, -np.inf).max(axis=1)
    origin = corners[rows, order[:, 0]]
    loops = np.split(flat_j, start[1:-1])
    for f in rows:
        blk = bi[f]
        faces[blk].append(loops[f].tolist())
        facets[blk].append(Facet(normal[f], float(offset[f]), origin[f], e1[f], e2[f], shapes[f], lo[f], hi[f]))
    for i in np.flatnonzero(ok_block):
        cen = centre[i, 0] + mom[i] / vol6[i]
        out_list[i] = Polyhedron(ids[i], P[i], faces[i], float(volume[i]), cen, facets[i], True, 0.0)
    return out_list


def convex_polyhedra(ids, vertex_sets, tol: float) -> list:
    """Convex hulls of the vertex sets (arrays (k, 3)) as Polyhedra, in bulk; None for a
    block left to the general path (too many corners, repeated corners, no volume)."""
    out = [None] * len(ids)
    by_k = {}
    for i, v in enumerate(vertex_sets):
        v = np.asarray(v, dtype=float)
        if v.ndim == 2 and v.shape[1] == 3 and 4 <= len(v) <= MAX_CORNERS and np.isfinite(v).all():
            by_k.setdefault(len(v), []).append(i)
    for k, members in by_k.items():
        P = np.array([np.asarray(vertex_sets[i], dtype=float) for i in members])
        for i, p in zip(members, _group([str(ids[i]) for i in members], P, tol)):
            out[i] = p
    return out
