"""A small circular tower under a horizontal load: certified by the default run, and the
same multiplier whichever of its symmetric headings the load takes."""
import math

import pytest

from lamodel.geometry import tower
from lamodel.io.json3d import structure3d_from_spec
from lamodel.search.certify3d import RESIDUAL_TOLERANCE
from lamodel.search.search3d import solve3d


def _solved(heading_deg=0.0):
    turn = math.radians(heading_deg)
    spec = tower(courses=4, per_course=8, live_load=(math.cos(turn), math.sin(turn), 0.0))
    r = solve3d(structure3d_from_spec(spec))
    assert r.status == "certified", r.message
    assert max(r.state.residual.values()) <= RESIDUAL_TOLERANCE      # rechecked in the user's units
    assert 0 < r.alpha <= r.associative + 1e-9
    return r


@pytest.mark.slow
def test_a_tower_of_four_courses_is_certified_and_its_symmetric_headings_agree():
    # 8 voussoirs a course, alternate courses turned by half a voussoir: turned by 45
    # degrees the tower is itself, so the load along +x and along 45 degrees is one problem
    along, turned = _solved(0.0), _solved(45.0)
    # the ring is far from overturning as a whole (2.4 / 0.8 = 3) or sliding (mu = 0.7):
    # the collapse cracks it
    assert along.alpha < 0.7
    assert turned.alpha == pytest.approx(along.alpha, rel=1e-6)
