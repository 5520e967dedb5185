"""Single-block mechanisms: one block moving on its own joints, every other at rest.

A loose top block, a step of a stepped stack, a voussoir that slides out: collapses of one
block are where the gap alternation can stall without a certificate (the least-alpha_K
mechanism of a statics is then a blend of many such motions, which no one statics holds).
Here each block is ranked by its own multiplier, the largest alpha its joints can carry it
at with the rest of the structure rigid (a tiny LP a block, for the fictitious system of
the given cohesions; in space the Coulomb cone is inscribed by a polygon of
SINGLE_BLOCK_FACETS sides: a ranking, not a certificate). The few lowest are then asked of
the formulation itself as mechanisms that flow on that block's rows only, and certified
like every other state.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..tuning import SINGLE_BLOCK_FACETS, SINGLE_BLOCKS

log = logging.getLogger(__name__)


def _joints(structure):
    """Per joint (plane: contact; space: contact point) the indices of its two blocks (-1: a support)."""
    if getattr(structure, "dimension", 2) == 3:
        return structure.point_blocks()
    index = {b: k for k, b in enumerate(structure.blocks)}
    return (np.array([index.get(a, -1) for a in structure.block_a]),
            np.array([index.get(b, -1) for b in structure.block_b]))


def _local_alpha(form, j, joints, c, d=None) -> float:
    """The largest alpha at which block j stands on its joints ``joints`` (the rest rigid),
    their forces within the fictitious system's domain for cohesions c; inf: it never
    goes, nan: it cannot stand even at alpha = 0 on them alone."""
    space = d is None
    per = 6 if space else 3
    n = form.np if space else form.nc
    cols = np.concatenate([joints + k * n for k in range(3)])
    m = len(joints)
    A = sp.hstack([form.A[per * j:per * (j + 1)][:, cols], form.fbar[per * j:per * (j + 1), None]]).tocsr()
    b = -form.f0[per * j:per * (j + 1)]
    bounds = [(None, 0.0)] * m                               # N <= 0
    if space:
        bounds += [(None, None)] * (2 * m) + [(None, None)]
        theta = 2 * np.pi * np.arange(SINGLE_BLOCK_FACETS) / SINGLE_BLOCK_FACETS
        radius = np.cos(np.pi / SINGLE_BLOCK_FACETS)            # an inscribed polygon of the cone
        rows = [sp.hstack([sp.csr_matrix((m, m)), sp.diags(np.full(m, np.cos(t))), sp.diags(np.full(m, np.sin(t))),
                           sp.csr_matrix((m, 1))]) for t in theta]
        A_ub, b_ub = sp.vstack(rows), np.tile(radius * c[joints], len(theta))
    else:
        bounds += [(-c[k], c[k]) for k in joints] + [(None, None)] * m + [(None, None)]
        dk = sp.diags(d[joints])
        z, one = sp.csr_matrix((m, m)), sp.identity(m)
        A_ub = sp.vstack([sp.hstack([dk, z, one, sp.csr_matrix((m, 1))]),   # |M| <= -d N
                          sp.hstack([dk, z, -one, sp.csr_matrix((m, 1))])])
        b_ub = np.zeros(2 * m)
    cost = np.zeros(3 * m + 1)
    cost[-1] = -1.0
    from scipy.optimize import linprog  # here: scipy.optimize's import is a tenth of a small wall's solve
    res = linprog(cost, A_ub=A_ub, b_ub=b_ub, A_eq=A, b_eq=b, bounds=bounds, method="highs")
    if res.status == 3:
        return np.inf
    return float(res.x[-1]) if res.status == 0 else np.nan


def ranked(problem, c) -> list:
    """(alpha, block) of every block moved by the live load, least alpha first."""
    form = problem.form
    structure = form.structure
    space = getattr(structure, "dimension", 2) == 3
    ia, ib = _joints(structure)
    per = 6 if space else 3
    loaded = np.abs(form.fbar.reshape(-1, per)).max(axis=1) > 0
    found = []
    for j in np.flatnonzero(loaded):
        joints = np.flatnonzero((ia == j) | (ib == j))
        if joints.size:
            a = _local_alpha(form, j, joints, c, None if space else structure.d)
            if np.isfinite(a) and a >= 0:
                found.append((a, int(j)))
    return sorted(found)


def rows_of(problem, j) -> np.ndarray:
    """The rows (eq. 4's, as the formulation numbers them) of block j's joints."""
    structure = problem.form.structure
    ia, ib = _joints(structure)
    mine = (ia == j) | (ib == j)
    kinds = 2 if getattr(structure, "dimension", 2) == 3 else 4  # (open, slip) a point; 4 rows a contact
    return np.tile(mine, kinds)


def single_blocks(problem, certifier, x, source="single-block"):
    """Up to SINGLE_BLOCKS blocks, least own multiplier first (for the cohesions of the
    statics x), each as a mechanism of that block alone: the first certified (or None).
    The first, not the least of all: the ranking already orders them, and in space a
    failed certification can cost a minute. Not descended here: on a 204-box pyramid the
    certificate took 3 s and its descent 181 s (six cone programs, none lower); the
    search's later phases start from it."""
    if problem.slack(x).size != rows_of(problem, 0).size:
        return None  # rows of another kind (joints with strengths): no single-block ranking of them
    c = -problem.mu * problem.N_of(x)
    for alpha_j, j in ranked(problem, c)[:SINGLE_BLOCKS]:
        status, _, _, u, xi = problem.mechanism(c, rows_of(problem, j))
        if status != "optimal":
            continue
        st = certifier.certify(u, xi, source)
        log.debug("single block %d: own alpha %.6f, %s", j, alpha_j, "certified" if st is not None else "no statics")
        if st is not None:
            return st
    return None


@dataclass(frozen=True)
class SingleBlocks:
    """The strategy of a lane (:mod:`.lanes`): :func:`single_blocks` for the cohesions of
    the associative statics."""

    name = "single block"
    once = None

    def run(self, engine, start):
        return single_blocks(engine.problem, engine.certifier, start.x_assoc)
