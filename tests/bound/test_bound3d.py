"""The proven lower bound in space: closed forms, extruded seed structures, frame and unit
invariance, soundness on random stacks, the exact checks on the cone, the result folder."""
from __future__ import annotations

import json
import math
from fractions import Fraction

import numpy as np
import pytest

from builders3d import box_on_ground, stack_of_boxes, transformed
from lamodel.bound.exact import floor_float
from lamodel.bound.lower import lower_bound
from lamodel.bound.space import BETA, ZONES, BoundLPs3D, ExactData3D, pyramid_vertices, zone_directions
from lamodel.formulation.extrude import extrude
from lamodel.io import read
from conftest import INSTANCES, bound_parts


def stack_closed_form(n, a, b, h, mu, phi):
    c, s = abs(math.cos(phi)), abs(math.sin(phi))
    return min(mu, a / (n * h * c) if c > 1e-12 else math.inf, b / (n * h * s) if s > 1e-12 else math.inf)


def test_polygons_hold_and_lie_in_the_circle_exactly():
    """The pyramid's sides are outside the unit circle and the zonotope's vertices inside
    it, checked in rationals (the certificates do not rely on it, the LPs' tightness does)."""
    w = [tuple(Fraction(float(x)) for x in v) for v in pyramid_vertices()]
    for (x1, y1), (x2, y2) in zip(w, w[1:] + w[:1]):
        cross, dx, dy = x1 * y2 - x2 * y1, x2 - x1, y2 - y1
        assert cross > 0 and cross * cross >= dx * dx + dy * dy  # the side's distance from 0 >= 1
    d = [tuple(Fraction(float(x)) for x in v) for v in zone_directions()]
    beta = Fraction(BETA)
    for start in range(2 * ZONES):  # vertices: consecutive sign patterns
        signs = [1 if (i - start) % (2 * ZONES) < ZONES else -1 for i in range(ZONES)]
        vx = sum(s * beta * v[0] for s, v in zip(signs, d))
        vy = sum(s * beta * v[1] for s, v in zip(signs, d))
        assert vx * vx + vy * vy < 1


@pytest.mark.parametrize("phi", [0.0, 90.0])
def test_one_block_is_proven_at_its_closed_form(phi):
    """A block 1 x 0.5 x 2 on four corner points turns about a base edge at
    alpha = min(a / h, b / h) along x or y: the bound meets it (turning involves no cone)."""
    p = math.radians(phi)
    s = box_on_ground(1.0, 0.5, 2.0, 0.6, (math.cos(p), math.sin(p), 0.0))
    closed = stack_closed_form(1, 1.0, 0.5, 2.0, 0.6, p)
    lb = lower_bound(s, closed, budget=60.0, max_nodes=200)
    assert lb.alpha_lower <= closed + 1e-12
    assert lb.proven_global and lb.exact_check == "passed", lb


def test_a_sliding_block_is_bounded_below_its_friction_coefficient():
    """A squat block slides at mu: the bound stays below it and rises above 0 by branching."""
    s = box_on_ground(2.0, 2.0, 0.2, 0.6, (1.0, 0.0, 0.0))
    lb = lower_bound(s, 0.6, budget=60.0, max_nodes=60)
    assert 0.3 < lb.alpha_lower <= 0.6 + 1e-12, lb


@pytest.mark.parametrize("name", ["portal_columns.dat", "portal.dat"])
def test_extruded_seed_structure_is_bounded_below_its_planar_alpha(name):
    """Extruded one unit deep, the seed's portals collapse in plane at their planar alpha:
    the 3D bound, searched over a range twice as high, stays below it."""
    s2 = read(INSTANCES / name)
    planar = {"portal_columns.dat": 0.269098380930622, "portal.dat": 0.20038733167465722}[name]
    lb = lower_bound(extrude(s2, depth=1.0), 2 * planar, budget=60.0, max_lps=400)
    assert 0.0 <= lb.alpha_lower <= planar + 1e-9


