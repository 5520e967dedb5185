"""Two bridge runs side by side: the adequacy tables ``lamodel bridge --adequacy`` writes.

``lamodel compare A B`` on two such folders (or their adequacy.csv) matches the rows by
load position and prints, with the same columns and exit codes as a comparison of two
results (:mod:`lamodel.output.compare`): a row per position (A's and B's adequacy factor,
B - A, whether certified), then the governing position and factor of each. A and B differ
when the positions differ, when a factor differs by more than ``atol`` (NaN against a
number included), or when one is certified where the other is not.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError
from .adequacy import COLUMNS

ADEQUACY = "adequacy.csv"


def adequacy_path(path) -> Path | None:
    """The adequacy.csv that ``path`` names (the file, or a folder holding it without a
    summary.csv), else None."""
    p = Path(path)
    if p.name == ADEQUACY:
        return p
    if p.is_dir() and (p / ADEQUACY).exists() and not (p / "summary.csv").exists():
        return p / ADEQUACY
    return None


def read_adequacy(path) -> pd.DataFrame:
    """An adequacy table, checked: InputError (one line) on a missing file or column."""
    p = Path(path)
    if not p.exists():
        raise InputError(f"{p}: no such file; expected the adequacy.csv of a bridge run")
    try:
        df = pd.read_csv(p)
    except (ValueError, OSError) as exc:
        raise InputError(f"{p}: not a readable table ({exc})") from None
    missing = [c for c in ("position", "adequacy", "certified") if c not in df.columns]
    if missing:
        raise InputError(f"{p}: no column '{missing[0]}'; expected the columns {', '.join(COLUMNS)}")
    df["position"] = pd.to_numeric(df["position"], errors="coerce")
    df["adequacy"] = pd.to_numeric(df["adequacy"], errors="coerce")
    if df["position"].isna().any():
        raise InputError(f"{p}: a 'position' is not a number")
    df["certified"] = df["certified"].astype(str).str.lower() == "true"
    return df


def _governing(df: pd.DataFrame) -> tuple:
    """(position, factor) of the least certified factor; (nan, nan) if none is certified."""
    ok = df[df["certified"] & df["adequacy"].notna()]
    if ok.empty:
        return math.nan, math.nan
    row = ok.loc[ok["adequacy"].idxmin()]
    return float(row["position"]), float(row["adequacy"])


def compare_adequacy(a: pd.DataFrame, b: pd.DataFrame, atol: float):
    """(table, differ): rows ``x=<position>`` and ``governing``, columns A, B, difference,
    tolerance, differs, detail (module doc)."""
    rows = {}
    pa, pb = np.round(a["position"].to_numpy(float), 9), np.round(b["position"].to_numpy(float), 9)
    only_a, only_b = sorted(set(pa) - set(pb)), sorted(set(pb) - set(pa))
    rows["positions"] = dict(A=len(pa), B=len(pb), difference="", tolerance="", differs=bool(only_a or only_b),
                             detail=(f"only in A: {only_a[:5]}; only in B: {only_b[:5]}" if only_a or only_b
                                     else "same load positions"))
    ia, ib = dict(zip(pa, a.index)), dict(zip(pb, b.index))
    for x in sorted(set(pa) & set(pb)):
        ra, rb = a.loc[ia[x]], b.loc[ib[x]]
        fa, fb = float(ra["adequacy"]), float(rb["adequacy"])
        both_nan = math.isnan(fa) and math.isnan(fb)
        diff = 0.0 if both_nan else (fb - fa if not (math.isnan(fa) or math.isnan(fb)) else math.inf)
        certified = bool(ra["certified"]) == bool(rb["certified"])
        rows[f"x={x:g}"] = dict(A=fa, B=fb, difference=diff, tolerance=atol,
                                differs=bool(abs(diff) > atol or not certified),
                                detail="B - A" if certified else
                                f"certified in {'A' if ra['certified'] else 'B'} only")
    (xa, ga), (xb, gb) = _governing(a), _governing(b)
    rows["governing"] = dict(A=ga, B=gb, difference=gb - ga, tolerance=atol,
                             differs=bool(not (abs(gb - ga) <= atol or (math.isnan(ga) and math.isnan(gb)))),
                             detail=f"at x = {xa:g} in A, x = {xb:g} in B")
    table = pd.DataFrame.from_dict(rows, orient="index")[["A", "B", "difference", "tolerance", "differs", "detail"]]
    return table, bool(table["differs"].any())
