"""The result of one limit analysis as four tables, and their CSV files.

A result folder holds (the output contract; other code and external checkers rely on it):

``summary.csv``
    one row: instance, alpha, certified, alpha_associative, n_blocks, n_contacts, n_starts,
    n_certified, wall_time_s — then any extra columns (seed, status, message, picture, ...;
    a solve adds ``alpha_lower``: no collapse state lies below it under this load pattern,
    proven; ``proven_global``: alpha is the global minimum within 1e-6 relative;
    ``alpha_lower_seconds``, ``alpha_lower_check``: see :mod:`lamodel.bound`; without a
    certified state ``alpha_stalled`` and ``gap_stalled``: where the search came nearest a
    collapse state, never an answer).
``blocks.csv``
    one row per movable block: block, x, y (centroid), dead_x, dead_y, live_x, live_y,
    ux, uy, theta — the collapse mechanism, normalised so that ``sum(live . u) = 1``.
``contacts.csv``
    one row per contact: contact, block_a, block_b (a support's id for a support), cx, cy,
    nx, ny, d, mu, N, V, M, mode. The normal n points from a to b; ``N n + V t`` with
    ``t = (-n_y, n_x)`` and the couple M act on block a; ``N <= 0`` is compression; mode is
    one of :data:`MODES`.
``runs.csv``
    one row per start of the solver: start, source, alpha_ipopt, status, alpha_certified,
    iterations, seconds; the search writes one more, path (the lane of the plan that
    certified that start's state, :mod:`lamodel.search.plan`; empty when none).

Sign conventions are those of :mod:`lamodel.structure`. Floats are written with 17
significant digits and read back with Python's correctly rounded parser, so a
write/read round trip is bit-identical. :class:`Results` holds no solver logic: the driver
decides every value, including the contact modes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError
from .folder import TABLE_FILES, ResultFolder
from .modes import MODES
from .tablefiles import read_table as _read_table, summary_folder as _summary_folder, write_table as _write_table
from .text import aligned


# Column name -> kind, in contract order. Kinds: "id" (text, never empty), "str" (text),
# "float" (float64, empty or nan means NaN), "int" (int64, required), "Int" (nullable
# integer: empty means missing), "bool", "mode" (one of MODES).
SUMMARY_COLUMNS = {
    "instance": "id", "alpha": "float", "certified": "bool", "alpha_associative": "float",
    "n_blocks": "int", "n_contacts": "int", "n_starts": "int", "n_certified": "int",
    "wall_time_s": "float",
}
BLOCK_COLUMNS = {
    "block": "id", "x": "float", "y": "float", "dead_x": "float", "dead_y": "float",
    "live_x": "float", "live_y": "float", "ux": "float", "uy": "float", "theta": "float",
}
CONTACT_COLUMNS = {
    "contact": "id", "block_a": "id", "block_b": "id", "cx": "float", "cy": "float",
    "nx": "float", "ny": "float", "d": "float", "mu": "float",
    "N": "float", "V": "float", "M": "float", "mode": "mode",
}
RUN_COLUMNS = {
    "start": "int", "source": "str", "alpha_ipopt": "float", "status": "str",
    "alpha_certified": "float", "iterations": "Int", "seconds": "float",
}

#: table name -> (file name, column kinds, id column that must be unique or None)
TABLES = {
    "summary": (TABLE_FILES["summary"], SUMMARY_COLUMNS, None),
    "blocks": (TABLE_FILES["blocks"], BLOCK_COLUMNS, "block"),
    "contacts": (TABLE_FILES["contacts"], CONTACT_COLUMNS, "contact"),
    "runs": (TABLE_FILES["runs"], RUN_COLUMNS, "start"),
}


_TRUE = {"true", "1", "yes"}
_FALSE = {"false", "0", "no"}


# --------------------------------------------------------------------------- value parsing
class _BadValue(ValueError):
    """A cell that does not hold a value of its column's kind (message: what was expected)."""


def _is_missing(v) -> bool:
    if v is None or v is pd.NA:
        return True
    if isinstance(v, str):
        return v.strip() == ""
    try:
        return bool(pd.isna(v))
    except (TypeError, ValueError):
        return False


