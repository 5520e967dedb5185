"""Block assemblies from geometry: convex polygons in, contacts and loads out.

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
``"live": [fx, fy]`` replacing the computed loads, ``"mu"`` (a contact takes the smaller
``mu`` of its two bodies), ``"description"``.

Loads. The dead load of a block is its weight ``unit_weight * area`` pointing down; its live
load is ``live_load * unit_weight * area`` (the base load that alpha multiplies). Both act
at the centroid of the polygon.

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
import math
import warnings
from pathlib import Path

import numpy as np

from .errors import InputError
from .structure import Structure

#: Geometric tolerance relative to the size of the model (diagonal of its bounding box):
#: points closer than ``DEFAULT_TOLERANCE * size`` are the same point.
DEFAULT_TOLERANCE = 1e-9

TOP_FIELDS = ("name", "description", "mu", "unit_weight", "live_load", "tolerance", "blocks")
BODY_FIELDS = ("id", "vertices", "support", "dead", "live", "mu", "description")


# ================================================================== reading the JSON
def structure_from_json(source, name: str | None = None, tolerance: float | None = None) -> Structure:
    """Build a :class:`Structure` from a JSON file (path) or an already parsed dict.

    ``name`` overrides the ``"name"`` field (default: the file stem). ``tolerance``
    overrides the ``"tolerance"`` field (relative to the model size). Raises
    :class:`InputError` naming the file and the body for anything that is not a valid
    assembly of convex blocks; unknown fields only give a warning.
    """
    spec, where = _load_spec(source)
    return _build(spec, where, name=name, tolerance=tolerance)


def _load_spec(source):
    if isinstance(source, dict):
        return source, f"geometry '{source.get('name', '<dict>')}'"
    path = Path(source)
    where = str(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise InputError(f"{where}: cannot read the geometry file ({exc.strerror}); expected a readable JSON file") from None
    try:
        spec = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{where}: malformed JSON at line {exc.lineno}, column {exc.colno} ({exc.msg}); "
                         "expected a JSON object describing the blocks") from None
    if not isinstance(spec, dict):
        raise InputError(f"{where}: the file holds a JSON {type(spec).__name__}; expected a JSON object with a 'blocks' list")
    if "name" not in spec:
        spec = dict(spec, name=path.stem)
    return spec, where


def _number(value, where, what, minimum=None):
    """A finite float from JSON, or an InputError saying what was expected."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"{where}: {what} is {json.dumps(value)}; expected a finite number")
    if minimum is not None and value < minimum:
        raise InputError(f"{where}: {what} is {value}; expected a number >= {minimum}")
    return float(value)


def _vector2(value, where, what):
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise InputError(f"{where}: {what} is {json.dumps(value)}; expected a pair [x, y] of numbers")
    return np.array([_number(v, where, what) for v in value])


def _warn_unknown(where, keys, known, kind):
    unknown = sorted(set(keys) - set(known))
    if unknown:
        warnings.warn(f"{where}: unknown {kind} field(s) {', '.join(repr(k) for k in unknown)} ignored; "
                      f"known fields are {', '.join(known)}", stacklevel=4)


