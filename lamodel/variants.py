"""Variants of a structure: copies with another friction coefficient, other joint
strengths, an added dead force, a rotated live load or scaled blocks (what a study varies, :mod:`lamodel.parametric`).

Every variant is a deep copy; the structure passed in is never modified.
"""
from __future__ import annotations

import copy
import dataclasses
import math

import numpy as np

from .errors import InputError
from .structure import Structure


def in_space(structure) -> bool:
    return getattr(structure, "dimension", 2) == 3


def friction_places(structure) -> int:
    """How many friction coefficients the structure has: a contact's in the plane, a
    contact point's in space."""
    return structure.n_points if in_space(structure) else structure.n_contacts


def joint_places(structure) -> int:
    """The joints a what-if changes: every friction place but the restraints (a bridge's
    passive fill pressure, :mod:`lamodel.io.restraints`), which come last and keep their
    own capacity and no friction."""
    return friction_places(structure) - (0 if in_space(structure) else int(structure.restraints))


def with_friction(structure: Structure, mu: float) -> Structure:
    """A copy of the structure with the friction coefficient mu on every contact (in
    space: every contact point); restraints keep none."""
    mu = float(mu)
    if not np.isfinite(mu) or mu < 0:
        raise InputError(f"friction coefficient {mu}: expected a finite number >= 0")
    s = copy.deepcopy(structure)
    n = joint_places(s)
    s.mu = np.concatenate([np.full(n, mu), np.asarray(structure.mu, dtype=float)[n:]])
    s.name = f"{structure.name}_mu{mu:g}"
    return s


def with_strengths(structure: Structure, fc: float | None = None, ft: float | None = None,
                   cohesion: float | None = None) -> Structure:
    """A copy of the structure with these strengths on every joint (None: the structure's
    own; :mod:`lamodel.formulation.joints`; in space on every contact point,
    :mod:`lamodel.formulation.space`), checked (InputError naming the field); restraints
    keep their capacity."""
    s = copy.deepcopy(structure)
    n = joint_places(s)
    for name, value in (("fc", fc), ("ft", ft), ("cohesion", cohesion)):
        if value is not None:
            column = np.full(friction_places(s), float(value))
            column[n:] = np.asarray(getattr(s, name), dtype=float)[n:]  # the restraints' own
            setattr(s, name, column)
    return s.validate()


def with_dead_force(structure: Structure, block: str, fx: float = 0.0, fy: float = 0.0,
                    name: str | None = None) -> Structure:
    """A copy of the structure with a constant force (fx, fy) added at the centroid of
    ``block`` to its dead load f0 (e.g. a tie force found by a user's study)."""
    index = structure.block_index()
    if block not in index:
        raise InputError(f"structure '{structure.name}': no movable block '{block}'; expected one of "
                         f"{', '.join(structure.blocks[:8])}{', ...' if structure.n_blocks > 8 else ''}")
    s = copy.deepcopy(structure)
    s.dead[index[block]] += (float(fx), float(fy))
    s.name = name or f"{structure.name}_{block}_force"
    return s


def with_load_angle(structure: Structure, degrees: float) -> Structure:
    """A copy with every live force rotated by ``degrees`` counter-clockwise (in space:
    about the vertical axis z, forces and couples alike)."""
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    out = copy.deepcopy(structure)
    if in_space(structure):
        turn = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])  # row vectors: v @ turn
        out.live = structure.live @ turn
        out.live_m = structure.live_m @ turn
        return out
    turn = np.array([[c, s], [-s, c]])
    out.live = structure.live @ turn
    # a live point load's moment about its block's centroid turns with its force (a couple
    # the file gave stays: a couple in the plane does not change as the forces turn)
    from .loads import moment
    index, live_m = structure.block_index(), np.array(structure.live_m, dtype=float)
    loads = []
    for p in structure.point_loads:
        if p.kind == "live":
            j, f = index[p.block], np.asarray(p.force, dtype=float)
            live_m[j] += moment(p.at, structure.centroid[j], f @ turn) - moment(p.at, structure.centroid[j], f)
            p = dataclasses.replace(p, force=tuple(float(v) for v in f @ turn))
        loads.append(p)
    out.live_m, out.point_loads = live_m, loads
    return out


def with_block_sizes(structure: Structure, factors) -> Structure:
    """A copy with block j's size scaled by factors[j] in place: its weight and live force
    scale with its area (factor squared), each joint's half-length with the smaller factor
    of its two bodies (supports do not change); positions are kept."""
    f = np.asarray(factors, dtype=float)
    out = copy.deepcopy(structure)
    out.dead = structure.dead * (f ** 2)[:, None]
    out.live = structure.live * (f ** 2)[:, None]
    ia, ib = structure.contact_blocks()
    fa = np.where(ia >= 0, f[ia], np.inf)
    fb = np.where(ib >= 0, f[ib], np.inf)
    out.d = structure.d * np.minimum(fa, fb)
    return out
