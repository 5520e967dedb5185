"""The result folder of a solve in space, written by :func:`write_results3d` alone:
summary.csv, blocks.csv, contacts.csv, runs.csv (and methods.csv for ``--method all``).

Columns, in the order written (``docs/guide/results.md`` gives their meanings):

* ``summary.csv`` (:data:`SUMMARY_COLUMNS3D`), one row: ``instance``, ``alpha``,
  ``certified``, ``alpha_associative``, ``alpha_stalled``, ``gap_stalled``, ``status``,
  ``message``, ``method``, ``path``,
  ``residual``, ``n_blocks``, ``n_supports``, ``n_interfaces``, ``n_contacts``,
  ``first_alpha``, ``first_time_s``, ``wall_time_s``, ``cone_programs``, ``lps``,
  ``dimension``, ``source``, ``mu``, ``unit_weight``, ``live_load``, ``defaults_applied``,
  ``length_unit``, ``force_unit``, ``seed``, ``time_limit``, ``picture``, ``view``,
  ``alpha_lower``, ``proven_global``, ``alpha_lower_seconds``, ``alpha_lower_check``.
  ``method`` is the method's name as ``--method`` spells it and ``path`` how its state
  was found and certified (e.g. ``gap+certify-lp``), as in runs.csv. ``live_load`` is the
  live force per unit weight applied to the blocks' weight (``X Y Z``), empty when the
  input gave live point loads and no ``live_load`` (alpha then multiplies those alone).
* ``blocks.csv`` and ``contacts.csv``: :mod:`lamodel.output.tables3d` (centroids, loads and
  their moments, motions; one row per contact point with its frame, N, T1, T2 and mode).
  The statics is rebuilt from these two files and alpha alone. Without a certified state
  alpha, the motions and the forces are empty (NaN) and the modes ``unknown``.
* ``runs.csv`` (:data:`RUN_COLUMNS3D`): one row per method run: ``run``, ``method``,
  ``alpha_raw`` (its own answer), ``alpha_certified`` (that answer certified),
  ``certified``, ``path`` (how the certified state was found and certified), ``seconds``.
* ``methods.csv``: the methods side by side, the columns of
  :data:`lamodel.output.methods.METHOD_COLUMNS`.

Floats are written with 17 significant digits (a round trip is exact).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ..io.files import atomic_write
from ..search.state import CERTIFIED, NOT_CERTIFIED
from ..structure3d import Structure3D
from .methods import METHOD_COLUMNS
from .tablefiles import FLOAT_FORMAT
from .tables3d import blocks_table, contacts_table
from .words import stall_columns

#: summary.csv's columns, in the order written (any other column after them).
SUMMARY_COLUMNS3D = (
    "instance", "alpha", "certified", "alpha_associative", "alpha_stalled", "gap_stalled", "status", "message",
    "method", "path", "residual", "n_blocks", "n_supports", "n_interfaces", "n_contacts", "first_alpha", "first_time_s", "wall_time_s",
    "cone_programs", "lps", "dimension", "source", "mu", "unit_weight", "live_load", "defaults_applied",
    "length_unit", "force_unit", "seed", "time_limit", "picture", "view",
    "alpha_lower", "proven_global", "alpha_lower_seconds", "alpha_lower_check")
#: runs.csv's columns, in the order written.
RUN_COLUMNS3D = ("run", "method", "alpha_raw", "alpha_certified", "certified", "path", "seconds")

#: What each method is, in methods.csv's notes.
NOTES = {
    "associative": "the associative cone program (an upper bound); its mechanism certified",
    "gap": "the gap alternation from the associative statics (rho 1e3, 1e4)",
    "successive-lp": "successive cone programming (capacities from the previous normal forces, relaxed)",
    "lamodel": "the certified search (as in the plane): gap alternation, descents, continuations, the GA",
}


def _csv(frame: pd.DataFrame, path: Path) -> str:
    floats = frame.select_dtypes("float").columns
    frame = frame.assign(**{c: frame[c] + 0.0 for c in floats})   # + 0.0: -0.0 (a block at rest) is written 0
    return atomic_write(path, lambda tmp: frame.to_csv(tmp, index=False, float_format=FLOAT_FORMAT,
                                                       lineterminator="\n", na_rep=""))


def summary_row(s: Structure3D, result, method: str, extra: dict) -> dict:
    """The row of summary.csv (see the module doc) for a :class:`Result3D`."""
    state = result.state
    meta = s.meta
    live = meta.get("live_load")
    row = {
        "instance": s.name, "alpha": result.alpha, "certified": state is not None,
        "alpha_associative": result.associative, **stall_columns(getattr(result, "stalled", None)),
        "status": result.status, "message": result.message,
        "method": method, "path": result.path,
        "residual": max(state.residual.values()) if state is not None and state.residual else np.nan,
        "n_blocks": s.n_blocks, "n_supports": len(s.supports), "n_interfaces": s.n_interfaces,
        "n_contacts": s.n_points, "first_alpha": result.first_alpha, "first_time_s": result.first_time,
        "wall_time_s": result.seconds, "cone_programs": result.n_cone, "lps": result.n_lp,
        "dimension": 3, "source": meta.get("source", ""), "mu": meta.get("mu", np.nan),
        "unit_weight": meta.get("unit_weight", np.nan),
        "live_load": " ".join(f"{float(c):.17g}" for c in live) if live is not None else "",
        "defaults_applied": " ".join(meta.get("defaults") or []),
        "length_unit": s.units.get("length", ""), "force_unit": s.units.get("force", ""),
    }
    row.update(extra)
    return row


def bound_columns3d(s: Structure3D, result, search_seconds: float, prove: float | None = None, beside=None) -> dict:
    """summary.csv's columns of the proven lower bound in space
    (:func:`lamodel.output.report.bound_columns`): the top of the range is the certified
    alpha, else the associative bound; none for an unstable structure or one that does
    not collapse. ``beside``: the bound started beside the search (see
    :func:`~lamodel.output.report.bound_columns`)."""
    from .report import bound_columns
    upper = result.alpha if result.state is not None else result.associative
    ok = result.status in (CERTIFIED, NOT_CERTIFIED)
    return bound_columns(s, upper if ok else np.nan, result.state is not None, search_seconds, prove, beside)


def runs_frame(runs: list) -> pd.DataFrame:
    """runs.csv from (method, its ``Result3D.methods`` entry or a row) pairs."""
    rows = []
    for k, (method, m) in enumerate(runs, start=1):
        cert = m.get("own", m.get("certified", np.nan))
        rows.append({"run": k, "method": method, "alpha_raw": m.get("raw", np.nan), "alpha_certified": cert,
                     "certified": bool(np.isfinite(cert)), "path": m.get("own_path", m.get("path", "")),
                     "seconds": m.get("seconds", np.nan)})
    return pd.DataFrame(rows, columns=list(RUN_COLUMNS3D))


def methods_frame3d(runs: pd.DataFrame, iterations: dict) -> pd.DataFrame:
    """methods.csv's table from runs.csv's (``iterations``: method -> cone programs and LPs
    of the run that produced it)."""
    cert = runs["alpha_certified"].to_numpy(dtype=float)
    best = np.nanmin(cert) if np.isfinite(cert).any() else np.nan
    return pd.DataFrame({
        "method": runs["method"], "alpha_raw": runs["alpha_raw"], "alpha_certified": cert,
        "certified": runs["certified"], "gap_to_best": cert - best, "seconds": runs["seconds"],
        "iterations": [int(iterations.get(m, 0)) for m in runs["method"]],
        "notes": [NOTES.get(m, "") for m in runs["method"]],
    }, columns=list(METHOD_COLUMNS))


def write_results3d(folder, s: Structure3D, result, summary: dict, runs: pd.DataFrame,
                    methods: pd.DataFrame | None = None) -> list:
    """Write the result folder's tables into ``folder`` (see the module doc); returns
    their paths. Without a certified state the forces and motions are NaN, never zeros."""
    folder = Path(folder)
    state = result.state
    forces = None if state is None else np.column_stack([state.N, state.T1, state.T2])
    order = [c for c in SUMMARY_COLUMNS3D if c in summary] + [c for c in summary if c not in SUMMARY_COLUMNS3D]
    tables = {"summary.csv": pd.DataFrame([summary], columns=order), "blocks.csv": blocks_table(s, result.motions),
              "contacts.csv": contacts_table(s, forces, None if state is None else state.modes),
              "runs.csv": runs}
    if methods is not None:
        tables["methods.csv"] = methods
    return [_csv(frame, folder / name) for name, frame in tables.items()]
