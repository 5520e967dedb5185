"""A bridge of several spans: each span's ring and backing (:mod:`.ring`, :mod:`.backing`)
placed side by side, a pier between each two spans, the abutments at the ends, the bed of
the fill continuous over the piers; one span is the bridge of :mod:`.ring` as it is.

Span k (from 1, left to right) has voussoirs ``s{k}v1 ..`` (``s{k}r1v1 ..`` with several
rings) and backing blocks ``s{k}b1 ..``; the piers are ``pier1 ..``, the backing over a
pier ``backing_pier1 ..``. A pier's top holds the two springing joints next to it, its
``width`` is the distance between their intrados ends, and it stands ``height`` below the
springings: a support, or (kind ``block``) a block on its own rigid ``ground_pier{k}``, free
to slide and rock. x = 0 is the middle of the bridge, y = 0 the springings.
"""
from __future__ import annotations

import numpy as np

from ..errors import InputError
from .backing import backing_blocks, bed as span_bed
from .description import Bridge
from .ring import abutments, joint_points, restraint_support as span_support, voussoirs

#: Blocks of one span that stand at its ends, named once for the whole bridge.
ENDS = ("abutment_left", "abutment_right", "backing_left", "backing_right", "ground")


def layout(bridge: Bridge) -> list:
    """(one-span bridge, shift of its mid-span along x) of each span, left to right."""
    if not bridge.piers:
        return [(bridge, 0.0)]
    left, out = -bridge.span / 2, []
    for k in range(len(bridge.spans)):
        part = bridge.part(k)
        out.append((part, left + part.span / 2))
        left += part.span + (bridge.piers[k].width if k < len(bridge.piers) else 0.0)
    return out


def _moved(block: dict, shift: float, prefix: str) -> dict:
    """A span's block shifted along x, its id prefixed with the span's."""
    out = dict(block, vertices=[[x + shift, y] for x, y in block["vertices"]])
    if block["id"] not in ENDS:
        out["id"] = prefix + block["id"]
    return out


def _springings(part: Bridge, shift: float, end: int) -> tuple:
    """(intrados, extrados) points of a span's springing joint at ``end`` (0 left, -1 right)."""
    move = np.array([shift, 0.0])
    return joint_points(part, 0.0)[end] + move, joint_points(part, part.thickness)[end] + move


def _pier(bridge: Bridge, k: int, spans: list) -> list:
    """Pier k (0-based) between spans k and k + 1, with its ground when it is a block."""
    pier = bridge.piers[k]
    a1, b1 = _springings(*spans[k], -1)
    a2, b2 = _springings(*spans[k + 1], 0)
    if b1[0] >= b2[0]:
        raise InputError(f"bridge '{bridge.name}': piers[{k}]: 'width' is {pier.width:g}; expected more than "
                         f"{pier.width + b1[0] - b2[0]:.4g}, room for the springing joints of both spans on its top")
    bottom = -pier.height
    corners = [a1, [a1[0], bottom], [a2[0], bottom], a2, b2, b1]
    _convex_top(bridge, k, spans, [a2, b2, b1, a1])
    out = [{"id": f"pier{k + 1}", "support": pier.kind == "rigid",
            "vertices": [list(map(float, c)) for c in corners]}]
    if pier.kind == "block":
        depth = pier.height / 2
        out.append({"id": f"ground_pier{k + 1}", "support": True,
                    "vertices": [[a1[0] - depth, bottom - depth], [a2[0] + depth, bottom - depth],
                                 [a2[0] + depth, bottom], [a1[0] - depth, bottom]]})
    return out


def _convex_top(bridge: Bridge, k: int, spans: list, top) -> None:
    """InputError unless pier k's top (the two springing joints, right to left) is convex: a
    block is convex, and spans of other shapes or ring thicknesses can meet on a pier in
    joints at angles that make its top concave."""
    p = np.asarray(top, dtype=float)
    size = max(float(np.ptp(p[:, 0])), float(np.ptp(p[:, 1])), 1e-300)
    for u, v, w in zip(p, p[1:], p[2:]):
        d1, d2 = v - u, w - v
        if d1[0] * d2[1] - d1[1] * d2[0] < -1e-9 * size * size:   # a right turn: a dip in the top
            left, right = spans[k][0], spans[k + 1][0]
            raise InputError(
                f"bridge '{bridge.name}': piers[{k}]: the springing joints of spans[{k}] ({left.shape}, ring "
                f"{left.thickness:g}) and spans[{k + 1}] ({right.shape}, ring {right.thickness:g}) make the pier's top "
                "concave; expected spans that meet on a pier with the same shape and ring thickness (a block is convex)")


