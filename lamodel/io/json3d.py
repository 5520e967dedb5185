"""JSON geometry of a block assembly in space: polyhedra in, a :class:`Structure3D` out.

The 2D format (:mod:`lamodel.io.jsonspec`) with 3-component vertices, z up::

    { "name": "stack", "dimension": 3,          # optional: inferred from [x, y, z] vertices
      "mu": 0.6, "unit_weight": 1.0,            # weight per unit volume (default 1)
      "live_load": [1, 0, 0],                   # live force per unit weight (default [1, 0, 0])
      "units": {"length": "m", "force": "kN"},
      "tolerance": 1e-6,                        # optional, relative to the structure's size
      "contact_points": "vertices",             # or "grid:n" (adds interior points)
      "fc": 5000, "ft": 0, "cohesion": 0,       # optional: the joints' strengths (stresses)
      "joints": [ {"between": ["b1", "b2"], "fc": 3000} ],
      "blocks": [ {"id": "b1", "vertices": [[0,0,0], [1,0,0], ...],
                   "faces": [[0, 3, 2, 1], ...],    # optional: default the convex hull
                   "support": false, "dead": [fx,fy,fz], "live": [fx,fy,fz],
                   "dead_m": [mx,my,mz], "live_m": [mx,my,mz], "mu": 0.5, "fc": 4000} ],
      "loads": [ {"block": "b1", "at": [x,y,z], "force": [fx,fy,fz], "kind": "live"} ] }

Faces are vertex loops ordered counter-clockwise seen from outside. The dead load of a
block is ``unit_weight * volume`` along -z at its centroid; its live load is
``live_load * unit_weight * volume``. Point loads add their force and their moment about the
centroid (each at a point of its block: inside, or on its surface within the tolerance and
``LOAD_POINT_SLACK`` of the block's size); when the file gives live point loads but no ``live_load``, alpha multiplies only
them (and ``meta["live_load"]`` is None: no live load per unit weight was applied). A contact takes the smaller ``mu`` of its two bodies.

The joints' strengths (the point-contact model of :mod:`lamodel.formulation.space`):
``"fc"`` (compressive strength; omitted: no crushing), ``"ft"`` (tensile strength) and
``"cohesion"``, stresses in the file's force per length squared, at the top level for every
interface, on a body for its interfaces (an interface takes the smaller value of its two
bodies), in ``"joints"`` for every interface of those two bodies. Each contact point
carries them over its tributary area (:mod:`lamodel.geometry.tributary`).

Readers of other formats (COMPAS assemblies, meshes) produce this same spec, with the
defaults they applied listed under ``"meta"``; :func:`structure3d_from_spec` builds all of them.
"""
from __future__ import annotations

import json

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..errors import InputError
from ..geometry.interfaces3d import find_interfaces, interface_points, parse_contact_points
from ..geometry.hulls import convex_polyhedra
from ..geometry.polyhedra import polyhedron, surface_distance, winding_number
from ..search.tuning import LOAD_POINT_SLACK, SUPPORT_LEVEL
from ..structure3d import Structure3D, tangent_frame
from .joints3d import JointProbe, warn_missed_joints
from ..geometry.tributary import areas_in_frame
from .jsonfields import (blocks_of, body_head, body_support_mu, check_supports, joint_strengths, load_spec, number,
                         strengths, units, validated, warn_unknown, writes_live)

#: Geometric tolerance relative to the structure's size (diagonal of its bounding box):
#: loose enough for CAD files written in single precision.
DEFAULT_TOLERANCE_3D = 1e-6

#: The joints' strengths in space (stresses; no thickness: a point's area is its own).
STRENGTH_FIELDS_3D = ("fc", "ft", "cohesion")
STRENGTH_DEFAULTS_3D = {"fc": np.inf, "ft": 0.0, "cohesion": 0.0}
TOP_FIELDS_3D = ("name", "description", "dimension", "mu", "unit_weight", "live_load", "tolerance", "blocks",
                 "loads", "units", "contact_points", "meta", "joints", *STRENGTH_FIELDS_3D)
BODY_FIELDS_3D = ("id", "vertices", "faces", "support", "dead", "live", "dead_m", "live_m", "mu", "description",
                  *STRENGTH_FIELDS_3D)


