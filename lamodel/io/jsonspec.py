"""JSON geometry of a block assembly: convex polygons in, a Structure out (and back).

A structure is described in JSON by the polygons of its bodies (movable blocks and fixed
supports); everything the limit analysis needs — centroids, weights, live loads and the
contact interfaces of eq. (1)-(4) — is derived here, so that instances are never typed by
hand. The JSON format::

    { "name": "wall33",
      "description": "free text (optional)",
      "mu": 0.65,                 # friction of every contact
      "unit_weight": 1.0,         # optional, default 1: weight per unit area (unit width)
      "live_load": [1.0, 0.0],    # optional, default [1, 0]: live force per unit weight
      "tolerance": 1e-9,          # optional: geometric tolerance relative to the model size
      "blocks": [ {"id": "b1", "vertices": [[0,0],[2,0],[2,1.75],[0,1.75]]},
                  {"id": "ground", "vertices": [[-1,-1],[21,-1],[21,0],[-1,0]],
                   "support": true} ] }

Per body, optional: ``"support": true`` (a fixed body), ``"dead": [fx, fy]`` and
``"live": [fx, fy]`` replacing the computed loads, ``"dead_m"``/``"live_m"`` (couples about
the centroid), ``"mu"`` (a contact takes the smaller ``mu`` of its two bodies),
``"description"``.

Loads. The dead load of a block is its weight ``unit_weight * area`` pointing down; its live
load is ``live_load * unit_weight * area`` (the base load that alpha multiplies). Both act
at the centroid of the polygon. Optional, at the top level (:mod:`lamodel.loads`):

* ``"loads": [{"block": "v3", "at": [x, y], "force": [fx, fy], "kind": "live" | "dead",
  "case": "name"}]`` — point loads where they act (their moment about the centroid enters
  eq. 1); ``kind`` defaults to live; a live load with a ``case`` belongs to that load case
  only, without one to every case;
* ``"rolling_load": {"force": [fx, fy], "axles": [0, 1.5], "positions": [x, ...]}`` — a
  live axle group moved across the top (``positions`` omitted: the top edges' midpoints);
* ``"units": {"length": "m", "force": "kN"}`` — carried into tables, CSV, pictures, report.

Joints (:mod:`lamodel.formulation.joints`). ``"fc"`` (compressive strength; omitted: no
crushing), ``"ft"`` (tensile strength), ``"cohesion"`` and ``"thickness"`` (the joints'
width out of the plane, default 1) at the top level hold for every contact; on a body, for
its contacts (a contact takes the smaller value of its two bodies, a body without its own
having the file's); in ``"joints": [{"between":
["b1", "b2"], "fc": ...}]``, for the contact of those two bodies. Stresses are in the
file's force per length squared (kN and m: kPa).

Restraints (:mod:`lamodel.io.restraints`). ``"restraints": [{"support", "block", "at",
"direction", "half_length", "capacity"}]`` adds one-way reactions of bounded force from a
support (a bridge's passive fill pressure): contacts given, not found, after the others.

When the file gives live point loads or a rolling load but no ``"live_load"``, the blocks'
own live load is zero but where a body writes its ``"live"``: alpha multiplies only the
loads written.

Contacts. Two bodies are in contact where an edge of one and an edge of the other lie on
one line (within the tolerance), face each other (opposite outward normals) and overlap
over a positive length. Two convex bodies with disjoint interiors touch along at most one
segment, so there is at most one contact per pair of bodies. The contact's centre is the
midpoint of the overlap and ``d`` its half-length (the largest eccentricity of N).

Orientation conventions (the ``a -> b`` normal of :mod:`lamodel.structure`):

* a contact with a support has the **support as block a**: the normal points from the
  support into the block (up, for the ground);
* a contact between two blocks has as block a the body whose outward normal points up
  (``n_y > 0``) or, for a vertical joint, to the right (``n_x > 0``): a is below b, or
  left of b. In a wall, bed joints have ``n = (0, 1)`` and head joints ``n = (1, 0)``.

Contact ids are ``c1, c2, ...`` sorted by the positions, in the JSON list of bodies, of the
two bodies of the contact (first the smaller position, then the larger), so they do not
depend on how the contacts were found.

Contact detection is linear-logarithmic in the number of bodies: a sweep over bounding
boxes sorted along one axis proposes pairs of bodies, and the exact tests (separating axes
for interpenetration, collinear facing edges for contacts) run vectorised over all pairs.
"""
from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np

