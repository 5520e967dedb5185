"""Block assemblies from other tools: COMPAS assembly JSON and meshes (OBJ, PLY, STL, glTF).

Both give a 3D spec (:mod:`lamodel.io.json3d`) built into a :class:`Structure3D`. These
inputs carry no mechanical data, so the caller's ``mu``, ``unit_weight`` and ``live_load``
are used, with the defaults **unit weight 1, mu = 0.6, live load horizontal along +x equal
to each block's weight**; the values applied are recorded in ``Structure3D.meta``
(``defaults`` lists those not given). Supports: COMPAS's ``is_support`` flags, or
``supports`` (a list of block ids), or ``supports_below=Z`` (blocks whose lowest point is
below Z).

* COMPAS: ``"dtype": "compas_assembly.datastructures/Assembly"`` (or compas_cra's
  ``CRA_Assembly``); each node's ``block`` mesh (``vertex``, ``face``) is one block, named by
  its node key; lamodel finds the interfaces itself, and when the file stores COMPAS's own
  (edges with ``interfaces``) warns of the block pairs they join that it does not
  (:mod:`lamodel.io.joints3d`, with the tolerance that joins them). Warped
  (non-planar) faces, COMPAS's approximation of curved intrados and extrados, are split
  into triangles; a contact is found only between planar pieces.
* Meshes (through trimesh): a file of several geometries (OBJ objects, glTF nodes, placed)
  gives one block per geometry; a single geometry gives one block per connected component
  (blocks whose corners coincide then merge: give them as separate geometries). Blocks are
  named ``b1, b2, ...`` in the file's order.
"""
from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..errors import InputError
from ..structure3d import Structure3D
from .files import read_text
from .json3d import structure3d_from_spec
from .kinds import MESH_SUFFIXES, is_3d_spec, is_compas  # noqa: F401 (MESH_SUFFIXES: read here by others)
from .options3d import flag

DEFAULT_MU = 0.6
DEFAULT_UNIT_WEIGHT = 1.0
DEFAULT_LIVE_LOAD = (1.0, 0.0, 0.0)


def _mechanics(spec, where, mu=None, unit_weight=None, live_load=None, supports=None, supports_below=None,
               source=""):
    """Fill the mechanical data a geometry-only input lacks; record what was applied."""
    given = {"mu": mu, "unit_weight": unit_weight, "live_load": live_load}
    defaults = {"mu": DEFAULT_MU, "unit_weight": DEFAULT_UNIT_WEIGHT, "live_load": list(DEFAULT_LIVE_LOAD)}
    for key, value in given.items():
        spec[key] = defaults[key] if value is None else (list(map(float, value)) if key == "live_load" else value)
    ids = [b["id"] for b in spec["blocks"]]
    if supports is not None:
        unknown = sorted(set(map(str, supports)) - set(ids))
        if unknown:
            raise InputError(f"--supports: '{unknown[0]}' is not a block of {where}; expected ids among "
                             f"{', '.join(ids[:5])}{', ...' if len(ids) > 5 else ''}")
        for b in spec["blocks"]:
            b["support"] = b["id"] in set(map(str, supports))
    if supports_below is not None:
        for b in spec["blocks"]:
            b["support"] = bool(b.get("support")) or float(np.min(np.asarray(b["vertices"])[:, 2])) < supports_below
    spec["meta"] = {"source": source, "defaults": [k for k, v in given.items() if v is None]}
    return spec


# ---------------------------------------------------------------------------- COMPAS
def _graph(data):
    """The graph dict of a COMPAS assembly (node, edge), for the versions seen in the wild."""
    d = data.get("data", data)
    graph = d.get("graph", d)
    return graph.get("data", graph) if isinstance(graph, dict) else graph


