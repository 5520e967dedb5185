"""Certification of a candidate by the two LPs (lamodel.search.certify), for the methods."""
import numpy as np

from lamodel.geometry import running_bond_wall
from lamodel.io.jsonspec import structure_from_json
from lamodel.output.modes import modes_from_flow
from lamodel.search.certify import certify, certify_flow, descend, residuals
from lamodel.search.driver import SolveOptions, solve
from lamodel.search.lp import LimitLPs


def small_wall():
    """A 3-course running-bond wall (8 blocks): quick, yet with sliding and hinging."""
    return structure_from_json(running_bond_wall([[0.5, 1, 1, 0.5], [1, 1, 1], [0.5, 1, 1, 0.5]], name="wall8"))


def test_certified_lp_state_passes_an_independent_residual_check():
    s = small_wall()
    lps = LimitLPs(s)
    assoc = lps.associative()
    res, u, xi = lps.cohesive(-s.mu * lps.split(assoc.x)[0])
    state = certify_flow(lps, u, xi)
    assert state is not None
    assert max(state.residual.values()) < 1e-8
    assert state.alpha <= assoc.alpha + 1e-9


def test_perturbed_point_is_rejected(wall33):
    lps = LimitLPs(wall33)
    o = solve(wall33, SolveOptions(starts=0, pop_size=6, generations=2))
    best = o.best
    # a mechanism broken by a slip on one closed contact is no mechanism at all
    xi = best.xi.copy()
    closed = [k for k, m in enumerate(modes_from_flow(wall33, best.xi)) if m == "closed"]
    xi[closed[0]] += 0.05
    assert certify_flow(lps, best.u, xi) is None
    # forces pushed off their yield rows and a mechanism pushed off the flow rule: rejected
    rng = np.random.default_rng(0)
    assert certify(lps, best.N * (1 + 0.3 * rng.random(best.N.size)), best.V * 0.5, best.M * 0.5,
                   best.alpha, best.u + 0.1 * rng.normal(size=best.u.size), xi,
                   tolerances=(1e-9,)) is None


def test_descend_never_increases_alpha(wall33):
    lps = LimitLPs(wall33)
    assoc = lps.associative()
    res, u, xi = lps.cohesive(-wall33.mu * lps.split(assoc.x)[0])
    state = certify_flow(lps, u, xi)
    better = descend(lps, state)
    assert better.alpha <= state.alpha + 1e-12
    r = residuals(lps, better.N, better.V, better.M, better.alpha, better.u, better.xi)
    assert max(r.values()) < 1e-7
