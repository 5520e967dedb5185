"""The tributary area of each contact point of an interface (the point-contact model's A_i).

A joint's strengths act on its contact points as forces: the crushing cap ``f_c A_i``,
the tensile cap ``f_t A_i`` and the cohesion ``c0 A_i`` of point i. Its area A_i is its
**Voronoi cell clipped to the interface polygon**: the part of the joint nearer to it than
to any other point of the same interface (the joint cut by the half-plane on its side of
each bisector, shapely's intersections). The areas of an
interface add up to its polygon's area (holes excluded); on a rectangle's four corners
each takes a quarter; with interior points (``"contact_points": "grid:n"``) the corners
keep the small cells at the corners and the interior points the rest, so the caps follow
the stresses over the joint as n grows. Points at one place share their cell equally.
"""
from __future__ import annotations

import numpy as np
import shapely


def plane_frame(polygon: np.ndarray):
    """(origin, e1, e2) of the plane of a planar 3D polygon (k, 3) (Newell's normal)."""
    p = np.asarray(polygon, float)
    n = np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)
    n /= np.linalg.norm(n)
    e1 = p[1] - p[0] if len(p) > 1 else np.array([1.0, 0.0, 0.0])
    e1 = e1 - (e1 @ n) * n
    e1 /= np.linalg.norm(e1)
    return p.mean(axis=0), e1, np.cross(n, e1)


def tributary_areas(shape, xy: np.ndarray) -> np.ndarray:
    """The areas of the Voronoi cells of the points ``xy`` (k, 2) clipped to the shapely
    polygon ``shape`` (both in the joint's plane)."""
    xy = np.asarray(xy, float).reshape(-1, 2)
    if len(xy) == 0:
        return np.zeros(0)
    scale = max(float(np.ptp(xy, axis=0).max()), shape.length, 1e-300)
    key = np.round(xy / (1e-9 * scale)).astype(np.int64)
    uniq, first, which = np.unique(key, axis=0, return_index=True, return_inverse=True)
    which = which.reshape(-1)
    sites = xy[first]
    area = np.array([_cell(shape, sites, i).area for i in range(len(sites))])
    return area[which] / np.bincount(which)[which]


def _cell(shape, sites: np.ndarray, i: int):
    """Site i's Voronoi cell within ``shape``: the shape cut by the half-plane nearer to site
    i than to each other site. (GEOS's Voronoi diagram, on the four cocircular corners of a
    rectangle, gave one corner three quarters of the joint and the areas a sum above its
    area, changing with where the joint lies.)"""
    others = np.delete(sites, i, axis=0)
    if not len(others):
        return shape
    x0, y0, x1, y1 = shape.bounds
    big = 4.0 * max(x1 - x0, y1 - y0, float(np.ptp(sites, axis=0).max()), 1e-300)
    p = sites[i]
    n = (others - p) / np.linalg.norm(others - p, axis=1)[:, None]   # towards each other site
    m, t = (p + others) / 2, np.column_stack([-n[:, 1], n[:, 0]]) * big
    halves = shapely.polygons(np.stack([m + t, m - t, m - t - n * big, m + t - n * big], axis=1))
    return shapely.intersection_all(np.append(halves, shape))


def areas_in_frame(shape, frame, points: np.ndarray) -> np.ndarray:
    """:func:`tributary_areas` of 3D points on a joint whose polygon is ``shape`` in the
    plane frame ``(origin, e1, e2)``."""
    o, e1, e2 = frame
    rel = np.asarray(points, float).reshape(-1, 3) - o
    return tributary_areas(shape, np.column_stack([rel @ e1, rel @ e2]))


def point_areas(polygons, point_interface, point, holes=()) -> np.ndarray:
    """A_i of every contact point of a structure given as outlines: interface k's polygon
    ``polygons[k]`` (k, 3) less its holes ``holes[k]`` (rings (m, 3); none if ``holes``
    is empty) shared among its points by :func:`tributary_areas`."""
    point_interface = np.asarray(point_interface, int)
    out = np.zeros(len(point_interface))
    for k, poly in enumerate(polygons):
        on = np.flatnonzero(point_interface == k)
        if on.size:
            frame = plane_frame(poly)
            o, e1, e2 = frame
            flat = lambda ring: np.column_stack([(ring - o) @ e1, (ring - o) @ e2])  # noqa: E731
            shape = shapely.Polygon(flat(poly), [flat(np.asarray(h, float)) for h in (holes[k] if holes else [])])
            out[on] = areas_in_frame(shape, frame, point[on])
    return out
