"""The non-dimensional problem: forces by the mean dead load of a block, lengths by the
size of the structure.

Block loads stay O(1) at every size, so that HiGHS's absolute tolerances mean the same on
30 and 3000 blocks. The search solves the scaled structure; its states go back to the
user's units (:meth:`lamodel.search.gap.problem.ScaledProblem.to_user`).
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


def scaled(structure: Structure, F: float, L: float) -> Structure:
    """The structure in the units (F, L) of :func:`scales`: forces / F, lengths / L,
    moments / (F L); friction and topology unchanged."""
    return Structure(name=structure.name, blocks=structure.blocks, centroid=structure.centroid / L,
                     dead=structure.dead / F, live=structure.live / F, supports=structure.supports,
                     contacts=structure.contacts, block_a=structure.block_a, block_b=structure.block_b,
                     centre=structure.centre / L, normal=structure.normal, d=structure.d / L, mu=structure.mu,
                     dead_m=structure.dead_m / (F * L), live_m=structure.live_m / (F * L),
                     polygons={k: v / L for k, v in structure.polygons.items()})  # size() 1, as L
