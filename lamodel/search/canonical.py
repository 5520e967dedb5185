"""The canonical order of a planar assembly's blocks and contacts: the search works on it,
and its answers are told back in the user's order.

The LPs of the search are degenerate: the vertex a solve returns depends on the order of
its rows and columns, so the collapse state the search reaches would otherwise depend on
how the file was written (blocks shuffled, the ground first or last, other ids). The
canonical order depends only on the geometry and the loads:

* blocks by their centroid (y, then x: course after course, left to right), rounded to
  CANONICAL_TOLERANCE times the structure's size; ties by area, then by vertices, then by
  loads;
* contacts by the canonical ranks of their two bodies (the lower first; the supports after
  every block, among themselves by their own centroid), then by their centre along the
  joint; the restraints a file gave stay last, as the formulation expects.

Ids are kept, so every output names the user's blocks and contacts; :func:`to_user` puts
the arrays of a collapse state back in the user's order. In space (:class:`Structure3D`)
the order is the user's (not canonicalised).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..structure import Structure
from .state import CollapseState
from .tuning import CANONICAL_TOLERANCE


@dataclass(frozen=True)
class Order:
    """Canonical position -> the user's index: ``blocks[j]`` is the user's block at
    canonical row j, ``contacts[k]`` the user's contact at canonical row k."""

    blocks: np.ndarray
    contacts: np.ndarray


def canonical(structure):
    """The structure in its canonical order and the :class:`Order` that maps it back (None
    where the order is kept: in space, or already canonical)."""
    if not isinstance(structure, Structure):
        return structure, None
    order = canonical_order(structure)
    if (np.array_equal(order.blocks, np.arange(structure.n_blocks))
            and np.array_equal(order.contacts, np.arange(structure.n_contacts))):
        return structure, None
    bo, co = order.blocks, order.contacts
    per_block = {k: getattr(structure, k)[bo] for k in ("centroid", "dead", "live", "dead_m", "live_m")}
    per_contact = {k: getattr(structure, k)[co] for k in ("centre", "normal", "d", "mu", "fc", "ft", "cohesion",
                                                          "thickness")}
    ids = {k: [getattr(structure, k)[i] for i in idx]
           for k, idx in (("blocks", bo), ("contacts", co), ("block_a", co), ("block_b", co))}
    return dataclasses.replace(structure, **per_block, **per_contact, **ids), order


def canonical_order(s: Structure) -> Order:
    """The canonical order of the blocks and contacts of ``s`` (see the module doc)."""
    size = s.size()
    tol = CANONICAL_TOLERANCE * size

    def grid(x, unit):  # coordinates equal within the tolerance compare equal
        return tuple(int(v) for v in np.round(np.ravel(x) / unit))

    polygon = {k: np.asarray(v, dtype=float).reshape(-1, 2) for k, v in s.polygons.items()}
    loads = np.column_stack([s.dead, s.live, s.dead_m, s.live_m])
    load_unit = CANONICAL_TOLERANCE * max(float(np.abs(loads).max(initial=0.0)), 1e-300)

    def shape(body):  # area, then the vertices as a set (where the file gave the polygon)
        v = polygon.get(body)
        if v is None or len(v) < 3:
            return (0,), ()
        area = 0.5 * abs(float(np.dot(v[:, 0], np.roll(v[:, 1], -1)) - np.dot(v[:, 1], np.roll(v[:, 0], -1))))
        return grid(area, tol * size), tuple(sorted(grid(p, tol) for p in v))

    block_keys = [(grid(c[::-1], tol), *shape(b), grid(f, load_unit))
                  for b, c, f in zip(s.blocks, s.centroid, loads)]
    blocks = np.array(sorted(range(s.n_blocks), key=lambda j: (block_keys[j], j)), dtype=int)
    rank = {s.blocks[j]: r for r, j in enumerate(blocks)}

    def support_key(body):  # supports by their polygon's mean vertex (else by id: no geometry)
        v = polygon.get(body)
        return (0, grid(v.mean(axis=0)[::-1], tol), shape(body)[1]) if v is not None and len(v) else (1, body)

    for r, body in enumerate(sorted(s.supports, key=support_key)):
        rank[body] = s.n_blocks + r
    along = np.einsum("ij,ij->i", s.centre, s.tangent)
    first_restraint = s.n_contacts - s.restraints

    def contact_key(k):
        ends = sorted((rank[s.block_a[k]], rank[s.block_b[k]]))
        return (k >= first_restraint, ends, grid(along[k], tol), grid(s.centre[k][::-1], tol),
                grid(s.normal[k], CANONICAL_TOLERANCE), k)

    contacts = np.array(sorted(range(s.n_contacts), key=contact_key), dtype=int)
    return Order(blocks, contacts)


def to_user(state: CollapseState | None, order: Order | None) -> CollapseState | None:
    """A collapse state of the canonical structure, in the user's order of blocks and contacts."""
    if state is None or order is None:
        return state
    bo, co = order.blocks, order.contacts

    def per_contact(x, width=1):  # stacked by kind (N; or the 4 yield rows), contact after contact
        x = np.asarray(x).reshape(width, -1)
        out = np.empty_like(x)
        out[:, co] = x
        return out.reshape(-1) if width > 1 else out[0]

    u = np.asarray(state.u).reshape(len(bo), -1)
    u_user = np.empty_like(u)
    u_user[bo] = u
    return dataclasses.replace(state, N=per_contact(state.N), V=per_contact(state.V), M=per_contact(state.M),
                               u=u_user.reshape(-1), xi=per_contact(state.xi, 4), flow=per_contact(state.flow, 4))


def rows_to_user(rows, order: Order | None):
    """Indices of yield rows (4 nc, stacked by row kind) of the canonical structure, in the
    user's numbering (sorted)."""
    if rows is None or order is None:
        return rows
    rows = np.asarray(rows, dtype=int)
    nc = len(order.contacts)
    return np.sort(rows // nc * nc + order.contacts[rows % nc])