def stored_joints(data) -> set | None:
    """The block pairs (sorted id tuples) that a COMPAS assembly's own interfaces join (its
    edges with a non-empty ``interfaces`` list); None when the file stores none."""
    graph = _graph(data)
    edges = graph.get("edge") if isinstance(graph, dict) else None
    pairs = set()
    for a, row in (edges.items() if isinstance(edges, dict) else ()):
        for b, attrs in (row.items() if isinstance(row, dict) else ()):
            if isinstance(attrs, dict) and attrs.get("interfaces") and str(a) != str(b):
                pairs.add(tuple(sorted((str(a), str(b)))))
    return pairs or None


def _graph_nodes(data, where):
    """The node dict of a COMPAS assembly (its graph)."""
    graph = _graph(data)
    nodes = graph.get("node") if isinstance(graph, dict) else None
    if not isinstance(nodes, dict) or not nodes:
        raise InputError(f"{where}: no assembly nodes found (data.graph.data.node); expected a COMPAS Assembly")
    return nodes


def compas_spec(data: dict, where: str = "COMPAS assembly") -> dict:
    """A 3D spec (geometry only) from a parsed COMPAS assembly JSON."""
    blocks = []
    for key, node in _graph_nodes(data, where).items():
        at = f"{where}: node '{key}'"
        mesh = node.get("block") if isinstance(node, dict) else None
        mesh = mesh.get("data", mesh) if isinstance(mesh, dict) else None
        if not isinstance(mesh, dict) or not isinstance(mesh.get("vertex"), dict) or not isinstance(mesh.get("face"), dict):
            raise InputError(f"{at} has no block mesh ('block' with 'vertex' and 'face'); expected a COMPAS Block")
        keys = list(mesh["vertex"])
        index = {str(k): i for i, k in enumerate(keys)}
        try:
            verts = [[float(mesh["vertex"][k][c]) for c in "xyz"] for k in keys]
            faces = [[index[str(v)] for v in f] for f in mesh["face"].values()]
        except (KeyError, TypeError, ValueError):
            raise InputError(f"{at}: a vertex or a face of its block mesh is malformed; expected x, y, z per vertex "
                             "and faces naming vertex keys") from None
        blocks.append({"id": str(key), "vertices": verts, "faces": faces, "support": bool(node.get("is_support"))})
    return {"name": str((data.get("data", {}).get("attributes") or {}).get("name") or "assembly"),
            "blocks": blocks}


def read_compas(path, name=None, tolerance=None, contact_points=None, units=None, where=None,
                **mechanics) -> Structure3D:
    """A Structure3D from a COMPAS assembly JSON file (or parsed dict); ``mechanics``: mu,
    unit_weight, live_load, supports, supports_below (see the module docs)."""
    if isinstance(path, dict):
        data, where = path, where or "COMPAS assembly"
    else:
        where = str(path)
        try:
            data = json.loads(read_text(path, "COMPAS assembly JSON file"))
        except json.JSONDecodeError as exc:
            raise InputError(f"{where}: malformed JSON at line {exc.lineno} ({exc.msg}); expected a COMPAS "
                             "assembly") from None
        name = name or Path(path).stem
    spec = _mechanics(compas_spec(data, where), where, source="COMPAS assembly", **mechanics)
    if units:
        spec["units"] = dict(units)
    return structure3d_from_spec(spec, where, name=name, tolerance=tolerance, contact_points=contact_points,
                                 split_nonplanar=True, stored_joints=stored_joints(data))


