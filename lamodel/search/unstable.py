"""Where a structure is unstable under its dead load: a mechanism of the dead load alone.

When no statically admissible state exists at alpha = 0 (``A s + f0 = 0``, ``Y s <= 0``
infeasible, eq. 1-4), Farkas' lemma gives a certificate: block motions u and rates
``z >= 0`` with ``-A^T u = Y^T z`` (a mechanism flowing on the yield rows of eq. 4) on which
the dead loads do positive work, ``f0^T u > 0``. This module finds one by a small LP
(normalised ``f0^T u = 1``, least total flow ``sum z`` so that only what must move moves);
its moving blocks are the ones to name and highlight.

In space (:func:`dead_load_mechanism3d`) the yield rows are the Coulomb cones
``||T|| <= -mu N``, whose dual is the associative flow ``opening >= mu ||slip||``: the same
certificate is a second-order cone program (Clarabel), with the least total opening.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..formulation.matrices import Formulation
from ..formulation.space import Formulation3D, scaled, scales
from ..structure import Structure
from ..structure3d import Structure3D
from .tuning import DEAD_LOAD_REST, DEAD_LOAD_ROUNDS


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


def dead_load_mechanism3d(structure: Structure3D, held=None, form=None):
    """u (nb, 6: motion and rotation at the centroid) of a mechanism in space under dead
    load alone, or None if the dead loads can be carried (see the module doc); blocks
    ``held`` (bool, nb) do not move. Solved on the non-dimensional structure (``form``: its
    :class:`Formulation3D`, if built), given back in the structure's lengths."""
    import clarabel
    F, L = scales(structure)
    form = form or Formulation3D.of(scaled(structure, F, L))
    n, At = form.np, form.A.T.tocsr()
    mu = np.asarray(form.mu, float)
    # s = b - G u: first f0^T u = 1 (zero cone), then per point (opening, mu slip1, mu slip2)
    # in the second-order cone, where (opening, slip1, slip2) = q = -A^T u
    rows = np.arange(n)
    order = np.concatenate([rows, n + rows, 2 * n + rows])
    weight = np.concatenate([np.ones(n), mu, mu])
    place = np.concatenate([3 * rows, 3 * rows + 1, 3 * rows + 2])
    cone = sp.csr_matrix((weight, (place, np.arange(3 * n))), shape=(3 * n, 3 * n)) @ At[order]
    free = np.repeat(~np.asarray(held, bool), 6) if held is not None else np.ones(6 * form.nb, bool)
    G = sp.vstack([sp.csr_matrix(form.f0[None, :]), cone]).tocsc()[:, free]
    b = np.concatenate([[1.0], np.zeros(3 * n)])
    cost = -np.asarray(At[:n].sum(axis=0)).ravel()[free]   # the total opening, sum of -A^T u over the normals
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.max_threads = 1
    sol = clarabel.DefaultSolver(sp.csc_matrix((G.shape[1], G.shape[1])), cost, G, b,
                                 [clarabel.ZeroConeT(1)] + [clarabel.SecondOrderConeT(3)] * n, settings).solve()
    if str(sol.status).split(".")[-1] not in ("Solved", "AlmostSolved"):
        return None
    u = np.zeros(6 * form.nb)
    u[free] = sol.x
    u = u.reshape(-1, 6)
    u[:, :3] *= L   # translations in the structure's lengths; rotations have none
    return u


def unheld_blocks3d(structure: Structure3D, rounds: int = DEAD_LOAD_ROUNDS):
    """(the blocks that no statics holds, whether the list is complete): the moving blocks
    of a dead-load mechanism, then, those held fixed, of the next one, until the rest
    stands or after ``rounds`` mechanisms. Held fixed, these blocks leave a structure that
    carries its dead load: the places to look at (missing joints, a block out of place)."""
    F, L = scales(structure)
    form = Formulation3D.of(scaled(structure, F, L))
    held = np.zeros(structure.n_blocks, dtype=bool)
    for _ in range(rounds):
        u = dead_load_mechanism3d(structure, held, form)
        if u is None:
            return [b for b, h in zip(structure.blocks, held) if h], True
        moving = moving_blocks3d(structure, u) & ~held
        if not moving.any():
            break
        held |= moving
    return [b for b, h in zip(structure.blocks, held) if h], False


def moving_blocks3d(structure: Structure3D, u, rest: float = DEAD_LOAD_REST) -> np.ndarray:
    """Boolean per block: its largest vertex motion under u (nb, 6) exceeds ``rest`` times
    the largest of all blocks."""
    s = structure
    big = np.zeros(s.n_blocks)
    for j, b in enumerate(s.blocks):
        v = np.asarray(s.polyhedra[b][0]) if b in s.polyhedra else s.centroid[j][None, :]
        big[j] = np.linalg.norm(u[j, :3] + np.cross(u[j, 3:], v - s.centroid[j]), axis=1).max()
    top = big.max(initial=0.0)
    return big > rest * top if top > 0 else np.zeros(s.n_blocks, dtype=bool)
