"""Compare two limit-analysis results (result folders or their summary.csv files).

``lamodel compare A B [--atol 1e-5]`` (or ``python scripts/compare.py A B``) prints a table of the differences and
exits with

* 0 when A and B agree within the tolerance,
* 1 when they differ,
* 2 on a malformed or missing input (one line ``compare.py: error: <message>`` on stderr).

A and B differ when any of the following holds:

* the collapse multipliers differ: ``|alpha_B - alpha_A| > atol``;
* ``certified`` differs;
* the units differ (``length_unit``, ``force_unit`` of the summaries; none against some
  counts as different): the numbers are not comparable;
* the structures differ: other block ids, other contact ids, a contact joining other
  bodies, or another number of blocks or contacts in the summaries (then the row
  ``structure`` says "different structures" and contacts and blocks are not matched:
  their forces and motions would not be comparable);
* a contact (matched by contact id) changed its mode;
* a contact force differs, matched by contact id:
  ``max |N_B - N_A|`` (likewise V, M) ``> atol * max(1, max |N| of A)`` (the row
  ``max |dN|`` shows that difference; its A and B are N at the contact where it is largest) — the forces are
  measured against the largest normal force of A, so the test is relative for heavy
  structures and absolute for light ones;
* a block displacement differs, matched by block id:
  ``max |ux_B - ux_A|`` (likewise uy, theta) ``> atol * max(1, max |u| of A)``, where
  ``max |u|`` is the largest of |ux|, |uy|, |theta| over the blocks of A (the mechanism is
  normalised by ``sum(live . u) = 1``, so its size is fixed by the live load).

NaN equals NaN; NaN against a number is a difference. Rows ``instance`` and
``alpha_associative`` are shown for information and never count as differences.

Two result folders of structures in space (``dimension`` 3 in summary.csv,
:mod:`lamodel.output.results3d`) are compared by the same rules, with their own quantities:
``status`` differs when the statuses differ; the structures differ when the numbers of
blocks, interfaces or contact points differ, or their ids, or the bodies a contact point
joins; a contact point is matched by its interface and its place among the interface's
points (``i3#2``: the second point of interface i3), its forces are N, T1, T2 and its mode
one of the 3D modes; a block's motion is ``(ux, uy, uz, rx, ry, rz)``. A planar result
and a result in space are not compared (InputError, exit 2).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError
from .folder import TABLE_FILES
from .results import Results, _canonical
from .tablefiles import read_table as _read_table, summary_folder as _summary_folder

DEFAULT_ATOL = 1e-5
FORCE_COLUMNS = ("N", "V", "M")
DISPLACEMENT_COLUMNS = ("ux", "uy", "theta")
TABLE_COLUMNS = ["A", "B", "difference", "tolerance", "differs", "detail"]


@dataclass(frozen=True)
class Matching:
    """What is matched between two results of one dimension: the contact's id column and
    its name in the table, the force and motion columns, the counts of the summary."""

    contact: str
    noun: str
    forces: tuple
    motions: tuple
    counts: tuple


PLANE = Matching("contact", "contact", FORCE_COLUMNS, DISPLACEMENT_COLUMNS,
                 (("n_blocks", "blocks"), ("n_contacts", "contacts")))
SPACE = Matching("point", "contact point", ("N", "T1", "T2"), ("ux", "uy", "uz", "rx", "ry", "rz"),
                 (("n_blocks", "blocks"), ("n_interfaces", "interfaces"), ("n_contacts", "contact points")))

#: The columns of a 3D result folder that the comparison reads (:mod:`lamodel.output.results3d`).
SPACE_COLUMNS = {
    "summary": {"instance": "id", "alpha": "float", "certified": "bool", "alpha_associative": "float",
                "status": "str", "n_blocks": "int", "n_interfaces": "int", "n_contacts": "int"},
    "blocks": {"block": "id", **{c: "float" for c in SPACE.motions}},
    "contacts": {"interface": "id", "block_a": "id", "block_b": "id", **{c: "float" for c in SPACE.forces},
                 "mode": "str"},
}


@dataclass
class SpaceResults:
    """The tables of a 3D result folder that a comparison reads; ``contacts`` gains the
    column ``point`` (interface#k, the k-th point of the interface)."""

    summary: pd.DataFrame
    blocks: pd.DataFrame
    contacts: pd.DataFrame
    matching = SPACE

    instance = property(lambda self: str(self.summary["instance"].iloc[0]), doc="Name of the structure.")
    alpha = property(lambda self: float(self.summary["alpha"].iloc[0]), doc="The certified multiplier (NaN: none).")
    certified = property(lambda self: bool(self.summary["certified"].iloc[0]), doc="Whether alpha is certified.")
    alpha_associative = property(lambda self: float(self.summary["alpha_associative"].iloc[0]),
                                 doc="The associative bound.")
    status = property(lambda self: str(self.summary["status"].iloc[0]), doc="The outcome of the solve.")


def _is_space(folder: Path) -> bool:
    """Whether summary.csv says ``dimension`` 3."""
    summary = _read_table(folder / TABLE_FILES["summary"])
    return "dimension" in summary.columns and summary["dimension"].astype(str).str.strip().isin(["3", "3.0"]).any()


def _space_table(folder: Path, table: str) -> pd.DataFrame:
    path = folder / TABLE_FILES[table]
    contract = (SPACE_COLUMNS[table], "block" if table == "blocks" else None)
    return _canonical(_read_table(path), table, str(path), contract)


def read_result(path):
    """A result folder (or its summary.csv) for a comparison: a planar one as
    :class:`Results`, one in space as :class:`SpaceResults`; InputError, one line, when
    it is neither."""
    folder = _summary_folder(path)
    if not _is_space(folder):
        return Results.read(path)
    tables = {t: _space_table(folder, t) for t in SPACE_COLUMNS}
    contacts = tables["contacts"]
    contacts.insert(0, "point", contacts["interface"] + "#" + (contacts.groupby("interface").cumcount() + 1).astype(str))
    return SpaceResults(**tables)


def _dimension(r) -> str:
    return "a result in space (3D)" if getattr(r, "matching", PLANE) is SPACE else "a planar result (2D)"


def _ids(values, limit: int = 10) -> str:
    values = list(values)
    shown = ", ".join(str(v) for v in values[:limit])
    return shown + (f", ... ({len(values) - limit} more)" if len(values) > limit else "")


def _abs_diff(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """|b - a| elementwise, with NaN vs NaN counted as 0 and NaN vs a number as inf."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    with np.errstate(invalid="ignore"):
        d = np.abs(b - a)
    both = np.isnan(a) & np.isnan(b)
    d[both] = 0.0
    d[np.isnan(d)] = np.inf
    return d


def _scale(values: np.ndarray) -> float:
    """max(1, largest finite |value|)."""
    v = np.abs(np.asarray(values, dtype=float).ravel())
    v = v[np.isfinite(v)]
    return max(1.0, float(v.max())) if v.size else 1.0


def _matched_rows(a: pd.DataFrame, b: pd.DataFrame, key: str, columns, tol: float, kind: str, rows: dict):
    """Largest |B - A| of each column over the rows of a and b with the same ``key``."""
    common = a[[key, *columns]].merge(b[[key, *columns]], on=key, suffixes=("_A", "_B"), sort=False)
    for c in columns:
        label = f"max |d{c}|"
        if common.empty:
            rows[label] = dict(A="", B="", difference=0.0, tolerance=tol, differs=False,
                               detail=f"no common {kind} ids")
            continue
        d = _abs_diff(common[f"{c}_A"].to_numpy(), common[f"{c}_B"].to_numpy())
        i = int(np.argmax(d))
        worst = common.iloc[i]
        rows[label] = dict(A=worst[f"{c}_A"], B=worst[f"{c}_B"], difference=float(d[i]), tolerance=tol,
                           differs=bool(d[i] > tol), detail=f"{c} at {kind} {worst[key]}")


def _id_sets(a: pd.DataFrame, b: pd.DataFrame, key: str, kind: str, rows: dict):
    ia, ib = list(a[key]), list(b[key])
    only_a = [x for x in ia if x not in set(ib)]
    only_b = [x for x in ib if x not in set(ia)]
    parts = []
    if only_a:
        parts.append(f"only in A: {_ids(only_a)}")
    if only_b:
        parts.append(f"only in B: {_ids(only_b)}")
    rows[f"{kind}s"] = dict(A=len(ia), B=len(ib), difference=len(only_a) + len(only_b), tolerance="",
                            differs=bool(parts), detail="; ".join(parts) if parts else f"same {kind} ids")


def _different_structures(a, b, m: Matching) -> str:
    """Why A and B are not results of one structure ("" when they are)."""
    counts = [f"{int(a.summary[c].iloc[0])} vs {int(b.summary[c].iloc[0])} {kind}"
              for c, kind in m.counts if int(a.summary[c].iloc[0]) != int(b.summary[c].iloc[0])]
    if counts:
        return ", ".join(counts)
    ids = [f"other {noun} ids" for table, key, noun in (("blocks", "block", "block"), ("contacts", m.contact, m.noun))
           if set(getattr(a, table)[key]) != set(getattr(b, table)[key])]
    if ids:
        return ", ".join(ids)
    key = m.contact
    ends = a.contacts[[key, "block_a", "block_b"]].merge(
        b.contacts[[key, "block_a", "block_b"]], on=key, suffixes=("_A", "_B"))
    moved = ends[(ends.block_a_A != ends.block_a_B) | (ends.block_b_A != ends.block_b_B)]
    return f"{m.noun} {moved[key].iloc[0]} joins other bodies" if len(moved) else ""


def _units(r) -> str:
    """The result's units as its summary gives them ('none': dimensionless)."""
    summary = getattr(r, "summary", None)
    row = summary.iloc[0] if isinstance(summary, pd.DataFrame) and len(summary) else {}
    given = [str(row.get(key, "") or "") for key in ("length_unit", "force_unit")]
    given = ["" if g in ("nan", "-") else g for g in given]
    return ", ".join(f"{k} {v}" for k, v in zip(("length", "force"), given) if v) or "none"


def _sizes(r, m: Matching) -> str:
    """The structure's counts, as its tables give them."""
    if m is PLANE:
        return f"{len(r.blocks)} blocks, {len(r.contacts)} contacts"
    return f"{len(r.blocks)} blocks, {r.contacts['interface'].nunique()} interfaces, {len(r.contacts)} contact points"


def compare_results(a, b, atol: float = DEFAULT_ATOL):
    """Compare result B with result A (both :class:`Results`, or both :class:`SpaceResults`:
    :func:`read_result` reads either).

    Returns ``(table, differ)``: ``table`` is a DataFrame indexed by quantity (instance,
    alpha, certified, alpha_associative, blocks, contacts, mode changes, max |dN|, max |dV|,
    max |dM|, max |dux|, max |duy|, max |dtheta|; in space also status, and contact points,
    T1, T2, uz, rx, ry, rz) with columns A, B, difference, tolerance, differs, detail;
    ``differ`` is True when any row differs beyond the tolerance (see the module docstring
    for the rules and the scaling of the tolerance). InputError when one is planar and the
    other in space.
    """
    atol = float(atol)
    if not math.isfinite(atol) or atol < 0:
        raise InputError(f"atol is {atol}; expected a finite tolerance >= 0")
    m = getattr(a, "matching", PLANE)
    if getattr(b, "matching", PLANE) is not m:
        raise InputError(f"A is {_dimension(a)} and B {_dimension(b)}; expected two results of the same "
                         "dimension")
    rows = {}
    rows["instance"] = dict(A=a.instance, B=b.instance, difference="", tolerance="", differs=False,
                            detail="same instance" if a.instance == b.instance else "different names (not counted)")
    d_alpha = float(_abs_diff([a.alpha], [b.alpha])[0])
    different = _different_structures(a, b, m)
    rows["structure"] = dict(A=_sizes(a, m), B=_sizes(b, m), difference="", tolerance="",
                             differs=bool(different),
                             detail=f"different structures: {different}" if different else "same structure")
    rows["alpha"] = dict(A=a.alpha, B=b.alpha, difference=b.alpha - a.alpha if math.isfinite(d_alpha) else d_alpha,
                         tolerance=atol, differs=bool(d_alpha > atol), detail="B - A")
    rows["certified"] = dict(A=a.certified, B=b.certified, difference="", tolerance="",
                             differs=a.certified != b.certified,
                             detail="same" if a.certified == b.certified else "certification differs")
    if m is SPACE:
        rows["status"] = dict(A=a.status, B=b.status, difference="", tolerance="", differs=a.status != b.status,
                              detail="same" if a.status == b.status else "status differs")
    rows["alpha_associative"] = dict(A=a.alpha_associative, B=b.alpha_associative,
                                     difference=b.alpha_associative - a.alpha_associative, tolerance="",
                                     differs=False, detail="information (not counted)")
    units_a, units_b = _units(a), _units(b)
    rows["units"] = dict(A=units_a, B=units_b, difference="", tolerance="", differs=units_a != units_b,
                         detail="same" if units_a == units_b else "other units: the numbers are not comparable")
    _id_sets(a.blocks, b.blocks, "block", "block", rows)
    _id_sets(a.contacts, b.contacts, m.contact, m.noun, rows)

    if different:  # contacts and blocks of two structures are not matched by their ids
        table = pd.DataFrame.from_dict(rows, orient="index")[TABLE_COLUMNS].astype(object)
        return table, True
    key = m.contact
    modes = a.contacts[[key, "mode"]].merge(b.contacts[[key, "mode"]], on=key, suffixes=("_A", "_B"), sort=False)
    changed = modes[modes["mode_A"] != modes["mode_B"]]
    rows["mode changes"] = dict(
        A="", B="", difference=len(changed), tolerance=0, differs=len(changed) > 0,
        detail=_ids((f"{getattr(r, key)} ({r.mode_A} -> {r.mode_B})" for r in changed.itertuples()), limit=3)
        if len(changed) else f"none among {len(modes)} common {m.noun}s")

    force_tol = atol * _scale(a.contacts["N"].to_numpy())
    _matched_rows(a.contacts, b.contacts, key, m.forces, force_tol, m.noun, rows)
    disp_tol = atol * _scale(a.blocks[list(m.motions)].to_numpy())
    _matched_rows(a.blocks, b.blocks, "block", m.motions, disp_tol, "block", rows)

    table = pd.DataFrame.from_dict(rows, orient="index")[TABLE_COLUMNS].astype(object)
    return table, bool(table["differs"].any())


def print_comparison(table: pd.DataFrame, differ: bool, a, b, atol: float) -> int:
    """Print the table and the verdict; returns the exit status (0 agree, 1 differ)."""
    width = int(table["detail"].astype(str).str.len().max()) if len(table) else 0
    with pd.option_context("display.width", 250, "display.float_format", lambda v: f"{v:.10g}"):
        text = table.to_string(formatters={"detail": lambda v: f"{v:<{width}}"})  # left-aligned
    print(f"A: {a}\nB: {b}\n")
    print("\n".join(line.rstrip() for line in text.splitlines()))
    if any(str(i).startswith("max |d") for i in table.index):
        print("(max |dX|: difference = the largest |B - A| of X; A and B = X where it is largest)")
    if "structure" in table.index and bool(table.loc["structure", "differs"]):
        why = str(table.loc["structure", "detail"]).split(": ", 1)[-1]
        print(f"\nA and B are different structures ({why}): their contacts and blocks are not compared")
        return 1
    bad = list(table.index[table["differs"].astype(bool)])
    if differ:
        print(f"\nA and B differ (atol={atol:g}): {', '.join(bad)}")
        return 1
    print(f"\nA and B agree (atol={atol:g})")
    return 0
