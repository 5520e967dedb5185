"""Reading and writing structures: Pyomo .dat files, JSON polygon geometry, and in 3D
JSON polyhedra, COMPAS assemblies and meshes.

:func:`read` takes any of them, by its extension and content: a planar input gives a
validated Structure, a 3D one a validated Structure3D.
"""
from __future__ import annotations

from pathlib import Path

from ..errors import InputError


def read(path, **options):
    """A validated Structure from a .dat or a 2D .json file, a Structure3D from a 3D .json
    (lamodel or COMPAS) or a mesh (.obj, .ply, .stl, .gltf, .glb); InputError, one line,
    otherwise. ``options`` go to the 3D readers (:mod:`lamodel.io.assemblies`: mu,
    unit_weight, live_load, supports, supports_below, units, tolerance, contact_points)."""
    p = Path(path)
    ext = p.suffix.lower()
    if p.is_dir():
        raise InputError(f"{path}: is a folder; expected a .dat instance or a .json geometry file")
    if not p.is_file():
        raise InputError(f"{path}: no such file; expected a .dat instance or a .json geometry")
    if ext == ".json":
        from .assemblies import read_3d_json
        s3 = read_3d_json(p, **options)
        if s3 is not None:
            return s3
        from .jsonspec import structure_from_json
        return structure_from_json(path)
    if ext == ".dat":  # first: the 3D readers' imports (shapely, scipy.spatial) cost 0.1-0.2 s
        from .datfile import read_dat
        return read_dat(path)
    from .assemblies import MESH_SUFFIXES
    if ext in MESH_SUFFIXES:
        from .assemblies import read_mesh
        return read_mesh(p, **options)
    raise InputError(f"{path}: unknown file type '{ext}'; expected .dat (Pyomo data), .json (polygons, "
                     "polyhedra, COMPAS assembly) or a mesh (.obj, .ply, .stl, .gltf, .glb)")


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