def _to_float(v) -> float:
    if _is_missing(v):
        return math.nan
    if isinstance(v, (bool, np.bool_)):
        raise _BadValue("expected a number")
    try:
        return float(v.strip() if isinstance(v, str) else v)
    except (TypeError, ValueError):
        raise _BadValue("expected a number") from None


def _to_int(v, nullable: bool):
    if _is_missing(v):
        if nullable:
            return pd.NA
        raise _BadValue("expected an integer")
    if isinstance(v, (bool, np.bool_)):
        raise _BadValue("expected an integer")
    if isinstance(v, (int, np.integer)):
        return int(v)
    try:
        if isinstance(v, str):
            try:
                return int(v.strip())
            except ValueError:
                pass
        f = float(v.strip() if isinstance(v, str) else v)
    except (TypeError, ValueError):
        raise _BadValue("expected an integer") from None
    if not f.is_integer():
        raise _BadValue("expected an integer")
    return int(f)


def _to_bool(v) -> bool:
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (int, np.integer)) and v in (0, 1):
        return bool(v)
    if isinstance(v, str):
        s = v.strip().lower()
        if s in _TRUE:
            return True
        if s in _FALSE:
            return False
    raise _BadValue("expected True or False")


def _to_text(v, kind: str) -> str:
    if _is_missing(v):
        if kind == "str":
            return ""
        raise _BadValue("expected a non-empty id" if kind == "id" else f"expected one of {', '.join(MODES)}")
    s = str(v)
    if kind == "mode" and s not in MODES:
        raise _BadValue(f"expected one of {', '.join(MODES)}")
    return s


def _convert_column(values, kind: str, where: str, column: str, row_ids) -> pd.Series:
    """Convert one column to its canonical dtype; InputError names the first bad cell."""
    out = []
    for i, v in enumerate(values):
        try:
            if kind == "float":
                out.append(_to_float(v))
            elif kind in ("int", "Int"):
                out.append(_to_int(v, nullable=kind == "Int"))
            elif kind == "bool":
                out.append(_to_bool(v))
            else:
                out.append(_to_text(v, kind))
        except _BadValue as exc:
            shown = "" if _is_missing(v) else str(v)
            raise InputError(f"{where}: column '{column}', {row_ids(i)}, is '{shown}'; {exc}") from None
    dtype = {"float": "float64", "int": "int64", "Int": "Int64", "bool": "bool"}.get(kind, object)
    return pd.Series(out, dtype=dtype)


def _infer_extra(values) -> pd.Series:
    """Canonical form of a column outside the contract: numbers if all cells are numbers
    (or empty), booleans if all are True/False, otherwise text."""
    s = pd.Series(list(values), dtype=object)
    if s.map(_is_missing).all():
        return pd.Series([math.nan] * len(s), dtype="float64")
    if s.map(lambda v: isinstance(v, (bool, np.bool_))).all() and len(s):
        return s.astype(bool)
    if all(isinstance(v, str) for v in s):
        low = s.str.strip().str.lower()
        if len(s) and low.isin(["true", "false"]).all():
            return low.eq("true").astype(bool)
        try:
            ints = [_to_int(v, nullable=True) for v in s]
            return pd.Series(ints, dtype="Int64" if any(x is pd.NA for x in ints) else "int64")
        except _BadValue:
            pass
        try:
            return pd.Series([_to_float(v) for v in s], dtype="float64")
        except _BadValue:
            return s
    if len(s) and s.map(lambda v: isinstance(v, (int, np.integer)) and not isinstance(v, (bool, np.bool_))).all():
        return s.astype("int64")
    if len(s) and s.map(lambda v: _is_missing(v) or isinstance(v, (int, float, np.number))
                        and not isinstance(v, (bool, np.bool_))).all():
        return s.astype("float64")
    return s.map(lambda v: "" if _is_missing(v) else str(v)).astype(object)


