"""The fill as assessment practice models it (Gilbert 2007; Cavicchi & Gambarotta 2005;
LimitState:RING's theory manual): forces on the extrados of the ring, chord by chord.

* **Dead weight**: the fill above each extrados chord, ``gamma_f b z`` per unit length
  (z the depth below the road surface, b the bridge width), at its centroid.
* **Horizontal pressure** (dead): ``K gamma_f b z`` on the chord's vertical projection,
  pushing the ring towards mid-span; K is at rest, active or zero.
* **Surface loads** (live): each axle's line load, on a patch of length a, spreads through
  the fill at the angle theta from the vertical: at depth z it is spread uniformly over
  ``a + 2 z tan(theta)``. Or (``dispersal: "boussinesq"``) as the vertical stress under a
  strip load on an elastic half-space (Boussinesq 1885; the strip's closed form as in Poulos
  & Davis 1974): ``sigma_z = p / pi (t1 - t2 + sin t1 cos t1 - sin t2 cos t2)``,
  ``t1,2 = arctan((x -/+ a / 2) / z)`` from the strip's centre, sampled out to
  BOUSSINESQ_REACH depths beyond the patch (the share beyond, below 0.05 %, is left out).
  The intensities are integrated over each chord and scaled so that the shares (with what
  lands beyond the springings, carried by the abutments) sum to the axle's force.
* **Passive restraint**: where the ring moves into the fill, the fill resists up to the
  mobilised passive pressure ``m K_p gamma_f z`` on the chord's vertical projection; the
  horizontal pressure already applied is part of it, so the restraint (a one-way bounded
  reaction, :mod:`lamodel.io.restraints`) adds ``(m K_p - K) gamma_f b z`` at most.

Every force is a point load at a point of the chord (its moment enters eq. 1) or a
restraint: the structure file, its tables and the certification see them all.
"""
from __future__ import annotations

import math

import numpy as np

from ..search.tuning import BOUSSINESQ_REACH, BRIDGE_KNIFE_EDGE, BRIDGE_SAMPLES, BRIDGE_SAMPLES_BEYOND
from .description import Bridge, lateral_coefficient, passive_coefficient
from .deck import deck_bed, deck_blocks, restraint_support, span_centre


def _linear_centroid(lo: float, hi: float, z_lo: float, z_hi: float) -> float:
    """The centroid of a load varying linearly from z_lo at lo to z_hi at hi."""
    return lo + (hi - lo) * (z_lo + 2 * z_hi) / (3 * (z_lo + z_hi))


def _on_chord(p, q, coordinate: int, value: float):
    """The point of chord pq whose x (coordinate 0) or y (1) is ``value``."""
    t = (value - p[coordinate]) / (q[coordinate] - p[coordinate])
    return (p + t * (q - p)).tolist()


def chords(bridge: Bridge):
    """(block, left end, right end) of each segment of the fill's bed: the extrados
    chords, the backing's top where there is backing (:mod:`.backing`), the piers' tops."""
    return deck_bed(bridge)


def _on_support(bridge: Bridge) -> set:
    """The bodies of the bed that are supports (a rigid pier's top): they carry their load
    to the ground, and take none in the structure."""
    return {b["id"] for b in deck_blocks(bridge)["foundations"] if b["support"]}


def dead_loads(bridge: Bridge) -> list:
    """The fill's weight and horizontal pressure on the ring: JSON dead point loads."""
    out, road, k = [], bridge.road, lateral_coefficient(bridge)
    unit, rigid = bridge.fill_weight * bridge.width, _on_support(bridge)
    for block, p, q in chords(bridge):
        if block in rigid:
            continue
        za, zb = road - p[1], road - q[1]
        if unit > 0 and za + zb > 0:
            x = _linear_centroid(p[0], q[0], za, zb)
            out.append({"block": block, "at": _on_chord(p, q, 0, x),
                        "force": [0.0, -unit * (q[0] - p[0]) * (za + zb) / 2], "kind": "dead"})
        h = _horizontal(bridge, p, q, k * unit)
        if h is not None:
            out.append({"block": block, "at": h[0], "force": [h[1], 0.0], "kind": "dead"})
    return out


def _horizontal(bridge: Bridge, p, q, per_depth: float):
    """(point, signed force) of a horizontal pressure ``per_depth * z`` on chord pq's vertical
    projection, pushing towards mid-span; None where it vanishes."""
    lo, hi = (p, q) if p[1] < q[1] else (q, p)
    dy = hi[1] - lo[1]
    if per_depth <= 0 or dy <= 1e-12 * bridge.span:
        return None
    z_lo, z_hi = bridge.road - lo[1], bridge.road - hi[1]
    y = _linear_centroid(lo[1], hi[1], z_lo, z_hi)
    side = 1.0 if (p[0] + q[0]) / 2 < span_centre(bridge, (p[0] + q[0]) / 2) else -1.0
    return _on_chord(p, q, 1, y), side * per_depth * dy * (z_lo + z_hi) / 2, dy


