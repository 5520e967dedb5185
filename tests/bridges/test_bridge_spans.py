"""Bridges of several spans on piers: a symmetric bridge loaded at mirrored points gives the
same adequacy factor, a slender pier on the ground rocks and lowers it against a rigid one,
the fill and backing run on over the piers, bad spans and piers are one line naming the
field; the mortar between rings resists ring separation and nothing else."""
import json
import subprocess
import sys

import numpy as np
import pytest

from oracle import check_state

from conftest import ROOT

from lamodel.bridges import bridge_spec, read_bridge
from lamodel.bridges.adequacy import structure_of
from lamodel.bridges.deck import deck_bed
from lamodel.errors import InputError
from lamodel.loads import case_structure
from lamodel.output.modes import modes_from_flow
from lamodel.search.driver import SolveOptions, solve

LP_ONLY = SolveOptions(starts=0, progress=False)
TWO = {"name": "two", "units": {"length": "m", "force": "kN"},
       "spans": [{"span": 6.0, "rise": 1.5}, {"span": 6.0, "rise": 1.5}],
       "piers": [{"height": 3.0, "width": 1.0, "kind": "block"}],
       "ring": {"thickness": 0.3, "voussoirs": 12, "unit_weight": 20.0, "mu": 0.6},
       "abutments": {"height": 1.0, "width": 1.0}, "backing": {"height": 0.6},
       "fill": {"depth": 0.4, "unit_weight": 18.0, "phi": 35.0, "passive": 0.33},
       "load": {"force": 50.0, "patch": 0.2, "positions": [-2.0, 2.0]}}


def spec(base=TWO, **changes):
    out = json.loads(json.dumps(base))
    out.update(changes)
    return out


def outcome(b, x):
    o = solve(case_structure(structure_of(b), f"x={x:.6g}"), LP_ONLY)
    assert o.certified, o.message
    check_state(o.structure, o.best)        # statics, mechanism and work rebuilt independently
    return o


def alpha(b, x):
    return outcome(b, x).best.alpha


def test_a_symmetric_two_span_bridge_loaded_at_mirrored_points_gives_the_same_alpha():
    b = read_bridge(spec())
    assert alpha(b, -2.0) == pytest.approx(alpha(b, 2.0), rel=1e-6)


def test_a_slender_pier_rocks_and_lowers_alpha_against_a_rigid_one():
    rigid = read_bridge(spec(piers=[{"height": 3.0, "width": 1.0}]))
    slender = read_bridge(spec(piers=[{"height": 6.0, "width": 0.7, "kind": "block"}]))
    stout = alpha(rigid, -2.0)
    o = outcome(slender, -2.0)
    assert o.best.alpha < 0.9 * stout
    s = o.structure
    pier = s.blocks.index("pier1")
    u = np.asarray(o.best.u).reshape(-1, 3)[pier]   # the pier moves in the mechanism: both spans with it
    assert np.abs(u).max() > 1e-6 * np.abs(np.asarray(o.best.u)).max()


def test_a_three_span_bridge_loaded_in_span_one_or_mirrored_in_span_three_gives_the_same_alpha():
    three = spec(spans=[{"span": 5.0, "rise": 1.5}, {"span": 7.0, "rise": 2.2}, {"span": 5.0, "rise": 1.5}],
                 piers=[{"height": 3.0, "width": 1.0, "kind": "block"}] * 2)
    left_quarter = -(5.0 + 7.0 + 5.0 + 2.0) / 2 + 5.0 / 4
    three["load"]["positions"] = [left_quarter, -left_quarter]
    b = read_bridge(three)
    assert alpha(b, left_quarter) == pytest.approx(alpha(b, -left_quarter), rel=1e-6)