def _canonical(df: pd.DataFrame, table: str, where: str, contract=None) -> pd.DataFrame:
    """The table with the contract's columns first, in order, each of its canonical dtype;
    ``contract`` (column kinds, id column) replaces the planar folder's (``TABLES``).

    Raises InputError on a missing column, a bad cell, a duplicated id or (for the summary)
    a number of rows other than one.
    """
    kinds, id_col = contract or TABLES[table][1:]
    if not isinstance(df, pd.DataFrame):
        raise InputError(f"{where}: expected a table (pandas DataFrame), got {type(df).__name__}")
    df = df.reset_index(drop=True)
    df.columns = [str(c).strip() for c in df.columns]
    dup = df.columns[df.columns.duplicated()]
    if len(dup):
        raise InputError(f"{where}: column '{dup[0]}' appears twice; expected each column once")
    missing = [c for c in kinds if c not in df.columns]
    if missing:
        raise InputError(f"{where}: column '{missing[0]}' is missing; expected columns "
                         f"{', '.join(kinds)} (extra columns may follow them)")
    if table == "summary" and len(df) != 1:
        raise InputError(f"{where}: has {len(df)} data rows; expected exactly one row (the summary)")

    def row_ids(i):
        label = f"row {i + 1}"
        if id_col and id_col in df.columns and i < len(df):
            label += f" ({id_col} '{df[id_col].iloc[i]}')"
        return label

    cols = {c: _convert_column(df[c].tolist(), k, where, c, row_ids) for c, k in kinds.items()}
    for c in df.columns:
        if c not in kinds:
            cols[c] = _infer_extra(df[c].tolist())
    out = pd.DataFrame(cols, index=pd.RangeIndex(len(df)))
    if id_col:
        dups = out[id_col][out[id_col].duplicated()]
        if len(dups):
            raise InputError(f"{where}: {id_col} '{dups.iloc[0]}' appears twice; expected unique {id_col} ids")
    return out


# the folder's file names live in .folder (no pandas there); re-exported here
from .folder import COMPANION_FILES, PICTURE_STEM, RESULT_FILES, foreign_files  # noqa: E402,F401


