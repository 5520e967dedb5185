"""The checks a planar and a spatial block assembly share, worded once.

:meth:`lamodel.structure.Structure.validate` and :meth:`lamodel.structure3d.Structure3D.validate`
call these for what is the same in the plane and in space (ids, the bodies a contact joins,
free blocks, finite numbers, friction, a live load), and keep only what differs (a contact's
half-length in the plane, the frame of a contact point in space). Every check raises
:class:`lamodel.errors.InputError`, one line starting with ``where``.
"""
from __future__ import annotations

import numpy as np

from .errors import InputError


def check_ids(where: str, blocks: list, supports: list, contacts: tuple, has_contacts: bool):
    """At least one block and one contact; ids non-empty and unique per kind; no body both a
    block and a support. ``contacts``: (kind, ids), e.g. ("contact", [...]) or ("interface", [...])."""
    if not blocks:
        raise InputError(f"{where}: the set of blocks is empty; expected at least one movable block")
    if not has_contacts:
        raise InputError(f"{where}: there are no contacts; expected blocks resting on supports or on each other")
    for kind, ids in (("block", blocks), ("support", supports), contacts):
        seen = set()
        for i in ids:
            if not i.strip():
                raise InputError(f"{where}: a {kind} id is empty; expected non-empty ids")
            if i in seen:
                raise InputError(f"{where}: {kind} '{i}' is declared twice; expected unique ids")
            seen.add(i)
    both = set(blocks) & set(supports)
    if both:
        raise InputError(f"{where}: '{sorted(both)[0]}' is both a block and a support; expected one or the other")


def check_finite(where: str, arrays):
    """``arrays``: (name, array, owner) with ``owner(i)`` naming what row i belongs to;
    InputError at the first entry that is not a finite number."""
    for name, arr, owner in arrays:
        i = first(~np.isfinite(arr))
        if i is not None:
            raise InputError(f"{where}: {name} of {owner(i)} is not a finite number; expected finite values")


def check_ends(where: str, kind: str, ids: list, a: list, b: list, blocks: list, supports: list,
               ends=("block_a", "block_b")):
    """Each contact (of ``kind``: contact, interface) joins two declared, different bodies,
    not both supports; ``ends`` name its two bodies in the messages."""
    known, fixed = set(blocks) | set(supports), set(supports)
    for k, x, y in zip(ids, a, b):
        for end, body in zip(ends, (x, y)):
            if body not in known:
                raise InputError(f"{where}: {kind} '{k}' names unknown {end} '{body}'; "
                                 "expected a declared block or support")
        if x == y:
            raise InputError(f"{where}: {kind} '{k}' joins '{x}' to itself; expected two different bodies")
        if x in fixed and y in fixed:
            raise InputError(f"{where}: {kind} '{k}' joins two supports '{x}' and '{y}'; "
                             "expected at least one movable block")


def check_friction(where: str, mu: np.ndarray, owner):
    """No negative friction coefficient; ``owner(i)`` names the contact of entry i."""
    i = first(mu < 0)
    if i is not None:
        raise InputError(f"{where}: mu of {owner(i)} is {mu[i]:.6g}; expected a friction coefficient >= 0")


def check_touched(where: str, blocks: list, ia: np.ndarray, ib: np.ndarray):
    """Every block is body a or b of some contact (indices, -1 for a support)."""
    touched = np.zeros(len(blocks), dtype=bool)
    touched[ia[ia >= 0]] = True
    touched[ib[ib >= 0]] = True
    j = first(~touched)
    if j is not None:
        raise InputError(f"{where}: block '{blocks[j]}' touches nothing (a free body); "
                         "expected every block to have a contact")


def check_live(where: str, loaded: bool):
    """Something for alpha to multiply."""
    if not loaded:
        raise InputError(f"{where}: every live load is zero; expected a live load for alpha to multiply")


def first(mask) -> int | None:
    """The row of the first True entry of ``mask`` (any shape), or None."""
    hit = np.argwhere(np.asarray(mask))
    return int(hit[0][0]) if len(hit) else None


def check_strengths(where: str, fc, ft, cohesion, thickness, owner):
    """The joint's strengths (:mod:`lamodel.formulation.joints`): f_c > 0 (inf: none),
    f_t >= 0, cohesion >= 0, finite thickness > 0, and f_t <= f_c; ``owner(i)`` names
    contact i."""
    for name, v, ok, expected in (("fc", fc, lambda x: x > 0, "a compressive strength > 0 (inf: no crushing)"),
                                  ("ft", ft, lambda x: np.isfinite(x) & (x >= 0), "a finite tensile strength >= 0"),
                                  ("cohesion", cohesion, lambda x: np.isfinite(x) & (x >= 0), "a finite cohesion >= 0"),
                                  ("thickness", thickness, lambda x: np.isfinite(x) & (x > 0),
                                   "a finite thickness > 0")):
        i = first(~ok(np.asarray(v, float)))
        if i is not None:
            raise InputError(f"{where}: {name} of {owner(i)} is {v[i]:.6g}; expected {expected}")
    i = first(ft > fc)
    if i is not None:
        raise InputError(f"{where}: ft of {owner(i)} is {ft[i]:.6g}, above its fc {fc[i]:.6g}; "
                         "expected a tensile strength at most the compressive one")