from ..errors import InputError
from .restraints import restraint_contacts, restraints_of
from .jsonfields import (STRENGTH_FIELDS, blocks_of, body_head, body_support_mu, check_supports, joint_strengths,
                         json_object, load_spec, number, strengths, units, validated, warn_unknown, writes_live)
from ..geometry.contacts import area_centroid, clean_polygons, find_contacts
from ..search.tuning import LOAD_POINT_SLACK
from ..structure import JOINT_DEFAULTS, Structure

#: Geometric tolerance relative to the size of the model (diagonal of its bounding box):
#: points closer than ``DEFAULT_TOLERANCE * size`` are the same point.
DEFAULT_TOLERANCE = 1e-9

TOP_FIELDS = ("name", "description", "dimension", "mu", "unit_weight", "live_load", "tolerance", "blocks", "loads", "units",
              "rolling_load", "joints", "restraints", *STRENGTH_FIELDS)
BODY_FIELDS = ("id", "vertices", "support", "dead", "live", "dead_m", "live_m", "mu", "description", *STRENGTH_FIELDS)
LOAD_FIELDS = ("block", "at", "force", "kind", "case")
ROLLING_FIELDS = ("force", "axles", "positions")


# ================================================================== reading the JSON
def structure_from_json(source, name: str | None = None, tolerance: float | None = None) -> Structure:
    """Build a :class:`Structure` from a JSON file (path) or an already parsed dict.

    ``name`` overrides the ``"name"`` field (default: the file stem). ``tolerance``
    overrides the ``"tolerance"`` field (relative to the model size). Raises
    :class:`InputError` naming the file and the body for anything that is not a valid
    assembly of convex blocks; unknown fields only give a warning.
    """
    spec, where = load_spec(source)
    return structure_from_spec(spec, where, name=name, tolerance=tolerance)


def _vector2(value, where, what):
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise InputError(f"{where}: {what} is {json.dumps(value)}; expected a pair [x, y] of numbers")
    return np.array([number(v, where, what) for v in value])