def _build(spec, where, name=None, tolerance=None) -> Structure:
    _warn_unknown(where, spec.keys(), TOP_FIELDS, "top-level")
    bodies = spec.get("blocks")
    if not isinstance(bodies, list) or not bodies:
        raise InputError(f"{where}: 'blocks' is missing or empty; expected a list of blocks with 'id' and 'vertices'")
    name = str(name if name is not None else spec.get("name") or "structure")
    mu_all = _number(spec["mu"], where, "'mu'", 0.0) if "mu" in spec else None
    unit_weight = _number(spec.get("unit_weight", 1.0), where, "'unit_weight'", 0.0)
    live_load = _vector2(spec.get("live_load", [1.0, 0.0]), where, "'live_load'")
    rel_tol = tolerance if tolerance is not None else spec.get("tolerance", DEFAULT_TOLERANCE)
    rel_tol = _number(rel_tol, where, "'tolerance'", 0.0)

    # --- per body: id, raw vertices, flags (parsed first: the tolerance needs the size)
    ids, raw, is_support, mus, dead_over, live_over = [], [], [], [], {}, {}
    seen, unknown = {}, set()
    for pos, body in enumerate(bodies):
        if not isinstance(body, dict):
            raise InputError(f"{where}: blocks[{pos}] is {json.dumps(body)[:40]}; expected an object with 'id' and 'vertices'")
        if "id" not in body or isinstance(body["id"], (dict, list, bool)) or body["id"] is None:
            raise InputError(f"{where}: blocks[{pos}] has no valid 'id'; expected a string or integer id")
        bid = str(body["id"])
        at = f"{where}: block '{bid}'"
        if bid in seen:
            raise InputError(f"{at} is declared twice (blocks[{seen[bid]}] and blocks[{pos}]); expected unique ids")
        seen[bid] = pos
        unknown |= set(body) - set(BODY_FIELDS)
        if "vertices" not in body:
            raise InputError(f"{at} has no 'vertices'; expected a list of [x, y] corners of a convex polygon")
        verts = body["vertices"]
        if not isinstance(verts, list) or not all(isinstance(v, (list, tuple)) and len(v) == 2 for v in verts):
            raise InputError(f"{at}: 'vertices' is not a list of [x, y] pairs; expected [[x1, y1], [x2, y2], ...]")
        if len(verts) < 3:
            raise InputError(f"{at} has {len(verts)} vertices; expected at least 3 corners of a convex polygon")
        raw.append(np.array([[_number(c, at, "a vertex coordinate") for c in v] for v in verts]))
        support = body.get("support", False)
        if not isinstance(support, bool):
            raise InputError(f"{at}: 'support' is {json.dumps(support)}; expected true or false")
        is_support.append(support)
        if "mu" in body:
            mus.append(_number(body["mu"], at, "'mu'", 0.0))
        elif mu_all is None:
            raise InputError(f"{at} has no friction coefficient; expected a top-level 'mu' or a 'mu' on every block")
        else:
            mus.append(mu_all)
        for key, store in (("dead", dead_over), ("live", live_over)):
            if key in body:
                if support:
                    warnings.warn(f"{at} is a support: its '{key}' load is ignored", stacklevel=3)
                else:
                    store[pos] = _vector2(body[key], at, f"'{key}'")
        ids.append(bid)
    if unknown:
        _warn_unknown(where, unknown, BODY_FIELDS, "block")
    is_support = np.array(is_support, dtype=bool)
    if not is_support.any():
        raise InputError(f"{where}: no block is a support; expected at least one body with \"support\": true")
    if is_support.all():
        raise InputError(f"{where}: every body is a support; expected at least one movable block")

    allv = np.vstack(raw)
    size = float(np.hypot(*(allv.max(axis=0) - allv.min(axis=0)))) or 1.0
    tol = rel_tol * size

    polygons = _clean_polygons(raw, tol, ids, where)
    area, centroid = _area_centroid(polygons)

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
    row = {int(p): r for r, p in enumerate(moving)}
    for pos, f in dead_over.items():
        dead[row[pos]] = f
    for pos, f in live_over.items():
        live[row[pos]] = f

    mus = np.asarray(mus)
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
        centre=contacts["centre"],
        normal=contacts["normal"],
        d=contacts["d"],
        mu=np.minimum(mus[ia], mus[ib]),
        polygons={b: p for b, p in zip(ids, polygons)},
    )
    try:
        return structure.validate()
    except InputError as exc:  # name the file, not the structure ("structure 'x': ...")
        raise InputError(f"{where}: {str(exc).split(': ', 1)[1]}") from None


# ====================================================================== polygons
def _clean_polygon(v: np.ndarray, tol: float, at: str) -> np.ndarray:
    """Counter-clockwise convex polygon without repeated or collinear vertices.

    Collinear vertices are dropped so that every side of a block is one edge: a face
    split in two would otherwise give two contacts where the mechanics has one.
    """
    v = np.asarray(v, dtype=float)
    # repeated consecutive vertices (including a closing copy of the first one)
    keep = np.hypot(*(np.roll(v, -1, axis=0) - v).T) > tol
    v = v[keep]
    # drop vertices lying on the segment joining their neighbours, until none is left
    while len(v) >= 3:
        prev, nxt = np.roll(v, 1, axis=0), np.roll(v, -1, axis=0)
        chord = nxt - prev
        length = np.hypot(chord[:, 0], chord[:, 1])
        rel = v - prev
        cross = chord[:, 0] * rel[:, 1] - chord[:, 1] * rel[:, 0]
        dist = np.where(length > tol, np.abs(cross) / np.maximum(length, tol), np.hypot(rel[:, 0], rel[:, 1]))
        flat = dist <= tol
        if not flat.any():
            break
        if flat.all():
            v = v[:0]
            break
        v = v[~flat]
    if len(v) < 3:
        raise InputError(f"{at} has zero area (its vertices are collinear); expected a polygon with a positive area")
    e = np.roll(v, -1, axis=0) - v
    ep = np.roll(e, 1, axis=0)  # edge arriving at each vertex
    turn = ep[:, 0] * e[:, 1] - ep[:, 1] * e[:, 0]
    if (turn > 0).any() and (turn < 0).any():
        minority = turn < 0 if (turn < 0).sum() <= (turn > 0).sum() else turn > 0
        x, y = v[np.flatnonzero(minority)[0]]
        raise InputError(f"{at} is not convex or crosses itself (its boundary turns the other way at vertex ({x:g}, {y:g})); "
                         "expected the corners of a convex polygon in order")
    if turn[0] < 0:  # clockwise: reverse to counter-clockwise
        v = v[::-1].copy()
        e = np.roll(v, -1, axis=0) - v
        ep = np.roll(e, 1, axis=0)
    angles = np.arctan2(ep[:, 0] * e[:, 1] - ep[:, 1] * e[:, 0], (ep * e).sum(axis=1))
    if abs(angles.sum() - 2 * np.pi) > 1e-6:
        raise InputError(f"{at} is self-intersecting (its boundary winds {angles.sum() / (2 * np.pi):.0f} times); "
                         "expected the corners of a convex polygon in order")
    area = 0.5 * np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1])
    perimeter = np.hypot(e[:, 0], e[:, 1]).sum()
    if area <= tol * perimeter / 2:
        raise InputError(f"{at} has zero area ({area:.3g}); expected a polygon with a positive area")
    return v


