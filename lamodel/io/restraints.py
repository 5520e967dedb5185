"""Restraints: bounded one-way reactions a JSON geometry gives explicitly (not found from
the polygons), such as the passive resistance of a bridge's fill on the arch ring.

A restraint pushes a movable block from a support along a fixed direction, with a force
between 0 and its ``capacity``, whatever the block's other forces: it is a contact of
eq. (1)-(4) whose support is body a, whose normal is the direction, without friction or
cohesion (so no tangential force, and the fictitious cohesion mu |N| of the seed is 0)
and whose compressive strength caps the normal force at the capacity
(:mod:`lamodel.formulation.joints`: ``|N| <= 2 d b f_c``). Its half-length ``d`` is the
segment over which the pressure acts; the resultant may sit anywhere on it (the N-M
parabola of a bounded pressure). It opens freely when the block moves away from the
support: a restraint never pulls. JSON::

    "restraints": [{"support": "fill_left", "block": "v3", "at": [x, y], "direction": [1, 0],
                    "half_length": 0.12, "capacity": 8.5, "thickness": 1.0}]

``thickness`` (default 1) is the out-of-plane width, so that ``f_c = capacity / (2 d b)``
is the bounding pressure.
"""
from __future__ import annotations

import json

import numpy as np

from ..errors import InputError
from .jsonfields import json_object, number

RESTRAINT_FIELDS = ("support", "block", "at", "direction", "half_length", "capacity", "thickness")


def _pair(value, at, what):
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise InputError(f"{at}: {what} is {json.dumps(value)[:40]}; expected a pair [x, y] of numbers")
    return [number(v, at, what) for v in value]


def restraint_contacts(spec, where, ids, is_support) -> dict | None:
    """The restraints of the file as contact columns (``a``, ``b`` body positions,
    ``centre``, ``normal``, ``d``, ``fc``, ``thickness``), or None when it has none."""
    given = spec.get("restraints")
    if given is None:
        return None
    if not isinstance(given, list):
        raise InputError(f"{where}: 'restraints' is {json.dumps(given)[:40]}; expected a list of "
                         "{\"support\", \"block\", \"at\", \"direction\", \"half_length\", \"capacity\"}")
    position = {b: k for k, b in enumerate(ids)}
    cols = {key: [] for key in ("a", "b", "centre", "normal", "d", "fc", "thickness")}
    for i, raw in enumerate(given):
        at = f"{where}: restraints[{i}]"
        r = json_object(raw, at, "the restraint", RESTRAINT_FIELDS)
        missing = [key for key in RESTRAINT_FIELDS[:-1] if key not in r]
        if missing:
            raise InputError(f"{at} has no '{missing[0]}'; expected the fields {', '.join(RESTRAINT_FIELDS[:-1])}")
        support, block = str(r["support"]), str(r["block"])
        if support not in position or not is_support[position[support]]:
            raise InputError(f"{at}: 'support' is '{support}'; expected the id of a support body")
        if block not in position or is_support[position[block]]:
            raise InputError(f"{at}: 'block' is '{block}'; expected the id of a movable block")
        direction = np.array(_pair(r["direction"], at, "'direction'"))
        norm = float(np.hypot(*direction))
        if norm == 0:
            raise InputError(f"{at}: 'direction' is [0, 0]; expected the direction the restraint pushes the block")
        d = number(r["half_length"], at, "'half_length'", 0.0)
        capacity = number(r["capacity"], at, "'capacity'", 0.0)
        thickness = number(r.get("thickness", 1.0), at, "'thickness'", 0.0)
        for key, value in (("half_length", d), ("capacity", capacity), ("thickness", thickness)):
            if value == 0:
                raise InputError(f"{at}: '{key}' is 0; expected a number > 0 (omit the restraint for none)")
        cols["a"].append(position[support])
        cols["b"].append(position[block])
        cols["centre"].append(_pair(r["at"], at, "'at'"))
        cols["normal"].append(direction / norm)
        cols["d"].append(d)
        cols["fc"].append(capacity / (2 * d * thickness))
        cols["thickness"].append(thickness)
    if not cols["a"]:
        return None
    return {key: np.array(value, dtype=int if key in ("a", "b") else float) for key, value in cols.items()}


def restraints_of(structure, first: int) -> list:
    """The JSON restraints of a structure whose contacts from ``first`` on are restraints."""
    out = []
    for k in range(first, structure.n_contacts):
        d, b = float(structure.d[k]), float(structure.thickness[k])
        out.append({"support": structure.block_a[k], "block": structure.block_b[k],
                    "at": structure.centre[k].tolist(), "direction": structure.normal[k].tolist(),
                    "half_length": d, "capacity": float(structure.fc[k]) * 2 * d * b, "thickness": b})
    return out