def structure_from_spec(spec: dict, where: str, name: str | None = None, tolerance: float | None = None) -> Structure:
    """A validated :class:`Structure` from a parsed planar spec; ``where`` (the file) starts
    every message. ``name`` and ``tolerance`` as :func:`structure_from_json`."""
    if "blocks" not in spec:  # no blocks (a bridge description, say): that error, without field warnings first
        blocks_of(spec, where)
    warn_unknown(where, spec.keys(), TOP_FIELDS, "top-level")
    dimension = spec.get("dimension", 2)
    if dimension != 2 or isinstance(dimension, bool):
        expected = ("2 here (a file of polyhedra is read by lamodel.io.read)" if dimension == 3 else
                    "2 (polygons) or 3 (polyhedra)")
        raise InputError(f"{where}: 'dimension' is {json.dumps(dimension)[:20]}; expected {expected}")
    bodies = blocks_of(spec, where)
    name = str(name if name is not None else spec.get("name") or "structure")
    mu_all = number(spec["mu"], where, "'mu'", 0.0) if "mu" in spec else None
    unit_weight = number(spec.get("unit_weight", 1.0), where, "'unit_weight'", 0.0)
    live_load = _vector2(spec.get("live_load", [1.0, 0.0]), where, "'live_load'")
    rel_tol = tolerance if tolerance is not None else spec.get("tolerance", DEFAULT_TOLERANCE)
    rel_tol = number(rel_tol, where, "'tolerance'", 0.0)

    # --- per body: id, raw vertices, flags (parsed first: the tolerance needs the size)
    ids, raw, is_support, mus, dead_over, live_over, body_strengths = [], [], [], [], {}, {}, []
    moment_over = {"dead_m": {}, "live_m": {}}
    seen, unknown = {}, set()
    for pos, body in enumerate(bodies):
        bid, at = body_head(body, pos, where, seen, "a list of [x, y] corners of a convex polygon")
        unknown |= set(body) - set(BODY_FIELDS)
        verts = body["vertices"]
        if not isinstance(verts, list) or not all(isinstance(v, (list, tuple)) and len(v) == 2 for v in verts):
            raise InputError(f"{at}: 'vertices' is not a list of [x, y] pairs; expected [[x1, y1], [x2, y2], ...]")
        if len(verts) < 3:
            raise InputError(f"{at} has {len(verts)} vertices; expected at least 3 corners of a convex polygon")
        raw.append(np.array([[number(c, at, "a vertex coordinate") for c in v] for v in verts]))
        support, mu = body_support_mu(body, at, mu_all)
        is_support.append(support)
        mus.append(mu)
        body_strengths.append(strengths(body, at))
        for key, store in (("dead", dead_over), ("live", live_over)):
            if key in body:
                if support:
                    warnings.warn(f"{at} is a support: its '{key}' load is ignored", stacklevel=3)
                else:
                    store[pos] = _vector2(body[key], at, f"'{key}'")
        for key, store in moment_over.items():
            if key in body and not support:
                store[pos] = number(body[key], at, f"'{key}'")
        ids.append(bid)
    if unknown:
        warn_unknown(where, unknown, BODY_FIELDS, "block")
    is_support = np.array(is_support, dtype=bool)
    check_supports(where, is_support)

    allv = np.vstack(raw)
    size = float(np.hypot(*(allv.max(axis=0) - allv.min(axis=0)))) or 1.0
    tol = rel_tol * size

    polygons = clean_polygons(raw, tol, ids, where, f"{tol:.3g} (the 'tolerance' {rel_tol:g} times the model's size "
                                                    f"{size:.3g})")
    area, centroid = area_centroid(polygons)

    contacts = find_contacts(polygons, is_support, tol, ids=ids, where=where)
    ia, ib = contacts["a"], contacts["b"]

    moving = np.flatnonzero(~is_support)
    touched = np.zeros(len(ids), dtype=bool)
    touched[ia] = touched[ib] = True
    free = moving[~touched[moving]]
    if free.size:
        raise InputError(f"{where}: block '{ids[free[0]]}' touches no other body (a free body); "
                         "expected every block to share an edge segment with a block or a support")

    weight = unit_weight * area[moving]
    dead = np.column_stack([np.zeros_like(weight), -weight])
    live = weight[:, None] * live_load[None, :]
    if "live_load" not in spec and writes_live(spec, also=("rolling_load",)):
        live[:] = 0.0  # alpha multiplies only the live loads the file writes (a body's own "live" among them)
    row = {int(p): r for r, p in enumerate(moving)}
    for pos, f in dead_over.items():
        dead[row[pos]] = f
    for pos, f in live_over.items():
        live[row[pos]] = f

    dead_m, live_m = np.zeros(len(moving)), np.zeros(len(moving))
    for store, arr in ((moment_over["dead_m"], dead_m), (moment_over["live_m"], live_m)):
        for pos, m in store.items():
            arr[row[pos]] = m

    mus = np.asarray(mus)
    joints = joint_strengths(spec, where, ids, body_strengths, ia, ib, JOINT_DEFAULTS)
    mu = np.minimum(mus[ia], mus[ib])
    centre, normal, half = contacts["centre"], contacts["normal"], contacts["d"]
    extra = restraint_contacts(spec, where, ids, is_support)
    if extra is not None:  # restraints after the contacts found from the polygons (lamodel.io.restraints)
        m = extra["a"].size
        for key, default in JOINT_DEFAULTS.items():
            tail = extra[key] if key in extra else np.full(m, default)
            joints[key] = np.concatenate([joints.get(key, np.full(ia.size, default)), tail])
        ia, ib = np.concatenate([ia, extra["a"]]), np.concatenate([ib, extra["b"]])
        mu = np.concatenate([mu, np.zeros(m)])  # no tangential force, no fictitious cohesion
        centre, normal = np.vstack([centre, extra["centre"]]), np.vstack([normal, extra["normal"]])
        half = np.concatenate([half, extra["d"]])
    structure = Structure(
        name=name,
        blocks=[ids[j] for j in moving],
        centroid=centroid[moving],
        dead=dead,
        live=live,
        supports=[ids[j] for j in np.flatnonzero(is_support)],
        contacts=[f"c{k + 1}" for k in range(ia.size)],
        block_a=[ids[j] for j in ia],
        block_b=[ids[j] for j in ib],
        centre=centre,
        normal=normal,
        d=half,
        mu=mu,
        polygons={b: p for b, p in zip(ids, polygons)},
        dead_m=dead_m, live_m=live_m, units=units(spec, where),
        restraints=0 if extra is None else int(extra["a"].size),
        description=str(spec.get("description", "")), tolerance=rel_tol,
        **joints,
    )
    _point_loads(spec, where, structure, tol)
    if "rolling_load" in spec:
        structure.rolling = _rolling(spec["rolling_load"], where)
        if structure.cases:
            raise InputError(f"{where}: the file has load cases and a rolling load; expected one or the other "
                             "(a rolling load is a study of its own)")
    return validated(structure, where)


