"""Compare two limit-analysis results (result folders or their summary.csv files).

``lamodel compare A B [--atol 1e-5]`` (or ``python scripts/compare.py A B``) prints a table of the differences and
exits with

* 0 when A and B agree within the tolerance,
* 1 when they differ,
* 2 on a malformed or missing input (one line ``compare.py: error: <message>`` on stderr).

A and B differ when any of the following holds:

* the collapse multipliers differ: ``|alpha_B - alpha_A| > atol``;
* ``certified`` differs;
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
"""
from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..errors import InputError
from .results import Results

DEFAULT_ATOL = 1e-5
FORCE_COLUMNS = ("N", "V", "M")
DISPLACEMENT_COLUMNS = ("ux", "uy", "theta")
TABLE_COLUMNS = ["A", "B", "difference", "tolerance", "differs", "detail"]


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


def _different_structures(a: Results, b: Results) -> str:
    """Why A and B are not results of one structure ("" when they are)."""
    counts = [f"{int(a.summary[c].iloc[0])} vs {int(b.summary[c].iloc[0])} {kind}"
              for c, kind in (("n_blocks", "blocks"), ("n_contacts", "contacts"))
              if int(a.summary[c].iloc[0]) != int(b.summary[c].iloc[0])]
    if counts:
        return ", ".join(counts)
    ids = [f"other {key} ids" for table, key in (("blocks", "block"), ("contacts", "contact"))
           if set(getattr(a, table)[key]) != set(getattr(b, table)[key])]
    if ids:
        return ", ".join(ids)
    ends = a.contacts[["contact", "block_a", "block_b"]].merge(
        b.contacts[["contact", "block_a", "block_b"]], on="contact", suffixes=("_A", "_B"))
    moved = ends[(ends.block_a_A != ends.block_a_B) | (ends.block_b_A != ends.block_b_B)]
    return f"contact {moved.contact.iloc[0]} joins other bodies" if len(moved) else ""


def compare_results(a: Results, b: Results, atol: float = DEFAULT_ATOL):
    """Compare result B with result A.

    Returns ``(table, differ)``: ``table`` is a DataFrame indexed by quantity (instance,
    alpha, certified, alpha_associative, blocks, contacts, mode changes, max |dN|, max |dV|,
    max |dM|, max |dux|, max |duy|, max |dtheta|) with columns A, B, difference, tolerance,
    differs, detail; ``differ`` is True when any row differs beyond the tolerance (see the
    module docstring for the rules and the scaling of the tolerance).
    """
    atol = float(atol)
    if not math.isfinite(atol) or atol < 0:
        raise InputError(f"atol is {atol}; expected a finite tolerance >= 0")
    rows = {}
    rows["instance"] = dict(A=a.instance, B=b.instance, difference="", tolerance="", differs=False,
                            detail="same instance" if a.instance == b.instance else "different names (not counted)")
    d_alpha = float(_abs_diff([a.alpha], [b.alpha])[0])
    different = _different_structures(a, b)
    rows["structure"] = dict(A=f"{len(a.blocks)} blocks, {len(a.contacts)} contacts",
                             B=f"{len(b.blocks)} blocks, {len(b.contacts)} contacts", difference="", tolerance="",
                             differs=bool(different),
                             detail=f"different structures: {different}" if different else "same structure")
    rows["alpha"] = dict(A=a.alpha, B=b.alpha, difference=b.alpha - a.alpha if math.isfinite(d_alpha) else d_alpha,
                         tolerance=atol, differs=bool(d_alpha > atol), detail="B - A")
    rows["certified"] = dict(A=a.certified, B=b.certified, difference="", tolerance="",
                             differs=a.certified != b.certified,
                             detail="same" if a.certified == b.certified else "certification differs")
    rows["alpha_associative"] = dict(A=a.alpha_associative, B=b.alpha_associative,
                                     difference=b.alpha_associative - a.alpha_associative, tolerance="",
                                     differs=False, detail="information (not counted)")
    _id_sets(a.blocks, b.blocks, "block", "block", rows)
    _id_sets(a.contacts, b.contacts, "contact", "contact", rows)

    if different:  # contacts and blocks of two structures are not matched by their ids
        table = pd.DataFrame.from_dict(rows, orient="index")[TABLE_COLUMNS].astype(object)
        return table, True
    modes = a.contacts[["contact", "mode"]].merge(b.contacts[["contact", "mode"]], on="contact",
                                                   suffixes=("_A", "_B"), sort=False)
    changed = modes[modes["mode_A"] != modes["mode_B"]]
    rows["mode changes"] = dict(
        A="", B="", difference=len(changed), tolerance=0, differs=len(changed) > 0,
        detail=_ids((f"{r.contact} ({r.mode_A} -> {r.mode_B})" for r in changed.itertuples()), limit=3)
        if len(changed) else f"none among {len(modes)} common contacts")

    force_tol = atol * _scale(a.contacts["N"].to_numpy())
    _matched_rows(a.contacts, b.contacts, "contact", FORCE_COLUMNS, force_tol, "contact", rows)
    disp_tol = atol * _scale(a.blocks[list(DISPLACEMENT_COLUMNS)].to_numpy())
    _matched_rows(a.blocks, b.blocks, "block", DISPLACEMENT_COLUMNS, disp_tol, "block", rows)

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
