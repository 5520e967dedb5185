"""Rigid-block kinematics of a mechanism: point motions, the relative motion at each
contact, its mode and its pivot. No plotting here: the words and the tables use them
without loading matplotlib."""
from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..structure import Structure
from .modes import RTOL, modes_from_mechanism


def _block_motion(structure: Structure, u) -> np.ndarray:
    u = np.asarray(u, dtype=float)
    if u.shape != (structure.n_blocks, 3) or not np.isfinite(u).all():
        raise InputError(f"structure '{structure.name}': mechanism u has shape {u.shape}"
                         f"{'' if np.isfinite(u).all() else ' with non-finite values'}; "
                         f"expected finite (n_blocks, 3) = ({structure.n_blocks}, 3) rows (u_x, u_y, theta)")
    return u


def displace(points, centroid, u_block) -> np.ndarray:
    """Small-displacement rigid motion of points: ``(u_x - theta (y - y_G), u_y + theta (x - x_G))``."""
    p = np.asarray(points, dtype=float)
    ux, uy, th = u_block
    return np.column_stack([ux - th * (p[:, 1] - centroid[1]), uy + th * (p[:, 0] - centroid[0])])


def _point_motion(structure, u, owner, points):
    """Displacement of material points of bodies ``owner`` (block index, -1 = support)."""
    out = np.zeros_like(points)
    on = owner >= 0
    j = owner[on]
    g = structure.centroid[j]
    r = points[on] - g
    out[on, 0] = u[j, 0] - u[j, 2] * r[:, 1]
    out[on, 1] = u[j, 1] + u[j, 2] * r[:, 0]
    return out


def contact_kinematics(structure: Structure, u):
    """Relative motion of b with respect to a at each contact.

    Returns ``(opening, slip, rotation, end_gap)``: opening and slip at the centre (the
    contact strains ``q = -A^T u`` of :mod:`lamodel.structure`), the relative rotation,
    and the relative displacement magnitudes at the two ends ``centre -/+ d t`` (nc, 2).
    """
    u = _block_motion(structure, u)
    ia, ib = structure.contact_blocks()
    n, t, c, d = structure.normal, structure.tangent, structure.centre, structure.d
    rel = _point_motion(structure, u, ib, c) - _point_motion(structure, u, ia, c)
    opening = (rel * n).sum(axis=1)
    slip = (rel * t).sum(axis=1)
    th = np.where(ib >= 0, u[np.maximum(ib, 0), 2], 0.0) - np.where(ia >= 0, u[np.maximum(ia, 0), 2], 0.0)
    gaps = []
    for sign in (-1.0, 1.0):
        # a relative rotation th about the centre moves the end c + s d t by th k x (s d t) = -th s d n
        dn = opening - th * sign * d
        gaps.append(np.hypot(dn, slip))
    return opening, slip, th, np.column_stack(gaps)


def contact_modes(structure: Structure, u, rtol: float = RTOL) -> list:
    """The mode of every contact from the block motions u (:mod:`.modes`)."""
    return modes_from_mechanism(structure, _block_motion(structure, u), rtol)


def pivots(structure: Structure, u) -> np.ndarray:
    """For each contact, the end of the contact segment about which b rotates relative to a
    (a crushed joint's: the point inside it where its overlap ends).

    It is the end with the smaller relative displacement; when the two are equal it is
    ``centre + d t`` for a positive (counter-clockwise) relative rotation of b, else
    ``centre - d t``, with ``t = (-n_y, n_x)``.
    """
    opening, _, th, gaps = contact_kinematics(structure, u)
    t, c, d = structure.tangent, structure.centre, structure.d
    plus = np.where(np.isclose(gaps[:, 0], gaps[:, 1], rtol=1e-9, atol=0), th > 0, gaps[:, 1] < gaps[:, 0])
    out = c + np.where(plus, 1.0, -1.0)[:, None] * d[:, None] * t
    if getattr(structure, "has_materials", False):
        # a crushed joint turns about the point inside it where its normal opening
        # opening - th e (at c + e t) vanishes: the end of its overlap
        crushed = (np.minimum(opening - th * d, opening + th * d) < 0) & (th != 0)
        e = np.clip(opening[crushed] / th[crushed], -d[crushed], d[crushed])
        out[crushed] = c[crushed] + e[:, None] * t[crushed]
    return out