def _clean_polygons(raw, tol, ids, where):
    """:func:`_clean_polygon` for all bodies, vectorised over polygons of equal vertex count.

    Polygons already clean (no repeated or collinear vertex, convex, positive area) are
    only oriented counter-clockwise here; the others go through :func:`_clean_polygon`
    one by one, in file order, so the first faulty block is the one reported.
    """
    out = [None] * len(raw)
    slow = []
    count = np.array([len(v) for v in raw])
    for k in np.unique(count):
        group = np.flatnonzero(count == k)
        V = np.stack([raw[j] for j in group])                       # (m, k, 2)
        e = np.roll(V, -1, axis=1) - V
        length = np.hypot(e[..., 0], e[..., 1])
        ep = np.roll(e, 1, axis=1)
        turn = ep[..., 0] * e[..., 1] - ep[..., 1] * e[..., 0]
        chord = np.hypot(*(np.roll(V, -1, axis=1) - np.roll(V, 1, axis=1)).transpose(2, 0, 1))
        sign = np.sign(turn[:, :1])
        dist = np.abs(turn) / np.maximum(chord, tol)  # distance of a vertex from its neighbours' chord
        winding = np.arctan2(turn * sign, (ep * e).sum(axis=-1)).sum(axis=1)
        x, y = V[..., 0] - V[:, :1, 0], V[..., 1] - V[:, :1, 1]
        area = 0.5 * np.abs((x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y).sum(axis=1))
        good = ((length > tol).all(axis=1) & (dist > tol).all(axis=1) & (turn * sign > 0).all(axis=1)
                & (np.abs(winding - 2 * np.pi) <= 1e-6) & (area > tol * length.sum(axis=1) / 2))
        for j, ok, s in zip(group, good, sign[:, 0]):
            if ok:
                out[j] = raw[j] if s > 0 else raw[j][::-1].copy()
            else:
                slow.append(j)
    for j in sorted(slow):
        out[j] = _clean_polygon(raw[j], tol, f"{where}: block '{ids[j]}'")
    return out


def _area_centroid(polygons):
    """Areas and centroids of counter-clockwise polygons (shoelace formula, vectorised
    over polygons of equal vertex count, relative to a vertex to limit round-off)."""
    area = np.empty(len(polygons))
    centroid = np.empty((len(polygons), 2))
    count = np.array([len(p) for p in polygons])
    for k in np.unique(count):
        group = np.flatnonzero(count == k)
        V = np.stack([polygons[j] for j in group])
        x, y = V[..., 0] - V[:, :1, 0], V[..., 1] - V[:, :1, 1]
        x1, y1 = np.roll(x, -1, axis=1), np.roll(y, -1, axis=1)
        cross = x * y1 - x1 * y
        a = cross.sum(axis=1) / 2
        area[group] = a
        centroid[group] = V[:, 0] + np.column_stack([((x + x1) * cross).sum(axis=1),
                                                     ((y + y1) * cross).sum(axis=1)]) / (6 * a[:, None])
    return area, centroid


def _padded(polygons):
    """(n, K, 2) vertex array, each polygon padded by repeating its last vertex.

    The padding adds zero-length edges only, and leaves every real edge (including the
    closing one) in place for any width K >= the polygon's own vertex count.
    """
    count = np.array([len(p) for p in polygons])
    K = int(count.max())
    out = np.empty((len(polygons), K, 2))
    for j, p in enumerate(polygons):
        out[j, :len(p)] = p
        out[j, len(p):] = p[-1]
    return out, count


