"""Reading and writing structures: Pyomo .dat files and JSON polygon geometry.

:func:`read` takes either, by its extension; both give the same validated Structure.
"""
from __future__ import annotations

from pathlib import Path

from ..errors import InputError


def read(path):
    """A validated Structure from a .dat or a .json file (InputError, one line, otherwise)."""
    p = Path(path)
    ext = p.suffix.lower()
    if p.is_dir():
        raise InputError(f"{path}: is a folder; expected a .dat instance or a .json geometry file")
    if not p.is_file():
        raise InputError(f"{path}: no such file; expected a .dat instance or a .json geometry")
    if ext == ".json":
        from .jsonspec import structure_from_json
        return structure_from_json(path)
    if ext == ".dat":
        from .datfile import read_dat
        return read_dat(path)
    raise InputError(f"{path}: unknown file type '{ext}'; expected .dat (Pyomo data) or .json (polygons)")


def build_dat(geometry, output=None, name: str | None = None) -> str:
    """Write the Pyomo .dat instance of a JSON polygon geometry (``lamodel build``):
    to ``output`` (default: next to the JSON, with .dat), named ``name`` (default: the
    JSON 'name' or the file stem). Returns a one-line account of what was written."""
    from .datfile import write_dat
    from .jsonspec import structure_from_json
    output = Path(output) if output else Path(geometry).with_suffix(".dat")
    structure = structure_from_json(geometry, name=name)
    write_dat(structure, output)
    return (f"{output}: {structure.n_blocks} blocks, {len(structure.supports)} supports, "
            f"{structure.n_contacts} contacts")
