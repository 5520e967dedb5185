"""One CSV table of a result folder on disk: found from the folder or its summary.csv, read
as text cells (checked before it is read), written once into a staging folder. The tables'
columns and their meaning: :mod:`lamodel.output.results`."""
from __future__ import annotations

import os
import stat
from pathlib import Path

import pandas as pd

from ..errors import InputError

FLOAT_FORMAT = "%.17g"  # 17 significant digits: every float64 survives the round trip


def summary_folder(path) -> Path:
    """The result folder named by ``path``: the folder itself or the folder of its summary.csv."""
    p = Path(os.fspath(path))
    if p.is_dir():
        return p
    if p.name == "summary.csv":
        if not p.exists():
            raise InputError(f"{p}: no such file; expected a result folder or its summary.csv")
        return p.parent
    if p.exists():
        raise InputError(f"{p}: not a result folder or a summary.csv; expected a folder holding "
                         "summary.csv, blocks.csv, contacts.csv and runs.csv, or the path of its summary.csv")
    raise InputError(f"{p}: no such folder or file; expected a result folder or its summary.csv")


#: A result table larger than this is refused before it is read (a result folder of a
#: million-block structure is a few hundred MB).
MAX_TABLE_BYTES = 2**30


def read_table(path: Path) -> pd.DataFrame:
    """Read a CSV file as text cells (no type guessing); InputError on an unreadable file,
    on anything but a regular file (a device, a pipe) and on a file over MAX_TABLE_BYTES,
    before reading it."""
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file; expected it in every result folder") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read the file ({exc.strerror or exc}); expected a readable CSV table") from None
    if not stat.S_ISREG(info.st_mode):
        raise InputError(f"{path}: not a regular file (a device, a pipe or a folder); expected a CSV table")
    if info.st_size > MAX_TABLE_BYTES:
        raise InputError(f"{path}: {info.st_size / 2**20:.0f} MB; expected a result table of at most "
                         f"{MAX_TABLE_BYTES // 2**20} MB")
    try:
        return pd.read_csv(path, dtype=str, keep_default_na=False, na_filter=False,
                           skipinitialspace=False, encoding="utf-8")
    except FileNotFoundError:
        raise InputError(f"{path}: no such file; expected it in every result folder") from None
    except pd.errors.EmptyDataError:
        raise InputError(f"{path}: the file is empty; expected a header line and data rows") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a text file (invalid UTF-8); expected a CSV table") from None
    except (pd.errors.ParserError, ValueError) as exc:
        msg = " ".join(str(exc).split()) or type(exc).__name__
        raise InputError(f"{path}: not a valid CSV table ({msg}); expected comma-separated rows "
                         "with as many fields as the header") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read the file ({exc.strerror or exc}); expected a readable CSV table") from None


def write_table(path: Path, df: pd.DataFrame):
    """Write one table (into a staging folder nobody reads yet), flushed to disk."""
    with open(path, "x", newline="", encoding="utf-8") as fh:  # "x": never clobber another writer's file
        df.to_csv(fh, index=False, float_format=FLOAT_FORMAT, lineterminator="\n", na_rep="")
        fh.flush()
        os.fsync(fh.fileno())
