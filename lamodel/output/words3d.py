"""A mechanism in space in words: the macro-blocks and how each moves, the opening and
sliding interfaces.

From the block motions u (nb, 6) at the centroids and the mode of every contact point
(stuck, opening, sliding):

* blocks moving together as one rigid body form a **macro-block**
  (:func:`lamodel.output.motion3d.macro_blocks`, as the pictures colour them); each is a
  rotation about an axis (its direction and a point on it) or a translation;
* an interface is **opening** when some of its points open (it hinges or lifts off), and
  **sliding** when some of its points slide and none opens;
* with the joints' strengths, an interface is also **crushing** when some of its points
  close on their crushing caps (its hinge sits inside the joint).
"""
from __future__ import annotations

import numpy as np

from ..structure3d import Structure3D
from .motion3d import macro_blocks

#: Ids listed at most in one sentence (the rest counted).
SHOWN = 8
_AXES = ("+x", "-x", "+y", "-y", "+z", "-z")


def _ids(ids) -> str:
    ids = list(ids)
    text = ", ".join(ids[:SHOWN])
    return text + (f" and {len(ids) - SHOWN} more" if len(ids) > SHOWN else "")


def _vector(v) -> str:
    """A unit vector in words: an axis when it is one (within 1e-6), else its components."""
    v = np.asarray(v, dtype=float)
    for k, name in enumerate(_AXES):
        e = np.zeros(3)
        e[k // 2] = 1.0 if k % 2 == 0 else -1.0
        if np.abs(v - e).max() <= 1e-6:
            return name
    return "(" + ", ".join(f"{c:.3g}" for c in v) + ")"


def _point(p, unit, size) -> str:
    p = np.where(np.abs(p) <= 1e-9 * size, 0.0, p)   # round-off of the solvers is no coordinate
    return "(" + ", ".join(f"{c:.4g}" for c in p) + ")" + (f" {unit}" if unit else "")


def body_motion(s: Structure3D, u_row, centroid) -> str:
    """One rigid motion (ux, uy, uz, rx, ry, rz at ``centroid``) in words: a rotation about
    an axis through a point (the point of the axis nearest the centroid), or a translation."""
    v, w = np.asarray(u_row[:3], float), np.asarray(u_row[3:], float)
    wn = np.linalg.norm(w)
    unit = s.units.get("length", "")
    if wn * s.size() <= 1e-6 * max(np.linalg.norm(v), 1e-300):
        return f"translates along {_vector(v / np.linalg.norm(v))}"
    axis = w / wn
    # the velocity of a point c + r is v + w x r; on the axis it is parallel to w
    r = np.cross(w, v) / wn ** 2
    return f"turns about the axis {_vector(axis)} through {_point(centroid + r, unit, s.size())}"


def interface_modes(s: Structure3D, modes) -> dict:
    """Interface id -> 'opening', 'sliding' or 'stuck', from its points' modes."""
    out = {}
    for i, m in zip(s.point_interface, np.asarray(modes).astype(str)):
        k = s.interfaces[i]
        now = out.get(k, "stuck")
        if m == "opening" or now == "opening":
            out[k] = "opening"
        elif m in ("sliding", "crushing+sliding") or now == "sliding":
            out[k] = "sliding"
        else:
            out[k] = "stuck"
    return out


def describe3d(s: Structure3D, motions, modes) -> list:
    """The mechanism in words, one line each (see the module doc)."""
    if motions is None:
        return []
    u = np.asarray(motions, dtype=float).reshape(s.n_blocks, 6)
    label = macro_blocks(s, u)
    moving = np.flatnonzero(label >= 0)
    groups = sorted(set(label[moving].tolist()))
    lines = [f"Mechanism: {moving.size} of {s.n_blocks} blocks move, as {len(groups)} macro-block"
             f"{'s' if len(groups) != 1 else ''} (blocks moving as one rigid body):"]
    for g in groups:
        members = np.flatnonzero(label == g)
        j = int(members[0])
        lines.append(f"  macro-block {g + 1} ({members.size} block{'s' if members.size > 1 else ''}: "
                     f"{_ids(s.blocks[k] for k in members)}) {body_motion(s, u[j], s.centroid[j])}")
    kinds = interface_modes(s, modes)
    names = {k: f"{a}|{b}" for k, a, b in zip(s.interfaces, s.iface_a, s.iface_b)}
    for kind in ("opening", "sliding"):
        hit = [names[k] for k in s.interfaces if kinds.get(k) == kind]
        if hit:
            lines.append(f"{kind.capitalize()} interfaces ({len(hit)}): {_ids(hit)}")
    crushed = sorted({int(i) for i, m in zip(s.point_interface, np.asarray(modes).astype(str)) if m.startswith("crushing")})
    if crushed:
        hit = [names[s.interfaces[i]] for i in crushed]
        lines.append(f"Crushing interfaces ({len(hit)}): {_ids(hit)} (points on their crushing caps)")
    return lines
