"""The mechanism in words, and the joint marks the picture draws from the same list.

From a mechanism u and the contact modes (:mod:`.modes`):

* the blocks that move, grouped into rigid **macro-blocks** (moving blocks joined by a
  closed joint move as one body), each with its motion (a rotation about a centre, or a
  translation);
* each **hinge**: the joint (``block_a|block_b``), the end it turns about (the intrados or
  extrados of an arch's radial joint, else the left/right or bottom/top end) and the
  sense of the relative rotation;
* each **sliding** joint and the direction of the slip;
* each **crushed** joint (finite compressive strength): the end that overlaps and over
  what length ("the joint crushes over its last 0.12 m at the intrados").

Joints are numbered 1, 2, ... in contact order; the picture (:mod:`.plot`) writes the same
numbers next to its marks, because both take them from :func:`joint_marks` (up to
PICTURE_NUMBERS marks: more numbers than that cover the drawing, so the picture then
draws the marks alone and the words keep the numbers).

For an arch (joints whose lines meet at one centre) :func:`thrust_line` gives the centre of
pressure of every ring joint, at eccentricity ``e = -M/N`` along t from the contact centre
(N n + V t at c + e t has the moment -e N = M about c); ``|e| <= d`` is eq. (4)'s
eccentricity row, so a statically admissible state keeps it inside the ring.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..structure import Structure
from .modes import RTOL

#: Most joint marks the picture numbers. An 8 x 6 inch picture of a 1,020-block wall whose
#: mechanism has 1,100 marks is covered by their numbers; the seed's walls and arches have
#: 5-30 marks.
PICTURE_NUMBERS = 60


def numbered_in_picture(marks) -> bool:
    """Whether the picture writes the numbers of these joint marks (PICTURE_NUMBERS)."""
    return len(marks) <= PICTURE_NUMBERS

_DIRECTIONS = ("right", "up and right", "up", "up and left", "left", "down and left", "down", "down and right")


@dataclass
class JointMark:
    """A hinge or a sliding joint as named in the words and marked in the picture."""

    number: int        # the joint's number (words and picture)
    contact: str
    kind: str          # "hinge" or "sliding"
    point: np.ndarray  # hinge: the pivot (end of the joint); sliding: the contact centre
    vector: np.ndarray  # hinge: (relative rotation of b, 0); sliding: slip of b relative to a
    text: str


def direction(v) -> str:
    """A direction in words (8 compass sectors): 'right', 'up and left', ..."""
    angle = np.degrees(np.arctan2(v[1], v[0])) % 360.0
    return _DIRECTIONS[int(((angle + 22.5) % 360.0) // 45.0)]


def ring_centre(structure: Structure, sample: int = 200):
    """The common point of the joint lines of an arch (its centre), or None.

    The median of the pairwise intersections of the joint lines; it is a centre when at
    least three joints in at least three directions pass through it (a wall's joints
    have two directions only)."""
    s = structure
    if s.n_contacts < 3:
        return None
    k = np.linspace(0, s.n_contacts - 1, min(sample, s.n_contacts)).astype(int)
    c, t = s.centre[k], s.tangent[k]
    i, j = np.triu_indices(k.size, 1)
    cross = t[i, 0] * t[j, 1] - t[i, 1] * t[j, 0]
    ok = np.abs(cross) > 0.05
    if not ok.any():
        return None
    i, j, cross = i[ok], j[ok], cross[ok]
    w = c[j] - c[i]
    lam = (w[:, 0] * t[j, 1] - w[:, 1] * t[j, 0]) / cross
    centre = np.median(c[i] + lam[:, None] * t[i], axis=0)
    radial = radial_joints(s, centre)
    angles = np.unique(np.round(np.degrees(np.arctan2(s.tangent[radial, 1], s.tangent[radial, 0])) % 180.0))
    return centre if radial.size >= 3 and angles.size >= 3 else None


def radial_joints(structure: Structure, centre) -> np.ndarray:
    """Indices of the joints whose line passes through ``centre`` (within 1e-6 of the size)."""
    r = np.asarray(centre) - structure.centre
    t = structure.tangent
    dist = np.abs(r[:, 0] * t[:, 1] - r[:, 1] * t[:, 0])
    return np.flatnonzero(dist <= 1e-6 * structure.size())


def _end_name(structure, k, sign, centre, radial) -> str:
    """Which end of joint k is ``centre + sign d t``: intrados/extrados, else by position."""
    s = structure
    end, other = s.centre[k] + sign * s.d[k] * s.tangent[k], s.centre[k] - sign * s.d[k] * s.tangent[k]
    if centre is not None and k in radial:
        return "intrados" if np.hypot(*(end - centre)) < np.hypot(*(other - centre)) else "extrados"
    t = s.tangent[k]
    if abs(t[0]) >= abs(t[1]):
        return "right end" if end[0] > other[0] else "left end"
    return "top" if end[1] > other[1] else "bottom"


def joint_name(structure: Structure, k: int) -> str:
    return f"joint {structure.block_a[k]}|{structure.block_b[k]} ({structure.contacts[k]})"


def _sense(theta) -> str:
    return "counter-clockwise" if theta > 0 else "clockwise"


def joint_marks(structure: Structure, u, modes, N=None) -> list:
    """Hinges, crushed and sliding joints of the mechanism, numbered in contact order
    (``N``: the collapse state's normal forces, which give a crushed joint's depth)."""
    from .kinematics import contact_kinematics
    s = structure
    u = np.asarray(u, dtype=float).reshape(-1, 3)
    opening, slip, th, gaps = contact_kinematics(s, u)
    centre = ring_centre(s)
    radial = radial_joints(s, centre) if centre is not None else np.array([], dtype=int)
    marks, number = [], 0
    joints = s.n_contacts - getattr(s, "restraints", 0)   # the restraints (last) are no joints
    for k, mode in enumerate(modes[:joints]):
        if mode not in ("hinging", "sliding", "sliding+hinging", "crushing", "crushing+sliding"):
            continue
        number += 1
        a, b = s.block_a[k], s.block_b[k]
        relative = "about it" if a in s.supports else f"relative to {a}"
        if "crushing" in mode:
            marks.append(_crushing_mark(s, k, number, opening[k], th[k], centre, radial, relative,
                                        None if N is None else N[k]))
        if "hinging" in mode:
            # the pivot: the end that moves less (as the picture's pivots); ties by the sense
            tie = np.isclose(gaps[k, 0], gaps[k, 1], rtol=1e-9, atol=0)
            sign = (1.0 if th[k] > 0 else -1.0) if tie else (1.0 if gaps[k, 1] < gaps[k, 0] else -1.0)
            where = _end_name(s, k, sign, centre, radial)
            text = f"hinge at the {where} of {joint_name(s, k)}"
            if th[k] != 0:
                text += f": {b} turns {_sense(th[k])} {relative}"
            marks.append(JointMark(number, s.contacts[k], "hinge", s.centre[k] + sign * s.d[k] * s.tangent[k],
                                   np.array([th[k], 0.0]), text))
        if "sliding" in mode:
            v = slip[k] * s.tangent[k]
            text = f"sliding at {joint_name(s, k)}"
            if np.any(v):
                text += f": {b} slides {direction(v)} " + ("on it" if a in s.supports else f"relative to {a}")
            marks.append(JointMark(number, s.contacts[k], "sliding", s.centre[k].copy(), v, text))
    return marks


def _crushing_mark(s, k, number, opening, th, centre, radial, relative, N=None) -> JointMark:
    """A crushed joint: the end that overlaps (the ends' normal openings are
    ``opening -/+ th d``) and over what length: the depth of the compressive stress block
    that carries N, ``(2 d b f_t - N) / (b (f_c + f_t))`` (without N: where the mechanism's
    overlap ends, which the polygonal joint places within a facet of it)."""
    ends = {sign: opening - th * sign * s.d[k] for sign in (-1.0, 1.0)}  # end centre + sign d t
    sign = min(ends, key=ends.get)
    low, high = ends[sign], ends[-sign]
    if N is not None:
        b, fc, ft = s.thickness[k], s.fc[k], s.ft[k]
        depth = min(max((2 * s.d[k] * b * ft - N) / (b * (fc + ft)), 0.0), 2 * s.d[k])
    else:
        depth = 2 * s.d[k] if high <= 0 else 2 * s.d[k] * (-low) / (high - low)
    unit = f" {s.units['length']}" if s.units.get("length") else ""
    where = _end_name(s, k, sign, centre, radial)
    whole = depth >= 2 * s.d[k] * (1 - 1e-9)
    text = (f"crushing at {joint_name(s, k)}: " + ("the whole joint crushes" if whole else
            f"the joint crushes over its last {depth:.3g}{unit} at the {where}"))
    if th != 0:
        text += f"; {s.block_b[k]} turns {_sense(th)} {relative}"
    pivot = s.centre[k] + sign * (s.d[k] - min(depth, 2 * s.d[k])) * s.tangent[k]
    return JointMark(number, s.contacts[k], "hinge", pivot, np.array([th, 0.0]), text)


def moving_blocks(structure: Structure, u, rtol: float = RTOL) -> np.ndarray:
    """Boolean per block: does it move (a vertex or the centroid moves more than rtol of
    the largest motion)?"""
    from .kinematics import displace
    s = structure
    u = np.asarray(u, dtype=float).reshape(-1, 3)
    mag = np.hypot(u[:, 0], u[:, 1])
    for j, b in enumerate(s.blocks):
        if b in s.polygons:
            m = displace(s.polygons[b], s.centroid[j], u[j])
            mag[j] = max(mag[j], np.hypot(m[:, 0], m[:, 1]).max())
    top = mag.max(initial=0.0)
    return mag > rtol * top if top > 0 else np.zeros(s.n_blocks, dtype=bool)


def macro_blocks(structure: Structure, u, modes) -> list:
    """Groups (lists of block indices) of moving blocks joined by closed joints."""
    s = structure
    moving = moving_blocks(s, u)
    parent = list(range(s.n_blocks))

    def root(j):
        while parent[j] != j:
            parent[j] = parent[parent[j]]
            j = parent[j]
        return j

    ia, ib = s.contact_blocks()
    for a, b, mode in zip(ia, ib, modes):
        if a >= 0 and b >= 0 and mode == "closed" and moving[a] and moving[b]:
            parent[root(a)] = root(b)
    groups = {}
    for j in np.flatnonzero(moving):
        groups.setdefault(root(j), []).append(int(j))
    return sorted(groups.values(), key=lambda g: g[0])


def _fmt_point(p, unit) -> str:
    return f"({p[0]:.3g}, {p[1]:.3g}){unit}"


def describe(structure: Structure, u, modes, alpha=None, N=None) -> list:
    """The mechanism in words: a list of lines (macro-blocks, then numbered joints; ``N``:
    the normal forces, for the depth of a crushed joint)."""
    s = structure
    u = np.asarray(u, dtype=float).reshape(-1, 3)
    unit = f" {s.units['length']}" if s.units.get("length") else ""
    if not np.isfinite(u).all() or not np.any(u):
        return ["No mechanism (no certified collapse state)."]
    groups = macro_blocks(s, u, modes)
    n_moving = sum(len(g) for g in groups)
    # + 0.0: a multiplier of -0.0 (mu = 0) reads "0"
    head = "Mechanism" + (f" at alpha = {alpha + 0.0:.6g}" if alpha is not None and np.isfinite(alpha) else "")
    lines = [f"{head}: {n_moving} of {s.n_blocks} blocks move as {len(groups)} rigid macro-block"
             f"{'s' if len(groups) != 1 else ''}; {s.n_blocks - n_moving} stay at rest."]
    size = s.size()  # of every block's vertices: once, not once a macro-block
    scale = np.abs(u[:, :2]).max(initial=0.0) + np.abs(u[:, 2]).max(initial=0.0) * size
    for n, g in enumerate(groups, start=1):
        j = g[0]
        ux, uy, th = u[j]
        names = ", ".join(s.blocks[i] for i in g[:12]) + (f", ... ({len(g)} blocks)" if len(g) > 12 else "")
        if abs(th) * size > 1e-6 * scale:
            # instantaneous centre: where (ux - th (y - yG), uy + th (x - xG)) vanishes
            centre = s.centroid[j] + np.array([-uy / th, ux / th])
            motion = f"turns {_sense(th)} about {_fmt_point(centre, unit)}"
        else:
            motion = f"translates {direction((ux, uy))}"
        lines.append(f"  macro-block {n} [{names}] {motion}")
    marks = joint_marks(s, u, modes, N)
    if marks:
        lines.append("Joints (numbered as in the picture):" if numbered_in_picture(marks) else "Joints:")
        lines += [f"  {m.number}. {m.text}" for m in marks]
    joints = s.n_contacts - getattr(s, "restraints", 0)
    n_open = sum(m == "open" for m in modes[:joints])
    if n_open:
        lines.append(f"  {n_open} joint{'s' if n_open != 1 else ''} open (separate).")
    full = [s.block_b[k] for k in range(joints, s.n_contacts) if "crushing" in modes[k]]
    if joints < s.n_contacts:   # restraints (lamodel.io.restraints): bounded one-way reactions
        lines.append(f"Restraints: {len(full)} of {s.n_contacts - joints} at their capacity"
                     + (f" (on {', '.join(full[:12])}{', ...' if len(full) > 12 else ''})" if full else "")
                     + "; the others carry less or nothing.")
    return lines


def thrust_line(structure: Structure, N, M, rtol: float = 1e-9):
    """(points (k, 2), eccentricity ratios |e|/d (k,), joint indices) of the centres of
    pressure of an arch's ring joints, ordered around the ring; None if not an arch.
    Joints carrying no compression (N ~ 0) have no centre of pressure and are left out."""
    s = structure
    centre = ring_centre(s)
    if centre is None:
        return None
    N, M = np.asarray(N, dtype=float), np.asarray(M, dtype=float)
    k = radial_joints(s, centre)
    k = k[-N[k] > rtol * max(1.0, np.abs(N).max(initial=0.0))]
    e = -M[k] / N[k]
    points = s.centre[k] + e[:, None] * s.tangent[k]
    r = s.centre[k] - centre
    order = np.argsort(-np.arctan2(r[:, 1], r[:, 0]))  # from the left springing over to the right
    return points[order], (np.abs(e) / s.d[k])[order], k[order]


def bound_words(summary) -> list:
    """The proven lower bound in words (summary.csv's alpha_lower, proven_global), or []."""
    if summary is None or "alpha_lower" not in summary.columns:
        return []
    row = summary.iloc[0]
    low = float(row["alpha_lower"])
    if not np.isfinite(low):
        return []
    if low <= 0:
        return ["No lower bound above 0 was proven in the time given (lamodel solve --prove SECONDS gives more)."]
    if bool(row.get("proven_global", False)):
        return [f"Proven global minimum: collapse cannot occur below {low:.6g} under this load pattern "
                f"(alpha = {float(row['alpha']):.6g})."]
    return [f"Collapse cannot occur below {low:.6g} under this load pattern (a proven lower bound)."]


def stall_joints(structure, rows) -> list:
    """The joints (planar contacts, or interfaces in space) of the search's rows ``rows``:
    4 rows a contact in the plane, 2 a contact point in space, type by type."""
    rows = np.asarray(rows, dtype=int)
    if getattr(structure, "dimension", 2) == 3:
        faces = structure.point_interface[rows % len(structure.point_interface)]
        return [structure.interfaces[k] for k in dict.fromkeys(faces.tolist())]
    return [structure.contacts[k] for k in dict.fromkeys((rows % structure.n_contacts).tolist())]


def stall_columns(stalled) -> dict:
    """summary.csv's ``alpha_stalled`` and ``gap_stalled`` (NaN: something was certified, or
    the search made no step): the alpha of the statics nearest a collapse state the search
    reached, and its relative complementarity gap ``(alpha_K - alpha) / alpha_K``."""
    if stalled is None:
        return {"alpha_stalled": np.nan, "gap_stalled": np.nan}
    return {"alpha_stalled": stalled[0] + 0.0, "gap_stalled": stalled[2] + 0.0}


def stall_words(structure, stalled, shown: int = 8) -> list:
    """Where a search that certified nothing came nearest a collapse state, in words."""
    if stalled is None:
        return []
    alpha, alpha_k, rel, rows = stalled
    joints = stall_joints(structure, rows)
    held = (f"; the joints that hold the gap (its mechanism flows there, the statics keeps them slack): "
            f"{', '.join(map(str, joints[:shown]))}{', ...' if len(joints) > shown else ''} ({len(joints)})"
            if joints else "")
    return [f"Nearest a collapse state, not certified: a statics at alpha = {alpha:.6g} whose mechanism "
            f"(the fictitious system's) gives alpha_K = {alpha_k:.6g}, a gap of {100 * rel:.3g} %{held}. "
            "It is no answer: an uncertified number is never reported as alpha."]
