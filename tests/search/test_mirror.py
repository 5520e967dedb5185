"""Mirror symmetry: the reflection of an assembly onto itself is found (and only where it
exists), the image of a collapse state is a collapse state of the mirrored load (checked
by the independent oracle), and a study gives mirror images the same alpha."""
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from conftest import INSTANCES
from oracle import check_state

from lamodel.io import read
from lamodel.mirror import image_on, mirror_loads, mirror_of, mirror_state
from lamodel.search.driver import SolveOptions, solve

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bridges"))

LP_ONLY = SolveOptions(starts=0, progress=False)


def reflected_live(s):
    """The structure with its live loads reflected about the vertical (a mirror load case
    when the structure is symmetric about a vertical line through its centre)."""
    return replace(s, live=s.live * np.array([-1.0, 1.0]), live_m=-s.live_m)


def with_strengths(s, fc):
    return replace(s, fc=np.full(s.n_contacts, fc))


@pytest.mark.parametrize("name", ["arch.dat", "portal.dat", "wall33.dat"])
def test_the_seeds_symmetric_structures_have_a_mirror(name):
    s = read(INSTANCES / name)
    m = mirror_of(s)
    assert m is not None
    assert sorted(m.blocks) == list(range(s.n_blocks)) and sorted(m.contacts) == list(range(s.n_contacts))
    assert np.allclose(s.centroid[m.blocks, 0], 2 * m.x0 - s.centroid[:, 0])
    assert mirror_loads(s, reflected_live(s), m)
    assert not mirror_loads(s, s, m)           # a push along +x is not its own image


def test_an_asymmetric_structure_has_no_mirror():
    s = read(INSTANCES / "wall33.dat")
    dead = s.dead.copy()
    dead[0, 1] *= 1.01                          # one block a little heavier
    assert mirror_of(replace(s, dead=dead)) is None
    mu = s.mu.copy()
    mu[0] = 0.5                                  # one joint of another friction
    assert mirror_of(replace(s, mu=mu)) is None
    centroid = s.centroid.copy()
    centroid[3, 0] += 0.1 * float(s.d.max())     # one block moved
    assert mirror_of(replace(s, centroid=centroid)) is None


@pytest.mark.parametrize("name, fc", [("arch.dat", np.inf), ("wall33.dat", np.inf), ("wall33.dat", 4.0),
                                      ("portal.dat", 30.0)])
def test_the_image_of_a_collapse_state_is_one_of_the_mirrored_load(name, fc):
    s = with_strengths(read(INSTANCES / name), fc)
    o = solve(s, LP_ONLY)
    assert o.certified, o.message
    m = mirror_of(s)
    other = reflected_live(s)
    image = mirror_state(o.best, m)
    assert image.alpha == o.best.alpha
    check_state(other, image)                    # statics, mechanism and work rebuilt independently
    checked = image_on(other, o.best, m)
    assert checked is not None                  # the residuals of the state it reflects, up to round-off
    assert max(checked.residual.values()) <= 1.01 * max(o.best.residual.values()) + 1e-12
    assert image_on(s, o.best, m) is None        # not a collapse state of the load it reflects
    again = solve(other, LP_ONLY, mechanisms=[image])
    assert again.certified and again.best.alpha <= o.best.alpha * (1 + 1e-9)


@pytest.mark.slow
def test_mirror_positions_of_a_rolled_axle_get_the_same_adequacy_factor():
    """The three-span bridge, an axle 2.7 m from either end: each position's own search
    certifies a different state (1.849148 and 1.874129 when measured); the study gives
    the higher the image of the lower."""
    from test_bridge_mechanics import THREE_SPANS
    from lamodel.bridges import read_bridge
    from lamodel.bridges.adequacy import structure_of
    from lamodel.studies import load_case_study
    spec = {**THREE_SPANS, "load": {**THREE_SPANS["load"], "positions": [-12.2143, 12.2143]}}
    df, outcomes = load_case_study(structure_of(read_bridge(spec), True), LP_ONLY)
    assert df["certified"].all()
    assert df["alpha_c"].iloc[1] == pytest.approx(df["alpha_c"].iloc[0], rel=1e-6)
    for o in outcomes.values():
        check_state(o.structure, o.best)
    assert [o.best.source.startswith("mirror") for o in outcomes.values()].count(True) == 1


def test_the_study_gives_a_case_its_mirror_images_state():
    """The mirror pass alone: a case left uncertified (its outcome withdrawn here) takes
    the reflected state of its image, re-checked; the image's own row is unchanged."""
    from lamodel.output.rows import outcome_row
    from lamodel.search.state import CERTIFIED, NOT_CERTIFIED
    from lamodel.studies import _from_the_mirror
    s = read(INSTANCES / "wall33.dat")
    variants = [s, reflected_live(s)]
    labels = ["+x", "-x"]
    outcomes = {label: solve(v, LP_ONLY) for label, v in zip(labels, variants)}
    outcomes["-x"] = replace(outcomes["-x"], best=None, status=NOT_CERTIFIED)
    rows = [{"case": label, **outcome_row(outcomes[label])} for label in labels]
    _from_the_mirror("case", labels, variants, LP_ONLY, None, rows, outcomes)
    mirrored = outcomes["-x"]
    assert mirrored.status == CERTIFIED and rows[1]["certified"]
    assert mirrored.best.alpha == outcomes["+x"].best.alpha == rows[1]["alpha_c"]
    assert mirrored.runs[-1].path == "mirror" and mirrored.best.source.startswith("mirror")
    check_state(variants[1], mirrored.best)
    assert rows[0]["alpha_c"] == outcomes["+x"].best.alpha


def test_no_mirror_pass_where_the_loads_are_not_reflections():
    from lamodel.output.rows import outcome_row
    from lamodel.search.state import NOT_CERTIFIED
    from lamodel.studies import _from_the_mirror
    s = read(INSTANCES / "wall33.dat")
    up = replace(s, live=np.column_stack([s.live[:, 1], -s.live[:, 0]]), live_m=np.zeros(s.n_blocks))  # turned 90°
    variants, labels = [s, up], ["+x", "up"]
    outcomes = {"+x": solve(s, LP_ONLY), "up": replace(solve(s, LP_ONLY), best=None, status=NOT_CERTIFIED)}
    rows = [{"case": label, **outcome_row(outcomes[label])} for label in labels]
    _from_the_mirror("case", labels, variants, LP_ONLY, None, rows, outcomes)
    assert outcomes["up"].best is None and not rows[1]["certified"]
