"""Studies of structures in space: mu, fc and the load's heading (about the vertical) vary
as in the plane, the table counts interfaces by what they do, and what varies planar
structures only is refused in one line."""
import numpy as np
import pytest

from builders3d import box_on_ground
from lamodel.errors import InputError
from lamodel.parametric import run_study, study_from_dict


def table(structure, **spec):
    study = study_from_dict({"options": {"starts": 0}, **spec}, structure, where="study")
    return run_study(study, workers=1, progress=False)


def test_the_load_heading_turns_about_the_vertical():
    # a block 1 x 0.5 x 2 (mu 0.6): it rocks about its long edge (a / h) under a load
    # along x, about its short edge (b / h) under one along y
    df = table(box_on_ground(1.0, 0.5, 2.0, 0.6, (1.0, 0.0, 0.0)), vary={"load_angle": [0, 90, 180]})
    assert df["alpha"].tolist() == pytest.approx([0.5, 0.25, 0.5], abs=1e-7)
    assert df["n_hinging"].tolist() == [1, 1, 1] and df["n_sliding"].tolist() == [0, 0, 0]


def test_crushing_strength_and_friction_vary_in_space():
    # the box 2 x 1 x 4 (weight 1) on its four corners: alpha = (2 min(W, P_c) - W) a / (W h)
    # with P_c = f_c a b / 2 (tests/materials/test_joints3d.py); a squat box slides at mu
    df = table(box_on_ground(2.0, 1.0, 4.0, 5.0), vary={"fc": [10.0, 0.8]})
    assert df["alpha"].tolist() == pytest.approx([0.5, 0.3], abs=1e-7)
    df = table(box_on_ground(2.0, 2.0, 0.2, 0.6), vary={"mu": [0.3, 0.6]})
    assert df["alpha"].tolist() == pytest.approx([0.3, 0.6], abs=1e-7)
    assert df["n_sliding"].tolist() == [1, 1] and df["n_hinging"].tolist() == [0, 0]


def test_friction_at_random_per_point():
    df = table(box_on_ground(2.0, 2.0, 0.2, 0.6), random={"count": 2, "seed": 1, "mu": {"sd": 0.05}})
    assert df["certified"].all()
    assert np.all(df["alpha"] <= df["mu_mean"] + 0.15) and len(set(df["alpha"].round(9))) == 2


@pytest.mark.parametrize("spec, words", [
    ({"vary": {"dead_force": {"block": "B", "fx": [0.0, 1.0]}}}, "dead_force varies planar structures only"),
    ({"random": {"count": 2, "size": {"sd": 0.02}}}, "random.size varies planar structures only"),
])
def test_what_varies_planar_structures_only_is_refused(spec, words):
    with pytest.raises(InputError, match=words) as e:
        study_from_dict(spec, box_on_ground(1.0, 1.0, 1.0), where="study")
    assert "\n" not in str(e.value)
