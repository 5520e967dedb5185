"""Certification: turn a candidate into an exact collapse state, or reject it.

A collapse state of the frictional assembly is a statically admissible state s (eq. 1-4)
and a mechanism (u, xi) of the fictitious cohesive system (fbar^T u = 1, xi >= 0) whose
flow happens only on yield rows that s holds at equality. By virtual work its multiplier
is then exactly alpha = alpha_K = -u^T f0 - xi^T N_mu s_N (eq. 5), the seed's second
theorem. The candidate (an Ipopt point, an LP point) only suggests which rows are active:

1. the rows the candidate holds within a tolerance are *allowed* to flow; an LP finds a
   mechanism flowing only on them (the one of least alpha_K for the candidate's N);
2. an LP finds the statics with the rows that mechanism uses held at equality, with the
   least alpha.

Both feasible means an exact collapse state; its alpha comes from the LP, never from the
candidate. :func:`residuals` re-checks every condition with plain numpy.
:func:`descend` then alternates the two LPs, each step keeping or lowering alpha.
"""
from __future__ import annotations

import numpy as np

from ..formulation.scaling import block_sizes
from .lp import LimitLPs
from .state import CollapseState
from .tuning import (ACTIVE_TOLERANCES, CERTIFY_DESCENT_STEPS, FLOW_TOL, IMPROVEMENT, RESIDUAL_TOLERANCE,
                     SIZE_RESOLUTION)

__all__ = ["ACTIVE_TOLERANCES", "RESIDUAL_TOLERANCE", "certify", "certify_flow", "descend", "force_scale",
           "residuals", "block_sizes", "unresolved_blocks", "SIZE_RESOLUTION"]


def force_scale(lps: LimitLPs) -> float:
    """A force that measures the problem: the largest block load (dead or live)."""
    return float(max(np.abs(lps.f0).max(), np.abs(lps.fbar).max(), 1e-300))


def unresolved_blocks(structure) -> list:
    """The blocks smaller than :data:`SIZE_RESOLUTION` times the structure's size (by
    :func:`~lamodel.formulation.scaling.block_sizes`): double-precision geometry cannot
    place their contacts to the accuracy a certificate needs. However light a block is
    beside the others, its loads are resolved (the LPs scale light blocks:
    :func:`~lamodel.formulation.scaling.light_scales`)."""
    smallest = SIZE_RESOLUTION * structure.size()  # of every block's vertices: once, not once a block
    return [b for b, w in zip(structure.blocks, block_sizes(structure)) if w < smallest]


def residuals(lps: LimitLPs, N, V, M, alpha, u, xi) -> dict:
    """Relative violations of every condition of a collapse state (0 is exact).

    equilibrium (eq. 2), yield (eq. 4), compatibility with the cohesive flow rule, the
    normalisation fbar^T u = 1, complementarity (flow only on rows held at equality) and
    the virtual-work identity alpha = alpha_K (eq. 5), each against the largest load of
    the structure; and the same statics block by block and contact by contact
    (``block_equilibrium``: each block's equilibrium against its own loads and the
    contact forces on it, moments by its own size; ``contact_yield`` and
    ``contact_complementarity``: each contact's rows against its own forces, never less
    than the loads of the lighter of its blocks). A block far lighter than the rest (a
    1e-3 m block on a 1e3 m one) is thereby held to its own scale: a state that leaves it
    out of equilibrium by a fraction of its own weight is no collapse state, however
    small that weight is beside the structure's.
    """
    x = np.concatenate([N, V, M, [alpha]])
    s = x[:-1]
    nc = len(N)
    st = lps.structure
    # Every measure has one dimension, so that it has the same value in any units (a
    # moment against a force, or a rotation against a displacement, is not a ratio):
    # moments are made forces, and rotations lengths, by the structure's size.
    Ls = st.size()

    def per_block(v, scale):  # (x, y, moment or rotation) per block
        return np.concatenate([v[0::3], v[1::3], scale * v[2::3]])

    F = max(np.abs(per_block(lps.f0, 1 / Ls)).max(), np.abs(per_block(lps.fbar, 1 / Ls)).max(), 1e-300)
    u_l = per_block(u, Ls)
    xi_l = np.concatenate([xi[:2 * nc], Ls * xi[2 * nc:]])       # slips, hinge rotations
    U = max(np.abs(u_l).max(), np.abs(xi_l).max(), 1e-300)
    unbalanced = lps.A @ s + lps.f0 + alpha * lps.fbar
    eq = per_block(unbalanced, 1 / Ls)
    slack = lps.slack(x)                                          # slides: forces, hinges: moments
    slack_f = np.concatenate([slack[:2 * nc], slack[2 * nc:] / Ls])
    compat = -(lps.A.T @ u) - lps.G.T @ xi                         # opening, slip, rotation
    compat = np.concatenate([compat[:2 * nc], Ls * compat[2 * nc:]])
    work_scale = max(F * U, 1e-300)

    # --- block by block, contact by contact
    Lb = block_sizes(st)

    def blocks(v):  # (nb, 3): fx, fy, moment / the block's own size
        return np.abs(np.stack([v[0::3], v[1::3], v[2::3] / Lb], axis=1)).max(axis=1)
    acting = blocks(abs(lps.A) @ np.abs(s))                       # the contact forces on each block
    Sb = np.maximum.reduce([blocks(lps.f0), max(abs(alpha), 1.0) * blocks(lps.fbar), acting,
                            np.full(len(Lb), 1e-300)])
    d = np.maximum(st.d, 1e-300)
    ia, ib = st.contact_blocks()
    lighter = np.minimum(np.where(ia >= 0, Sb[np.maximum(ia, 0)], np.inf), np.where(ib >= 0, Sb[np.maximum(ib, 0)],
                                                                                    np.inf))
    Sc = np.maximum.reduce([np.abs(N), np.abs(V), np.abs(M) / d, lighter])
    kinds = len(slack) // nc                                      # rows a contact, a block of nc each
    Sc4 = np.tile(Sc, kinds)                                      # the yield rows of each contact
    slack_c = np.concatenate([slack[:2 * nc], slack[2 * nc:] / np.tile(d, kinds - 2)])
    return {
        "equilibrium": float(np.abs(eq).max() / F),
        "yield": float(max(-slack_f.min(), 0.0) / F),
        "compatibility": float(np.abs(compat).max() / U),
        "normalisation": float(abs(lps.fbar @ u - 1.0)),
        "nonnegative_flow": float(max(-xi_l.min(), 0.0) / U),
        "complementarity": float(np.abs(xi * slack).max() / work_scale),
        "virtual_work": float(abs(lps.kinematic_multiplier(u, xi, N) - alpha) / max(abs(alpha), 1.0)),
        "block_equilibrium": float((blocks(unbalanced) / Sb).max()),
        "contact_yield": float((np.maximum(-slack_c, 0.0) / Sc4).max()),
        "contact_complementarity": float((np.abs(xi_l * slack_c) / (Sc4 * U)).max()),
    }


