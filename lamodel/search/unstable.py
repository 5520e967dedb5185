"""Where a structure is unstable under its dead load: a mechanism of the dead load alone.

When no statically admissible state exists at alpha = 0 (``A s + f0 = 0``, ``Y s <= 0``
infeasible, eq. 1-4), Farkas' lemma gives a certificate: block motions u and rates
``z >= 0`` with ``-A^T u = Y^T z`` (a mechanism flowing on the yield rows of eq. 4) on which
the dead loads do positive work, ``f0^T u > 0``. This module finds one by a small LP
(normalised ``f0^T u = 1``, least total flow ``sum z`` so that only what must move moves);
its moving blocks are the ones to name and highlight.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..formulation.matrices import Formulation
from ..structure import Structure


def dead_load_mechanism(structure: Structure):
    """u (nb, 3) of a mechanism under dead load alone, or None if the dead loads can be
    carried (the LP is infeasible: a statically admissible state exists at alpha = 0)."""
    from scipy.optimize import linprog
    F = Formulation.of(structure)
    nb3, nz = 3 * F.nb, F.Y.shape[0]
    # columns (u, z): -A^T u - Y^T z = 0, f0^T u = 1; min sum z
    eq = sp.vstack([sp.hstack([-F.A.T, -F.Y.T]), sp.hstack([sp.csr_matrix(F.f0[None, :]),
                                                              sp.csr_matrix((1, nz))])]).tocsr()
    rhs = np.zeros(eq.shape[0])
    rhs[-1] = 1.0
    cost = np.concatenate([np.zeros(nb3), np.ones(nz)])
    bounds = [(None, None)] * nb3 + [(0, None)] * nz
    res = linprog(cost, A_eq=eq, b_eq=rhs, bounds=bounds, method="highs")
    if res.status != 0:
        return None
    return res.x[:nb3].reshape(-1, 3)
