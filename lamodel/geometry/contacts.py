"""Contacts of an assembly of convex polygons: cleaning, areas and centroids, contact search.

Two bodies are in contact where an edge of one and an edge of the other lie on one line
(within the tolerance), face each other (opposite outward normals) and overlap over a
positive length; the contact's centre is the midpoint of the overlap and ``d`` its
half-length (the largest eccentricity of N). Orientation conventions (the ``a -> b`` normal
of :mod:`lamodel.structure`): a contact with a support has the support as block a; between
blocks, a is below b (or left of b, for a vertical joint).

Contact detection is linear-logarithmic in the number of bodies: a sweep over bounding
boxes sorted along one axis proposes pairs of bodies, and the exact tests (separating axes
for interpenetration, collinear facing edges for contacts) run vectorised over all pairs.
"""
from __future__ import annotations

import numpy as np

from ..errors import InputError

# ====================================================================== polygons
def _clean_polygon(v: np.ndarray, tol: float, at: str, tol_text: str = "") -> np.ndarray:
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
        raise InputError(f"{at} has zero area within the geometric tolerance {tol_text or f'{tol:.3g}'} (its vertices "
                         "are collinear to that accuracy); expected a polygon with a positive area, wider "
                         "than the tolerance (or a smaller 'tolerance')")
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


def clean_polygons(raw, tol, ids, where, tol_text: str = ""):
    """Counter-clockwise convex polygons without repeated or collinear vertices, for all
    bodies, vectorised over polygons of equal vertex count; ``tol`` is absolute, and
    ``tol_text`` says in errors where it comes from (e.g. a tolerance relative to the
    model's size).

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
        out[j] = _clean_polygon(raw[j], tol, f"{where}: block '{ids[j]}'", tol_text)
    return out


def area_centroid(polygons):
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
