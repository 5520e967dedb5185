"""Loads where they act: point loads, named live-load cases, a rolling load.

A force f applied at a point x of block j (not at its centroid x_G) contributes to eq. (1)
its resultant f and its moment ``(x - x_G) ^ f`` about the centroid; the moments go into
the ``m`` rows of f0 (dead) and fbar (live) through ``Structure.dead_m`` / ``live_m``
(:func:`lamodel.formulation.matrices.load_vectors`).

* A **load case** is a named live-load pattern: the live loads common to every case (body
  live loads and point loads without a case) plus the point loads of that case. Solving a
  file with cases gives one alpha per case; the least governs.
* A **rolling load** is a point load, or an axle group (offsets from the lead axle), moved
  across the top of the structure: at each position x every axle acts, as a live load, on
  the topmost body surface above its own abscissa (together with the common live loads).

Every variant is a deep copy of the structure carrying one live pattern, so the driver
solves it as any other structure.
"""
from __future__ import annotations

import copy
from dataclasses import dataclass, field

import numpy as np

from .errors import InputError
from .structure import Structure

KINDS = ("live", "dead")


@dataclass(frozen=True)
class PointLoad:
    """A force ``force`` = (fx, fy) applied at the point ``at`` of ``block``; a live load
    (multiplied by alpha) or a dead one. ``case`` names the load case ("" = every case)."""

    block: str
    at: tuple
    force: tuple
    kind: str = "live"
    case: str = ""


@dataclass
class LoadCase:
    """A named live-load pattern: forces and moments per block, and its point loads."""

    name: str
    live: np.ndarray
    live_m: np.ndarray
    point_loads: list = field(default_factory=list)


@dataclass
class RollingLoad:
    """An axle group moved across the top: each axle carries ``force``; ``axles`` are the
    offsets (along x) of the axles from the lead one; ``positions`` the lead axle's
    abscissas (None: the midpoints of the top edges, :func:`top_positions`)."""

    force: tuple
    axles: tuple = (0.0,)
    positions: tuple | None = None


def moment(at, centroid, force) -> float:
    """(at - centroid) ^ force: the moment about the centroid (eq. 1's x ^ f)."""
    r = np.asarray(at, dtype=float) - np.asarray(centroid, dtype=float)
    return float(r[0] * force[1] - r[1] * force[0])


def add_point_load(force_rows, moment_rows, structure: Structure, load: PointLoad):
    """Add ``load`` to the per-block force (nb, 2) and moment (nb,) arrays in place."""
    j = structure.block_index()[load.block]
    force_rows[j] += load.force
    moment_rows[j] += moment(load.at, structure.centroid[j], load.force)


def on_polygon(point, polygon, tol) -> bool:
    """Whether a point lies inside or on a counter-clockwise convex polygon (within tol)."""
    p, v = np.asarray(point, dtype=float), np.asarray(polygon, dtype=float)
    e = np.roll(v, -1, axis=0) - v
    r = p - v
    cross = e[:, 0] * r[:, 1] - e[:, 1] * r[:, 0]
    return bool((cross >= -tol * np.hypot(e[:, 0], e[:, 1])).all())


# ------------------------------------------------------------------------ variants
def _variant(structure: Structure, live, live_m, point_loads) -> Structure:
    """A copy carrying one live pattern (no cases, no rolling load)."""
    s = copy.copy(structure)
    s.live, s.live_m = np.array(live, dtype=float), np.array(live_m, dtype=float)
    s.dead, s.dead_m = structure.dead.copy(), structure.dead_m.copy()
    s.point_loads = list(point_loads)
    s.cases, s.rolling = {}, None
    return s


def one_live_load(structure, what: str) -> None:
    """InputError unless the structure carries one live load pattern: ``what`` (a solve, a
    study) takes one; load cases and a rolling load are solved one pattern at a time
    (:func:`case_structure`, :func:`rolling_structure`; all of them:
    :mod:`lamodel.studies`)."""
    cases, rolling = getattr(structure, "cases", None), getattr(structure, "rolling", None)
    if cases:
        raise InputError(f"structure '{structure.name}' has load cases ({', '.join(list(cases)[:4])}"
                         f"{', ...' if len(cases) > 4 else ''}); a {what} takes one live load: expected "
                         "lamodel.loads.case_structure(structure, name) for one case, or "
                         "lamodel.studies.load_case_study(structure) for all (lamodel solve FILE solves them all)")
    if rolling is not None:
        raise InputError(f"structure '{structure.name}' has a rolling load; a {what} takes one live load: expected "
                         "lamodel.loads.rolling_structure(structure, x) for one position, or "
                         "lamodel.studies.rolling_study(structure) for all (lamodel solve FILE solves them all)")


def the_live_load(structure: Structure, what: str) -> Structure:
    """``structure`` itself when it carries one live load pattern; with one load case, or a
    rolling load at one position (a bridge at the position chosen with ``--positions``),
    the structure under it; else InputError (``what`` takes one live load: name one)."""
    cases, rolling = getattr(structure, "cases", None), getattr(structure, "rolling", None)
    if cases and len(cases) == 1:
        return case_structure(structure, next(iter(cases)))
    if rolling is not None and not cases:
        positions = rolling_positions(structure)
        if len(positions) == 1:
            return rolling_structure(structure, positions[0])
        raise InputError(f"{what}: the rolling load of '{structure.name}' has {len(positions)} positions, and "
                         "a method other than lamodel takes one live load; expected one position (--positions X)")
    if cases:
        raise InputError(f"{what}: '{structure.name}' has {len(cases)} load cases, and a method other than lamodel "
                         "takes one live load; expected a file with one load case (a bridge: lamodel bridge "
                         "--positions X)")
    return structure