# ----------------------------------------------------------------------------- meshes
def mesh_spec(path, where: str) -> dict:
    """A 3D spec (geometry only) from a mesh file: one block per connected component of each
    of its geometries (an OBJ's objects apart)."""
    import trimesh
    # an OBJ's objects ("o" lines) are kept apart: welded together, stacked blocks that share
    # corners became one component, one block
    split = {"split_objects": True} if Path(path).suffix.lower() == ".obj" else {}
    try:
        loaded = trimesh.load(str(path), process=False, **split)
    except Exception as exc:  # trimesh raises many kinds for a bad file
        raise InputError(f"{where}: cannot read the mesh ({str(exc).splitlines()[0][:80] if str(exc) else type(exc).__name__}); "
                         "expected an OBJ, PLY, STL or glTF file") from None
    if isinstance(loaded, trimesh.Scene):
        meshes = [g for g in loaded.dump() if isinstance(g, trimesh.Trimesh)] if loaded.geometry else []
    else:
        meshes = [loaded] if isinstance(loaded, trimesh.Trimesh) else []
    if not meshes or not sum(len(m.faces) for m in meshes):
        raise InputError(f"{where}: the file holds no triangles; expected a mesh of closed blocks")
    blocks = []
    for m in meshes:
        m = trimesh.Trimesh(m.vertices, m.faces, process=True, validate=False)  # weld duplicate vertices
        v, f = np.asarray(m.vertices), np.asarray(m.faces)
        edges = np.r_[f[:, [0, 1]], f[:, [1, 2]]]
        graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(len(v), len(v)))
        n, label = connected_components(graph, directed=False)
        for k in range(n):   # each connected component of each geometry (an OBJ object, a glTF node) a block
            keep = np.flatnonzero(label == k)
            faces = f[label[f[:, 0]] == k]
            if not len(faces):
                continue
            remap = -np.ones(len(v), dtype=int)
            remap[keep] = np.arange(len(keep))
            blocks.append({"id": f"b{len(blocks) + 1}", "vertices": v[keep].tolist(), "faces": remap[faces].tolist()})
    return {"name": Path(path).stem, "blocks": blocks}


def read_mesh(path, name=None, units=None, tolerance=None, contact_points=None, **mechanics) -> Structure3D:
    """A Structure3D from an OBJ / PLY / STL / glTF mesh (one block per connected component);
    ``units`` ({"length", "force"}) as given on the command line; ``mechanics`` as
    :func:`read_compas` (a support is needed: ``supports`` or ``supports_below``)."""
    where = str(path)
    spec = _mechanics(mesh_spec(path, where), where, source=f"mesh ({Path(path).suffix.lstrip('.').upper()})",
                      **mechanics)
    if units:
        spec["units"] = dict(units)
    return structure3d_from_spec(spec, where, name=name, tolerance=tolerance, contact_points=contact_points)


def read_3d_json(path, **options):
    """A Structure3D when the JSON file is 3D (a COMPAS assembly or a lamodel spec with
    ``"dimension": 3`` or [x, y, z] vertices), else None (a planar file; left to the 2D
    reader, which also reports malformed JSON)."""
    try:
        data = json.loads(read_text(path, "JSON geometry file"))
    except (json.JSONDecodeError, RecursionError, InputError):  # the planar reader says what is wrong
        return None
    return read_3d_spec(data, path, **options)


def read_3d_spec(data, path, **options):
    """:func:`read_3d_json` on the file's parsed JSON ``data`` (None for a planar spec)."""
    if is_compas(data):
        return read_compas(data, name=Path(path).stem, where=str(path), **options)
    if not is_3d_spec(data):
        return None
    if options.get("units"):
        given, own = dict(options.pop("units")), data.get("units") if isinstance(data.get("units"), dict) else {}
        for key, unit in given.items():
            if own.get(key) not in (None, unit):   # labels only: the numbers are not converted
                warnings.warn(f"{path}: --{key}-unit {unit} replaces the file's {key} unit {own[key]}; its numbers "
                              "are read unchanged, as that unit", stacklevel=2)
        data["units"] = {**own, **given}
    spec_keys = ("tolerance", "contact_points")
    extra = sorted(set(options) - set(spec_keys))
    if extra:
        raise InputError(f"{flag(extra[0])}: applies to COMPAS assemblies and meshes only; expected a 3D JSON "
                         f"file without it ({path} gives its own mechanical data)")
    data.setdefault("name", Path(path).stem)
    return structure3d_from_spec(data, str(path), **options)