def test_an_unsymmetric_bridge_mirrored_gives_the_same_alpha_at_the_mirrored_point():
    b = read_bridge(spec(spans=[{"span": 5.0, "rise": 1.5}, {"span": 7.0, "rise": 2.0}],
                         piers=[{"height": 3.0, "width": 1.0}], backing={"height": 0.0},
                         load={"force": 50.0, "patch": 0.2, "positions": [-2.5]}))
    assert alpha(b, -2.5) == pytest.approx(alpha(b.mirrored(), 2.5), rel=1e-6)


def test_the_fill_runs_on_over_the_piers_and_the_road_is_level():
    b = read_bridge(spec(spans=[{"span": 5.0, "rise": 1.2}, {"span": 7.0, "rise": 2.0}]))
    bed = deck_bed(b)
    for (_, _, q), (_, p, _) in zip(bed, bed[1:]):   # one bed, no gap, from abutment to abutment
        assert np.allclose(q, p)
    assert "backing_pier1" in [block for block, _, _ in bed]
    assert b.road == pytest.approx(2.0 + 0.3 + 0.4)
    built = bridge_spec(b)
    weight = -sum(load["force"][1] for load in built["loads"] if load["kind"] == "dead")
    length = bed[-1][2][0] - bed[0][1][0]
    under = sum((q[0] - p[0]) * (p[1] + q[1]) / 2 for _, p, q in bed)
    assert weight == pytest.approx(18.0 * 1.0 * (b.road * length - under), rel=1e-9)


def test_a_span_of_its_own_ring_is_built_with_it_and_carries_more_when_thicker():
    """The second span's ring 0.45 thick of 16 voussoirs (the first's: the bridge's 0.3, 12):
    its voussoirs are that thick and that many, the road stays level over the thicker
    crown, and an axle on that span finds a higher collapse load than on the same bridge
    with one ring for both."""
    own = {"thickness": 0.45, "voussoirs": 16}
    b = read_bridge(spec(spans=[{"span": 6.0, "rise": 1.5}, {"span": 6.0, "rise": 1.5, "ring": own}]))
    blocks = {k["id"]: np.array(k["vertices"]) for k in bridge_spec(b)["blocks"]}
    first = [v for k, v in blocks.items() if k.startswith("s1v")]
    second = [v for k, v in blocks.items() if k.startswith("s2v")]
    assert len(first) == 12 and len(second) == 16
    # a voussoir's radial joints are as long as its ring is thick
    for v, t in ((first[3], 0.3), (second[5], 0.45)):
        sides = np.hypot(*(np.roll(v, -1, axis=0) - v).T)
        assert np.sum(np.isclose(sides, t, rtol=1e-9)) == 2, sides
    assert b.road == pytest.approx(1.5 + 0.45 + 0.4)
    assert b.part(0).fill_depth == pytest.approx(0.4 + 0.15) and b.part(1).fill_depth == pytest.approx(0.4)
    assert "ring thickness 0.45" in bridge_spec(b)["description"]
    uniform = read_bridge(spec())
    assert alpha(b, 2.0) > alpha(uniform, 2.0)


def test_a_spans_ring_warns_of_what_it_cannot_change():
    with pytest.warns(UserWarning, match="mu"):
        read_bridge(spec(spans=[{"span": 6.0, "rise": 1.5}, {"span": 6.0, "rise": 1.5, "ring": {"mu": 0.3}}]))


