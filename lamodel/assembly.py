"""What a planar and a spatial block assembly share as data: the base of
:class:`lamodel.structure.Structure` and :class:`lamodel.structure3d.Structure3D`.

Ids are text, numbers are float arrays of fixed shapes, units are text; blocks are looked up
by id, and the two bodies a contact (2D) or an interface (3D) joins by their block index
(-1 for a support). Their checks are :mod:`lamodel.validation`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class Assembly:
    """The fields every assembly starts with, and lookups and conversions on them
    (``d`` is 2 in the plane, 3 in space)."""

    name: str
    blocks: list            # ids of the movable blocks
    centroid: np.ndarray    # (nb, d)
    dead: np.ndarray        # (nb, d) constant force f0 at the centroid
    live: np.ndarray        # (nb, d) base live force fbar at the centroid (times alpha)
    supports: list          # ids of the fixed bodies

    def _as_text(self, *names):
        """The id lists ``names`` as lists of str; ``units`` as {str: str} without empty values."""
        for name in names:
            setattr(self, name, [str(x) for x in getattr(self, name)])
        self.units = {str(k): str(v) for k, v in (self.units or {}).items() if v}

    @staticmethod
    def _floats(x, shape) -> np.ndarray:
        return np.asarray(x, dtype=float).reshape(shape)

    @property
    def n_blocks(self) -> int:
        """The number of movable blocks."""
        return len(self.blocks)

    def block_index(self) -> dict:
        """Block id -> its row in the per-block arrays."""
        return {b: j for j, b in enumerate(self.blocks)}

    def _ends(self, a: list, b: list):
        """Indices of the bodies ``a`` and ``b`` (ids), -1 for a support."""
        idx = self.block_index()
        return (np.array([idx.get(x, -1) for x in a], dtype=int), np.array([idx.get(x, -1) for x in b], dtype=int))
