"""Tables as text for a terminal: numbers right-aligned, words left-aligned under their
names (:meth:`lamodel.output.results.Results.to_text`)."""
from __future__ import annotations

import numpy as np
import pandas as pd


def aligned(table: pd.DataFrame, fmt) -> str:
    """``table`` as text, numbers right-aligned and text left-aligned under their names (a
    long status then widens its own column only)."""
    def cell(v, text):
        if text:
            return "" if pd.isna(v) else " ".join(str(v).splitlines())
        if isinstance(v, (float, np.floating)):
            return "NaN" if np.isnan(v) else fmt(v)
        return str(v)

    columns = []
    for name in table.columns:
        text = table[name].dtype in (object, bool)
        cells = [cell(v, text) for v in table[name]]
        width = max(len(name), *map(len, cells))
        columns.append([f"{c:<{width}}" if text else f"{c:>{width}}" for c in [name, *cells]])
    return "\n".join("  ".join(row).rstrip() for row in zip(*columns))

