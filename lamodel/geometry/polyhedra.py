"""Closed polyhedral blocks: built from vertices (convex hull) or vertices and faces, checked,
with their volume, centroid and planar **facets** (coplanar faces merged, as the contact
search needs them: a triangulated mesh face of a cube is one square facet).

Checks raise a one-line :class:`InputError` naming the block: too few or non-finite
vertices, bad face indices, non-planar or self-intersecting faces, an open or inconsistently
oriented surface, faces pointing inward, zero volume, a surface that crosses itself.
All tolerances are lengths given by the caller (relative to the structure's size).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely
from scipy.spatial import ConvexHull, QhullError, cKDTree

from ..errors import InputError
from ..structure3d import tangent_frame


@dataclass
class Facet:
    """A planar piece of a block's surface: all its faces in one plane, merged."""

    normal: np.ndarray     # (3,) outward unit normal
    offset: float          # normal . x on the plane
    origin: np.ndarray     # (3,) origin of the in-plane frame
    e1: np.ndarray         # (3,) in-plane axes, (e1, e2, normal) right-handed
    e2: np.ndarray
    shape: object          # shapely Polygon / MultiPolygon in (e1, e2) coordinates
    lo: np.ndarray         # (3,) bounding box of the facet
    hi: np.ndarray
    warp: float = 0.0      # largest distance of its vertices from its plane (warped CAD faces)

    def to_3d(self, xy) -> np.ndarray:
        """Points (k, 2) of the facet's frame in space (k, 3)."""
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        return self.origin + xy[:, :1] * self.e1 + xy[:, 1:] * self.e2


@dataclass
class Polyhedron:
    """A closed, outward-oriented polyhedral block."""

    id: str
    vertices: np.ndarray   # (k, 3)
    faces: list            # outward-oriented vertex loops
    volume: float
    centroid: np.ndarray
    facets: list = field(default_factory=list)
    convex: bool = True
    warp: float = 0.0      # largest off-plane distance of a warped face split into triangles

    @property
    def lo(self):
        """Lowest corner of the bounding box."""
        return self.vertices.min(axis=0)

    @property
    def hi(self):
        """Highest corner of the bounding box."""
        return self.vertices.max(axis=0)

    def triangles(self) -> np.ndarray:
        """The surface as triangles (t, 3, 3), outward (for volume, pictures, point tests)."""
        return np.concatenate([_face_triangles(self.vertices, f) for f in self.faces])


def _newell(points: np.ndarray) -> np.ndarray:
    """Area vector of a planar loop (Newell's method): its length is the area."""
    nxt = np.roll(points, -1, axis=0)
    return 0.5 * np.cross(points, nxt).sum(axis=0)


def _face_triangles(vertices, face) -> np.ndarray:
    """Triangles of one planar face loop, keeping its orientation (exact for non-convex)."""
    p = vertices[face]
    if len(face) == 3:
        return p[None]
    n = _newell(p)
    n = n / (np.linalg.norm(n) or 1.0)
    e1, e2 = (x[0] for x in tangent_frame(n))
    xy = np.c_[(p - p[0]) @ e1, (p - p[0]) @ e2]
    poly = shapely.Polygon(xy)
    if poly.convex_hull.area - poly.area <= 1e-12 * max(poly.area, 1e-300):
        return np.stack([np.repeat(p[:1], len(p) - 2, axis=0), p[1:-1], p[2:]], axis=1)
    tris = shapely.get_parts(shapely.constrained_delaunay_triangles(poly))
    out = []
    for t in tris:
        c = np.asarray(t.exterior.coords)[:3]
        if (c[1, 0] - c[0, 0]) * (c[2, 1] - c[0, 1]) - (c[1, 1] - c[0, 1]) * (c[2, 0] - c[0, 0]) < 0:
            c = c[::-1]
        out.append(p[0] + c[:, :1] * e1 + c[:, 1:] * e2)
    return np.array(out)