def _active(lps, x, tol):
    return lps.slack(x) <= tol * force_scale(lps)


def _state_from(lps, st, u, xi, flow, source):
    N, V, M, alpha = lps.split(st.x)
    res = residuals(lps, N, V, M, alpha, u, xi)
    if max(res.values()) > RESIDUAL_TOLERANCE:
        return None
    return CollapseState(alpha=float(alpha), N=N.copy(), V=V.copy(), M=M.copy(), u=u.copy(), xi=xi.copy(),
                         flow=flow.copy(), source=source, residual=res)


def certify_flow(lps: LimitLPs, u, xi, source="", flow_tol=FLOW_TOL):
    """Certify a mechanism that is already exact (e.g. the duals of an LP): statics with
    its flowing rows held at equality. Returns a CollapseState or None."""
    xi = np.maximum(np.asarray(xi, dtype=float), 0.0)
    flow = xi > flow_tol * max(xi.max(), 1e-300)
    st = lps.statics(flow)
    if not st.ok:
        return None
    xi = np.where(flow, xi, 0.0)
    return _state_from(lps, st, np.asarray(u, dtype=float), xi, flow, source)


def certify(lps: LimitLPs, N, V, M, alpha=None, u=None, xi=None, source="", tolerances=ACTIVE_TOLERANCES):
    """Certify a candidate (forces, and optionally its mechanism) as in the module doc.

    Tries the tolerances in turn and keeps the least certified alpha; None if no
    tolerance yields an exact collapse state.
    """
    x = np.concatenate([N, V, M, [0.0 if alpha is None else alpha]])
    best = None
    tried = set()
    for tol in tolerances:
        allowed = _active(lps, x, tol)
        key = allowed.tobytes()
        if key in tried or not allowed.any():
            continue
        tried.add(key)
        mres, u_lp, xi_lp = lps.mechanism(allowed, N)
        candidates = []
        if mres.ok:
            candidates.append((u_lp, xi_lp))
        if u is not None and xi is not None:
            # the candidate's own flow, cleaned to the allowed rows, when it is exact enough
            candidates.append((np.asarray(u, dtype=float), np.where(allowed, np.maximum(xi, 0.0), 0.0)))
        for uu, xx in candidates:
            state = certify_flow(lps, uu, xx, source)
            if state is not None and (best is None or state.alpha < best.alpha):
                best = state
        if best is not None:
            break
    return best


def descend(lps: LimitLPs, state: CollapseState, max_steps: int = CERTIFY_DESCENT_STEPS,
            tol: float = ACTIVE_TOLERANCES[0]) -> CollapseState:
    """Alternate the two certification LPs from a collapse state; alpha never increases.

    With the rows the statics holds at equality allowed to flow, the current mechanism is
    feasible, so the least-alpha_K mechanism does no worse; with the rows that mechanism
    uses held, the current statics is feasible, so the least-alpha statics does no worse.
    """
    for _ in range(max_steps):
        allowed = _active(lps, state.forces, tol)
        mres, u, xi = lps.mechanism(allowed, state.N)
        if not mres.ok:
            break
        nxt = certify_flow(lps, u, xi, state.source)
        if nxt is None or nxt.alpha >= state.alpha - IMPROVEMENT * max(1.0, abs(state.alpha)):
            break
        state = nxt
    return state
