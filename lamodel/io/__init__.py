"""Reading and writing structures: Pyomo .dat files, JSON polygon geometry, and in 3D
JSON polyhedra, COMPAS assemblies and meshes.

:func:`read` takes any of them, by its extension and content: a planar input gives a
validated Structure, a 3D one a validated Structure3D.
"""
from __future__ import annotations

import warnings
from pathlib import Path

from ..errors import InputError

from .kinds import MESH_SUFFIXES, dimension  # noqa: F401 (light: the kind of a file, without reading it)

#: What :func:`read` reads, in its messages.
KINDS = ".dat (Pyomo data), .json (polygons, polyhedra, COMPAS assembly) or a mesh (.obj, .ply, .stl, .gltf, .glb)"


def read(path, **options):
    """A validated Structure from a .dat or a 2D .json file, a Structure3D from a 3D .json
    (lamodel or COMPAS) or a mesh (.obj, .ply, .stl, .gltf, .glb); InputError, one line,
    otherwise. ``options`` go to the 3D readers (:mod:`lamodel.io.assemblies`: mu,
    unit_weight, live_load, supports, supports_below, units, tolerance, contact_points)."""
    from .options3d import check_input_options
    check_input_options(options)   # a value the caller gave is refused as the caller's, not the file's
    p = Path(path)
    ext = p.suffix.lower()
    if p.is_dir():
        raise InputError(f"{path}: is a folder; expected a structure file: {KINDS}")
    if not p.is_file():
        raise InputError(f"{path}: no such file; expected a structure file: {KINDS}")
    if ext == ".json":  # parsed once, read as what it holds
        from .assemblies import read_3d_spec
        from .jsonfields import load_spec
        from .jsonspec import structure_from_spec
        spec, where = load_spec(p)
        s3 = read_3d_spec(spec, p, **options)
        return s3 if s3 is not None else structure_from_spec(spec, where)
    if ext in MESH_SUFFIXES:
        from .assemblies import read_mesh
        return read_mesh(p, **options)
    if ext == ".dat":
        from .datfile import read_dat
        return read_dat(path)
    raise InputError(f"{path}: unknown file type '{ext}'; expected {KINDS}")


def build_dat(geometry, output=None, name: str | None = None) -> str:
    """Write the Pyomo .dat instance of a JSON polygon geometry (``lamodel build``):
    to ``output`` (default: next to the JSON, with .dat), named ``name`` (default: the
    JSON 'name' or the file stem). Returns a one-line account of what was written."""
    from .datfile import write_dat
    from .jsonspec import structure_from_json
    if Path(geometry).suffix.lower() != ".json":
        raise InputError(f"{geometry}: not a .json file; expected a JSON polygon geometry (a .dat file is an "
                         "instance already; a mesh is a structure in space)")
    output = Path(output) if output else Path(geometry).with_suffix(".dat")
    if output.exists() and output.resolve() == Path(geometry).resolve():
        raise InputError(f"{output}: the geometry itself; expected another output path (the input is never "
                         "overwritten)")
    if str(output) == "-" or output.is_dir():
        raise InputError(f"{output}: {'a folder' if output.is_dir() else 'not a file name'}; expected the path "
                         "of the .dat file to write")
    structure = structure_from_json(geometry, name=name)
    kept_only_in_json = [what for what, there in (("load cases", structure.cases), ("a rolling load",
                                                  structure.rolling is not None)) if there]
    if kept_only_in_json:   # a .dat holds one live load pattern
        raise InputError(f"{geometry}: has {' and '.join(kept_only_in_json)}, which a .dat file cannot hold (one "
                         f"live load); expected lamodel solve {geometry} on the JSON itself")
    if structure.units:
        units = ", ".join(f"{k} {v}" for k, v in structure.units.items())
        warnings.warn(f"{output}: a .dat file keeps no units ({units}); its tables will have none", stacklevel=2)
    if name and name != output.stem:
        warnings.warn(f"{output}: a .dat instance is named by its file: lamodel solve will call it "
                      f"'{output.stem}', not '{name}'", stacklevel=2)
    output.parent.mkdir(parents=True, exist_ok=True)
    write_dat(structure, output)
    return (f"{output}: {structure.n_blocks} blocks, {len(structure.supports)} supports, "
            f"{structure.n_contacts} contacts")
