"""The proven lower bound: sound against the truth, proofs on the seed's instances,
frame-free, and its exact check refuses what it must.

Soundness: on tiny random assemblies (the generators of tests/search/test_properties.py,
at most 3 blocks and 4 contacts) the true least collapse multiplier is found by
enumeration (:mod:`truth`); ``alpha_lower <= alpha_c(true) <= alpha`` (lamodel's).
"""
from __future__ import annotations

import math
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "search"))

from lamodel.bound.exact import ExactData, floor_float  # noqa: E402
from lamodel.bound.lower import lower_bound  # noqa: E402
from lamodel.bound.lps import BoundLPs  # noqa: E402
from lamodel.geometry import arch  # noqa: E402
from lamodel.io import read  # noqa: E402
from lamodel.io.jsonspec import structure_from_json  # noqa: E402
from lamodel.search.driver import SolveOptions, solve  # noqa: E402
from test_metamorphic import CASES, transform_spec  # noqa: E402
from test_properties import piers, stacks, trilithons, with_friction_and_load  # noqa: E402
from truth import true_alpha_c  # noqa: E402

from conftest import INSTANCES, bound_parts  # noqa: E402

OPTIONS = SolveOptions(starts=0, pop_size=4, generations=2, progress=False)
SETTINGS = settings(max_examples=6, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


def check_sound(case):
    spec, _ = case
    s = structure_from_json(spec)
    assume(s.n_blocks <= 3 and s.n_contacts <= 4)
    o = solve(s, OPTIONS)
    assume(o.certified)
    truth = true_alpha_c(s)
    alpha = o.best.alpha
    assert truth <= alpha + 1e-7 * max(1.0, alpha)
    lb = lower_bound(s, alpha, budget=20.0)
    assert lb.alpha_lower <= truth + 1e-9 * max(1.0, truth), (lb, truth)
    if lb.proven_global:
        assert alpha - truth <= 1e-6 * max(1.0, alpha)
    # any top of the range: the claim "no collapse below alpha_lower" stays true
    wide = lower_bound(s, 2.0 * alpha + 0.1, budget=20.0, max_nodes=30)
    assert wide.alpha_lower <= truth + 1e-9 * max(1.0, truth), (wide, truth)


@SETTINGS
@given(with_friction_and_load(stacks()))
def test_bound_is_sound_on_random_stacks(case):
    check_sound(case)


@SETTINGS
@given(with_friction_and_load(piers()))
def test_bound_is_sound_on_random_piers(case):
    check_sound(case)


@pytest.mark.slow
@SETTINGS
@given(with_friction_and_load(trilithons()))
def test_bound_is_sound_on_random_trilithons(case):
    check_sound(case)


def trilithon(mu):
    from conftest import rect
    blocks = [{"id": "ground", "support": True, "vertices": rect(-5, -1, 5, 0)},
              {"id": "l", "vertices": rect(-1.0, 0, -0.5, 1.0)}, {"id": "r", "vertices": rect(0.5, 0, 1.0, 1.0)},
              {"id": "lintel", "vertices": rect(-1.0, 1.0, 1.0, 1.4)}]
    return structure_from_json({"name": "trilithon", "mu": mu, "live_load": [1.0, 0.0], "blocks": blocks})


@pytest.mark.slow
def test_branching_raises_the_bound_beyond_the_rounds_and_stays_below_the_truth():
    """A trilithon sliding on the ground (alpha_c = mu): per-contact minima of the two
    piers' normal forces undercount their sum, so the rounds stall below alpha_c; the
    branching on the normal-force ranges raises the bound, never above the truth."""
    s = trilithon(0.3)
    truth = true_alpha_c(s)
    assert truth == pytest.approx(0.3, rel=1e-9)
    lb = lower_bound(s, 0.3, budget=120.0, max_nodes=40)
    assert lb.root_bound < 0.25 and lb.excluded > 0
    assert lb.root_bound + 0.02 < lb.alpha_lower <= truth + 1e-12


def test_polygon_of_two_contacts_raises_the_root_and_stays_below_the_truth():
    """The lintel of the trilithon slides on both piers: the polygon of their normal forces
    (their sum carries the lintel) lifts the root's bound above the box corner's."""
    s = trilithon(0.3)
    corner = lower_bound(s, 0.3, budget=60.0, max_nodes=1)
    polygon = lower_bound(s, 0.3, budget=60.0, max_nodes=1, pairs="root")
    assert corner.alpha_lower + 0.02 < polygon.alpha_lower <= 0.3
    deeper = lower_bound(s, 0.3, budget=120.0, max_nodes=30, pairs="all")
    assert polygon.alpha_lower <= deeper.alpha_lower <= 0.3


@pytest.mark.parametrize("name", ["arch", "portal", "portal_columns"])
def test_seed_instances_are_proven_global_minima(name):
    s = read(INSTANCES / f"{name}.dat")
    o = solve(s, SolveOptions(starts=0, progress=False))
    assert o.certified
    lb = lower_bound(s, o.best.alpha, budget=60.0)
    assert lb.proven_global, lb
    assert lb.exact_check == "passed"
    assert o.best.alpha - 1e-6 * max(1.0, o.best.alpha) <= lb.alpha_lower <= o.best.alpha


@pytest.mark.parametrize("case", ["force x1e9", "length x1e-3", "rotated 0.7 rad", "blocks and vertices renumbered",
                                  "all at once"])
def test_alpha_lower_is_frame_free(case):
    """Units, rotation and numbering do not change alpha_lower. The range's top is 1.5
    alpha so that the rounds do work before they meet the truth."""
    spec = arch(7, 5.0, 1.5, impost_height=2.0, impost_width=2.5, name="arch7")
    base = structure_from_json(spec)
    o = solve(base, SolveOptions(starts=0, progress=False))
    top = 1.5 * o.best.alpha
    ref = lower_bound(base, top, budget=60.0, max_nodes=1).alpha_lower
    assert ref > 0
    kw = dict(CASES[case])
    if kw.get("perm") == "random":
        kw["perm"] = np.random.default_rng(1).permutation(len(spec["blocks"]))
    other = lower_bound(structure_from_json(transform_spec(spec, **kw)), top, budget=60.0, max_nodes=1)
    assert other.alpha_lower == pytest.approx(ref, rel=1e-6)


# ------------------------------------------------------------------ the exact check
@pytest.fixture(scope="module")
def portal():
    return bound_parts(read(INSTANCES / "portal.dat"))


def test_dual_bound_is_below_the_lp_minimum_and_a_corrupted_point_cannot_claim_more(portal):
    s, lps, ex = portal
    nc = s.n_contacts
    lo, hi = np.zeros(nc), np.full(nc, np.inf)
    k = int(np.argmax(s.centre[:, 1] < 1e-9))  # a contact on the ground: carries weight
    ans = lps.normal_force(k, 0.0, 0.2, lo, hi)
    q = ex.dual_bound(ans.y, k, 0.0, 0.2, lo, hi)
    assert q > 0 and float(q) <= ans.value * (1 + 1e-9)
    assert float(q) == pytest.approx(ans.value, rel=1e-7)
    # any multipliers give a valid (lower) bound: a corrupted point never claims more
    rng = np.random.default_rng(0)
    for _ in range(5):
        bad = ans.y * (1 + 0.05 * rng.standard_normal(ans.y.size))
        qb = ex.dual_bound(bad, k, 0.0, 0.2, lo, hi)
        assert qb is None or qb <= q
    # without the correction direction, a point HiGHS left infeasible by rounding is refused
    ex2 = ExactData(s)
    bad = ans.y + 1e-3 * np.abs(ans.y).max()
    assert ex2.dual_bound(bad, k, 0.0, 0.2, lo, hi) is None


def test_cohesive_certificate_is_rebuilt_exactly_and_a_corrupted_one_is_rejected(portal):
    s, lps, ex = portal
    nc = s.n_contacts
    nmin = np.array([max(0.0, lps.normal_force(k, 0.0, 0.2, np.zeros(nc), np.full(nc, np.inf)).value)
                     for k in range(nc)]) * 0.999
    c = [ex.mu[k] * Fraction(float(nmin[k])) for k in range(nc)]
    cf = np.array([floor_float(v) for v in c])
    ans = lps.cohesive(cf)
    q = ex.cohesive_bound(ans, lps.cohesive_limits(cf), c, lps.d_shrunk)
    assert q is not None and float(q) == pytest.approx(ans.value, rel=1e-9)
    # claimed for smaller cohesions than the statics uses: rejected
    smaller = [v / 2 for v in c]
    assert ex.cohesive_bound(ans, lps.cohesive_limits(cf), smaller, lps.d_shrunk) is None
    # a statics off equilibrium by one ulp of alpha: rejected
    N = [Fraction(0)] * nc
    assert not ex.check_cohesive(N, N, N, Fraction(ans.value), c)


def test_summary_and_words_carry_the_bound(tmp_path):
    from lamodel.output.report import lower_bound_columns, outcome_results
    from lamodel.output.results import Results
    from lamodel.output.words import bound_words
    s = read(INSTANCES / "portal_columns.dat")
    o = solve(s, SolveOptions(starts=0, progress=False))
    r = outcome_results(o, lower_bound_columns(o, prove=60.0))
    r.write(tmp_path / "out")
    back = Results.read(tmp_path / "out")
    row = back.summary.iloc[0]
    assert bool(row.proven_global) and row.alpha_lower <= row.alpha
    assert "proven global minimum" in " ".join(bound_words(back.summary)).lower()


def test_default_bound_proves_a_portal_and_stops_early_on_a_wall():
    """The default (the root's rounds to their fixed point): the portal is proven; on a
    running-bond wall the first round raises nothing and the bound stops within a few LPs
    (counted, not timed), its claim 0."""
    from lamodel.bound.lower import default_budget
    for name, proven in (("portal_columns", True), ("wall33", False)):
        s = read(INSTANCES / f"{name}.dat")
        o = solve(s, SolveOptions(starts=0, progress=False))
        lb = lower_bound(s, o.best.alpha, **default_budget(1.0, s))
        assert lb.proven_global is proven and lb.nodes == 1
        if not proven:
            assert lb.alpha_lower == 0.0 and lb.lps <= 10


def test_open_contact_probe_agrees_with_the_minimisation():
    """The feasibility LP 'can contact k be open?' that stands in for Nmin_k = 0 answers
    yes exactly where the minimisation gives 0 (wall33 on alpha in [0.6, 0.638982])."""
    s = read(INSTANCES / "wall33.dat")
    lps = BoundLPs(s)
    nc = s.n_contacts
    lo, hi = np.zeros(nc), np.full(nc, np.inf)
    positive = 0
    for k in range(nc):
        shut = hi.copy()
        shut[k] = 0.0
        can_open = lps.normal_force(None, 0.6, 0.638982, lo, shut).status == "optimal"
        nmin = lps.normal_force(k, 0.6, 0.638982, lo, hi).value
        assert can_open == (nmin <= 1e-9), (k, nmin)
        positive += not can_open
    assert 0 < positive < nc