def case_structure(structure: Structure, name: str) -> Structure:
    """The structure under load case ``name`` (its live loads only; dead loads as ever)."""
    if name not in structure.cases:
        raise InputError(f"structure '{structure.name}': no load case '{name}'; expected one of "
                         f"{', '.join(structure.cases) or '(none)'}")
    c = structure.cases[name]
    return _variant(structure, c.live, c.live_m, c.point_loads)


def rolling_structure(structure: Structure, x: float, rolling: RollingLoad | None = None) -> Structure:
    """The structure with the rolling load's lead axle at abscissa ``x`` (plus the common
    live loads). InputError when no axle lands on a movable block."""
    rolling = rolling or structure.rolling
    live, live_m = structure.live.copy(), structure.live_m.copy()
    loads = list(structure.point_loads)
    placed = 0
    for offset in rolling.axles:
        top = top_point(structure, x + offset)
        if top is None:   # this axle is off the structure (or on a support)
            continue
        load = PointLoad(top[0], (x + offset, top[1]), tuple(rolling.force), "live", "rolling")
        add_point_load(live, live_m, structure, load)
        loads.append(load)
        placed += 1
    if not placed:
        raise InputError(f"structure '{structure.name}': at position x = {x:g} no axle of the rolling load stands on "
                         "a movable block; expected positions over the top of the structure")
    return _variant(structure, live, live_m, loads)


# ------------------------------------------------------------------------ the top
def _crossings(polygon, x):
    """The y values where the vertical line at x meets the polygon's edges."""
    v = np.asarray(polygon, dtype=float)
    a, b = v, np.roll(v, -1, axis=0)
    lo, hi = np.minimum(a[:, 0], b[:, 0]), np.maximum(a[:, 0], b[:, 0])
    on = (lo <= x) & (x <= hi) & (hi > lo)
    t = (x - a[on, 0]) / (b[on, 0] - a[on, 0])
    return a[on, 1] + t * (b[on, 1] - a[on, 1])


def top_point(structure: Structure, x: float):
    """(block, y) of the topmost body surface at abscissa x, if it belongs to a movable
    block; None if nothing is there or a support is on top."""
    best, owner = -np.inf, None
    for body, poly in structure.polygons.items():
        ys = _crossings(poly, x)
        if ys.size and ys.max() > best:
            best, owner = float(ys.max()), body
    if owner is None or owner not in structure.block_index():
        return None
    return owner, best


def top_positions(structure: Structure) -> list:
    """The midpoints (abscissas) of the upward-facing edges of the movable blocks that are
    the top of the structure there: where a rolling load stands by default."""
    xs = []
    size = structure.size()
    for b in structure.blocks:
        v = structure.polygons.get(b)
        if v is None:
            continue
        e = np.roll(v, -1, axis=0) - v
        up = -e[:, 0] > 1e-9 * size          # outward normal (e_y, -e_x) of a CCW polygon has n_y > 0
        for m in (v[up] + 0.5 * e[up]):
            top = top_point(structure, m[0])
            if top is not None and top[0] == b and abs(top[1] - m[1]) <= 1e-9 * size:
                xs.append(float(f"{m[0]:.12g}"))  # no -3e-16 for a crown at 0
    xs = sorted(xs)
    return [x for i, x in enumerate(xs) if i == 0 or x - xs[i - 1] > 1e-9 * size]


def rolling_positions(structure: Structure) -> list:
    """The lead axle positions of the structure's rolling load (given or automatic)."""
    r = structure.rolling
    if r.positions is not None:
        return [float(x) for x in r.positions]
    return top_positions(structure)


def unit_label(structure: Structure, kind: str) -> str:
    """' [m]' for kind 'length' when the input gave units, else ''."""
    u = structure.units.get(kind)
    return f" [{u}]" if u else ""


def with_rolling(structure: Structure, force=None, axles=None, positions=None, source: str = "") -> Structure:
    """The structure with a rolling load of ``force`` (FX, FY per axle) replacing its live
    loads, or, with ``force=None``, its own rolling load moved by new ``axles`` (offsets
    from the lead axle) and/or ``positions`` (of the lead axle). Unchanged when nothing is
    given. ``source`` names the input in errors."""
    import dataclasses
    if force is None and not (axles or positions):
        return structure
    if force is None and structure.rolling is None:
        raise InputError("axles and positions move a rolling load; expected a rolling force FX,FY or a "
                         "'rolling_load' in the JSON")
    if not structure.polygons:
        raise InputError(f"{source or structure.name}: no block outlines; expected a JSON geometry (or a .dat with "
                         "VERTICES) to find the top of the structure for a rolling load")
    s = dataclasses.replace(structure)
    if force is not None:
        if not any(force):
            raise InputError(f"rolling force {force[0]:g},{force[1]:g}: expected a non-zero force per axle")
        s.live, s.live_m = structure.live * 0.0, structure.live_m * 0.0
        s.point_loads = [p for p in structure.point_loads if p.kind == "dead"]
        s.cases = {}
        base = RollingLoad(tuple(force))
    else:
        base = structure.rolling
    s.rolling = RollingLoad(base.force, tuple(axles) if axles else base.axles,
                            tuple(positions) if positions else base.positions)
    return s