def _convex_polyhedron(bid, v, tol) -> Polyhedron:
    """The convex hull of ``v`` as a Polyhedron, vectorised (the common case: it must be fast)."""
    span = v.max(axis=0) - v.min(axis=0)
    if len(v) < 4 or np.sort(span)[1] <= tol:
        raise InputError(f"block '{bid}': its {len(v)} vertices do not span a solid; "
                         "expected at least 4 vertices not all in one plane")
    try:
        hull = ConvexHull(v)
    except QhullError:
        raise InputError(f"block '{bid}': its vertices are all in one plane (zero volume); "
                         "expected the corners of a solid") from None
    eq = hull.equations
    size = float(np.linalg.norm(span))
    same = (eq[:, :3] @ eq[:, :3].T > 1 - 0.5 * (tol / size) ** 2 - 1e-12) & \
        (np.abs(eq[:, 3:4] - eq[:, 3]) <= tol)
    label = np.argmax(same, axis=1)          # each simplex joins the first of its plane
    groups = np.unique(label)
    normal = np.array([eq[label == g, :3].mean(axis=0) for g in groups])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    e1, e2 = tangent_frame(normal)
    used = np.unique(hull.simplices)
    remap = -np.ones(len(v), dtype=int)
    remap[used] = np.arange(len(used))
    faces, coords, index, facets_pts = [], [], [], []
    for k, g in enumerate(groups):
        ids = np.unique(hull.simplices[label == g])
        p = v[ids]
        xy = np.c_[p @ e1[k], p @ e2[k]]
        c = xy.mean(axis=0)
        order = np.argsort(np.arctan2(xy[:, 1] - c[1], xy[:, 0] - c[0]))
        faces.append(remap[ids[order]].tolist())
        coords.append(xy[order] - (p[order[0]] @ e1[k], p[order[0]] @ e2[k]))
        index.append(np.full(len(ids), k))
        facets_pts.append(p[order])
    shapes = shapely.polygons(shapely.linearrings(np.vstack(coords), indices=np.concatenate(index)))
    v = v[used]
    facets = []
    for k, pts in enumerate(facets_pts):
        off = float(np.mean(pts @ normal[k]))
        facets.append(Facet(normal[k], off, pts[0], e1[k], e2[k], shapes[k], pts.min(axis=0), pts.max(axis=0)))
    tris = np.array([[v[f[0]], v[f[i]], v[f[i + 1]]] for f in faces for i in range(1, len(f) - 1)])
    vol, centroid = _volume_centroid(tris)
    if vol <= tol * size * size:
        raise InputError(f"block '{bid}': it has zero volume; expected a solid block")
    return Polyhedron(bid, v, faces, vol, np.asarray(centroid), facets, True, 0.0)


def _split_face(vertices, face) -> list:
    """Index triangles of a (non-planar) face loop, triangulated in its mean plane."""
    p = vertices[face]
    n = _newell(p)
    e1, e2 = (x[0] for x in tangent_frame(n / (np.linalg.norm(n) or 1.0)))
    xy = np.c_[p @ e1, p @ e2]
    poly = shapely.Polygon(xy)
    if poly.convex_hull.area - poly.area <= 1e-12 * max(poly.area, 1e-300) or not poly.is_valid:
        return [[face[0], face[k], face[k + 1]] for k in range(1, len(face) - 1)]
    where = {tuple(c): i for c, i in zip(np.round(xy, 12), face)}
    out = []
    for t in shapely.get_parts(shapely.constrained_delaunay_triangles(poly)):
        c = np.round(np.asarray(t.exterior.coords)[:3], 12)
        tri = [where[tuple(x)] for x in c]
        if (c[1, 0] - c[0, 0]) * (c[2, 1] - c[0, 1]) - (c[1, 1] - c[0, 1]) * (c[2, 0] - c[0, 0]) < 0:
            tri = tri[::-1]
        out.append(tri)
    return out


