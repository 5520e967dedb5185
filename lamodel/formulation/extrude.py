"""A planar block assembly extruded to a depth: the 2D structures as 3D ones.

The plane of the 2D structure becomes the vertical plane x-z of space (2D x -> x, 2D y -> z,
so gravity stays downwards); the depth runs along y, from -depth/2 to +depth/2. The map
(x, y, z_2D) -> (x, -z_2D, y) is a proper rotation, so a 2D couple m (about the 2D z axis)
becomes the moment (0, -m, 0). Each 2D contact becomes one interface with four contact
points: its two end points (centre +/- d t) at the front and at the back face. A 2D contact
with the bound |M| <= -d N and |V| <= -mu N carries exactly the same in-plane forces as
these four points on their cones, so an in-plane load gives the 2D alpha.
"""
from __future__ import annotations

import numpy as np

from ..structure import Structure
from ..structure3d import Structure3D, tangent_frame


def _to_space(xy: np.ndarray, y: float = 0.0) -> np.ndarray:
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    return np.column_stack([xy[:, 0], np.full(len(xy), y), xy[:, 1]])


def _prism(polygon: np.ndarray, depth: float):
    """(vertices, faces) of a planar polygon extruded along y over [-depth/2, depth/2]."""
    k = len(polygon)
    front, back = _to_space(polygon, -depth / 2), _to_space(polygon, depth / 2)
    faces = [list(range(k)), list(range(2 * k - 1, k - 1, -1))]
    faces += [[i, (i + 1) % k, k + (i + 1) % k, k + i] for i in range(k)]
    return np.vstack([front, back]), faces


def extrude(s: Structure, depth: float = 1.0) -> Structure3D:
    """The planar structure ``s`` as a Structure3D of thickness ``depth``.

    Loads are the 2D loads (per unit width) times ``depth``; the live loads stay in the
    plane (set ``live`` of the result, e.g. along y, for an out-of-plane load).
    """
    depth = float(depth)
    nc = s.n_contacts
    n3 = _to_space(s.normal)
    t3 = _to_space(s.tangent)
    c3 = _to_space(s.centre)
    half = depth / 2
    # points per interface: end 1 front, end 1 back, end 2 back, end 2 front (a polygon)
    ends = [(+1, -half), (+1, half), (-1, half), (-1, -half)]
    point = np.stack([c3 + e * s.d[:, None] * t3 + np.array([0.0, y, 0.0]) for e, y in ends], axis=1)  # (nc, 4, 3)
    point = point.reshape(-1, 3)
    normal = np.repeat(n3, 4, axis=0)
    t1, t2 = tangent_frame(normal)
    polyhedra = {k: _prism(v, depth) for k, v in s.polygons.items()}
    return Structure3D(
        name=s.name, blocks=s.blocks, centroid=_to_space(s.centroid), dead=_to_space(s.dead) * depth,
        live=_to_space(s.live) * depth, supports=s.supports, interfaces=s.contacts, iface_a=s.block_a,
        iface_b=s.block_b, iface_polygon=list(point.reshape(nc, 4, 3)), point_interface=np.repeat(np.arange(nc), 4),
        point=point, normal=normal, tangent1=t1, tangent2=t2, mu=np.repeat(s.mu, 4),
        dead_m=np.column_stack([np.zeros(s.n_blocks), -s.dead_m * depth, np.zeros(s.n_blocks)]),
        live_m=np.column_stack([np.zeros(s.n_blocks), -s.live_m * depth, np.zeros(s.n_blocks)]),
        polyhedra=polyhedra, units=dict(s.units), meta={"extruded_from": s.name, "depth": depth})