# --------------------------------------------------------------------------- the object
@dataclass
class Results:
    """Collapse multiplier, mechanism and contact forces of one limit analysis.

    ``summary`` has one row; ``blocks``, ``contacts`` and ``runs`` one row per movable block,
    per contact and per solver start. On construction every table is brought to its
    canonical form: contract columns first and in order, ids as text (``start`` as int64),
    floats as float64, counts as int64 (``iterations`` as nullable Int64), ``certified`` as
    bool. Extra columns keep their order after the contract's.
    """

    summary: pd.DataFrame
    blocks: pd.DataFrame
    contacts: pd.DataFrame
    runs: pd.DataFrame

    def __post_init__(self):
        for table in TABLES:
            setattr(self, table, _canonical(getattr(self, table), table, f"{table} table"))

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_frames(cls, summary: dict, blocks: pd.DataFrame, contacts: pd.DataFrame,
                    runs: pd.DataFrame) -> "Results":
        """Build from the driver's tables: ``summary`` is a dict of the one summary row.

        Columns are put in contract order (extra columns after them, in their given order);
        a missing column or a value of the wrong kind raises InputError.
        """
        if isinstance(summary, pd.DataFrame):
            summary_df = summary
        else:
            summary_df = pd.DataFrame([dict(summary)])
        return cls(summary=summary_df, blocks=pd.DataFrame(blocks), contacts=pd.DataFrame(contacts),
                   runs=pd.DataFrame(runs))

    # ------------------------------------------------------------------ files
    def write(self, folder, also=None) -> str:
        """Replace ``folder`` as a whole by one holding summary.csv, blocks.csv, contacts.csv,
        runs.csv (and what ``also(staging_folder)`` writes there, e.g. the picture).

        Everything is written into a hidden sibling folder first, then swapped in
        (:class:`lamodel.output.folder.ResultFolder`): a reader sees the complete old folder or
        the complete new one, also if the process is killed; on any failure the old folder
        is untouched. A folder holding files lamodel did not write is refused (InputError),
        never emptied. Returns the folder path.
        """
        with ResultFolder(folder, foreign_files) as stage:
            self.write_into(stage.path)
            if also is not None:
                also(stage.path)
            return stage.commit()

    def write_into(self, folder):
        """Write the four CSV files into an existing folder nobody reads yet (a staging folder)."""
        for table, (name, _, _) in TABLES.items():
            _write_table(Path(folder) / name, getattr(self, table))

    @classmethod
    def read(cls, path) -> "Results":
        """Read a result folder (or the path of its summary.csv) written by :meth:`write`.

        Raises InputError, with a one-line message naming the file and the column or row,
        on a missing file or column, an unparsable value, an empty summary or duplicated ids.
        """
        folder = _summary_folder(path)
        frames = {}
        for table, (name, _, _) in TABLES.items():
            f = folder / name
            frames[table] = _canonical(_read_table(f), table, str(f))
        summary = frames["summary"].iloc[0]
        for table, count in (("blocks", "n_blocks"), ("contacts", "n_contacts")):   # a half-written folder
            said = pd.to_numeric(summary.get(count), errors="coerce")
            if pd.notna(said) and len(frames[table]) != int(said):
                raise InputError(f"{folder / TABLES[table][0]}: {len(frames[table])} rows where summary.csv says "
                                 f"{count} = {int(said)}; expected the folder as lamodel wrote it")
        return cls(**frames)

    # ------------------------------------------------------------------ quick access
    def _get(self, column):
        return self.summary[column].iloc[0]

    @property
    def instance(self) -> str:
        """Name of the analysed structure."""
        return str(self._get("instance"))

    @property
    def alpha(self) -> float:
        """The collapse load multiplier (NaN when none was found)."""
        return float(self._get("alpha"))

    @property
    def certified(self) -> bool:
        """Whether alpha was certified (a statically and kinematically admissible pair)."""
        return bool(self._get("certified"))

    @property
    def alpha_associative(self) -> float:
        """The collapse multiplier of the associative (dilatant) problem, an upper reference."""
        return float(self._get("alpha_associative"))

    def mechanism(self) -> np.ndarray:
        """The collapse mechanism, (n_blocks, 3): ux, uy, theta of each block centroid."""
        return self.blocks[["ux", "uy", "theta"]].to_numpy(dtype=float)

    def modes(self) -> list:
        """Mode of each contact (one of :data:`MODES`), in the order of contacts.csv."""
        return [str(m) for m in self.contacts["mode"]]

    def mode_counts(self) -> pd.Series:
        """Number of contacts in each mode (every mode of :data:`MODES` listed; ``unknown``,
        and the crushing modes of joints with strengths, only when some contact is)."""
        counts = self.contacts["mode"].value_counts().reindex(list(MODES), fill_value=0).astype(int)
        rare = [m for m in ("crushing", "crushing+sliding", "unknown") if not counts[m]]
        return counts.drop(rare)  # listed only when they occur

    # ------------------------------------------------------------------ text
    def to_text(self) -> str:
        """A readable multi-table text: the summary (transposed), the runs, the contact modes."""
        fmt = lambda v: f"{v + 0.0:.10g}"  # noqa: E731  (+ 0.0: a signed zero is shown as 0)
        row = self.summary.iloc[0]
        # names and values left-aligned: a long message then widens its own line only
        width = max(map(len, self.summary.columns))
        summary = "\n".join(f"{name:<{width}}  {fmt(v) if isinstance(v, (float, np.floating)) else v}".rstrip()
                             for name, v in row.items())
        modes = self.mode_counts().rename("contacts").to_frame()
        modes.index.name = None
        runs = aligned(self.runs, fmt) if len(self.runs) else "(no runs)"
        return "\n".join([
            f"Limit analysis of '{self.instance}'",
            "",
            summary,
            "",
            f"Solver starts ({len(self.runs)}):",
            runs,
            "",
            f"Contact modes ({len(self.contacts)} contacts):",
            modes.to_string(),
        ])

    def __str__(self) -> str:
        return self.to_text()
