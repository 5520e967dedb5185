"""The names in a result folder: lamodel's files, and the user's that it must never delete.

No pandas here: the command line checks a result folder before solving, while pandas
loads in the background (:mod:`lamodel.cli`).
"""
from __future__ import annotations

import csv
import os
import re
from pathlib import Path

#: The four tables of a result folder (:mod:`lamodel.output.results`), by name.
TABLE_FILES = {"summary": "summary.csv", "blocks": "blocks.csv", "contacts": "contacts.csv", "runs": "runs.csv"}

#: The files of a result folder. The picture, the HTML report and the animation, when
#: written into it, are named in summary.csv's columns ``picture``, ``report`` and
#: ``animation`` (by the command line); ``mechanism.*`` is the picture's default name.
RESULT_FILES = tuple(TABLE_FILES.values())
#: What ``lamodel solve`` writes beside them for --method all, load cases, rolling loads.
COMPANION_FILES = ("methods.csv", "cases.csv", "rolling.csv", "rolling.png")
PICTURE_STEM = "mechanism"
_PICTURE_EXTENSIONS = {"png", "svg", "svgz", "pdf", "eps", "ps", "jpg", "jpeg", "tif", "tiff", "webp", "pgf",
                       "raw", "rgba", "gif", "avif"}  # matplotlib's formats
_RECORDED = {"picture": _PICTURE_EXTENSIONS, "report": {"html", "htm"}, "animation": {"gif"}}
_LEFTOVER = re.compile(r"^\.(?P<name>.+)\.[^.]+\.(tmp|bak)$")  # temporary files of older lamodel versions


def recorded_files(folder: Path) -> set:
    """The files beside the tables that the folder's summary.csv names as written there."""
    try:
        with open(folder / "summary.csv", newline="", encoding="utf-8") as fh:
            row = next(csv.DictReader(fh), None) or {}
    except (OSError, UnicodeDecodeError, csv.Error):
        return set()
    names = set()
    for column, extensions in _RECORDED.items():
        name = str(row.get(column) or "")
        if name == Path(name).name and not name.startswith(".") and name.rsplit(".", 1)[-1].lower() in extensions:
            names.add(name)
    return names


def foreign_files(folder, names) -> list:
    """The names in a result folder that lamodel did not write (they make it refuse to
    replace the folder: a user's own files are never deleted)."""
    folder = Path(folder)
    ours = {*RESULT_FILES, *COMPANION_FILES, *recorded_files(folder)}

    def owned(name):
        if name in ours or (name.startswith(PICTURE_STEM + ".")
                            and name[len(PICTURE_STEM) + 1:].lower() in _PICTURE_EXTENSIONS):
            return os.path.isfile(folder / name) or os.path.islink(folder / name)
        m = _LEFTOVER.match(name)
        return bool(m) and owned(m["name"])
    return [n for n in names if not owned(n)]
