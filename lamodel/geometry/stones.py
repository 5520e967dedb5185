"""Walls of irregular stones: a panel cut into convex polygonal stones on a rigid ground.

The stones are the cells of a centroidal Voronoi tessellation of the panel (Lloyd's
relaxation of random seeds: Lloyd, "Least squares quantization in PCM", IEEE Trans.
Information Theory 28, 1982), the usual model of random rubble masonry in limit analysis;
neighbouring cells share whole edges, so every joint is found by the contact search. The
seeds come from ``numpy.random.default_rng(seed)``: the same arguments give the same wall.
"""
from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import MultiPoint, box
from shapely.geometry.polygon import orient

from ..errors import InputError
from .generators import _finish, _rectangle

#: Lloyd steps: the cells' sizes even out within a few steps (more change little)
LLOYD_STEPS = 8
#: vertices closer than this share of the mean stone size are merged into one (Voronoi
#: cells may have edges of round-off length: joints no statics can use)
SHORT_EDGE = 1e-3


def _cells(points, panel):
    """The Voronoi cells of ``points`` clipped to ``panel``, in the points' order."""
    cells = shapely.voronoi_polygons(MultiPoint(points), extend_to=panel)
    found = [None] * len(points)
    for cell in cells.geoms:
        clipped = cell.intersection(panel)
        if clipped.is_empty:
            continue
        k = int(np.argmin(np.hypot(*(np.asarray(points) - np.asarray(clipped.representative_point().coords[0])).T)))
        # the cell holds its own seed: find it by containment, the nearest seed as a fallback
        inside = [i for i, p in enumerate(points) if cell.covers(shapely.Point(p))]
        found[inside[0] if inside else k] = clipped
    return found


def _snapped(cells, size, width, height) -> list:
    """Each cell's counter-clockwise vertices, every cluster of vertices closer than
    :data:`SHORT_EDGE` x ``size`` replaced by one of them (the same for every cell that
    has them: the stones still tile the panel), a vertex on the panel's edge preferred."""
    from scipy.spatial import cKDTree
    rings = [np.asarray(orient(c, 1.0).exterior.coords)[:-1] for c in cells]
    xy = np.vstack(rings)
    parent = np.arange(len(xy))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i
    on_edge = (np.isclose(xy[:, 0], 0.0) | np.isclose(xy[:, 0], width) | np.isclose(xy[:, 1], 0.0)
               | np.isclose(xy[:, 1], height))
    for i, j in sorted(cKDTree(xy).query_pairs(SHORT_EDGE * size)):
        a, b = root(i), root(j)
        if a != b:
            if on_edge[b] and not on_edge[a]:
                a, b = b, a
            parent[b] = a
    out, k = [], 0
    for ring in rings:
        idx = [root(i) for i in range(k, k + len(ring))]
        k += len(ring)
        keep = [i for n, i in enumerate(idx) if i != idx[n - 1]]
        out.append([[float(xy[i, 0]), float(xy[i, 1])] for i in keep])
    return out


def stone_wall(n_stones: int = 80, width: float = 8.0, height: float = 4.0, seed: int = 0, mu: float = 0.65,
               unit_weight: float = 1.0, live_load=(1.0, 0.0), name: str = "stones",
               description: str | None = None) -> dict:
    """JSON spec of a ``width`` x ``height`` panel of ``n_stones`` irregular convex stones
    (centroidal Voronoi cells, :data:`LLOYD_STEPS` Lloyd steps from seeds drawn with
    ``seed``) on a rigid ground. Stones are named ``s1, s2, ...`` bottom to top; the
    support ``ground`` spans the panel and a quarter of its height on each side."""
    if not (isinstance(n_stones, (int, np.integer)) and n_stones >= 2):
        raise InputError(f"stone_wall: n_stones is {n_stones!r}; expected a whole number >= 2")
    if not (width > 0 and height > 0):
        raise InputError(f"stone_wall: the panel is {width!r} x {height!r}; expected a width and height > 0")
    rng = np.random.default_rng(seed)
    panel = box(0.0, 0.0, float(width), float(height))
    points = rng.uniform((0.0, 0.0), (width, height), size=(int(n_stones), 2))
    for _ in range(LLOYD_STEPS):
        cells = _cells(points, panel)
        points = np.array([c.centroid.coords[0] if c is not None else p for c, p in zip(cells, points)])
    cells = [c for c in _cells(points, panel) if c is not None and c.area > 0]
    size = float(np.sqrt(width * height / len(cells)))
    cells.sort(key=lambda c: (round(c.centroid.y / size, 6), c.centroid.x))
    blocks = [{"id": f"s{i + 1}", "vertices": v} for i, v in enumerate(_snapped(cells, size, width, height))]
    margin = height / 4
    blocks.append({"id": "ground", "support": True, "vertices": _rectangle(-margin, -margin, width + margin, 0.0)})
    return _finish(name, description, mu, unit_weight, live_load, blocks)