# ================================================================ pairs of bodies
def _candidate_pairs(lo: np.ndarray, hi: np.ndarray, tol: float):
    """Pairs (i, j), i < j, of bodies whose bounding boxes touch or overlap (within tol).

    Sweep and prune: sort the boxes by their lower end along one axis; the boxes that
    overlap box k along that axis are the next ones in the order whose lower end does not
    exceed box k's upper end — a contiguous run found by a binary search. The axis giving
    fewer candidates is used. The other axis then filters the candidates.
    """
    n = lo.shape[0]
    best = None
    for axis in (0, 1):
        order = np.argsort(lo[:, axis], kind="stable")
        start = lo[order, axis]
        end = np.searchsorted(start, hi[order, axis] + tol, side="right")
        count = np.maximum(end - np.arange(n) - 1, 0)
        if best is None or count.sum() < best[2].sum():
            best = (axis, order, count)
    axis, order, count = best
    total = int(count.sum())
    first = np.repeat(np.arange(n), count)
    offset = np.arange(total) - np.repeat(np.cumsum(count) - count, count)
    second = first + 1 + offset
    i, j = order[first], order[second]
    other = 1 - axis
    keep = (lo[j, other] <= hi[i, other] + tol) & (lo[i, other] <= hi[j, other] + tol)
    i, j = i[keep], j[keep]
    return np.minimum(i, j), np.maximum(i, j)


def _edges(V):
    """Start points, unit tangents, outward unit normals and lengths of padded CCW polygons."""
    q = np.roll(V, -1, axis=-2)
    vec = q - V
    length = np.hypot(vec[..., 0], vec[..., 1])
    safe = np.where(length > 0, length, 1.0)
    tangent = vec / safe[..., None]
    normal = np.stack([tangent[..., 1], -tangent[..., 0]], axis=-1)  # interior on the left
    return V, q, tangent, normal, length


def _penetration(VA, VB, tol):
    """Depth of overlap of convex polygon pairs: the smallest projection overlap over the
    edge normals of both (separating axis theorem). <= tol means they do not overlap."""
    _, _, _, nA, lA = _edges(VA)
    _, _, _, nB, lB = _edges(VB)
    axes = np.concatenate([nA, nB], axis=1)                    # (P, 2K, 2)
    real = np.concatenate([lA, lB], axis=1) > tol
    pa = np.einsum("pax,pvx->pav", axes, VA)
    pb = np.einsum("pax,pvx->pav", axes, VB)
    depth = np.minimum(pa.max(-1), pb.max(-1)) - np.maximum(pa.min(-1), pb.min(-1))
    depth = np.where(real, depth, np.inf)
    return depth.min(axis=1)


def _facing_edges(VA, VB, tol):
    """The contact between polygon pairs, if any: for each pair the overlap of an edge of A
    and an edge of B that are collinear (every endpoint within tol of the other edge's
    line), anti-parallel, and overlap by more than tol.

    Returns (found, normal of A's edge, centre, half-length) per pair.
    """
    pA, qA, tA, nA, lA = _edges(VA)
    pB, qB, tB, nB, lB = _edges(VB)
    # (P, K_A, K_B) quantities: A's edge i against B's edge j
    pA_, qA_, tA_, nA_, lA_ = (x[:, :, None] for x in (pA, qA, tA, nA, lA))
    pB_, qB_, nB_, lB_ = (x[:, None, :] for x in (pB, qB, nB, lB))
    dot = lambda x, y: x[..., 0] * y[..., 0] + x[..., 1] * y[..., 1]  # noqa: E731
    off_p = dot(nA_, pB_ - pA_)
    off_q = dot(nA_, qB_ - pA_)
    ok = (lA_ > tol) & (lB_ > tol) & (dot(nA_, nB_) < -0.5)
    ok &= (np.abs(off_p) <= tol) & (np.abs(off_q) <= tol)
    ok &= (np.abs(dot(nB_, pA_ - pB_)) <= tol) & (np.abs(dot(nB_, qA_ - pB_)) <= tol)
    s_p = dot(tA_, pB_ - pA_)
    s_q = dot(tA_, qB_ - pA_)
    low = np.maximum(0.0, np.minimum(s_p, s_q))
    high = np.minimum(lA_, np.maximum(s_p, s_q))
    overlap = np.where(ok, high - low, -np.inf)
    P, KA, KB = overlap.shape
    best = overlap.reshape(P, -1).argmax(axis=1)
    bi, bj = np.divmod(best, KB)
    rows = np.arange(P)
    length = overlap[rows, bi, bj]
    found = length > tol
    mid = 0.5 * (low + high)[rows, bi, bj]
    shift = 0.25 * (off_p + off_q)[rows, bi, bj]  # halfway between the two lines
    normal = nA[rows, bi]
    centre = pA[rows, bi] + tA[rows, bi] * mid[:, None] + normal * shift[:, None]
    return found, normal, centre, 0.5 * np.where(found, length, 0.0)


