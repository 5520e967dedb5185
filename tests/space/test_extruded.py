"""The planar seed structures extruded to 3D: the planar alpha in plane, the overturning
closed form out of plane, and the same alpha however the structure is moved, numbered or
measured."""
import numpy as np
import pytest

from builders3d import box_on_ground, transformed
from lamodel.formulation.extrude import extrude
from lamodel.io import read
from lamodel.search.certify3d import RESIDUAL_TOLERANCE
from lamodel.search.gap import GapSearch
from lamodel.search.search3d import solve3d
from conftest import INSTANCES
from lamodel.search.gap.phases import associative
from lamodel.search.plan import first_certificate

SEED = ["wall33.dat", "wall55.dat", "arch.json", "portal.json", "portal_columns.json"]


def planar_first_certificate(s2):
    eng = GapSearch(s2)
    _, _, x0 = associative(eng)
    first_certificate(eng, x0)
    return eng.record.first[0]


@pytest.mark.parametrize("name", SEED)
def test_in_plane_load_gives_the_planar_first_certificate(name):
    # the same path as the planar engine's first certificate: the main gap ladder from the
    # associative statics, without the continuations and descents
    s2 = read(INSTANCES / name)
    r = solve3d(extrude(s2, depth=1.0), method="gap", explore=False)
    assert r.status == "certified"
    assert max(r.state.residual.values()) <= RESIDUAL_TOLERANCE
    assert r.alpha == pytest.approx(planar_first_certificate(s2), abs=1e-6)
    if name == "wall33.dat":
        assert r.alpha == pytest.approx(0.638982, abs=1e-6)  # the seed's Table 1 (Ferris and Tin-Loi 0.63898)
    # no motion and no force out of the plane: the in-plane mechanism of the planar model
    m = r.motions
    assert np.abs(m[:, [1, 3, 5]]).max() <= 1e-7 * np.abs(m).max()


@pytest.mark.parametrize("name, courses", [("wall33.dat", 6), ("wall55.dat", 10)])
def test_out_of_plane_wall_overturns_as_a_whole_or_lower(name, courses):
    # the first certificate is the wall overturning as a whole (t / H); the search may then
    # certify a lower state (the extruded wall33: 0.074062, one base block left behind while
    # its neighbours slide past it on head joints that carry no compression)
    depth = 0.8
    s = extrude(read(INSTANCES / name), depth=depth)
    s.live = np.column_stack([np.zeros(s.n_blocks), -s.dead[:, 2], np.zeros(s.n_blocks)])
    r = solve3d(s)
    assert r.status == "certified"
    assert max(r.state.residual.values()) <= RESIDUAL_TOLERANCE
    assert r.first_alpha == pytest.approx(depth / (1.75 * courses), abs=1e-6)
    assert r.alpha <= depth / (1.75 * courses) + 1e-9


@pytest.mark.slow
def test_extruded_wall55_explored_reaches_below_its_first_certificate():
    # the continuation ladders certify 0.557520 (the planar search's best is 0.557416)
    r = solve3d(extrude(read(INSTANCES / "wall55.dat"), depth=1.0))
    assert r.status == "certified"
    assert 0.557416 - 1e-6 <= r.alpha < 0.558310 - 1e-4


def _rotation(rng):
    q, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    return q * np.sign(np.linalg.det(q))


@pytest.mark.parametrize("make", ["box", "portal"])
def test_alpha_is_invariant(make):
    rng = np.random.default_rng(7)
    if make == "box":
        s = box_on_ground(1.0, 0.5, 2.0, 0.6, (0.5, np.sqrt(3) / 2, 0.0))
    else:
        s = extrude(read(INSTANCES / "portal.json"), depth=1.0)
    base = solve3d(s).alpha
    mirror = np.diag([1.0, -1.0, 1.0])
    variants = {
        "rotated": transformed(s, R=_rotation(rng), shift=(3.0, -2.0, 7.0)),
        "mirrored": transformed(s, R=mirror @ _rotation(rng)),
        "renumbered": transformed(s, block_order=rng.permutation(s.n_blocks), point_order=rng.permutation(s.n_points)),
        "units": transformed(s, length=1000.0, force=9.81),
    }
    for what, v in variants.items():
        r = solve3d(v)
        assert r.status == "certified", what
        assert max(r.state.residual.values()) <= RESIDUAL_TOLERANCE, what
        assert r.alpha == pytest.approx(base, abs=1e-6), what