def _point_loads(spec, where, structure, tol):
    """Point loads into the structure: dead ones into dead/dead_m, live ones into the
    common live pattern or their load case (:mod:`lamodel.loads`)."""
    from ..loads import KINDS, LoadCase, PointLoad, add_point_load, on_polygon
    loads = spec.get("loads", [])
    if not isinstance(loads, list):
        raise InputError(f"{where}: 'loads' is {json.dumps(loads)[:40]}; expected a list of point loads "
                         "{\"block\", \"at\", \"force\", \"kind\", \"case\"}")
    index = structure.block_index()
    parsed = []
    for i, raw in enumerate(loads):
        at = f"{where}: loads[{i}]"
        load = json_object(raw, at, "the point load", LOAD_FIELDS)
        block = str(load.get("block"))
        if block not in index:
            raise InputError(f"{at} names block '{block}', which is not a movable block; expected the id of a "
                             "block that is not a support")
        for key in ("at", "force"):
            if key not in load:
                raise InputError(f"{at} has no '{key}'; expected \"{key}\": [x, y]")
        point, force = _vector2(load["at"], at, "'at'"), _vector2(load["force"], at, "'force'")
        kind = load.get("kind", "live")
        if kind not in KINDS:
            raise InputError(f"{at}: 'kind' is {json.dumps(kind)}; expected \"live\" or \"dead\"")
        case = load.get("case", "")
        if not isinstance(case, str) or ("case" in load and not case.strip()):
            raise InputError(f"{at}: 'case' is {json.dumps(case)}; expected a case name (text), or no 'case' for a "
                             "load of every case")
        if case and kind == "dead":
            raise InputError(f"{at}: a dead load with case '{case}'; expected dead loads without a case "
                             "(they act in every case)")
        polygon = np.asarray(structure.polygons[block], float)
        size = float(np.hypot(*(polygon.max(axis=0) - polygon.min(axis=0))))
        if not on_polygon(point, polygon, tol + LOAD_POINT_SLACK * size):
            raise InputError(f"{at}: point {point.tolist()} is not on block '{block}'; expected a point inside "
                             "or on the boundary of the block")
        parsed.append(PointLoad(block, tuple(point), tuple(force), kind, case))
    common = [p for p in parsed if not p.case]
    for p in common:
        if p.kind == "dead":
            add_point_load(structure.dead, structure.dead_m, structure, p)
        else:
            add_point_load(structure.live, structure.live_m, structure, p)
    structure.point_loads = common
    for name in dict.fromkeys(p.case for p in parsed if p.case):
        case = LoadCase(name, structure.live.copy(), structure.live_m.copy(), list(common))
        for p in parsed:
            if p.case == name:
                add_point_load(case.live, case.live_m, structure, p)
                case.point_loads.append(p)
        structure.cases[name] = case