def test_bound_is_frame_and_unit_free():
    """Rotated (and mirrored), in other units, renumbered: the same bound."""
    s = box_on_ground(1.0, 0.5, 2.0, 0.6, (math.cos(0.4), math.sin(0.4), 0.0))
    alpha = stack_closed_form(1, 1.0, 0.5, 2.0, 0.6, 0.4)
    base = lower_bound(s, alpha, budget=60.0, max_nodes=200)
    c, sn = math.cos(0.7), math.sin(0.7)
    R = np.array([[c, -sn, 0], [sn, c, 0], [0, 0, 1]]) @ np.diag([1.0, -1.0, 1.0])
    moved = transformed(s, R, length=1e-3, force=1e6, point_order=[2, 0, 3, 1], shift=(5.0, -2.0, 1.0))
    other = lower_bound(moved, alpha, budget=60.0, max_nodes=200)
    assert base.alpha_lower > 0
    assert other.alpha_lower == pytest.approx(base.alpha_lower, rel=1e-6, abs=1e-9)


@pytest.mark.parametrize("seed", range(4))
def test_bound_is_sound_on_random_stacks(seed):
    """Stacks of 1-3 blocks with random sizes, friction and load direction, whose least
    collapse multiplier has a closed form (the stack turns as a whole or slides at mu)."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 4))
    a, b, h = rng.uniform(0.5, 1.5), rng.uniform(0.5, 1.5), rng.uniform(0.2, 0.8)
    mu, phi = rng.uniform(0.2, 0.9), rng.uniform(0, 2 * math.pi)
    s = stack_of_boxes(n, a, b, h, mu, (math.cos(phi), math.sin(phi), 0.0))
    truth = stack_closed_form(n, a, b, h, mu, phi)
    for top in (truth, 1.5 * truth + 0.1):
        lb = lower_bound(s, top, budget=60.0, max_nodes=25)
        assert lb.alpha_lower <= truth * (1 + 1e-9), (lb, truth)


@pytest.fixture
def box3d():
    return bound_parts(box_on_ground(1.0, 0.5, 2.0, 0.6, (1.0, 0.0, 0.0)))


def test_dual_bound_on_the_cone_is_below_the_pyramid_minimum(box3d):
    s, lps, ex = box3d
    npt = s.n_points
    lo, hi = np.zeros(npt), np.full(npt, np.inf)
    k = int(np.argmax(s.point[:, 0]))  # a corner on the toe side
    ans = lps.normal_force(k, 0.25, 0.5, lo, hi)
    q = ex.dual_bound(ans.y, k, 0.25, 0.5, lo, hi)
    assert q > 0 and float(q) <= ans.value * (1 + 1e-9)
    rng = np.random.default_rng(1)
    for _ in range(5):
        bad = ans.y * (1 + 0.05 * rng.standard_normal(ans.y.size))
        qb = ex.dual_bound(bad, k, 0.25, 0.5, lo, hi)
        assert qb is None or qb <= q


def test_cohesive_certificate_on_the_disk_and_a_corrupted_one_is_rejected(box3d):
    s, lps, ex = box3d
    c = [ex.mu[p] * Fraction(1, 4) for p in range(s.n_points)]
    cf = np.array([floor_float(v) for v in c])
    ans = lps.cohesive(cf)
    q = ex.cohesive_bound(ans, lps.cohesive_limits(cf), c)
    assert q is not None and float(q) == pytest.approx(ans.value, rel=1e-9)
    # the full cohesions mu W / 4: sliding would need 0.6 (0.59 on the inscribed polygon),
    # turning about the toe 0.5
    assert float(q) == pytest.approx(0.5, rel=1e-6) and q <= Fraction(1, 2)
    assert ex.cohesive_bound(ans, lps.cohesive_limits(cf), [v / 2 for v in c]) is None


def test_summary_and_words_carry_the_bound_in_space(tmp_path):
    from lamodel.cli import main
    spec = {"name": "box", "dimension": 3, "mu": 0.6, "unit_weight": 1.0, "live_load": [1.0, 0.0, 0.0],
            "blocks": [{"id": "ground", "support": True, "vertices": _box(-2, -2, -0.5, 2, 2, 0)},
                       {"id": "B", "vertices": _box(-0.5, -0.25, 0, 0.5, 0.25, 2)}]}
    path = tmp_path / "box.json"
    path.write_text(json.dumps(spec))
    assert main(["solve", str(path), "--out", str(tmp_path / "out"), "--no-plot", "--quiet"]) in (0, None)
    import pandas as pd
    row = pd.read_csv(tmp_path / "out" / "summary.csv").iloc[0]
    assert row.alpha_lower == pytest.approx(0.5, abs=1e-9) and row.alpha_lower <= row.alpha + 1e-12
    assert bool(row.proven_global) and row.alpha_lower_check == "passed"


def _box(x0, y0, z0, x1, y1, z1):
    return [[x, y, z] for z in (z0, z1) for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]