def _vector3(value, where, what):
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise InputError(f"{where}: {what} is {json.dumps(value)[:60]}; expected [x, y, z] numbers")
    return np.array([number(v, where, what) for v in value])


def _bodies(spec, where, mu_all):
    bodies = blocks_of(spec, where)
    seen, out, unknown = {}, [], set()
    for pos, body in enumerate(bodies):
        bid, at = body_head(body, pos, where, seen, "a list of [x, y, z] corners")
        unknown |= set(body) - set(BODY_FIELDS_3D)
        support, mu = body_support_mu(body, at, mu_all)
        over = {k: _vector3(body[k], at, f"'{k}'") for k in ("dead", "live", "dead_m", "live_m")
                if k in body and not support}
        out.append((bid, body["vertices"], body.get("faces"), support, mu, over, strengths(body, at, STRENGTH_FIELDS_3D)))
    if unknown:
        warn_unknown(where, unknown, BODY_FIELDS_3D, "block")
    return out


def _check_connected(ids, is_support, interfaces, where):
    """Every block touches something, and every group of touching blocks reaches a support."""
    n = len(ids)
    a = np.array([f.a for f in interfaces], dtype=int)
    b = np.array([f.b for f in interfaces], dtype=int)
    touched = np.zeros(n, dtype=bool)
    touched[a] = touched[b] = True
    free = np.flatnonzero(~touched & ~is_support)
    if free.size:
        raise InputError(f"{where}: block '{ids[free[0]]}' touches nothing (a free body); "
                         "expected every block to share a face with a block or a support")
    graph = coo_matrix((np.ones(len(a)), (a, b)), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    held = np.isin(label, label[is_support])
    loose = np.flatnonzero(~held & ~is_support)
    if loose.size:
        raise InputError(f"{where}: block '{ids[loose[0]]}' is not connected to any support (its group of blocks "
                         "floats); expected every block to rest, through others, on a support")


def _polyhedra_and_interfaces(bodies, is_support, tol, split_nonplanar):
    """The bodies' polyhedra and their interfaces at the absolute tolerance ``tol``."""
    bulk = convex_polyhedra([b[0] for b in bodies], [b[1] if b[2] is None else [] for b in bodies], tol)
    polys = [p or polyhedron(b[0], b[1], b[2], tol, split_nonplanar) for p, b in zip(bulk, bodies)]
    return polys, find_interfaces(polys, is_support, tol)


def _check_supports3d(where, spec, ids, vertices, is_support):
    """:func:`check_supports`, and with no support the lowest block named: for an input
    without mechanical data (COMPAS, meshes) with both command-line ways to give supports."""
    if is_support.any():
        return check_supports(where, is_support)
    vertices = [v[np.isfinite(v).all(axis=1)] for v in vertices]
    low = np.array([v[:, 2].min() if len(v) else np.inf for v in vertices])
    j = int(np.argmin(low))
    every = np.vstack(vertices)
    if not len(every):   # no finite corner anywhere: nothing to point at
        return check_supports(where, is_support)
    level = low[j] + SUPPORT_LEVEL * float(np.linalg.norm(np.ptp(every, axis=0)))  # a course, not one point
    at = f"the lowest block is '{ids[j]}' (its lowest point at z = {low[j]:.6g}; {int((low < level).sum())} " \
         f"block(s) reach below z = {level:.6g})"
    source = str((spec.get("meta") or {}).get("source", ""))
    if not (source == "COMPAS assembly" or source.startswith("mesh")):   # the readers of lamodel.io.assemblies
        raise InputError(f"{where}: no block is a support; expected at least one body with \"support\": true; {at}")
    raise InputError(f"{where}: no block is a support; expected --supports-below Z (blocks whose lowest point is "
                     f"below Z are supports) or --supports ID,ID,...; {at}")


def structure3d_from_spec(spec: dict, where: str | None = None, name: str | None = None,
                          tolerance: float | None = None, contact_points=None,
                          split_nonplanar: bool = False, stored_joints=None) -> Structure3D:
    """Build a validated :class:`Structure3D` from a 3D spec dict (see the module docs).

    ``tolerance`` (relative to the size) and ``contact_points`` override the spec's fields;
    ``split_nonplanar`` splits warped faces into triangles (CAD inputs) instead of refusing them;
    ``stored_joints``: the block pairs a COMPAS file's own interfaces join (compared with the
    joints found, :mod:`lamodel.io.joints3d`). Raises InputError, one line naming the block,
    for anything that is not a block assembly; warns of joints the tolerance misses.
    """
    where = where or f"geometry '{spec.get('name', '<dict>')}'"
    warn_unknown(where, spec.keys(), TOP_FIELDS_3D, "top-level")
    name = str(name if name is not None else spec.get("name") or "structure")
    mu_all = number(spec["mu"], where, "'mu'", 0.0) if "mu" in spec else None
    unit_weight = number(spec.get("unit_weight", 1.0), where, "'unit_weight'", 0.0)
    live_load = _vector3(spec.get("live_load", [1.0, 0.0, 0.0]), where, "'live_load'")
    rel_tol = number(tolerance if tolerance is not None else spec.get("tolerance", DEFAULT_TOLERANCE_3D),
                      where, "'tolerance'", 0.0)
    try:
        grid = parse_contact_points(contact_points if contact_points is not None else spec.get("contact_points"))
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None
    bodies = _bodies(spec, where, mu_all)
    ids = [b[0] for b in bodies]
    is_support = np.array([b[3] for b in bodies], dtype=bool)
    bad = next((b[0] for b in bodies if not _is_points(b[1])), None)
    if bad is not None:
        raise InputError(f"{where}: block '{bad}': 'vertices' is not a list of [x, y, z] points; "
                         "expected [[x1, y1, z1], ...]")
    vertices = [np.asarray(b[1], dtype=float).reshape(-1, 3) for b in bodies]
    _check_supports3d(where, spec, ids, vertices, is_support)
    allv = np.vstack(vertices)
    finite = allv[np.isfinite(allv).all(axis=1)]
    size = float(np.linalg.norm(finite.max(axis=0) - finite.min(axis=0))) if len(finite) else 1.0
    tol = rel_tol * (size or 1.0)
    try:
        polys, interfaces = _polyhedra_and_interfaces(bodies, is_support, tol, split_nonplanar)
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None
    # before the connectivity check: a block that touches nothing is often a near-joint
    reread = lambda t: _polyhedra_and_interfaces(bodies, is_support, t, split_nonplanar)[1]  # noqa: E731
    warn_missed_joints(where, JointProbe(ids, is_support, polys, interfaces, rel_tol, tol, reread), stored_joints)
    _check_connected(ids, is_support, interfaces, where)

    moving = np.flatnonzero(~is_support)
    volume = np.array([polys[j].volume for j in moving])
    weight = unit_weight * volume
    dead = np.c_[np.zeros((len(moving), 2)), -weight]
    live = weight[:, None] * live_load[None, :]
    applied = live_load.tolist()  # the live load per unit weight, as summary.csv reports it
    if "live_load" not in spec and writes_live(spec):
        live[:] = 0.0  # alpha multiplies only the live loads the file writes
        applied = None
    dead_m, live_m = np.zeros((len(moving), 3)), np.zeros((len(moving), 3))
    rows = {"dead": dead, "live": live, "dead_m": dead_m, "live_m": live_m}
    row = {int(p): r for r, p in enumerate(moving)}
    for pos, body in enumerate(bodies):
        for key, value in body[5].items():
            rows[key][row[pos]] = value
    centroid = np.array([polys[j].centroid for j in moving])
    _point_loads(spec, where, {ids[j]: r for r, j in enumerate(moving)}, centroid, rows,
                 [polys[j] for j in moving], tol)

    pts = [interface_points(f, grid) for f in interfaces]
    count = np.array([len(p) for p in pts], dtype=int)
    normal = np.repeat(np.array([f.normal for f in interfaces]).reshape(-1, 3), count, axis=0)
    t1, t2 = tangent_frame(normal)
    mus = np.array([b[4] for b in bodies])
    iface_mu = np.array([min(mus[f.a], mus[f.b]) for f in interfaces])
    joints = joint_strengths(spec, where, ids, [b[6] for b in bodies], [f.a for f in interfaces],
                             [f.b for f in interfaces], STRENGTH_DEFAULTS_3D, STRENGTH_FIELDS_3D)
    joints = {k: np.repeat(v, count) for k, v in joints.items()}
    if joints:  # each point's share of its joint
        joints["area"] = np.concatenate([areas_in_frame(f.shape, f.frame, p) for f, p in zip(interfaces, pts)])
    meta = dict(spec.get("meta") or {})
    meta.setdefault("source", "lamodel JSON")
    meta.update(unit_weight=unit_weight, mu=mu_all, live_load=applied, tolerance=rel_tol,
                contact_points="vertices" if not grid else f"grid:{grid}")
    s = Structure3D(
        name=name, blocks=[ids[j] for j in moving], centroid=centroid, dead=dead, live=live,
        supports=[ids[j] for j in np.flatnonzero(is_support)],
        interfaces=[f"i{k + 1}" for k in range(len(interfaces))],
        iface_a=[ids[f.a] for f in interfaces], iface_b=[ids[f.b] for f in interfaces],
        iface_polygon=[f.polygon for f in interfaces], iface_holes=[list(f.holes) for f in interfaces],
        point_interface=np.repeat(np.arange(len(interfaces)), count),
        point=np.vstack(pts) if pts else np.zeros((0, 3)), normal=normal, tangent1=t1, tangent2=t2,
        mu=np.repeat(iface_mu, count), dead_m=dead_m, live_m=live_m, volume=volume,
        polyhedra={p.id: (p.vertices, p.faces) for p in polys}, units=units(spec, where), meta=meta, **joints)
    return validated(s, where)


def _is_points(v) -> bool:
    """A list of [x, y, z] numbers (true and false are not numbers, as in the planar reader)."""
    try:
        a = np.asarray(v, dtype=float)
    except (TypeError, ValueError):
        return False
    return a.ndim == 2 and a.shape[1] == 3 and not any(isinstance(c, (bool, np.bool_)) for p in v for c in p)


def _point_loads(spec, where, row, centroid, rows, polys, tol):
    """Point loads: the force and its moment about the block's centroid into dead or live;
    each at a point of its block (``polys``, a row's polyhedron), within the geometric
    tolerance ``tol`` and ``LOAD_POINT_SLACK`` of the block's size."""
    loads = spec.get("loads", [])
    if not isinstance(loads, list):
        raise InputError(f"{where}: 'loads' is {json.dumps(loads)[:40]}; expected a list of point loads")
    for k, load in enumerate(loads):
        at = f"{where}: loads[{k}]"
        if not isinstance(load, dict):
            raise InputError(f"{at} is {json.dumps(load)[:40]}; expected an object with 'block', 'at', 'force'")
        warn_unknown(at, load.keys(), ("block", "at", "force", "kind", "case"), "load")
        block = str(load.get("block"))
        if block not in row:
            raise InputError(f"{at}: block '{block}' is not a movable block; expected the id of a block")
        if load.get("case") is not None:
            raise InputError(f"{at}: load cases are not available for 3D structures; expected loads without 'case'")
        kind = load.get("kind", "live")
        if kind not in ("live", "dead"):
            raise InputError(f"{at}: 'kind' is {json.dumps(kind)}; expected \"live\" or \"dead\"")
        point, force = _vector3(load.get("at"), at, "'at'"), _vector3(load.get("force"), at, "'force'")
        r = row[block]
        _check_on_block(point, polys[r], tol, at)
        rows[kind][r] += force
        rows[kind + "_m"][r] += np.cross(point - centroid[r], force)


def _check_on_block(point, poly, tol, at):
    """InputError unless ``point`` is inside the polyhedron or within the slack of its surface."""
    size = float(np.linalg.norm(poly.hi - poly.lo))
    triangles = poly.triangles()
    if winding_number(triangles, point[None, :])[0] > 0.5:
        return
    gap = surface_distance(triangles, point)
    if gap > tol + LOAD_POINT_SLACK * size:
        raise InputError(f"{at}: point {point.tolist()} is not on block '{poly.id}' ({gap:.3g} from its surface, "
                         f"{gap / size:.3g} times its size); expected a point inside or on the boundary of the block")


def read_json3d(path_or_spec, name=None, **options) -> Structure3D:
    """A Structure3D from a 3D lamodel JSON file or dict (options: tolerance, contact_points)."""
    spec, where = load_spec(path_or_spec)
    return structure3d_from_spec(spec, where, name=name, **options)