def _check_faces(bid, vertices, faces, tol, split_nonplanar=False):
    """Face indices, planarity and simplicity of each face, closed and consistently oriented.

    ``split_nonplanar``: a non-planar face is split into triangles instead of refused
    (curved surfaces of CAD models approximated by warped polygons)."""
    where = f"block '{bid}'"
    n = len(vertices)
    out, loops, warp = [], [], 0.0
    for k, face in enumerate(faces):
        if (not isinstance(face, (list, tuple, np.ndarray)) or len(face) < 3
                or not all(isinstance(i, (int, np.integer)) and not isinstance(i, bool) for i in face)):
            raise InputError(f"{where}: face {k} is {str(face)[:40]}; expected a list of at least 3 vertex indices")
        face = [int(i) for i in face]
        if min(face) < 0 or max(face) >= n:
            raise InputError(f"{where}: face {k} names vertex {max(face) if max(face) >= n else min(face)}; "
                             f"expected indices 0 .. {n - 1}")
        if len(set(face)) != len(face):
            raise InputError(f"{where}: face {k} repeats a vertex; expected a simple loop of distinct vertices")
        p = vertices[face]
        area = _newell(p)
        norm = np.linalg.norm(area)
        if norm <= tol * tol:
            raise InputError(f"{where}: face {k} has zero area; expected a non-degenerate face")
        nrm = area / norm
        dist = np.abs((p - p.mean(axis=0)) @ nrm).max()
        if dist > tol and split_nonplanar:
            out.extend(_split_face(vertices, face))
            loops.append(face)
            warp = max(warp, dist)
            continue
        if dist > tol:
            raise InputError(f"{where}: face {k} is not planar (a vertex lies {dist:.3g} off its plane); "
                             "expected planar faces")
        if len(face) > 3:
            e1, e2 = (x[0] for x in tangent_frame(nrm))
            if not shapely.LinearRing(np.c_[p @ e1, p @ e2]).is_simple:
                raise InputError(f"{where}: face {k} crosses itself; expected a simple polygon")
        out.append(face)
        loops.append(face)
    edges = {}
    for k, face in enumerate(out):
        for i, j in zip(face, face[1:] + face[:1]):
            if (i, j) in edges:
                raise InputError(f"{where}: edge {i}-{j} is used twice in the same direction (faces {edges[(i, j)]} "
                                 f"and {k}); expected consistently oriented faces")
            edges[(i, j)] = k
    for (i, j), k in edges.items():
        if (j, i) not in edges:
            raise InputError(f"{where}: the surface is open at edge {i}-{j} (face {k} has no neighbour there); "
                             "expected a closed surface")
    return out, loops, warp


def _volume_centroid(triangles):
    """Signed volume and centroid of a closed triangulated surface (tetrahedra to the origin)."""
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    v = np.einsum("ij,ij->i", a, np.cross(b, c)) / 6.0
    vol = v.sum()
    if abs(vol) <= 0:
        return 0.0, triangles.reshape(-1, 3).mean(axis=0)
    return float(vol), (v[:, None] * (a + b + c)).sum(axis=0) / (4.0 * vol)


def _self_intersecting(triangles, faces_of_tri, tri_vertex_ids, tol) -> bool:
    """True when an edge of a triangle crosses another triangle sharing no vertex with it."""
    t = len(triangles)
    if t < 8:
        return False
    centre = triangles.mean(axis=1)
    radius = np.linalg.norm(triangles - centre[:, None], axis=2).max()
    pairs = cKDTree(centre).query_pairs(2 * radius + tol, output_type="ndarray")
    if not len(pairs):
        return False
    i, j = pairs[:, 0], pairs[:, 1]
    ids = tri_vertex_ids
    share = (ids[i][:, :, None] == ids[j][:, None, :]).any(axis=(1, 2)) | (faces_of_tri[i] == faces_of_tri[j])
    i, j = i[~share], j[~share]
    for p, q in ((i, j), (j, i)):
        tri = triangles[q]
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        for e in range(3):
            s0, s1 = triangles[p, e], triangles[p, (e + 1) % 3]
            d0 = np.einsum("ij,ij->i", s0 - tri[:, 0], n)
            d1 = np.einsum("ij,ij->i", s1 - tri[:, 0], n)
            scale = np.linalg.norm(n, axis=1) * tol
            cross = (d0 * d1 < 0) & (np.abs(d0) > scale) & (np.abs(d1) > scale)
            if not cross.any():
                continue
            k = np.flatnonzero(cross)
            x = s0[k] + (d0[k] / (d0[k] - d1[k]))[:, None] * (s1[k] - s0[k])
            a, b, c = tri[k, 0], tri[k, 1], tri[k, 2]
            nk = n[k]
            inside = np.ones(len(k), dtype=bool)
            for u, v in ((a, b), (b, c), (c, a)):
                inside &= np.einsum("ij,ij->i", np.cross(v - u, x - u), nk) > (np.linalg.norm(nk, axis=1) * tol
                                                                               * np.linalg.norm(v - u, axis=1))
            if inside.any():
                return True
    return False


