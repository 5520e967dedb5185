"""The canonical order of an assembly's blocks and contacts: the search works on it, and
its answers are told back in the user's order.

The LPs and cone programs of the search are degenerate: the vertex a solve returns
depends on the order of its rows and columns, so the collapse state the search reaches
would otherwise depend on how the file was written (blocks shuffled, the ground first or
last, other ids). The canonical order depends only on the geometry and the loads;
coordinates are compared on a grid of CANONICAL_TOLERANCE times the structure's size:

* blocks by their centroid (the vertical coordinate first: course after course, then
  along it), ties by their vertices, then by their loads;
* the supports after every block, among themselves by their mean vertex (or, where the
  file gave no geometry, their contacts' mean centre);
* planar contacts by the canonical ranks of their two bodies (the lower first), then by
  their centre along the joint; the restraints a file gave stay last, as the formulation
  expects. In space the interfaces likewise (by their polygon's mean vertex), and the
  contact points by their interface's rank, then their position.

Joints with strengths (fc, ft, cohesion) are solved in the file's order (see
:func:`canonical`). Ids are kept, so every output names the user's blocks and contacts; :func:`to_user` puts
a collapse state's arrays back in the user's order.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..structure3d import Structure3D
from .tuning import CANONICAL_TOLERANCE

#: per-contact arrays of a collapse state (planar; in space per contact point), stacked by
#: kind where a contact has several rows (the yield rows of eq. 4; openings and slips)
STATE_PER_CONTACT = ("N", "V", "M", "xi", "flow", "T1", "T2", "q", "crushable")


@dataclass(frozen=True)
class Order:
    """Canonical position -> the user's index: ``blocks[j]`` is the user's block at
    canonical row j, ``contacts[k]`` the user's contact (in space: contact point) at
    canonical row k; ``interfaces`` likewise in space (None in the plane)."""

    blocks: np.ndarray
    contacts: np.ndarray
    interfaces: np.ndarray | None = None

    def kept(self) -> bool:
        return all(x is None or np.array_equal(x, np.arange(len(x))) for x in (self.blocks, self.contacts,
                                                                                self.interfaces))


def canonical(structure):
    """The structure in its canonical order and the :class:`Order` that maps it back (None
    where the file's order is already canonical)."""
    if structure.has_materials:
        # joints with strengths stay in the file's order: on a bridge ring with fc = 1e6 the
        # canonical order leaves HiGHS with no status on the associative LP (its facets
        # span 2e-4 to 6e2), where the file's order solves
        return structure, None
    order = canonical_order(structure)
    if order.kept():
        return structure, None
    bo, co = order.blocks, order.contacts
    names = ("centroid", "dead", "live", "dead_m", "live_m") + (("volume",) if _in_space(structure) else ())
    new = {k: getattr(structure, k)[bo] for k in names}
    new["blocks"] = [structure.blocks[j] for j in bo]
    if _in_space(structure):
        io = order.interfaces
        rank = np.empty_like(io)
        rank[io] = np.arange(len(io))
        for k in ("interfaces", "iface_a", "iface_b", "iface_polygon"):
            new[k] = [getattr(structure, k)[i] for i in io]
        if len(structure.iface_holes) == len(io):
            new["iface_holes"] = [structure.iface_holes[i] for i in io]
        new["point_interface"] = rank[structure.point_interface[co]]
        points = ("point", "normal", "tangent1", "tangent2", "mu", "fc", "ft", "cohesion")
        new.update({k: getattr(structure, k)[co] for k in points})
        new["area"] = structure.area[co] if structure.area is not None else None
    else:
        contacts = ("centre", "normal", "d", "mu", "fc", "ft", "cohesion", "thickness")
        new.update({k: getattr(structure, k)[co] for k in contacts})
        for k in ("contacts", "block_a", "block_b"):
            new[k] = [getattr(structure, k)[i] for i in co]
    return dataclasses.replace(structure, **new), order


def canonical_order(s) -> Order:
    """The canonical order of the blocks and contacts of ``s`` (see the module doc)."""
    tol = CANONICAL_TOLERANCE * s.size()

    def grid(x, unit=tol):  # coordinates equal within the tolerance compare equal
        return tuple(int(v) for v in np.round(np.ravel(x) / unit))

    def up_first(p):  # the vertical coordinate first: (y, x) in the plane, (z, y, x) in space
        return grid(np.asarray(p)[::-1])

    vertices = _vertices(s)
    shape = {k: tuple(sorted(grid(p) for p in v)) for k, v in vertices.items()}
    loads = np.column_stack([s.dead, s.live, s.dead_m, s.live_m])
    load_unit = CANONICAL_TOLERANCE * max(float(np.abs(loads).max(initial=0.0)), 1e-300)
    keys = [(up_first(c), shape.get(b, ()), grid(f, load_unit)) for b, c, f in zip(s.blocks, s.centroid, loads)]
    blocks = np.array(sorted(range(s.n_blocks), key=lambda j: (keys[j], j)), dtype=int)
    rank = {s.blocks[j]: r for r, j in enumerate(blocks)}
    where = _support_places(s, vertices)
    placed = sorted(s.supports, key=lambda b: (up_first(where[b]), shape.get(b, ()), b) if b in where else ((), (), b))
    rank.update({b: s.n_blocks + r for r, b in enumerate(placed)})

    def ends(a, b):
        return sorted((rank[a], rank[b]))

    if not _in_space(s):
        along = np.einsum("ij,ij->i", s.centre, s.tangent)
        first_restraint = s.n_contacts - s.restraints
        contacts = sorted(range(s.n_contacts), key=lambda k: (
            k >= first_restraint, ends(s.block_a[k], s.block_b[k]), grid(along[k]), up_first(s.centre[k]),
            grid(s.normal[k], CANONICAL_TOLERANCE), k))
        return Order(blocks, np.array(contacts, dtype=int))
    faces = sorted(range(s.n_interfaces), key=lambda i: (
        ends(s.iface_a[i], s.iface_b[i]), up_first(np.asarray(s.iface_polygon[i]).mean(axis=0)), i))
    face_rank = np.empty(len(faces), dtype=int)
    face_rank[faces] = np.arange(len(faces))
    points = sorted(range(s.n_points), key=lambda k: (
        face_rank[s.point_interface[k]], up_first(s.point[k]), grid(s.normal[k], CANONICAL_TOLERANCE), k))
    return Order(blocks, np.array(points, dtype=int), np.array(faces, dtype=int))


def to_user(state, order: Order | None):
    """A collapse state of the canonical structure (planar or in space), in the user's order
    of blocks and contacts."""
    if state is None or order is None:
        return state
    bo, co = order.blocks, order.contacts
    back = {}
    for name in STATE_PER_CONTACT:
        x = getattr(state, name, None)
        if x is not None:
            kinds = np.size(x) // len(co)
            x = np.asarray(x).reshape(kinds, len(co))
            out = np.empty_like(x)
            out[:, co] = x
            back[name] = out.reshape(-1) if kinds > 1 else out[0]
    u = np.asarray(state.u).reshape(len(bo), -1)
    back["u"] = np.empty_like(u)
    back["u"][bo] = u
    back["u"] = back["u"].reshape(-1)
    fields = {f.name for f in dataclasses.fields(state)}
    out = dataclasses.replace(state, **{k: v for k, v in back.items() if k in fields})
    for k, v in back.items():  # the mechanism's flows set on a state in space after it was made
        if k not in fields:
            setattr(out, k, v)
    return out


def mechanism_from_user(u, xi, order: Order | None):
    """A mechanism (u per block, xi per yield row, rows stacked by kind) in the user's order
    of blocks and contacts, in the canonical order (the inverse of :func:`to_user`)."""
    u, xi = np.asarray(u, float), np.asarray(xi, float)
    if order is None:
        return u.copy(), xi.copy()
    bo, co = order.blocks, order.contacts
    u_c = u.reshape(len(bo), -1)[bo].reshape(-1)
    xi_c = xi.reshape(-1, len(co))[:, co].reshape(-1)
    return u_c, xi_c


def rows_to_user(rows, order: Order | None):
    """Indices of the search's rows (stacked by kind, contact after contact within each:
    4 a contact in the plane, 2 a contact point in space) of the canonical structure, in
    the user's numbering (sorted)."""
    if rows is None or order is None:
        return rows
    rows = np.asarray(rows, dtype=int)
    nc = len(order.contacts)
    return np.sort(rows // nc * nc + order.contacts[rows % nc])


def _in_space(s) -> bool:
    return isinstance(s, Structure3D)


def _support_places(s, vertices) -> dict:
    """Support id -> a point that places it: its mean vertex, or (a file without its
    geometry) the mean of its contacts' centres (in space: of its interfaces' polygons)."""
    if _in_space(s):
        ends, centres = (s.iface_a, s.iface_b), [np.asarray(p).mean(axis=0) for p in s.iface_polygon]
    else:
        ends, centres = (s.block_a, s.block_b), s.centre
    touching = {}
    for side in ends:
        for body, c in zip(side, centres):
            touching.setdefault(body, []).append(c)
    return {b: vertices[b].mean(axis=0) if b in vertices else np.mean(touching[b], axis=0)
            for b in s.supports if b in vertices or b in touching}


def _vertices(s) -> dict:
    """Body id -> its vertices (k, d), where the file gave the polygon or polyhedron."""
    if _in_space(s):
        return {k: np.asarray(v[0], dtype=float).reshape(-1, 3) for k, v in s.polyhedra.items() if len(v[0])}
    return {k: np.asarray(v, dtype=float).reshape(-1, 2) for k, v in s.polygons.items() if len(v)}