def _abutment_grounds(bridge: Bridge, ends: list) -> list:
    """The two abutments of a bridge of several spans, each on its own ground when a block."""
    out = []
    for block in ends:
        if block["id"] == "ground":
            continue
        out.append(block)
        if not block["support"]:
            v = np.array(block["vertices"])
            lo, hi, bottom, depth = v[:, 0].min(), v[:, 0].max(), v[:, 1].min(), bridge.abutment_height / 2
            side = block["id"].split("_")[1]
            out.append({"id": f"ground_{side}", "support": True,
                        "vertices": [[lo - depth, bottom - depth], [hi + depth, bottom - depth], [hi + depth, bottom],
                                     [lo - depth, bottom]]})
    return out


def deck_blocks(bridge: Bridge) -> dict:
    """The bridge's blocks by kind: ``voussoirs``, ``backing`` and ``foundations``
    (abutments, piers, grounds), as JSON bodies."""
    spans = layout(bridge)
    if len(spans) == 1:
        return {"voussoirs": voussoirs(bridge), "backing": backing_blocks(bridge), "foundations": abutments(bridge)}
    out = {"voussoirs": [], "backing": [], "foundations": []}
    last = len(spans) - 1
    for k, (part, shift) in enumerate(spans):
        prefix = f"s{k + 1}"
        out["voussoirs"] += [_moved(b, shift, prefix) for b in voussoirs(part)]
        drop = ({"backing_right"} if k < last else set()) | ({"backing_left"} if k > 0 else set())
        out["backing"] += [_moved(b, shift, prefix) for b in backing_blocks(part) if b["id"] not in drop]
        if k < last:
            out["backing"] += _pier_backing(bridge, k, spans)
            out["foundations"] += _pier(bridge, k, spans)
    ends = [_moved(b, spans[0][1], "") for b in abutments(spans[0][0]) if b["id"] == "abutment_left"]
    ends += [_moved(b, spans[-1][1], "") for b in abutments(spans[-1][0]) if b["id"] == "abutment_right"]
    out["foundations"] = _abutment_grounds(bridge, ends) + out["foundations"]
    return out


def _pier_backing(bridge: Bridge, k: int, spans: list) -> list:
    """The backing over pier k, from one span's springing to the next, up to its level."""
    (_, b1), (_, b2) = _springings(*spans[k], -1), _springings(*spans[k + 1], 0)
    h = bridge.backing
    if h <= max(b1[1], b2[1]):
        return []
    return [{"id": f"backing_pier{k + 1}", "vertices": [b1.tolist(), b2.tolist(), [b2[0], h], [b1[0], h]]}]


def deck_bed(bridge: Bridge) -> list:
    """(block, left end, right end) of each segment the fill rests on, left to right, over
    every span and pier (:func:`lamodel.bridges.backing.bed` for one span)."""
    spans = layout(bridge)
    if len(spans) == 1:
        return span_bed(bridge)
    out, last = [], len(spans) - 1
    move = lambda p, shift: np.array([p[0] + shift, p[1]])   # noqa: E731
    for k, (part, shift) in enumerate(spans):
        for block, p, q in span_bed(part):
            if (block == "backing_left" and k > 0) or (block == "backing_right" and k < last):
                continue
            out.append((block if block in ENDS else f"s{k + 1}{block}", move(p, shift), move(q, shift)))
        if k < last:
            top = _pier_backing(bridge, k, spans)
            if top:
                v = np.array(top[0]["vertices"])
                out.append((top[0]["id"], v[3], v[2]))
            else:
                (_, b1), (_, b2) = _springings(part, shift, -1), _springings(*spans[k + 1], 0)
                out.append((f"pier{k + 1}", b1, b2))
    return out


def span_centre(bridge: Bridge, x: float) -> float:
    """The mid-span of the span over x, or of the nearest one (0 with one span): the fill
    pushes the ring towards it."""
    return min(layout(bridge), key=lambda s: max(0.0, abs(x - s[1]) - s[0].span / 2))[1]


def restraint_support(bridge: Bridge, side: str) -> str:
    """The support the fill's restraints push from: a support's body (any: it does not move)."""
    if not bridge.piers:
        return span_support(bridge, side)
    supports = [b["id"] for b in deck_blocks(bridge)["foundations"] if b["support"]]
    return supports[0] if side == "left" else supports[-1]