def _merge(polys, tol, convex):
    """One shape from the faces of a facet: their convex hull on a convex block (exact),
    else their union with cracks narrower than ``tol`` closed (mitred, corners kept)."""
    if convex:
        return shapely.convex_hull(shapely.MultiPolygon(polys))
    shape = shapely.union_all(polys)
    if shape.geom_type != "Polygon" or len(shape.interiors):
        join = shapely.BufferJoinStyle.mitre
        shape = shape.buffer(tol, join_style=join).buffer(-tol, join_style=join)
    return shape


def _facets(vertices, faces, tol, convex=False) -> list:
    """Merge coplanar faces (normal and offset equal within the tolerance) into facets."""
    normals, offsets = [], []
    for face in faces:
        a = _newell(vertices[face])
        n = a / np.linalg.norm(a)
        normals.append(n)
        offsets.append(float(vertices[face].mean(axis=0) @ n))
    normals, offsets = np.array(normals), np.array(offsets)
    size = float(np.linalg.norm(vertices.max(axis=0) - vertices.min(axis=0))) or 1.0
    groups, label = [], -np.ones(len(faces), dtype=int)
    for k in range(len(faces)):
        if label[k] >= 0:
            continue
        same = (label < 0) & (normals @ normals[k] > 1 - 0.5 * (tol / size) ** 2 - 1e-12) \
            & (np.abs(offsets - offsets[k]) <= tol)
        label[same] = len(groups)
        groups.append(np.flatnonzero(same))
    out = []
    for g in groups:
        n = normals[g].sum(axis=0)
        n /= np.linalg.norm(n)
        pts = vertices[sorted({i for k in g for i in faces[k]})]
        origin = pts[0]
        e1, e2 = (x[0] for x in tangent_frame(n))
        polys = [shapely.Polygon(np.c_[(vertices[faces[k]] - origin) @ e1, (vertices[faces[k]] - origin) @ e2])
                 for k in g]
        shape = polys[0] if len(polys) == 1 else _merge(polys, tol, convex)
        shape = shapely.simplify(shape, tol * 0.5)
        off = float(np.mean(pts @ n))
        out.append(Facet(n, off, origin, e1, e2, shape, pts.min(axis=0), pts.max(axis=0),
                         float(np.abs(pts @ n - off).max())))
    return out