@pytest.mark.parametrize("changes, field", [
    ({"spans": [{"span": 6.0, "rise": 1.5}, {"span": 6.0, "rise": 1.5, "ring": {"thickness": -0.3}}]}, "'thickness'"),
    ({"spans": [{"span": 6.0, "rise": 1.5}, {"span": 6.0, "rise": 1.5, "ring": {"voussoirs": 2.5}}]}, "'voussoirs'"),
    ({"spans": [{"span": 6.0, "rise": 1.5, "ring": {"rings": 2}}], "piers": []}, "'ring'"),

    ({"piers": [{"height": 3.0, "width": -1.0}]}, "'width'"),
    ({"piers": [{"height": 3.0, "width": 0.2}]}, "'width'"),     # no room for the springing joints
    ({"piers": []}, "'piers'"),
    ({"piers": [{"height": 3.0, "width": 1.0}] * 2}, "'piers'"),
    ({"piers": [{"height": 3.0, "width": 1.0, "kind": "wood"}]}, "'kind'"),
    ({"span": 6.0}, "'span'"),
    ({"spans": [{"span": 6.0, "rise": 4.0}, {"span": 6.0, "rise": 1.5}]}, "'rise'"),
    # spans whose springing joints make the pier's top concave (a block is convex)
    ({"spans": [{"span": 6.0, "rise": 1.5}, {"span": 6.0, "rise": 1.5, "shape": "elliptical"}]},
     r"piers\[0\]: the springing joints of spans\[0\] \(segmental, ring 0.3\) and spans\[1\] \(elliptical"),
    ({"spans": [{"span": 6.0, "rise": 1.5}, {"span": 6.0, "rise": 1.5, "ring": {"thickness": 0.7}}]},
     "make the pier's top concave"),
])
def test_bad_spans_and_piers_are_one_line_naming_the_field(changes, field):
    with pytest.raises(InputError, match=field) as err:
        bridge_spec(read_bridge(spec(**changes)))
    assert "\n" not in str(err.value)


def test_the_command_line_refuses_a_negative_pier_width_in_one_line(tmp_path):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(spec(piers=[{"height": 3.0, "width": -1.0}])))
    run = subprocess.run([sys.executable, "-m", "lamodel.cli", "bridge", str(path)], capture_output=True, text=True,
                         cwd=ROOT)
    assert run.returncode == 2
    assert run.stderr.strip().count("\n") == 0 and f"{path}: piers[0]" in run.stderr and "'width'" in run.stderr


RINGS = {"name": "rings", "span": 6.0, "rise": 1.5,
         "ring": {"thickness": 0.3, "rings": 2, "voussoirs": 12, "unit_weight": 20.0, "mu": 0.6},
         "fill": {"depth": 0.4, "unit_weight": 18.0, "phi": 35.0, "passive": 0.0, "lateral": "none"},
         "load": {"force": 50.0, "patch": 0.2, "positions": [-1.5]}}


def ring_interfaces_moving(o) -> int:
    """How many joints between the two rings open or slide in the mechanism."""
    s, modes = o.structure, modes_from_flow(o.structure, o.best.xi)
    return sum(s.block_a[k].startswith("r1") and s.block_b[k].startswith("r2") and modes[k] != "closed"
               for k in range(s.n_contacts))


def test_mortar_between_the_rings_raises_alpha_where_they_separate():
    dry = outcome(read_bridge(RINGS), -1.5)
    assert ring_interfaces_moving(dry) > 0
    bonded = outcome(read_bridge(spec(RINGS, ring={**RINGS["ring"], "cohesion": 50.0, "ft": 20.0})), -1.5)
    assert bonded.best.alpha > 1.2 * dry.best.alpha


def test_mortar_between_the_rings_leaves_alpha_unchanged_where_they_do_not_separate():
    rough = spec(RINGS, ring={**RINGS["ring"], "mu": 10.0})   # the rings neither slide nor open
    dry = outcome(read_bridge(rough), -1.5)
    assert ring_interfaces_moving(dry) == 0
    bonded = outcome(read_bridge(spec(rough, ring={**rough["ring"], "cohesion": 50.0, "ft": 20.0})), -1.5)
    assert bonded.best.alpha == pytest.approx(dry.best.alpha, rel=1e-6)


def test_the_picture_of_several_spans_draws_every_pier(tmp_path):
    from lamodel.bridges.picture import plot_bridge
    path = plot_bridge(read_bridge(spec()), tmp_path / "two.png")
    assert (tmp_path / "two.png").stat().st_size > 10_000 and path.endswith("two.png")
