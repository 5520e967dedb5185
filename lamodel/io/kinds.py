"""The kind of a structure file, known at once (no numpy, no geometry): planar or in space,
by its extension and, for JSON, by what the parsed file holds. :func:`lamodel.io.read`
then reads it with the right reader; a command can prepare for the kind before reading
(``lamodel solve`` starts the planar picture's helper process only for a planar input).
"""
from __future__ import annotations

import json
from pathlib import Path

from ..errors import InputError
from .files import read_text

#: Mesh files, read through trimesh (:mod:`lamodel.io.assemblies`): structures in space.
MESH_SUFFIXES = (".obj", ".ply", ".stl", ".gltf", ".glb")


def is_3d_spec(spec) -> bool:
    """True for a 3D lamodel spec: ``"dimension": 3`` or a first vertex with 3 coordinates."""
    if not isinstance(spec, dict):
        return False
    if spec.get("dimension") is not None:
        return spec.get("dimension") == 3
    try:
        return len(spec["blocks"][0]["vertices"][0]) == 3
    except (KeyError, IndexError, TypeError):
        return False


def is_compas(data) -> bool:
    """True for a parsed COMPAS assembly (its ``dtype`` names an Assembly)."""
    return isinstance(data, dict) and "Assembly" in str(data.get("dtype", ""))


def dimension(path) -> int | None:
    """2 or 3: the dimension of the structure :func:`lamodel.io.read` would read from
    ``path``; None when the file cannot be read as one (the reader then says why)."""
    p = Path(path)
    ext = p.suffix.lower()
    if ext == ".dat":
        return 2
    if ext in MESH_SUFFIXES:
        return 3
    if ext != ".json" or not p.is_file():
        return None
    try:
        data = json.loads(read_text(p, "JSON geometry file"))
    except (json.JSONDecodeError, RecursionError, InputError):
        return None
    return 3 if is_compas(data) or is_3d_spec(data) else 2