def restraints(bridge: Bridge) -> list:
    """The passive restraint on every chord (module doc): JSON restraints from the
    abutment on the chord's side, pushing towards mid-span."""
    extra = bridge.passive * passive_coefficient(bridge.phi) - lateral_coefficient(bridge)
    out, rigid = [], _on_support(bridge)
    for block, p, q in chords(bridge):
        h = _horizontal(bridge, p, q, extra * bridge.fill_weight * bridge.width)
        if h is None or block in rigid:
            continue
        side = "left" if h[1] > 0 else "right"
        mid = ((p + q) / 2).tolist()
        out.append({"support": restraint_support(bridge, side), "block": block, "at": mid,
                    "direction": [1.0 if side == "left" else -1.0, 0.0], "half_length": h[2] / 2,
                    "capacity": abs(h[1]), "thickness": bridge.width})
    return out


def live_loads(bridge: Bridge, lead: float, case: str) -> list:
    """The axle group with its lead axle at ``lead`` on the road, dispersed onto the
    extrados: JSON live point loads of load case ``case`` (none if all lands beyond the
    springings)."""
    ch = chords(bridge)
    tan = math.tan(math.radians(bridge.spread))
    deepest = bridge.road - min(p[1] for _, p, _ in ch)
    patch = max(bridge.patch, BRIDGE_KNIFE_EDGE * bridge.span)
    elastic = bridge.dispersal == "boussinesq"
    force, moment = np.zeros(len(ch)), np.zeros(len(ch))
    lo, hi = ch[0][1][0], ch[-1][2][0]   # the outer springings
    for offset in bridge.axles:
        x0 = lead + offset
        half = patch / 2 + deepest * (BOUSSINESQ_REACH if elastic else tan)   # how far its load spreads
        if x0 - half >= hi or x0 + half <= lo:
            continue   # all of it on the abutments (and no sampling out to a far position)
        reach = abs(x0) + bridge.patch / 2 + deepest * (BOUSSINESQ_REACH if elastic else tan)
        xs, dx, zs, owner = _samples(bridge, ch, reach)
        if elastic:
            q = strip_stress(xs - x0, zs, patch) * dx
        else:
            width = np.maximum(bridge.patch + 2 * zs * tan, BRIDGE_KNIFE_EDGE * bridge.span)
            q = np.where(np.abs(xs - x0) <= width / 2, dx / width, 0.0)   # the intensity at depth z, integrated
        if q.sum() <= 0:
            continue
        q *= bridge.force / q.sum()   # the axle's force, shared (beyond the springings: the abutments')
        mine = owner >= 0
        np.add.at(force, owner[mine], q[mine])
        np.add.at(moment, owner[mine], q[mine] * xs[mine])
    rigid = _on_support(bridge)
    return [{"block": block, "at": _on_chord(p, q, 0, moment[i] / force[i]), "force": [0.0, -force[i]],
             "kind": "live", "case": case} for i, (block, p, q) in enumerate(ch) if force[i] > 0 and block not in rigid]


def strip_stress(x, z, a):
    """Boussinesq's vertical stress at depth z (> 0) and offset x from the centre of a strip
    of width a loaded by a unit pressure on an elastic half-space (module doc); at z = 0 the
    pressure itself (1 on the strip, 0 beside it). Over any depth it integrates to a."""
    x, z = np.asarray(x, float), np.asarray(z, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = np.arctan2(x + a / 2, z)
        t2 = np.arctan2(x - a / 2, z)
    return (t1 - t2 + np.sin(t1) * np.cos(t1) - np.sin(t2) * np.cos(t2)) / np.pi


def _samples(bridge: Bridge, ch, reach: float):
    """Abscissas, lengths, depths and chord index (-1 beyond the springings, over the
    abutments) of the extrados sampled at midpoints, out to ``reach`` from mid-span."""
    xs, dx, zs, owner = [], [], [], []
    t = (np.arange(BRIDGE_SAMPLES) + 0.5) / BRIDGE_SAMPLES
    for i, (_, p, q) in enumerate(ch):
        xs.append(p[0] + t * (q[0] - p[0]))
        dx.append(np.full(BRIDGE_SAMPLES, (q[0] - p[0]) / BRIDGE_SAMPLES))
        zs.append(bridge.road - (p[1] + t * (q[1] - p[1])))
        owner.append(np.full(BRIDGE_SAMPLES, i))
    ends = (ch[0][1], ch[-1][2])
    step = (ends[1][0] - ends[0][0]) / (BRIDGE_SAMPLES * len(ch))
    beyond = max(0.0, reach - ends[1][0])
    step = max(step, beyond / BRIDGE_SAMPLES_BEYOND)
    n = int(np.ceil(beyond / step))
    for end, sign in ((ends[0], -1.0), (ends[1], 1.0)):
        xs.append(end[0] + sign * (np.arange(n) + 0.5) * step)
        dx.append(np.full(n, step))
        zs.append(np.full(n, bridge.road - end[1]))
        owner.append(np.full(n, -1))
    return tuple(np.concatenate(v) for v in (xs, dx, zs, owner))
