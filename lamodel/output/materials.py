"""The joints' strengths a solve assumed, as the report states them among its inputs: the
compressive strength f_c, the tensile strength f_t and the cohesion c0 (and, in the plane,
the joints' thickness b), in the structure's units ({doc}`../method/materials`).

A structure gives them for every joint, per body or per joint; once read, each joint (each
interface in space) has its own values, so the report summarises them by value: the value
every joint has, or each value with the joints that have it (the few named). What-ifs
given on the command line (``--fc``, ``--ft``, ``--cohesion``) replace the file's values
on every joint and are named as such. A dry structure's report says so in one line.
"""
from __future__ import annotations

import numpy as np

#: Joints named at most beside a value that only a few joints have.
NAMED_JOINTS = 4
#: Distinct values listed one by one at most (more: their range).
LISTED_VALUES = 4

#: (field, the report's name, what the default means)
FIELDS = (("fc", "compressive strength fc", "no crushing"),
          ("ft", "tensile strength ft", "no tension"),
          ("cohesion", "cohesion c0", "no cohesion"))

DRY = ("dry joints (eq. 4): infinitely strong in compression, no tension, no cohesion; "
       "friction alone limits the shear")


def stress_unit(units: dict | None) -> str:
    """The unit of a stress in a structure's units (its force per length squared), e.g.
    ``kN/m²``; empty when the structure is dimensionless."""
    units = units or {}
    force, length = units.get("force"), units.get("length")
    return f"{force}/{length}²" if force and length else ""


def joints_of(structure):
    """(the joints' names, the index of one contact of each, their kind): the contacts in the
    plane (the restraints a file gave left out), the interfaces in space (one point each)."""
    if getattr(structure, "dimension", 2) == 3:
        first = np.full(structure.n_interfaces, -1)
        for p, i in enumerate(structure.point_interface):
            if first[i] < 0:
                first[i] = p
        kept = first >= 0
        names = [f"{structure.iface_a[i]}|{structure.iface_b[i]} ({structure.interfaces[i]})"
                 for i in np.flatnonzero(kept)]
        return names, first[kept], "interface"
    n = structure.n_contacts - int(getattr(structure, "restraints", 0) or 0)
    names = [f"{a}|{b} ({c})" for c, a, b in zip(structure.contacts[:n], structure.block_a, structure.block_b)]
    return names, np.arange(n), "joint"


def _value(v: float, unit: str) -> str:
    return "infinite" if np.isinf(v) else f"{v:.6g} {unit}".rstrip()


def summarise(values, ids, kind: str, unit: str) -> str:
    """One field's values over the joints, in words (see the module doc)."""
    values = np.asarray(values, dtype=float)
    n = len(values)
    plural = lambda k: f"{k} {kind}{'s' if k != 1 else ''}"  # noqa: E731
    distinct, counts = np.unique(values, return_counts=True)
    if len(distinct) == 1:
        return f"{_value(distinct[0], unit)} on every {kind} ({n})"
    if len(distinct) > LISTED_VALUES:
        finite = values[np.isfinite(values)]
        text = (f"{finite.min():.6g} to {_value(finite.max(), unit)} over {plural(len(finite))} "
                f"({len(distinct)} values)")
        infinite = n - len(finite)
        return text + (f"; infinite on {plural(infinite)}" if infinite else "")
    parts = []
    for k in np.argsort(-counts, kind="stable"):
        v, c = distinct[k], int(counts[k])
        named = [str(ids[i]) for i in np.flatnonzero(values == v)]
        shown = f": {', '.join(named)}" if c <= NAMED_JOINTS else ""
        parts.append(f"{_value(v, unit)} on {plural(c)}{shown}")
    return "; ".join(parts)


def strength_inputs(structure, asked: dict | None = None) -> list[tuple[str, str]]:
    """The report's input rows (name, value) on the joints' strengths of ``structure`` as
    solved; ``asked``: the what-ifs given on the command line ({"fc": 20, ...}, None or
    missing: not given). One row for a dry structure."""
    asked = {k: v for k, v in (asked or {}).items() if v is not None}
    unit = stress_unit(getattr(structure, "units", None))
    ids, at, kind = joints_of(structure)
    if not getattr(structure, "has_materials", False):
        rows = [("joint strengths", DRY)]
    else:
        rows = [("stress unit", unit or "- (dimensionless: the file's force per length squared)")]
        for name, label, default in FIELDS:
            values = np.asarray(getattr(structure, name), dtype=float)[at]
            plain = np.all(np.isinf(values)) if name == "fc" else np.all(values == 0)
            rows.append((label, summarise(values, ids, kind, unit) + (f": {default}" if plain else "")))
        if getattr(structure, "dimension", 2) == 2:
            length = (getattr(structure, "units", None) or {}).get("length", "")
            values = np.asarray(structure.thickness, dtype=float)[at]
            rows.append(("joint thickness b (out of the plane)", summarise(values, ids, kind, length)))
    if asked:
        given = ", ".join(f"--{k} {v:g}" for k, v in asked.items())
        rows.append(("set on the command line", f"{given}{f' ({unit})' if unit else ''} on every {kind}, replacing the file's values"))
    return rows


def strength_line(structure, asked: dict | None = None) -> str:
    """The same in one line (the browser view's subtitle in space)."""
    return "; ".join(f"{k}: {v}" for k, v in strength_inputs(structure, asked) if k != "stress unit")