def polyhedron(block_id, vertices, faces=None, tol: float = 1e-9, split_nonplanar: bool = False) -> Polyhedron:
    """A checked closed polyhedron: the convex hull of ``vertices`` when ``faces`` is None,
    else the polyhedron of the given outward faces (non-convex allowed).

    ``tol`` is a length (points closer than it coincide); ``split_nonplanar`` splits warped
    faces into triangles instead of refusing them. Raises InputError naming the block.
    """
    bid = str(block_id)
    try:
        v = np.asarray(vertices, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"block '{bid}': 'vertices' is not a list of [x, y, z] points; expected numbers") from None
    if v.ndim != 2 or v.shape[1] != 3:
        raise InputError(f"block '{bid}': 'vertices' is not a list of [x, y, z] points; expected 3 coordinates each")
    if not np.isfinite(v).all():
        raise InputError(f"block '{bid}': a vertex coordinate is not a finite number; expected finite numbers")
    if faces is None:
        return _convex_polyhedron(bid, v, tol)
    else:
        if not isinstance(faces, (list, tuple)) or len(faces) < 4:
            raise InputError(f"block '{bid}': 'faces' is not a list of at least 4 faces; expected vertex index loops")
        faces, loops, warp = _check_faces(bid, v, faces, tol, split_nonplanar)
        convex = None
    tri_list = [_face_triangles(v, f) for f in faces]
    tris = np.concatenate(tri_list)
    vol, centroid = _volume_centroid(tris)
    span = float(np.linalg.norm(v.max(axis=0) - v.min(axis=0)))
    if vol <= tol * span * span:
        if vol < -tol * span * span:
            raise InputError(f"block '{bid}': its faces point inward (volume {vol:.6g}); expected faces ordered "
                             "counter-clockwise seen from outside")
        raise InputError(f"block '{bid}': it has zero volume; expected a solid block")
    facets = _facets(v, loops, tol, convex=bool(convex))
    if convex is None:
        d = np.array([[f.offset for f in facets]]) - v @ np.array([f.normal for f in facets]).T
        convex = bool((d >= -tol).all())
        if not convex:
            face_of = np.repeat(np.arange(len(faces)), [len(t) for t in tri_list])
            ids = _triangle_vertex_ids(v, tris)
            if _self_intersecting(tris, face_of, ids, tol + warp):  # crossings within the warp: its triangulation
                raise InputError(f"block '{bid}': its surface crosses itself; expected a simple closed surface")
    return Polyhedron(bid, v, faces, vol, np.asarray(centroid), facets, convex, warp)


def _triangle_vertex_ids(vertices, tris) -> np.ndarray:
    """Index of each triangle corner among ``vertices`` (corners are vertices, exactly)."""
    tree = cKDTree(vertices)
    _, idx = tree.query(tris.reshape(-1, 3))
    return idx.reshape(-1, 3)


def winding_number(triangles: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Generalised winding number of closed outward surface ``triangles`` at ``points``:
    1 inside, 0 outside (solid angles, Van Oosterom & Strackee)."""
    a = triangles[None, :, 0] - points[:, None]
    b = triangles[None, :, 1] - points[:, None]
    c = triangles[None, :, 2] - points[:, None]
    la, lb, lc = (np.linalg.norm(x, axis=2) for x in (a, b, c))
    num = np.einsum("pti,pti->pt", a, np.cross(b, c))
    den = la * lb * lc + np.einsum("pti,pti->pt", a, b) * lc + np.einsum("pti,pti->pt", b, c) * la \
        + np.einsum("pti,pti->pt", c, a) * lb
    return np.arctan2(num, den).sum(axis=1) / (2 * np.pi)


def surface_distance(triangles: np.ndarray, point) -> float:
    """Least distance from ``point`` to the triangles (t, 3, 3) of a surface (Ericson,
    *Real-Time Collision Detection* 5.1.5: the nearest point of each triangle)."""
    p = np.asarray(point, dtype=float)
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    ab, ac, ap = b - a, c - a, p - a
    dot = lambda u, v: np.einsum("ij,ij->i", u, v)  # noqa: E731
    d1, d2 = dot(ab, ap), dot(ac, ap)
    bp, cp = p - b, p - c
    d3, d4, d5, d6 = dot(ab, bp), dot(ac, bp), dot(ab, cp), dot(ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = va + vb + vc
        v, w = vb / denom, vc / denom
        q = a + ab * v[:, None] + ac * w[:, None]                       # inside the face
        t_ab, t_ac = d1 / (d1 - d3), d2 / (d2 - d6)
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
    edges = [(vc <= 0) & (d1 >= 0) & (d3 <= 0), a + ab * t_ab[:, None],  # on edge ab
             (vb <= 0) & (d2 >= 0) & (d6 <= 0), a + ac * t_ac[:, None],  # on edge ac
             (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0), b + (c - b) * t_bc[:, None]]  # on edge bc
    for mask, at in reversed(list(zip(edges[::2], edges[1::2]))):
        q = np.where(mask[:, None], at, q)
    for mask, at in (((d6 >= 0) & (d5 <= d6), c), ((d3 >= 0) & (d4 <= d3), b), ((d1 <= 0) & (d2 <= 0), a)):
        q = np.where(mask[:, None], at, q)                               # a corner, last: it wins
    return float(np.nanmin(np.linalg.norm(q - p, axis=1)))