def find_contacts(polygons, is_support, tol, ids=None, where="geometry"):
    """Contacts of an assembly of convex CCW polygons (see the module docstring).

    Raises InputError when a block interpenetrates another body (overlap deeper than tol);
    overlapping supports are allowed (they never move). Returns a dict of arrays: ``a``,
    ``b`` (body positions, oriented by the conventions above), ``centre``, ``normal``,
    ``d``, sorted in contact-id order.
    """
    is_support = np.asarray(is_support, dtype=bool)
    n = len(polygons)
    ids = ids if ids is not None else [str(j) for j in range(n)]
    V, count = _padded(polygons)
    lo = np.array([p.min(axis=0) for p in polygons])
    hi = np.array([p.max(axis=0) for p in polygons])
    i, j = _candidate_pairs(lo, hi, tol)
    keep = ~(is_support[i] & is_support[j])
    i, j = i[keep], j[keep]
    # process pairs grouped by the vertex count they need, in chunks of bounded memory
    width = np.maximum(count[i], count[j])
    order = np.lexsort((j, i, width))
    i, j, width = i[order], j[order], width[order]
    found = np.zeros(i.size, dtype=bool)
    normal = np.zeros((i.size, 2))
    centre = np.zeros((i.size, 2))
    half = np.zeros(i.size)
    for K in np.unique(width):
        run = np.flatnonzero(width == K)
        step = max(1, 250_000 // (K * K))  # bounds the (pairs, K, K) temporaries to a few MB
        for s in range(0, run.size, step):
            r = run[s:s + step]
            VA, VB = V[i[r], :K], V[j[r], :K]
            depth = _penetration(VA, VB, tol)
            bad = np.flatnonzero(depth > tol)
            if bad.size:
                pairs = sorted(zip(i[r][bad], j[r][bad], depth[bad]))
                x, y, dep = pairs[0]
                kind = lambda z: "support" if is_support[z] else "block"  # noqa: E731
                raise InputError(f"{where}: {kind(x)} '{ids[x]}' and {kind(y)} '{ids[y]}' interpenetrate "
                                 f"(their polygons overlap by {dep:.3g}); expected bodies that touch only along "
                                 "their edges")
            found[r], normal[r], centre[r], half[r] = _facing_edges(VA, VB, tol)
    i, j, normal, centre, half = i[found], j[found], normal[found], centre[found], half[found]
    # orientation: the support is block a; between blocks, a is below (or left of) b
    upward = (normal[:, 1] > 1e-9) | ((np.abs(normal[:, 1]) <= 1e-9) & (normal[:, 0] > 0))
    a_is_i = np.where(is_support[i] | is_support[j], is_support[i], upward)
    a = np.where(a_is_i, i, j)
    b = np.where(a_is_i, j, i)
    normal = np.where(a_is_i[:, None], normal, -normal)
    order = np.lexsort((j, i))  # i < j: by first, then second position in the JSON list
    # "+ 0.0" turns the -0.0 of flipped axis-aligned normals into 0.0 (tidier output files)
    return {"a": a[order], "b": b[order], "centre": centre[order] + 0.0, "normal": normal[order] + 0.0,
            "d": half[order]}


# ==================================================================== writing JSON
def structure_to_json(source, path=None) -> dict:
    """The JSON spec of a generated geometry (a dict) or of a Structure; written to
    ``path`` if given (one body per line, so that files diff well). Returns the dict.

    A Structure is written with explicit ``dead`` and ``live`` loads per block; its
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
        Path(path).write_text("\n".join(lines) + "\n")
    return spec


def _spec_of_structure(s: Structure) -> dict:
    missing = [b for b in s.blocks + s.supports if b not in s.polygons]
    if missing:
        raise InputError(f"structure '{s.name}': block '{missing[0]}' has no polygon; expected polygons for every "
                         "body to write the geometry as JSON")
    spec = {"name": s.name}
    uniform = s.n_contacts and np.allclose(s.mu, s.mu[0], rtol=0, atol=1e-15)
    body_mu = {}
    if uniform:
        spec["mu"] = float(s.mu[0])
    else:
        for k in range(s.n_contacts):
            for x in (s.block_a[k], s.block_b[k]):
                body_mu[x] = max(body_mu.get(x, 0.0), float(s.mu[k]))
        for k in range(s.n_contacts):
            if min(body_mu[s.block_a[k]], body_mu[s.block_b[k]]) != s.mu[k]:
                raise InputError(f"structure '{s.name}': the friction of contact '{s.contacts[k]}' cannot be written "
                                 "as the smaller 'mu' of its two bodies; expected friction given per body")
    blocks = []
    for j, b in enumerate(s.blocks):
        body = {"id": b, "vertices": s.polygons[b].tolist(),
                "dead": s.dead[j].tolist(), "live": s.live[j].tolist()}
        if b in body_mu:
            body["mu"] = body_mu[b]
        blocks.append(body)
    for b in s.supports:
        body = {"id": b, "vertices": s.polygons[b].tolist(), "support": True}
        if b in body_mu:
            body["mu"] = body_mu[b]
        blocks.append(body)
    spec["blocks"] = blocks
    return spec


# ===================================================================== generators
def _rectangle(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


def _clean_number(x: float, scale: float) -> float:
    """Round-off below 1e-12 of the model's scale snapped to zero (tidier JSON files)."""
    x = float(x)
    return 0.0 if abs(x) < 1e-12 * scale else x


def _finish(name, description, mu, unit_weight, live_load, blocks):
    spec = {"name": name}
    if description:
        spec["description"] = description
    spec.update({"mu": mu, "unit_weight": unit_weight, "live_load": [float(v) for v in live_load], "blocks": blocks})
    return spec


def running_bond_wall(courses, full: float = 4.0, height=1.75, mu: float = 0.65,
                      unit_weight: float | None = None, live_load=(1.0, 0.0), name: str = "wall",
                      x0: float = 0.0, ground_margin: float | None = None,
                      ground_thickness: float | None = None, description: str | None = None) -> dict:
    """JSON spec of a dry-stone wall of rectangular blocks on a rigid ground.

    ``courses`` lists the rows, bottom row first; each row lists block lengths in units of
    the full block length ``full``, placed left to right from ``x0``; a negative entry is
    a gap (an opening) of that length. ``height`` is the course height (one number, or
    one per course). Blocks are named ``b1, b2, ...`` row by row, left to right; the
    support ``ground`` spans the whole wall plus ``ground_margin`` on each side.

    ``unit_weight`` defaults to ``1 / (full * height[0])``, so that a full block weighs
    1 (and, with the default ``live_load``, carries a unit horizontal live load, left to
    right), as in the seed's wall examples.
    """
    courses = [list(c) for c in courses]
    if not courses:
        raise InputError("running_bond_wall: no courses given; expected a list of rows of block lengths")
    heights = [float(height)] * len(courses) if np.isscalar(height) else [float(h) for h in height]
    if len(heights) != len(courses) or min(heights) <= 0:
        raise InputError(f"running_bond_wall: {len(heights)} course heights for {len(courses)} courses; "
                         "expected one positive height, or one per course")
    if unit_weight is None:
        unit_weight = 1.0 / (full * heights[0])
    blocks, y, xmin, xmax = [], 0.0, x0, x0
    for row, lengths in enumerate(courses):
        x = x0
        for length in lengths:
            if length == 0:
                raise InputError(f"running_bond_wall: course {row + 1} has a zero length; "
                                 "expected block lengths > 0 or gaps < 0")
            step = abs(length) * full
            if length > 0:
                blocks.append({"id": f"b{len(blocks) + 1}", "vertices": _rectangle(x, y, x + step, y + heights[row])})
            x += step
        xmax = max(xmax, x)
        y += heights[row]
    margin = full / 4 if ground_margin is None else ground_margin
    thick = full / 4 if ground_thickness is None else ground_thickness
    blocks.append({"id": "ground", "support": True,
                   "vertices": _rectangle(xmin - margin, -thick, xmax + margin, 0.0)})
    return _finish(name, description, mu, unit_weight, live_load, blocks)


def seed_wall(n_courses: int = 6, **kwargs) -> dict:
    """The seed's panels (Table 1): running bond of 4 x 1.75 full blocks, 5 blocks long.

    Courses alternate, from the bottom, [1/2, 1, 1, 1, 1, 1/2] and [1, 1, 1, 1, 1]; a full
    block weighs 1 and carries a unit horizontal live load (left to right); mu = 0.65.
    6 courses give the 33-block panel, 10 courses the 55-block one.
    """
    courses = [[0.5, 1, 1, 1, 1, 0.5] if r % 2 == 0 else [1, 1, 1, 1, 1] for r in range(n_courses)]
    n_blocks = sum(len(c) for c in courses)
    kwargs.setdefault("name", f"wall{n_blocks}")
    kwargs.setdefault("description",
                      f"Seed panel of {n_blocks} blocks in {n_courses} courses of running bond: full blocks "
                      "4 x 1.75 (weight 1, unit horizontal live load left to right), half blocks 2 x 1.75 "
                      "at the ends of the odd courses from the bottom; mu = 0.65; rigid ground.")
    return running_bond_wall(courses, **kwargs)


def _ring(n_voussoirs, inner_radius, thickness, angle, prefix="v"):
    """Voussoirs of a circular ring with radial joints, left to right.

    The ring subtends ``angle`` degrees (180: semicircular; less: segmental), symmetric
    about the vertical through the centre; the circle's centre is placed so that the
    intrados springing points lie on y = 0, at x = -/+ inner_radius * sin(angle / 2).
    Returns (blocks, (inner, outer) springing points of the left and right ends).
    """
    if n_voussoirs < 1 or inner_radius <= 0 or thickness <= 0 or not 0 < angle <= 180:
        raise InputError(f"arch: n_voussoirs={n_voussoirs}, inner_radius={inner_radius}, thickness={thickness}, "
                         f"angle={angle}; expected n >= 1, positive radius and thickness, 0 < angle <= 180 degrees")
    half = math.radians(angle) / 2
    r_in, r_out = inner_radius, inner_radius + thickness
    yc = -r_in * math.cos(half)
    phi = np.pi / 2 + half - np.arange(n_voussoirs + 1) * (2 * half / n_voussoirs)
    scale = r_out

    def point(r, p):
        return [_clean_number(r * math.cos(p), scale), _clean_number(yc + r * math.sin(p), scale)]

    blocks = []
    for k in range(n_voussoirs):
        blocks.append({"id": f"{prefix}{k + 1}",
                       "vertices": [point(r_in, phi[k]), point(r_in, phi[k + 1]),
                                    point(r_out, phi[k + 1]), point(r_out, phi[k])]})
    left = (point(r_in, phi[0]), point(r_out, phi[0]))
    right = (point(r_in, phi[-1]), point(r_out, phi[-1]))
    return blocks, left, right


def _skewback(inner, outer, width, y_base):
    """Convex block under a springing joint ``inner -> outer`` (inner point on y = 0).

    Vertical inner face under the inner point, vertical outer face ``width`` further out,
    flat base at ``y_base``; its top is the springing joint (cut by the outer face if the
    block is narrower than the joint) followed by a flat shoulder if it is wider.
    """
    (xi, yi), (xo, yo) = inner, outer
    side = -1.0 if xo < xi else 1.0  # -1: left springing, outer point further left
    x_out = xi + side * width
    top = [[xi, yi]]
    if side * (x_out - xo) >= 0:   # wider than the joint: whole joint, then a shoulder
        top.append([xo, yo])
        if abs(x_out - xo) > 1e-12 * max(1.0, abs(xo)):
            top.append([x_out, yo])
    else:                          # narrower: the joint is cut by the outer face
        top.append([x_out, yi + (yo - yi) * (x_out - xi) / (xo - xi)])
    verts = [[xi, y_base]] + top + [[x_out, y_base]]
    return verts if side < 0 else verts[::-1]


def arch(n_voussoirs: int = 13, inner_radius: float = 5.0, thickness: float = 1.5, angle: float = 180.0,
         impost_height: float = 2.0, impost_width: float | None = 2.5, mu: float = 0.5,
         unit_weight: float = 1.0, live_load=(-1.0, 0.0), name: str = "arch",
         description: str | None = None, ground_margin: float | None = None) -> dict:
    """JSON spec of a circular arch of ``n_voussoirs`` with radial joints.

    ``angle`` is the angle the ring subtends (180: semicircular; less: segmental, with
    inclined springing joints). With ``impost_height > 0`` the ring springs from two
    impost blocks (``impost_left``, ``impost_right``) of that height below the intrados
    springing point and ``impost_width`` wide (default: the horizontal extent of the
    springing joint), standing on a rigid ``ground``; with ``impost_height == 0`` it
    springs directly from two fixed skewbacks ``support_left`` and ``support_right``.
    Voussoirs are ``v1 ... vn`` from left to right.

    The default live load is horizontal, pointing left, and proportional to the weight:
    the seed's eq. (6), ``fbar = (-W, 0)``.
    """
    blocks, left, right = _ring(n_voussoirs, inner_radius, thickness, angle)
    r_out = inner_radius + thickness
    joint = abs(left[1][0] - left[0][0])
    width = joint if impost_width is None else float(impost_width)
    if width <= 0:
        raise InputError(f"arch: impost_width={width}; expected a positive width")
    if impost_height > 0:
        y_base = -float(impost_height)
        blocks.append({"id": "impost_left", "vertices": _skewback(*left, width, y_base)})
        blocks.append({"id": "impost_right", "vertices": _skewback(*right, width, y_base)})
        margin = r_out / 4 if ground_margin is None else ground_margin
        x_ext = abs(left[0][0]) + width
        blocks.append({"id": "ground", "support": True,
                       "vertices": _rectangle(-x_ext - margin, y_base - thickness, x_ext + margin, y_base)})
    else:
        blocks.append({"id": "support_left", "support": True, "vertices": _skewback(*left, width, -thickness)})
        blocks.append({"id": "support_right", "support": True, "vertices": _skewback(*right, width, -thickness)})
    return _finish(name, description, mu, unit_weight, live_load, blocks)


def portal(n_voussoirs: int = 11, inner_radius: float = 3.0, thickness: float = 1.5, angle: float = 180.0,
           pier_height: float = 3.0, pier_blocks: int = 2, pier_width: float | None = None,
           mu: float = 0.5, unit_weight: float = 1.0, live_load=(-1.0, 0.0), name: str = "portal",
           description: str | None = None, ground_margin: float | None = None) -> dict:
    """JSON spec of a portal: a circular arch (see :func:`arch`) on two piers.

    Each pier is a column of ``pier_blocks`` equal stacked blocks (1: a single block),
    ``pier_height`` tall in all and ``pier_width`` wide (default: the arch thickness),
    its inner face flush with the intrados springing point; the top block carries the
    springing joint (with a skewback top for a segmental ring). Piers are ``pl1 ...``
    (left) and ``pr1 ...`` (right), numbered from the bottom; they stand on ``ground``.
    """
    if pier_blocks < 1 or pier_height <= 0:
        raise InputError(f"portal: pier_blocks={pier_blocks}, pier_height={pier_height}; "
                         "expected at least one block and a positive height")
    blocks, left, right = _ring(n_voussoirs, inner_radius, thickness, angle)
    width = thickness if pier_width is None else float(pier_width)
    if width <= 0:
        raise InputError(f"portal: pier_width={width}; expected a positive width")
    h = pier_height / pier_blocks
    for prefix, (inner, outer) in (("pl", left), ("pr", right)):
        xi = inner[0]
        x_out = xi - width if prefix == "pl" else xi + width
        x0, x1 = min(xi, x_out), max(xi, x_out)
        for k in range(pier_blocks - 1):
            y0 = -pier_height + k * h
            blocks.append({"id": f"{prefix}{k + 1}", "vertices": _rectangle(x0, y0, x1, y0 + h)})
        blocks.append({"id": f"{prefix}{pier_blocks}", "vertices": _skewback(inner, outer, width, -h)})
    margin = (inner_radius + thickness) / 4 if ground_margin is None else ground_margin
    x_ext = abs(left[0][0]) + width
    blocks.append({"id": "ground", "support": True,
                   "vertices": _rectangle(-x_ext - margin, -pier_height - thickness, x_ext + margin, -pier_height)})
    return _finish(name, description, mu, unit_weight, live_load, blocks)


_SEED_LOADS = ("Live load horizontal, pointing left and equal to the weight (seed eq. 6: fbar = (-W, 0), "
               "f0 = (0, -W)); unit weight 1, mu = 0.5, unit width. Dimensions chosen for this project "
               "(the seed's figure gives none): ")


def seed_instances() -> dict:
    """JSON specs of the seed's examples, by name: the panels of Table 1 (exact) and
    drafts of the arch and portals of Figs 2-4 (the text gives loads and friction but no
    dimensions; these were chosen so that the collapse mechanisms have the character the
    seed describes). ``instances/<name>.json`` are these specs, written by
    :func:`structure_to_json`.
    """
    return {
        "wall33": seed_wall(6),
        "wall55": seed_wall(10),
        "arch": arch(13, 5.0, 1.5, impost_height=2.0, impost_width=2.5, name="arch", description=(
            _SEED_LOADS + "semicircular ring of 13 voussoirs with radial joints, intrados radius 5, thickness 1.5 "
            "(centre at (0, 0)); it springs from two impost blocks 2.5 wide and 2 high (inner faces flush with "
            "the intrados) standing on a rigid ground. Note: with every block loaded and flat frictional bases, "
            "alpha <= mu = 0.5 for any such model, so the seed's 0.63425 cannot be reproduced without its figure.")),
        "portal": portal(11, 3.0, 1.5, pier_height=3.0, pier_blocks=2, name="portal", description=(
            _SEED_LOADS + "portal of constant thickness 1.5: semicircular ring of 11 voussoirs, intrados radius 3, "
            "on two piers each made of 2 stacked 1.5 x 1.5 blocks (pier height 3, inner faces flush with the "
            "intrados), on a rigid ground.")),
        "portal_columns": portal(11, 3.0, 1.5, pier_height=4.5, pier_blocks=1, pier_width=2.25,
                                 name="portal_columns", description=(
            _SEED_LOADS + "semicircular ring of 11 voussoirs, intrados radius 3, thickness 1.5, on two columns "
            "each a single block 2.25 wide and 4.5 high (inner faces flush with the intrados), on a rigid ground.")),
    }
