"""The backing (masonry over the haunches, up to a level above the springings) as blocks,
and the bed the fill rests on: the backing's top where there is backing, the extrados of
the outer ring elsewhere.

Each extrados chord below the backing's level carries one backing block (a trapezoid, or a
triangle where the level cuts the chord), ``b1 .. bn`` as the voussoirs under them; an end
block over each abutment (``backing_left``, ``backing_right``) fills the rest up to the
abutment's far side. Neighbouring backing blocks share a vertical edge, so the backing can
open, slide and hinge like any masonry.
"""
from __future__ import annotations

import numpy as np

from .description import Bridge
from .ring import abutments, extrados, extrados_owner


def _cut(p, q, level):
    """The point of chord pq at height ``level``."""
    t = (level - p[1]) / (q[1] - p[1])
    return p + t * (q - p)


def backing_blocks(bridge: Bridge) -> list:
    """``[{"id", "vertices"}]`` of the backing (none when its height is 0)."""
    h = bridge.backing
    pts = extrados(bridge)
    if h <= max(pts[0, 1], pts[-1, 1]):
        return []
    out = []
    for i in range(len(pts) - 1):
        p, q = pts[i], pts[i + 1]
        if p[1] >= h and q[1] >= h:
            continue
        if p[1] < h and q[1] < h:
            corners = [p, q, [q[0], h], [p[0], h]]
        elif p[1] < h:
            corners = [p, _cut(p, q, h), [p[0], h]]
        else:
            corners = [_cut(p, q, h), q, [q[0], h]]
        out.append({"id": f"b{i + 1}", "vertices": [list(map(float, c)) for c in corners]})
    far = {b["id"]: np.array(b["vertices"])[:, 0] for b in abutments(bridge)}
    left, right = far["abutment_left"].min(), far["abutment_right"].max()
    out.append({"id": "backing_left", "vertices": [[left, pts[0, 1]], [pts[0, 0], pts[0, 1]], [pts[0, 0], h], [left, h]]})
    out.append({"id": "backing_right", "vertices": [[pts[-1, 0], pts[-1, 1]], [right, pts[-1, 1]], [right, h],
                                                    [pts[-1, 0], h]]})
    return out


def bed(bridge: Bridge) -> list:
    """(block, left end, right end) of each segment the fill rests on, left to right."""
    h = bridge.backing
    pts = extrados(bridge)
    backed = bool(backing_blocks(bridge))
    out = []
    if backed:
        out.append(("backing_left", np.array([pts[0, 0] - _end_width(bridge), h]), np.array([pts[0, 0], h])))
    for i in range(len(pts) - 1):
        p, q, owner = pts[i], pts[i + 1], extrados_owner(bridge, i)
        if not backed or (p[1] >= h and q[1] >= h):
            out.append((owner, p, q))
        elif p[1] < h and q[1] < h:
            out.append((f"b{i + 1}", np.array([p[0], h]), np.array([q[0], h])))
        elif p[1] < h:
            x = _cut(p, q, h)
            out += [(f"b{i + 1}", np.array([p[0], h]), x), (owner, x, q)]
        else:
            x = _cut(p, q, h)
            out += [(owner, p, x), (f"b{i + 1}", x, np.array([q[0], h]))]
    if backed:
        out.append(("backing_right", np.array([pts[-1, 0], h]), np.array([pts[-1, 0] + _end_width(bridge), h])))
    return out


def _end_width(bridge: Bridge) -> float:
    """How far the end backing block reaches beyond the springing's extrados."""
    pts = extrados(bridge)
    far = np.array(abutments(bridge)[0]["vertices"])[:, 0].min()
    return float(pts[0, 0] - far)
