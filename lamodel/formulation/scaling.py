"""The non-dimensional problem: forces by the mean dead load of a block, lengths by the
size of the structure.

Block loads stay O(1) at every size, so that HiGHS's absolute tolerances mean the same on
30 and 3000 blocks. The search solves the scaled structure; its states go back to the
user's units (:meth:`lamodel.search.gap.problem.ScaledProblem.to_user`).

A block far lighter than the mean (a 1e-3 m block on a 1e3 m one: loads 1e-12 of the
mean) would still be below those tolerances: :func:`light_scales` gives such a block's
equilibrium rows, and the forces of its contacts, scales of their own
(:class:`lamodel.search.gap.problem.ScaledProblem` solves the LPs in them).
"""
from __future__ import annotations

import numpy as np

from ..structure import Structure


def scales(structure: Structure):
    """(force, length) units of the non-dimensional problem.

    Forces by the mean dead load of a block (the total dead load over the number of
    blocks; the largest live load if there is no dead load): block loads stay O(1) at
    every size, so HiGHS's absolute tolerances mean the same thing on 30 and 3000 blocks.
    Lengths by the size of the structure (diagonal of its bounding box).
    """
    dead = np.hypot(structure.dead[:, 0], structure.dead[:, 1])
    F = dead.sum() / structure.n_blocks
    if not F > 0:
        F = float(np.hypot(structure.live[:, 0], structure.live[:, 1]).max())
    return float(F), float(structure.size())


def block_sizes(structure: Structure) -> np.ndarray:
    """A length per block: the farthest reach of its contacts from its centroid (centre
    distance plus half-length), so that a moment on the block becomes a force there."""
    ia, ib = structure.contact_blocks()
    size = np.zeros(structure.n_blocks)
    for idx in (ia, ib):
        on = idx >= 0
        reach = np.hypot(*(structure.centre[on] - structure.centroid[idx[on]]).T) + structure.d[on]
        np.maximum.at(size, idx[on], reach)
    return np.where(size > 0, size, structure.size())


def block_loads(structure: Structure) -> np.ndarray:
    """Each block's own load: the largest of its dead and live forces and moments, moments
    made forces by the block's size (:func:`block_sizes`)."""
    L = block_sizes(structure)
    return np.maximum.reduce([np.abs(structure.dead).max(axis=1), np.abs(structure.live).max(axis=1),
                              np.abs(structure.dead_m) / L, np.abs(structure.live_m) / L])


def light_scales(structure: Structure, light: float):
    """Scales of a scaled structure's light blocks: (rows, contacts).

    A block whose own load (:func:`block_loads`) w is positive and below ``light`` (the
    structure in the units of :func:`scales`: the mean block load is 1) is *light*: its
    force rows are divided by w and its moment row by w times its size, and the forces of
    every contact it touches are measured in w (the lightest such block's), so that its
    equilibrium, its contacts' yield rows and their mechanism flows are O(1) numbers in the
    LPs, as every other block's are. Every other row and contact has scale 1: a structure
    without light blocks is solved exactly as without this. Returns ``rows`` (3 nb: the
    equilibrium rows are multiplied by it) and ``contacts`` (nc: a contact's forces are
    ``contacts`` times the LP's columns).
    """
    w = block_loads(structure)
    lit = (w > 0) & (w < light)
    rows = np.ones(3 * structure.n_blocks)
    contacts = np.ones(structure.n_contacts)
    if not lit.any():
        return rows, contacts
    size = block_sizes(structure)
    b = np.flatnonzero(lit)
    rows[3 * b] = rows[3 * b + 1] = 1.0 / w[b]
    rows[3 * b + 2] = 1.0 / (w[b] * size[b])
    for idx in structure.contact_blocks():
        on = idx >= 0
        on[on] = lit[idx[on]]
        contacts[on] = np.minimum(contacts[on], w[idx[on]])
    return rows, contacts


def scaled(structure: Structure, F: float, L: float) -> Structure:
    """The structure in the units (F, L) of :func:`scales`: forces / F, lengths / L,
    moments / (F L), stresses / (F / L^2); friction and topology unchanged."""
    return Structure(name=structure.name, blocks=structure.blocks, centroid=structure.centroid / L,
                     dead=structure.dead / F, live=structure.live / F, supports=structure.supports,
                     contacts=structure.contacts, block_a=structure.block_a, block_b=structure.block_b,
                     centre=structure.centre / L, normal=structure.normal, d=structure.d / L, mu=structure.mu,
                     dead_m=structure.dead_m / (F * L), live_m=structure.live_m / (F * L),
                     polygons={k: v / L for k, v in structure.polygons.items()},  # size() 1, as L
                     fc=structure.fc * (L * L / F), ft=structure.ft * (L * L / F),
                     cohesion=structure.cohesion * (L * L / F), thickness=structure.thickness / L)
