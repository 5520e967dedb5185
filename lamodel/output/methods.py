"""Methods side by side as tables: ``methods.csv`` and each method's result folder.

``methods.csv`` (``lamodel solve --method all``): one row per method of
:data:`lamodel.search.methods.METHODS` with columns :data:`METHOD_COLUMNS` —
alpha_raw (the method's own answer, as it is), alpha_certified (that answer through
:func:`lamodel.search.certify.certify`; empty when it yields no collapse state), certified,
gap_to_best (alpha_certified minus the least alpha_certified of the table), seconds,
iterations (LPs for associative and successive-lp, Ipopt iterations for mpec and seed, the
driver's LPs and Ipopt iterations for lamodel) and notes.
"""
from __future__ import annotations

import numpy as np
import pandas as pd

from ..io.files import atomic_write
from .report import outcome_results
from .results import Results
from .tablefiles import FLOAT_FORMAT

METHOD_COLUMNS = ("method", "alpha_raw", "alpha_certified", "certified", "gap_to_best", "seconds", "iterations",
                  "notes")


def methods_frame(results: list) -> pd.DataFrame:
    """The table of :data:`METHOD_COLUMNS`, one row per MethodResult."""
    cert = np.array([r.alpha_certified for r in results], dtype=float)
    best = np.nanmin(cert) if np.isfinite(cert).any() else np.nan
    return pd.DataFrame({
        "method": [r.method for r in results],
        "alpha_raw": [r.alpha_raw for r in results],
        "alpha_certified": cert,
        "certified": [r.certified for r in results],
        "gap_to_best": cert - best,
        "seconds": [r.seconds for r in results],
        "iterations": [int(r.iterations) for r in results],
        "notes": [r.notes for r in results],
    }, columns=list(METHOD_COLUMNS))


def write_methods_csv(frame: pd.DataFrame, folder) -> str:
    """Write ``methods.csv`` into ``folder`` (atomically; floats with 17 digits)."""
    from pathlib import Path
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    return atomic_write(folder / "methods.csv", lambda tmp: frame.to_csv(
        tmp, index=False, float_format=FLOAT_FORMAT, lineterminator="\n", na_rep=""))


def method_results(result) -> Results:
    """The result folder of one method: its certified state (NaN without one), the method
    named in summary.csv's extra column ``method``."""
    return outcome_results(result.outcome(), {"method": result.method})


def methods_took(frame: pd.DataFrame) -> str:
    """How long ``--method all`` took, for the one-line result: every method's seconds (the
    kept state's method alone took its row's)."""
    return f"{frame['seconds'].sum():.1f} s for {len(frame)} methods"


def methods_text(frame: pd.DataFrame) -> str:
    """The table for a terminal, the notes of each method below it."""
    fmt = {c: (lambda v: "" if pd.isna(v) else f"{v:.6f}") for c in ("alpha_raw", "alpha_certified")}
    fmt["gap_to_best"] = lambda v: "" if pd.isna(v) else f"{v:.1e}"
    fmt["seconds"] = lambda v: f"{v:.1f}"
    table = frame.drop(columns="notes").to_string(index=False, formatters=fmt)
    return "\n".join([table, ""] + [f"  {m}: {n}" for m, n in zip(frame["method"], frame["notes"])])
