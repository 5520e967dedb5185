"""The circular tower generator: its courses, its staggered joints and its input checks."""
import math

import numpy as np
import pytest

from lamodel.errors import InputError
from lamodel.geometry import tower
from lamodel.io.json3d import structure3d_from_spec


def test_a_tower_has_its_courses_and_voussoirs_and_weighs_its_volume():
    spec = tower(courses=4, per_course=8, radius=2.0, thickness=0.4, course_height=0.5)
    s = structure3d_from_spec(spec)
    assert s.n_blocks == 4 * 8
    # a voussoir is the prism on the chords of its sector: (R_o^2 - R_i^2) sin(2 pi / n) / 2 x h
    area = (2.4 ** 2 - 2.0 ** 2) * math.sin(2 * math.pi / 8) / 2
    assert np.allclose(s.volume, area * 0.5, rtol=1e-9)
    # the dead load is the weight, down (unit weight 1)
    assert np.allclose(np.asarray(s.dead)[:, 2], -area * 0.5, rtol=1e-9)


def test_staggered_courses_share_no_head_joint():
    spec = tower(courses=2, per_course=6)
    angles = []
    for b in spec["blocks"][:12]:
        v = np.array(b["vertices"])
        angles.append(sorted({round(math.atan2(y, x) % (2 * math.pi), 9) for x, y, _ in v}))
    first = {a for ang in angles[:6] for a in ang}
    second = {a for ang in angles[6:] for a in ang}
    assert not first & second  # turned by half a voussoir
    plain = tower(courses=2, per_course=6, stagger=False)
    assert plain["blocks"][0]["vertices"][0][:2] == plain["blocks"][6]["vertices"][0][:2]


@pytest.mark.parametrize("bad", [dict(courses=0), dict(radius=-1.0), dict(per_course=2), dict(course_height=0.0)])
def test_bad_towers_are_refused_in_one_line(bad):
    with pytest.raises(InputError) as e:
        tower(**bad)
    assert "\n" not in str(e.value)
