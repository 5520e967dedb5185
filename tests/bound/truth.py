"""The true least collapse multiplier of a tiny assembly, by enumeration (an oracle).

A collapse state is an admissible statics s (eq. 1-4, alpha >= 0) and a mechanism (u, xi)
of the fictitious system (q = -A^T u = G^T xi, xi >= 0, fbar^T u = 1) with
``alpha_K - alpha = xi^T slack = 0``: the mechanism flows only on rows s holds tight.
So alpha_c = min over the sets R of yield rows on which some mechanism can flow of
min{alpha : s admissible, the rows of R tight}; both are monotone in R, so only the
minimal such sets need solving. A minimal set is the support of a vertex of the
mechanisms' polyhedron: at most (3 nc + 1) - 3 nb rows (the equations of compatibility and
normalisation less the block motions). Written with scipy's linprog on the matrices of
lamodel.formulation.matrices only (no code of lamodel's searches or of its bound).
"""
from __future__ import annotations

import itertools

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from lamodel.formulation.matrices import Formulation


def _mechanism_flows_on(F: Formulation, rows) -> bool:
    nb3, nr = F.A.shape[0], F.Y.shape[0]
    # variables (u, xi); -A^T u - G^T xi = 0, fbar^T u = 1, xi >= 0, xi = 0 off ``rows``
    Aeq = sp.vstack([sp.hstack([-F.A.T, -F.G.T]), sp.hstack([sp.csr_matrix(F.fbar.reshape(1, -1)),
                                                             sp.csr_matrix((1, nr))])])
    beq = np.concatenate([np.zeros(F.A.shape[1]), [1.0]])
    bounds = [(None, None)] * nb3 + [(0, None if i in rows else 0) for i in range(nr)]
    res = linprog(np.zeros(nb3 + nr), A_eq=Aeq, b_eq=beq, bounds=bounds, method="highs")
    return res.status == 0


def _least_alpha_holding(F: Formulation, rows) -> float:
    nc3 = F.A.shape[1]
    tight = sorted(rows)
    Aeq = sp.vstack([sp.hstack([F.A, sp.csr_matrix(F.fbar.reshape(-1, 1))]),
                     sp.hstack([F.Y[tight], sp.csr_matrix((len(tight), 1))])])
    beq = np.concatenate([-F.f0, np.zeros(len(tight))])
    Aub = sp.hstack([F.Y, sp.csr_matrix((F.Y.shape[0], 1))])
    cost = np.zeros(nc3 + 1)
    cost[-1] = 1.0
    res = linprog(cost, A_ub=Aub, b_ub=np.zeros(F.Y.shape[0]), A_eq=Aeq, b_eq=beq,
                  bounds=[(None, None)] * nc3 + [(0, None)], method="highs")
    return float(res.fun) if res.status == 0 else np.inf


def true_alpha_c(structure) -> float:
    """min alpha over all collapse states (inf when there is none)."""
    F = Formulation.of(structure)
    nr = F.Y.shape[0]
    minimal = []
    best = np.inf
    largest = min(nr, 3 * (structure.n_contacts - structure.n_blocks) + 1)
    for size in range(1, largest + 1):
        for rows in itertools.combinations(range(nr), size):
            R = set(rows)
            if any(m <= R for m in minimal):
                continue
            if _mechanism_flows_on(F, R):
                minimal.append(R)
                best = min(best, _least_alpha_holding(F, R))
    return best
