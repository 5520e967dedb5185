"""The one classifier of contact modes: closed, sliding, hinging, sliding+hinging, open,
crushing, crushing+sliding (and *unknown*: no certified collapse state, so nothing is
known of the contact).

A contact's mode is read from its strains ``q = (opening, slip, rotation)`` at the centre —
from the flow multipliers (``q = G^T xi``) or from the block motions (``q = -A^T u``); the
two agree for a compatible mechanism (:mod:`lamodel.formulation.matrices`). The ends of the
contact, ``centre -/+ d t``, open by ``opening +/- rotation d``; an end that closes (a
joint of finite compressive strength overlaps: :mod:`lamodel.formulation.joints`) crushes.
"""
from __future__ import annotations

import numpy as np

#: Contact modes of a mechanism (the ``mode`` column of contacts.csv); ``unknown`` when the
#: run certified no collapse state (the forces are then empty, not zero).
MODES = ("closed", "sliding", "hinging", "sliding+hinging", "open", "crushing", "crushing+sliding", "unknown")
#: The modes that slip, and those that turn about a point of the joint (an end, or inside
#: a crushed joint).
SLIDING = ("sliding", "sliding+hinging", "crushing+sliding")
TURNING = ("hinging", "sliding+hinging", "crushing", "crushing+sliding")

#: Motions smaller than this fraction of the largest one are taken as zero.
RTOL = 1e-7


def classify(d, opening, slip, rotation, rtol: float = RTOL) -> list:
    """Mode of each contact: *open* when both ends separate, *crushing* when an end closes
    (an overlap: the joint crushes), *hinging* when it opens about one end, *sliding* when
    it slips, *sliding+hinging* (*crushing+sliding*) when it does both."""
    d, opening, slip, rotation = (np.asarray(x, dtype=float) for x in (d, opening, slip, rotation))
    ends = np.column_stack([opening + rotation * d, opening - rotation * d])
    scale = max(np.abs(ends).max(initial=0.0), np.abs(slip).max(initial=0.0))
    eps = rtol * scale if scale > 0 else np.inf
    slides = np.abs(slip) > eps
    turns = np.abs(rotation * d) > eps
    opens = ends.min(axis=1) > eps
    crushes = ends.min(axis=1) < -eps
    return ["open" if o else ("crushing+sliding" if s else "crushing") if c else
            ("sliding+hinging" if s else "hinging") if t else ("sliding" if s else "closed")
            for o, c, s, t in zip(opens, crushes, slides, turns)]


def modes_from_flow(structure, xi, rtol: float = RTOL) -> list:
    """Modes from the flow multipliers xi (4 nc, stacked slide+, slide-, hinge+, hinge-;
    with the joints' strengths, the rows of :func:`~lamodel.formulation.matrices.strength_rows`)."""
    from ..formulation.matrices import flow_matrix, strength_rows
    G = strength_rows(structure)[1] if getattr(structure, "has_materials", False) else flow_matrix(structure)
    q = G.T @ np.asarray(xi, dtype=float)
    nc = structure.n_contacts
    return classify(structure.d, q[:nc], q[nc:2 * nc], q[2 * nc:], rtol)


def modes_from_mechanism(structure, u, rtol: float = RTOL) -> list:
    """Modes from the block motions u ((nb, 3) or 3 nb: ux, uy, theta)."""
    from ..formulation.matrices import equilibrium_matrix
    q = -(equilibrium_matrix(structure).T @ np.asarray(u, dtype=float).ravel())
    nc = structure.n_contacts
    return classify(structure.d, q[:nc], q[nc:2 * nc], q[2 * nc:], rtol)
