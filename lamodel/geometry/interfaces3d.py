"""Contacts between polyhedral blocks: interfaces (planar polygons) and their contact points.

Two bodies touch where a facet of one and a facet of the other have opposite outward
normals, lie in one plane (within the tolerance, a length relative to the structure's
size) and overlap over a positive area; the **interface polygon** is their intersection in
that plane (shapely). A pair of non-convex blocks may touch on several facets, and one
facet pair may give several polygons: each polygon is one interface.

The search is near-linear in the number of blocks: a KD-tree over the blocks' bounding-box
centres proposes pairs (blocks much larger than the median, such as a ground slab, are
tested against every block with a vectorised box test); facet pairs of proposed block pairs
are filtered by normals, planes and boxes with numpy; shapely intersects the survivors
in one vectorised call. Bodies whose interiors overlap are an error naming both.

Orientation (the ``a -> b`` normal of :class:`lamodel.structure3d.Structure3D`): a support
is always body a; between two blocks, a is the body below (normal with n_z > 0), else the
body on the -x side, else on the -y side. Interfaces are ordered by the positions of their
two bodies in the input (smaller first), then by the polygon's centroid.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..errors import InputError
from .polyhedra import winding_number


@dataclass
class Interface:
    """One planar contact polygon between bodies ``a`` and ``b`` (indices into the bodies)."""

    a: int
    b: int
    normal: np.ndarray      # (3,) unit, from a to b
    polygon: np.ndarray     # (k, 3) exterior, counter-clockwise about the normal
    holes: list             # [(m, 3)] interior rings, if any
    area: float
    shape: object           # the polygon in its plane frame (origin, e1, e2)
    frame: tuple


# ------------------------------------------------------------------------- broad phase
def candidate_pairs(lo: np.ndarray, hi: np.ndarray, tol: float) -> np.ndarray:
    """Pairs (i < j) of bodies whose bounding boxes touch or overlap (within ``tol``)."""
    n = len(lo)
    if n < 2:
        return np.zeros((0, 2), dtype=int)
    centre, half = (lo + hi) / 2, np.linalg.norm(hi - lo, axis=1) / 2
    big = half > 4 * np.median(half)
    small = np.flatnonzero(~big)
    pairs = []
    if len(small) > 1:
        r = 2 * half[small].max() + 2 * tol
        p = cKDTree(centre[small]).query_pairs(r, output_type="ndarray")
        pairs.append(small[p])
    for i in np.flatnonzero(big):
        others = np.arange(n)
        others = others[(others != i) & ~(big & (others < i))]
        pairs.append(np.c_[np.full(len(others), i), others])
    pairs = np.concatenate(pairs) if pairs else np.zeros((0, 2), dtype=int)
    pairs = np.sort(pairs, axis=1)
    touch = ((lo[pairs[:, 0]] <= hi[pairs[:, 1]] + tol) & (lo[pairs[:, 1]] <= hi[pairs[:, 0]] + tol)).all(axis=1)
    return np.unique(pairs[touch], axis=0)


# ------------------------------------------------------------------------ narrow phase
def _facet_table(polys):
    facets = [f for p in polys for f in p.facets]
    count = np.array([len(p.facets) for p in polys])
    start = np.concatenate([[0], np.cumsum(count)[:-1]])
    t = {
        "block": np.repeat(np.arange(len(polys)), count),
        "normal": np.array([f.normal for f in facets]),
        "origin": np.array([f.origin for f in facets]),
        "e1": np.array([f.e1 for f in facets]),
        "e2": np.array([f.e2 for f in facets]),
        "lo": np.array([f.lo for f in facets]),
        "hi": np.array([f.hi for f in facets]),
        "shape": np.array([f.shape for f in facets], dtype=object),
        "warp": np.array([f.warp for f in facets]),
    }
    t["extent"] = np.linalg.norm(t["hi"] - t["lo"], axis=1)
    return t, start, count


def _facet_pairs(pairs, start, count):
    """All (facet of i, facet of j) for the block pairs (i, j), vectorised."""
    i, j = pairs[:, 0], pairs[:, 1]
    rows = count[i] * count[j]
    first = np.cumsum(rows) - rows  # also when no two bodies' boxes meet (rows empty)
    k = np.arange(rows.sum()) - np.repeat(first, rows)
    nj = np.repeat(count[j], rows)
    return np.repeat(start[i], rows) + k // nj, np.repeat(start[j], rows) + k % nj


def _to_frame(t, fa, fb):
    """Facet b's shapes in facet a's plane frame (2D affine maps applied in one call)."""
    m = np.stack([np.stack([np.einsum("ij,ij->i", t["e1"][fb], t["e1"][fa]),
                            np.einsum("ij,ij->i", t["e2"][fb], t["e1"][fa])], axis=1),
                  np.stack([np.einsum("ij,ij->i", t["e1"][fb], t["e2"][fa]),
                            np.einsum("ij,ij->i", t["e2"][fb], t["e2"][fa])], axis=1)], axis=1)
    d = t["origin"][fb] - t["origin"][fa]
    off = np.c_[np.einsum("ij,ij->i", d, t["e1"][fa]), np.einsum("ij,ij->i", d, t["e2"][fa])]
    shapes = t["shape"][fb]
    which = np.repeat(np.arange(len(fb)), shapely.get_num_coordinates(shapes))

    def affine(xy):
        return np.einsum("kij,kj->ki", m[which], xy) + off[which]

    return shapely.transform(shapes, affine)


def _orientation_swap(normal, a_support, b_support):
    """True when the pair must be swapped so that a is the support, or below, or at -x, -y."""
    if a_support != b_support:
        return b_support
    for c in (2, 0, 1):
        if abs(normal[c]) > 1e-9:
            return normal[c] < 0
    return False


def find_interfaces(polys, is_support, tol: float, skip=None) -> list:
    """All interfaces of the bodies ``polys`` (list of Polyhedron); ``is_support`` per body;
    ``skip``: body pairs (i, j) to leave out (e.g. pairs already joined at a finer tolerance).

    Raises InputError when two bodies overlap (interiors intersect by more than ``tol``).
    """
    is_support = np.asarray(is_support, dtype=bool)
    lo = np.array([p.lo for p in polys])
    hi = np.array([p.hi for p in polys])
    pairs = candidate_pairs(lo, hi, tol)
    pairs = pairs[~(is_support[pairs[:, 0]] & is_support[pairs[:, 1]])]
    if skip is not None and len(skip) and len(pairs):
        n = len(polys)
        skip = np.sort(np.asarray(skip, dtype=int).reshape(-1, 2), axis=1)
        pairs = pairs[~np.isin(pairs[:, 0] * n + pairs[:, 1], skip[:, 0] * n + skip[:, 1])]
    check_overlaps(polys, pairs, lo, hi, tol)
    t, start, count = _facet_table(polys)
    fa, fb = _facet_pairs(pairs, start, count)
    na, nb = t["normal"][fa], t["normal"][fb]
    ext = np.minimum(t["extent"][fa], t["extent"][fb])
    gap = tol + t["warp"][fa] + t["warp"][fb]   # warped faces (CAD) meet within their warp
    ok = 1 + np.einsum("ij,ij->i", na, nb) <= 0.5 * (2 * gap / np.maximum(ext, tol)) ** 2 + 1e-15
    overlap = np.minimum(t["hi"][fa], t["hi"][fb]) - np.maximum(t["lo"][fa], t["lo"][fb])
    ok &= (overlap >= -tol).all(axis=1) & ((overlap > tol).sum(axis=1) >= 2)   # an area, not an edge
    # the planes' separation where the facets overlap (the centre of the boxes' overlap;
    # origins are vertices on, or warped, near the planes): measured at the origins, facets
    # of warped faces tilted by 1-3 degrees (compas_cra's Armadillo: 19 of its 1,014 joints)
    # were apart by the tilt times the origins' distance; coplanar facets are as before
    p = (np.maximum(t["lo"][fa], t["lo"][fb]) + np.minimum(t["hi"][fa], t["hi"][fb])) / 2
    sep = np.einsum("ij,ij->i", p - t["origin"][fa], na) + np.einsum("ij,ij->i", p - t["origin"][fb], nb)
    ok &= np.abs(sep) <= gap
    fa, fb = fa[ok], fb[ok]
    if not len(fa):
        return []
    sa, sb = t["shape"][fa], _to_frame(t, fa, fb)
    inter = shapely.intersection(sa, sb)
    # exact overlay of nearly identical polygons can fail in GEOS (a square and its rotated
    # copy gave two points): pairs without an area are redone snap-rounded on a binary grid
    # finer than the tolerance
    redo = np.flatnonzero(shapely.area(inter) <= tol * shapely.length(inter))
    if len(redo) and tol > 0:
        grid = 2.0 ** math.floor(math.log2(tol / 8))
        inter[redo] = shapely.intersection(sa[redo], sb[redo], grid_size=grid)
    parts, idx = shapely.get_parts(inter, return_index=True)
    area = shapely.area(parts)
    keep = (shapely.get_type_id(parts) == 3) & (area > tol * shapely.length(parts)) & (area > 0)
    parts, idx = shapely.orient_polygons(shapely.simplify(parts[keep], tol / 2)), idx[keep]
    keep = (shapely.get_type_id(parts) == 3) & ~shapely.is_empty(parts)
    parts, idx = parts[keep], idx[keep]
    if not len(parts):   # every overlap thinner than the tolerance
        return []
    f_a, f_b = fa[idx], fb[idx]
    # every exterior ring in space at once (rings are closed: the last point repeats the first)
    xy, ring = shapely.get_coordinates(shapely.get_exterior_ring(parts), return_index=True)
    last = np.r_[ring[1:] != ring[:-1], True]
    xy, ring = xy[~last], ring[~last]
    o, e1, e2 = t["origin"][f_a], t["e1"][f_a], t["e2"][f_a]
    xyz = o[ring] + xy[:, :1] * e1[ring] + xy[:, 1:] * e2[ring]
    cut = np.flatnonzero(np.r_[True, ring[1:] != ring[:-1]])
    rings = np.split(xyz, cut[1:])
    a_all, b_all = t["block"][f_a].astype(int), t["block"][f_b].astype(int)
    holes_of = shapely.get_num_interior_rings(parts)
    out = []
    for k, g in enumerate(parts):
        a, b, n = int(a_all[k]), int(b_all[k]), t["normal"][f_a[k]].copy()
        frame = (o[k], e1[k], e2[k])
        ext_ring = rings[k]
        holes = [frame[0] + c[:-1, :1] * frame[1] + c[:-1, 1:] * frame[2]
                 for c in (np.asarray(r.coords) for r in g.interiors)] if holes_of[k] else []
        if _orientation_swap(n, is_support[a], is_support[b]):
            a, b, n = b, a, -n
            ext_ring, holes = ext_ring[::-1], [h[::-1] for h in holes]
        out.append(Interface(a, b, n, ext_ring, holes, float(g.area), g, frame))
    centre = np.array([f.polygon.mean(axis=0) for f in out]).reshape(-1, 3)
    key = np.round(centre / max(tol, 1e-300))
    order = np.lexsort((key[:, 2], key[:, 1], key[:, 0], [max(f.a, f.b) for f in out], [min(f.a, f.b) for f in out]))
    return [out[i] for i in order]


# ------------------------------------------------------------------------------ overlaps
def _hull_normals(p):
    from scipy.spatial import ConvexHull
    if p.convex:
        return np.array([f.normal for f in p.facets])
    eq = ConvexHull(p.vertices).equations[:, :3]
    return np.unique(np.round(eq, 12), axis=0)


def _separated(va, vb, axes, tol) -> bool:
    """Some axis separates the vertex sets (a gap, or a touch within ``tol``)."""
    axes = axes[np.linalg.norm(axes, axis=1) > 1e-12]
    if not len(axes):
        return False
    axes = axes / np.linalg.norm(axes, axis=1, keepdims=True)
    pa, pb = va @ axes.T, vb @ axes.T
    return bool(((pa.max(axis=0) <= pb.min(axis=0) + tol) | (pb.max(axis=0) <= pa.min(axis=0) + tol)).any())


def _edges(p):
    e = {tuple(sorted((f[i], f[(i + 1) % len(f)]))) for f in p.faces for i in range(len(f))}
    d = np.array([p.vertices[j] - p.vertices[i] for i, j in e])
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return np.unique(np.round(d * np.sign(d[:, :1] + 1e-300), 9), axis=0)


def _overlap(pa, pb, tol) -> bool:
    axes = np.vstack([_hull_normals(pa), _hull_normals(pb)])
    if _separated(pa.vertices, pb.vertices, axes, tol):
        return False
    if pa.convex and pb.convex:
        ea, eb = _edges(pa), _edges(pb)
        cross = np.cross(ea[:, None], eb[None]).reshape(-1, 3)
        return not _separated(pa.vertices, pb.vertices, cross, tol)
    for p, q in ((pa, pb), (pb, pa)):
        tri = p.triangles()
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        inner = tri.mean(axis=1) - 4 * tol * n   # just below p's surface: inside p
        near = ((inner >= q.lo - tol) & (inner <= q.hi + tol)).all(axis=1)
        if near.any() and (winding_number(q.triangles(), inner[near]) > 0.5).any():
            return True
    return False


def check_overlaps(polys, pairs, lo, hi, tol):
    """InputError naming the first two bodies whose interiors intersect."""
    depth = np.minimum(hi[pairs[:, 0]], hi[pairs[:, 1]]) - np.maximum(lo[pairs[:, 0]], lo[pairs[:, 1]])
    for i, j in pairs[(depth > tol).all(axis=1)]:
        # warped faces split into triangles may cross their neighbour's by the warp
        if _overlap(polys[i], polys[j], tol + polys[i].warp + polys[j].warp):
            raise InputError(f"blocks '{polys[i].id}' and '{polys[j].id}' overlap (their interiors intersect); "
                             "expected blocks that touch without interpenetrating")


# ---------------------------------------------------------------------- contact points
#: The most interior points a side of ``grid:n`` (n^2 points a joint): past it the cone
#: programs' size, not the stress block's accuracy, grows (grid:100000 asked 149 GiB).
GRID_MAX = 64
#: What ``contact_points`` may be, in the messages that refuse another value.
CONTACT_POINTS = f'"vertices" or "grid:n" with a whole n from 1 to {GRID_MAX}'


def parse_contact_points(mode) -> int:
    """0 for ``"vertices"`` (the default), n for ``"grid:n"`` (n >= 1); InputError otherwise."""
    if mode in (None, "vertices"):
        return 0
    if isinstance(mode, str) and mode.startswith("grid:"):
        try:
            n = int(mode[5:])
        except ValueError:
            n = 0
        if 1 <= n <= GRID_MAX:
            return n
    raise InputError(f"'contact_points' is {mode!r}; expected {CONTACT_POINTS}")


def interface_points(f: Interface, grid: int = 0) -> np.ndarray:
    """Contact points of an interface: its polygon's vertices (and holes' vertices), plus,
    with ``grid = n``, the centres of an n x n grid over the polygon's smallest enclosing
    rectangle that fall inside the polygon."""
    pts = [f.polygon] + list(f.holes)
    if grid:
        rect = np.asarray(shapely.minimum_rotated_rectangle(f.shape).exterior.coords)[:4]
        u, v = rect[1] - rect[0], rect[3] - rect[0]
        s = (np.arange(grid) + 0.5) / grid
        xy = rect[0] + s[:, None, None] * u + s[None, :, None] * v
        xy = xy.reshape(-1, 2)
        xy = xy[shapely.contains_xy(f.shape, xy[:, 0], xy[:, 1])]
        o, e1, e2 = f.frame
        pts.append(o + xy[:, :1] * e1 + xy[:, 1:] * e2)
    return np.vstack(pts)
