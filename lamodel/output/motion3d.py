"""Rigid block motions in space for pictures: displaced polyhedra, macro-blocks, amplification.

A motion ``u = (ux, uy, uz, rx, ry, rz)`` at the centroid c moves a point x by
``(ux, uy, uz) + r x (x - c)`` (small displacements; drawn amplified).
"""
from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..structure3d import Structure3D

#: Motions smaller than this fraction of the largest one are rest (pictures only).
REST = 1e-6


def check_motions(s: Structure3D, motions):
    """Motions as an (nb, 6) array, or None; InputError on a wrong shape."""
    if motions is None:
        return None
    u = np.asarray(motions, dtype=float)
    if u.shape != (s.n_blocks, 6) or not np.isfinite(u).all():
        raise InputError(f"structure '{s.name}': motions have shape {u.shape}; expected ({s.n_blocks}, 6) finite "
                         "numbers (ux, uy, uz, rx, ry, rz per block)")
    return u


def displaced(vertices, centroid, u, amplification: float) -> np.ndarray:
    """Vertices (k, 3) of a block moved rigidly by ``amplification * u``."""
    v = np.asarray(vertices, dtype=float)
    return v + amplification * (u[:3] + np.cross(u[3:], v - centroid))


def default_amplification(s: Structure3D, u) -> float:
    """Amplification drawing the largest vertex displacement as 10 % of the structure's size."""
    if u is None:
        return 0.0
    idx = s.block_index()
    big = 0.0
    for b, (v, _) in s.polyhedra.items():
        if b in idx:
            j = idx[b]
            d = u[j, :3] + np.cross(u[j, 3:], np.asarray(v) - s.centroid[j])
            big = max(big, float(np.linalg.norm(d, axis=1).max()))
    return 0.1 * s.size() / big if big > 0 else 0.0


def macro_blocks(s: Structure3D, u) -> np.ndarray:
    """Label per block: blocks moving together (one rigid motion) share a label; -1 at rest."""
    if u is None:
        return -np.ones(s.n_blocks, dtype=int)
    # the motion of each block carried to the origin: equal for blocks moving as one body
    g = np.c_[u[:, :3] - np.cross(u[:, 3:], s.centroid), u[:, 3:] * s.size()]
    scale = float(np.abs(g).max()) or 1.0
    label = -np.ones(s.n_blocks, dtype=int)
    moving = np.flatnonzero(np.abs(g).max(axis=1) > REST * scale)
    reps = []
    for j in moving:
        for k, r in enumerate(reps):
            if np.abs(g[j] - g[r]).max() <= 1e-6 * scale:
                label[j] = k
                break
        else:
            label[j] = len(reps)
            reps.append(j)
    return label
