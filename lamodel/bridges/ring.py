"""The arch ring and its abutments as polygons: voussoirs between radial joints, rings
one above the other sharing their chords (so each ring interface is a contact), and a
rigid abutment under each springing.

x = 0 at mid-span, y = 0 at the springings; voussoirs ``v1 .. vn`` from left to right
(with several rings, ``r1v1 .. r1vn`` is the intrados ring, ``r2v1 ..`` the next).
"""
from __future__ import annotations

import numpy as np

from .description import Bridge


def joint_angles(bridge: Bridge) -> np.ndarray:
    """The angles (about the intrados centre) of the radial joints, left springing first."""
    half = np.arcsin(min(1.0, bridge.span / (2 * bridge.radius)))
    return np.linspace(np.pi / 2 + half, np.pi / 2 - half, bridge.voussoirs + 1)


def centre(bridge: Bridge) -> np.ndarray:
    """The centre of the intrados circle."""
    return np.array([0.0, bridge.rise - bridge.radius])


def ring_point(bridge: Bridge, radius: float, angle) -> np.ndarray:
    """Points at ``radius`` from the centre, at the given angles: shape (..., 2)."""
    a = np.asarray(angle, float)
    return centre(bridge) + radius * np.stack([np.cos(a), np.sin(a)], axis=-1)


def voussoir_id(bridge: Bridge, ring: int, i: int) -> str:
    """The id of voussoir i (0-based, from the left) of ring ``ring`` (0: the intrados ring)."""
    return f"v{i + 1}" if bridge.rings == 1 else f"r{ring + 1}v{i + 1}"


def voussoirs(bridge: Bridge) -> list:
    """``[{"id", "vertices"}]`` of every voussoir, ring after ring."""
    angles = joint_angles(bridge)
    out = []
    for k in range(bridge.rings):
        inner = ring_point(bridge, bridge.radius + k * bridge.thickness / bridge.rings, angles)
        outer = ring_point(bridge, bridge.radius + (k + 1) * bridge.thickness / bridge.rings, angles)
        for i in range(bridge.voussoirs):
            out.append({"id": voussoir_id(bridge, k, i),
                        "vertices": [inner[i].tolist(), inner[i + 1].tolist(), outer[i + 1].tolist(),
                                     outer[i].tolist()]})
    return out


def extrados(bridge: Bridge) -> np.ndarray:
    """The extrados polyline (n + 1 points, left to right): the outer ring's chords."""
    return ring_point(bridge, bridge.radius + bridge.thickness, joint_angles(bridge))


def extrados_owner(bridge: Bridge, i: int) -> str:
    """The voussoir whose extrados is chord i of :func:`extrados`."""
    return voussoir_id(bridge, bridge.rings - 1, i)


def abutments(bridge: Bridge) -> list:
    """The two abutments under each springing joint, ``abutment_height`` below the
    springing and ``abutment_width`` beyond its outer end, topped level with the
    springing's extrados end: rigid supports, or (kind ``block``) blocks on a rigid
    ``ground``."""
    angles = joint_angles(bridge)
    inner = ring_point(bridge, bridge.radius, angles[[0, -1]])
    outer = ring_point(bridge, bridge.radius + bridge.thickness, angles[[0, -1]])
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