def _rolling(value, where):
    from ..loads import RollingLoad
    r = json_object(value, where, "'rolling_load'", ROLLING_FIELDS)
    if "force" not in r:
        raise InputError(f"{where}: 'rolling_load' has no 'force'; expected \"force\": [fx, fy] per axle")
    force = _vector2(r["force"], where, "the rolling load's 'force'")
    if not np.any(force):
        raise InputError(f"{where}: the rolling load's 'force' is zero; expected a non-zero force per axle")
    axles = r.get("axles", [0.0])
    if not isinstance(axles, list) or not axles:
        raise InputError(f"{where}: the rolling load's 'axles' is {json.dumps(axles)}; expected a list of offsets "
                         "from the lead axle, e.g. [0, 1.5]")
    axles = tuple(number(a, where, "an axle offset") for a in axles)
    positions = r.get("positions")
    if positions is not None:
        if not isinstance(positions, list) or not positions:
            raise InputError(f"{where}: the rolling load's 'positions' is {json.dumps(positions)[:40]}; expected "
                             "a list of abscissas of the lead axle (or no field: the top edges' midpoints)")
        positions = tuple(number(x, where, "a rolling load position") for x in positions)
    return RollingLoad(tuple(force), axles, positions)


# ==================================================================== writing JSON
def structure_to_json(source, path=None) -> dict:
    """The JSON spec of a generated geometry (a dict) or of a Structure; written to
    ``path`` if given (one body per line, so that files diff well). Returns the dict.

    A Structure is written with its point loads as ``loads`` (those of its load cases with
    their ``case``), the rest of each block's ``dead`` and ``live`` loads explicit, its
    rolling load as ``rolling_load``; its
    friction is written as a top-level ``mu`` when all contacts share one value, else per
    body (the largest of its contacts), which must reproduce every contact's ``mu`` as
    the smaller of its two bodies' values.
    """
    spec = source if isinstance(source, dict) else _spec_of_structure(source)
    if path is not None:
        lines = ["{"]
        for key, value in spec.items():
            if key != "blocks":
                lines.append(f"  {json.dumps(key)}: {json.dumps(value)},")
        lines.append('  "blocks": [')
        bodies = spec.get("blocks", [])
        for k, body in enumerate(bodies):
            lines.append("    " + json.dumps(body) + ("," if k + 1 < len(bodies) else ""))
        lines += ["  ]", "}"]
        from .files import atomic_write_text
        atomic_write_text(path, "\n".join(lines) + "\n")  # never half a file, whatever stops the run
    return spec


