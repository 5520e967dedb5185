"""The arch ring and its abutments as polygons: voussoirs between joints across the ring
(segmental, elliptical or pointed, :func:`intrados`), rings
one above the other sharing their chords (so each ring interface is a contact), and a
rigid abutment under each springing.

x = 0 at mid-span, y = 0 at the springings; voussoirs ``v1 .. vn`` from left to right
(with several rings, ``r1v1 .. r1vn`` is the intrados ring, ``r2v1 ..`` the next).
"""
from __future__ import annotations

import numpy as np

from .description import Bridge


def _circle(centre, radius, angles):
    """Points of a circle at the given angles, and the outward normals there."""
    a = np.asarray(angles, float)
    normal = np.stack([np.cos(a), np.sin(a)], axis=-1)
    return np.asarray(centre, float) + radius * normal, normal


def intrados(bridge: Bridge):
    """The intrados at the joints, left springing first: points (n + 1, 2) and the joints'
    unit directions (n + 1, 2), outwards. Segmental: radial joints at equal angles;
    elliptical: joints normal to the intrados at equal parametric angles; pointed: two
    circular arcs, radial joints at equal angles on each half, a vertical joint at the apex."""
    n = bridge.voussoirs
    half_span = bridge.span / 2
    if bridge.shape == "elliptical":
        t = np.linspace(np.pi, 0.0, n + 1)
        a, b = half_span, bridge.rise
        points = np.stack([a * np.cos(t), b * np.sin(t)], axis=-1)
        normal = np.stack([np.cos(t) / a, np.sin(t) / b], axis=-1)
        return points, normal / np.hypot(normal[:, :1], normal[:, 1:])
    if bridge.shape == "pointed":
        radius = (half_span ** 2 + bridge.rise ** 2) / bridge.span   # each arc through a springing and the apex
        centre = radius - half_span                                     # the left arc's centre is (centre, 0)
        apex = np.arctan2(bridge.rise, -centre)
        left, nl = _circle((centre, 0.0), radius, np.linspace(np.pi, apex, n // 2 + 1))
        right, nr = _circle((-centre, 0.0), radius, np.linspace(np.pi - apex, 0.0, n // 2 + 1))
        nl[-1] = (0.0, 1.0)
        return np.vstack([left, right[1:]]), np.vstack([nl, nr[1:]])
    half = np.arcsin(min(1.0, half_span / bridge.radius))
    return _circle((0.0, bridge.rise - bridge.radius), bridge.radius,
                   np.linspace(np.pi / 2 + half, np.pi / 2 - half, n + 1))


def joint_points(bridge: Bridge, offset: float) -> np.ndarray:
    """The points of the joints at ``offset`` outwards from the intrados (n + 1, 2)."""
    points, normal = intrados(bridge)
    return points + offset * normal


def voussoir_id(bridge: Bridge, ring: int, i: int) -> str:
    """The id of voussoir i (0-based, from the left) of ring ``ring`` (0: the intrados ring)."""
    return f"v{i + 1}" if bridge.rings == 1 else f"r{ring + 1}v{i + 1}"


def voussoirs(bridge: Bridge) -> list:
    """``[{"id", "vertices"}]`` of every voussoir, ring after ring."""
    out = []
    for k in range(bridge.rings):
        inner = joint_points(bridge, k * bridge.thickness / bridge.rings)
        outer = joint_points(bridge, (k + 1) * bridge.thickness / bridge.rings)
        for i in range(bridge.voussoirs):
            block = {"id": voussoir_id(bridge, k, i),
                     "vertices": [inner[i].tolist(), inner[i + 1].tolist(), outer[i + 1].tolist(), outer[i].tolist()]}
            if bridge.fc is not None:   # a contact takes the smaller fc of its two bodies: every ring joint crushes
                block["fc"] = bridge.fc
            out.append(block)
    return out


def extrados(bridge: Bridge) -> np.ndarray:
    """The extrados polyline (n + 1 points, left to right): the outer ring's chords."""
    return joint_points(bridge, bridge.thickness)


def extrados_owner(bridge: Bridge, i: int) -> str:
    """The voussoir whose extrados is chord i of :func:`extrados`."""
    return voussoir_id(bridge, bridge.rings - 1, i)


def abutments(bridge: Bridge) -> list:
    """The two abutments under each springing joint, ``abutment_height`` below the
    springing and ``abutment_width`` beyond its outer end, topped level with the
    springing's extrados end: rigid supports, or (kind ``block``) blocks on a rigid
    ``ground``."""
    inner = joint_points(bridge, 0.0)[[0, -1]]
    outer = joint_points(bridge, bridge.thickness)[[0, -1]]
    out = []
    for side, a, b in (("left", inner[0], outer[0]), ("right", inner[1], outer[1])):
        sign = -1.0 if side == "left" else 1.0
        far = (max(abs(a[0]), abs(b[0])) + bridge.abutment_width) * sign
        bottom = -bridge.abutment_height
        corners = [a.tolist(), [a[0], bottom], [far, bottom], [far, b[1]], b.tolist()]
        out.append({"id": f"abutment_{side}", "support": bridge.abutment_kind == "rigid", "vertices": corners})
    if bridge.abutment_kind == "block":
        xs = [x for b in out for x, _ in b["vertices"]]
        low, depth = -bridge.abutment_height, bridge.abutment_height / 2
        out.append({"id": "ground", "support": True,
                    "vertices": [[min(xs), low - depth], [max(xs), low - depth], [max(xs), low], [min(xs), low]]})
    return out


def restraint_support(bridge: Bridge, side: str) -> str:
    """The support the fill's restraints on one side push from (the ground under block abutments)."""
    return f"abutment_{side}" if bridge.abutment_kind == "rigid" else "ground"
