"""The 3D search against closed forms: blocks on the ground, torsion, panels, extruded walls."""
import numpy as np
import pytest

from builders3d import box_on_ground
from lamodel.search.certify3d import RESIDUAL_TOLERANCE
from lamodel.search.search3d import solve3d


def certified(s, **kw):
    r = solve3d(s, **kw)
    assert r.status == "certified", r.message
    assert max(r.state.residual.values()) <= RESIDUAL_TOLERANCE
    return r


@pytest.mark.parametrize("phi, expected", [(0, 0.5), (30, 0.5), (60, 0.288675), (90, 0.25)])
def test_tall_block_overturns_or_slides(phi, expected):
    # a x b x h = 1 x 0.5 x 2, mu 0.6: alpha = min(mu, a / (h |cos|), b / (h |sin|))
    p = np.radians(phi)
    a, b, h, mu = 1.0, 0.5, 2.0, 0.6
    closed = min(mu, a / (h * abs(np.cos(p))) if np.cos(p) > 1e-12 else np.inf,
                 b / (h * abs(np.sin(p))) if np.sin(p) > 1e-12 else np.inf)
    assert closed == pytest.approx(expected, abs=1e-6)
    r = certified(box_on_ground(a, b, h, mu, (np.cos(p), np.sin(p), 0.0)))
    assert r.alpha == pytest.approx(closed, abs=1e-6)
    # it overturns: two base corners open, the block turns about the other two
    assert list(r.modes).count("opening") == 2
    assert np.abs(r.motions[0, 3:]).max() > 0


@pytest.mark.parametrize("phi", [0, 17, 45, 90, 200, 300])
def test_squat_block_slides_at_mu_in_every_direction(phi):
    p = np.radians(phi)
    r = certified(box_on_ground(2.0, 2.0, 0.2, 0.6, (np.cos(p), np.sin(p), 0.0)))
    assert r.alpha == pytest.approx(0.6, abs=1e-6)
    assert set(r.modes) == {"sliding"}
    # it translates along the load: the slip is parallel to W (cos, sin, 0)
    ux, uy = r.motions[0, :2]
    assert ux * np.sin(p) - uy * np.cos(p) == pytest.approx(0.0, abs=1e-6)


def test_torsion_on_four_corners_is_the_cone_value():
    # a square block a x a on 4 corner points under a twisting couple: every corner slides
    # perpendicular to its radius a sqrt(2)/2, T = mu P a sqrt(2)/2 (the 4-facet pyramid
    # aligned with the edges would give mu P a, the inscribed one mu P a / 2)
    a, P, mu = 1.0, 3.0, 0.6
    r = certified(box_on_ground(a, a, 0.5, mu, (0.0, 0.0, 0.0), live_m=(0.0, 0.0, 1.0), weight=P))
    assert r.alpha == pytest.approx(mu * P * a * np.sqrt(2) / 2, abs=1e-6)
    assert abs(r.alpha - mu * P * a) > 0.1 and abs(r.alpha - mu * P * a / 2) > 0.1
    assert set(r.modes) == {"sliding"}
    assert r.motions[0, 5] > 0 and np.abs(r.motions[0, :5]).max() < 1e-9  # a turn about the vertical axis


def test_monolithic_panel_overturns_out_of_plane():
    L, t, H = 3.0, 0.3, 2.0
    r = certified(box_on_ground(L, t, H, 0.6, (0.0, 1.0, 0.0)))
    assert r.alpha == pytest.approx(t / H, abs=1e-6)


@pytest.mark.parametrize("method", ["gap", "successive"])
def test_each_method_certifies_on_its_own(method):
    r = certified(box_on_ground(1.0, 0.5, 2.0, 0.6, (0.5, np.sqrt(3) / 2, 0.0)), method=method, explore=False)
    assert r.alpha == pytest.approx(0.288675, abs=1e-6)
    assert r.path.startswith(method)
    assert set(r.methods) == {method}


def test_unknown_method_is_an_input_error():
    from lamodel.errors import InputError
    with pytest.raises(InputError, match="method 'ipopt'"):
        solve3d(box_on_ground(1, 1, 1), method="ipopt")


def test_a_block_that_needs_the_live_load_to_stand_is_unstable():
    s = box_on_ground(1.0, 1.0, 2.0, 0.6, (-1.0, 0.0, 0.0))
    s.dead[0] = [0.8, 0.0, -1.0]   # tips over about x = +a/2 without live load (needs <= 0.5)
    r = solve3d(s)
    assert r.status == "unstable" and r.state is None and np.isnan(r.alpha)
    # the planar search's words: it needs the live load at 0.3 of its value to stand
    assert "unstable under dead load" in r.message and "alpha >= 0.3 " in r.message


def test_a_live_load_pressing_on_the_ground_never_collapses():
    r = solve3d(box_on_ground(1.0, 1.0, 1.0, 0.6, (0.0, 0.0, -1.0)))
    assert r.status == "no_collapse" and r.associative == np.inf


def test_random_blocks_slide_or_overturn_at_the_closed_form():
    # tall and squat blocks, any load direction and mu: sliding with unequal normal forces
    # (the overturning moment loads the front corners) needs the exact sliding directions
    rng = np.random.default_rng(3)
    for _ in range(16):
        a, b, h = rng.uniform(0.3, 2.0, 3)
        mu, phi = rng.uniform(0.2, 0.9), rng.uniform(0, 2 * np.pi)
        c, s = np.cos(phi), np.sin(phi)
        closed = min(mu, a / (h * abs(c)), b / (h * abs(s)))
        r = certified(box_on_ground(a, b, h, mu, (c, s, 0.0)))
        assert r.alpha == pytest.approx(closed, abs=1e-6), (a, b, h, mu, phi)


@pytest.mark.parametrize("phi, mu", [(0, 0.6), (35, 0.6), (70, 0.6), (35, 0.1)])
def test_stack_of_blocks_turns_as_a_whole_or_slides(phi, mu):
    from builders3d import stack_of_boxes
    p = np.radians(phi)
    n, a, b, h = 3, 1.0, 0.8, 0.5
    c, s = np.cos(p), np.sin(p)
    closed = min(mu, a / (n * h * abs(c)), b / (n * h * abs(s)) if s > 0 else np.inf)
    r = certified(stack_of_boxes(n, a, b, h, mu, (c, s, 0.0)))
    assert r.alpha == pytest.approx(closed, abs=1e-6)