def _spec_of_structure(s: Structure) -> dict:
    missing = [b for b in s.blocks + s.supports if b not in s.polygons]
    if missing:
        raise InputError(f"structure '{s.name}': block '{missing[0]}' has no polygon; expected polygons for every "
                         "body to write the geometry as JSON")
    spec = {"name": s.name}
    if s.description:
        spec["description"] = s.description
    if s.tolerance is not None and s.tolerance != DEFAULT_TOLERANCE:
        spec["tolerance"] = float(s.tolerance)
    if s.units:
        spec["units"] = dict(s.units)
    n = s.n_contacts - s.restraints  # the contacts found from the polygons; then the restraints
    uniform = n and np.allclose(s.mu[:n], s.mu[0], rtol=0, atol=1e-15)
    body_mu = {}
    if uniform:
        spec["mu"] = float(s.mu[0])
    elif n:
        spec["mu"] = float(np.max(s.mu[:n]))  # for the bodies in no contact (their own below)
        for k in range(n):
            for x in (s.block_a[k], s.block_b[k]):
                body_mu[x] = max(body_mu.get(x, 0.0), float(s.mu[k]))
        for k in range(n):
            if min(body_mu[s.block_a[k]], body_mu[s.block_b[k]]) != s.mu[k]:
                raise InputError(f"structure '{s.name}': the friction of contact '{s.contacts[k]}' cannot be written "
                                 "as the smaller 'mu' of its two bodies; expected friction given per body")
    blocks, index = [], s.block_index()
    # the point loads acting here are written where they act (pictures draw them), the blocks'
    # own loads without them
    from ..loads import moment
    own = {"dead": s.dead.astype(float), "live": s.live.astype(float),
           "dead_m": np.array(s.dead_m, dtype=float), "live_m": np.array(s.live_m, dtype=float)}
    loads = []
    for p in s.point_loads:
        j, f = index[p.block], np.asarray(p.force, dtype=float)
        own[p.kind][j] -= f
        own[f"{p.kind}_m"][j] -= moment(p.at, s.centroid[j], f)
        loads.append({"block": p.block, "at": [float(v) for v in p.at], "force": [float(v) for v in f],
                      **({"kind": "dead"} if p.kind == "dead" else {})})
    force = max(float(np.abs(s.dead).max(initial=0.0)), float(np.abs(s.live).max(initial=0.0)), 1e-300)
    for key, scale in (("dead", force), ("live", force), ("dead_m", force * s.size()), ("live_m", force * s.size())):
        own[key][np.abs(own[key]) < 1e-13 * scale] = 0.0   # what the point loads leave: round-off is none
    for b in s.polygons:  # the file's order of bodies: contacts found again in the same order, same ids
        if b in index:
            j = index[b]
            body = {"id": b, "vertices": s.polygons[b].tolist(),
                    "dead": own["dead"][j].tolist(), "live": own["live"][j].tolist()}
            for key in ("dead_m", "live_m"):
                if own[key][j]:
                    body[key] = float(own[key][j])
        else:
            body = {"id": b, "vertices": s.polygons[b].tolist(), "support": True}
        if b in body_mu:
            body["mu"] = body_mu[b]
        blocks.append(body)
    spec["blocks"] = blocks
    value = {key: getattr(s, key)[:n] for key in STRENGTH_FIELDS}
    if any(np.any(value[key] != JOINT_DEFAULTS[key]) for key in STRENGTH_FIELDS):
        # the joints' strengths: the file's when uniform, else joint by joint
        uniform = {key: v[0] for key, v in value.items() if np.all(v == v[0])}
        spec.update({key: float(v) for key, v in uniform.items() if v != JOINT_DEFAULTS[key]})
        rest = [key for key in STRENGTH_FIELDS if key not in uniform]
        if rest:
            spec["joints"] = [{"between": [s.block_a[k], s.block_b[k]],
                               **{key: float(value[key][k]) for key in rest
                                  if np.isfinite(value[key][k])}} for k in range(n)]
    if s.restraints:
        spec["restraints"] = restraints_of(s, n)
    # the load cases' own point loads (those of every case are above)
    loads += [{"block": p.block, "at": [float(v) for v in p.at], "force": [float(v) for v in p.force], "case": name}
              for name, case in s.cases.items() for p in case.point_loads if p.case == name]
    if loads:
        spec["loads"] = loads
    if s.rolling is not None:
        r = s.rolling
        spec["rolling_load"] = {"force": [float(v) for v in r.force], "axles": [float(v) for v in r.axles],
                                **({} if r.positions is None else {"positions": [float(v) for v in r.positions]})}
    return spec
