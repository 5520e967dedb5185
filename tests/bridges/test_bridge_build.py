"""A bridge description read, checked and built into blocks: the fill's forces add up to
what the fill weighs and what the axle carries, the restraints survive a round trip, bad
input is one line naming the field."""
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from conftest import INSTANCES, ROOT

from lamodel.bridges import bridge_spec, read_bridge
from lamodel.bridges.fill import dead_loads, live_loads, restraints, strip_stress
from lamodel.bridges.ring import extrados
from lamodel.errors import InputError
from lamodel.io.jsonspec import structure_from_spec, structure_to_json

BASE = {"name": "b", "span": 6.0, "rise": 1.5, "width": 2.0,
        "ring": {"thickness": 0.3, "voussoirs": 16, "unit_weight": 20.0, "mu": 0.6},
        "fill": {"depth": 0.4, "unit_weight": 18.0, "phi": 35.0, "passive": 0.5}, "backing": {"height": 0.0},
        "load": {"force": 50.0, "patch": 0.2, "positions": [-1.5, 0.0]}}


def bridge(**changes):
    spec = json.loads(json.dumps(BASE))
    for key, value in changes.items():
        if isinstance(value, dict):
            spec.setdefault(key, {}).update(value)
        else:
            spec[key] = value
    return read_bridge(spec)


def test_the_fill_weighs_what_lies_between_the_road_and_the_extrados():
    b = bridge()
    p = extrados(b)
    under = np.trapezoid(p[:, 1], p[:, 0])   # the area under the extrados polyline
    fill_area = b.road * (p[-1, 0] - p[0, 0]) - under
    vertical = sum(f["force"][1] for f in dead_loads(b))
    assert vertical == pytest.approx(-b.fill_weight * b.width * fill_area, rel=1e-12)


def test_the_horizontal_pressures_balance_on_a_symmetric_arch_and_follow_k0():
    b = bridge()
    h = [f["force"][0] for f in dead_loads(b) if f["force"][0]]
    assert sum(h) == pytest.approx(0.0, abs=1e-9)
    # each half: K0 gamma b (road depth) integrated over the height of the extrados
    p = extrados(b)
    top, low = p[:, 1].max(), p[0, 1]
    k0 = 1 - math.sin(math.radians(35.0))
    expected = k0 * 18.0 * 2.0 * ((b.road - low) ** 2 - (b.road - top) ** 2) / 2
    assert sum(x for x in h if x > 0) == pytest.approx(expected, rel=1e-12)


def test_an_axle_within_the_span_puts_its_whole_force_on_the_ring():
    b = bridge()
    for x in (-1.5, 0.0, 0.7):
        loads = live_loads(b, x, "c")
        assert sum(f["force"][1] for f in loads) == pytest.approx(-50.0, rel=1e-12)
        centre = sum(f["at"][0] * f["force"][1] for f in loads) / sum(f["force"][1] for f in loads)
        # under the axle, shifted towards the deeper fill (it spreads wider there)
        assert 0 <= (centre - x) * np.sign(x) < 0.2 if x else abs(centre) < 1e-9
    # a wider spread angle loads more voussoirs
    narrow = live_loads(bridge(fill={"spread": 10.0}), -1.5, "c")
    wide = live_loads(bridge(fill={"spread": 45.0}), -1.5, "c")
    assert len(wide) > len(narrow)


def test_boussinesqs_strip_stress_carries_the_load_and_tends_to_flamants_line_load():
    a = 0.3
    x = np.linspace(-400.0, 400.0, 800001)
    for z in (0.05, 0.5, 2.0):
        s = strip_stress(x, z, a)
        # equilibrium: every depth carries the strip's load (the tails beyond 400 m: < 1e-5)
        assert np.trapezoid(s, x) == pytest.approx(a, rel=1e-4)
        assert s.max() == pytest.approx(strip_stress(0.0, z, a)) and s.max() <= 1.0
    # the peak falls with depth; at the surface the pressure is the strip's
    peaks = [strip_stress(0.0, z, a) for z in (0.1, 0.5, 1.0, 3.0)]
    assert all(p > q for p, q in zip(peaks, peaks[1:]))
    assert strip_stress([0.0, 0.1, 0.2], 0.0, a) == pytest.approx([1.0, 1.0, 0.0])
    # a narrow strip is Flamant's line load P = a: 2 P z^3 / (pi (x^2 + z^2)^2)
    z, xs = 1.0, np.array([0.0, 0.5, 1.5, 4.0])
    flamant = 2 * 1e-3 * z ** 3 / (np.pi * (xs ** 2 + z ** 2) ** 2)
    assert strip_stress(xs, z, 1e-3) == pytest.approx(flamant, rel=1e-5)


def test_boussinesq_dispersal_spreads_the_axle_wider_the_deeper_the_fill():
    def spread(b, x=0.0):
        loads = live_loads(b, x, "c")
        f = np.array([-l["force"][1] for l in loads])
        at = np.array([l["at"][0] for l in loads])
        centre = (f * at).sum() / f.sum()
        return f.sum(), np.sqrt((f * (at - centre) ** 2).sum() / f.sum()), f.max(), centre

    shallow = spread(bridge(fill={"dispersal": "boussinesq", "depth": 0.2}))
    deep = spread(bridge(fill={"dispersal": "boussinesq", "depth": 1.0}))
    for carried, _, _, centre in (shallow, deep):
        assert 0.8 * 50.0 < carried < 50.0   # the tails beyond the springings: the abutments'
        assert abs(centre) < 1e-9                             # symmetric under a central axle
    assert deep[1] > 1.5 * shallow[1] and deep[2] < shallow[2]
    # off-centre, the same axle as the 30 deg spread puts more of it beyond its patch
    b_spread, b_elastic = bridge(), bridge(fill={"dispersal": "boussinesq"})
    assert spread(b_elastic, -1.5)[1] > spread(b_spread, -1.5)[1]
    assert "Boussinesq" in bridge_spec(b_elastic)["description"]


def test_an_axle_at_the_springing_leaves_part_of_its_force_to_the_abutment():
    b = bridge()
    carried = -sum(f["force"][1] for f in live_loads(b, -3.0, "c"))
    assert 0 < carried < 50.0


def test_passive_capacity_is_the_mobilised_share_above_the_lateral_pressure():
    b = bridge()
    kp = (1 + math.sin(math.radians(35))) / (1 - math.sin(math.radians(35)))
    k0 = 1 - math.sin(math.radians(35))
    lateral = sum(abs(f["force"][0]) for f in dead_loads(b))
    passive = sum(r["capacity"] for r in restraints(b))
    assert passive == pytest.approx(lateral * (0.5 * kp - k0) / k0, rel=1e-12)
    assert all(r["direction"][0] == (1.0 if r["at"][0] < 0 else -1.0) for r in restraints(b))


def _area(v):
    x, y = np.asarray(v).T
    return 0.5 * abs(x @ np.roll(y, -1) - y @ np.roll(x, -1))


def test_the_built_structure_carries_every_force_and_restraint():
    b = bridge()
    s = structure_from_spec(bridge_spec(b), "b")
    assert s.restraints == len(restraints(b)) > 0
    assert sorted(s.cases) == ["x=-1.5", "x=0"]
    ring = sum(_area(s.polygons[k]) for k in s.blocks)   # the ring's weight and the fill's
    assert s.dead[:, 1].sum() == pytest.approx(sum(f["force"][1] for f in dead_loads(b)) - 20.0 * 2.0 * ring,
                                               rel=1e-9)
    k = s.n_contacts - s.restraints
    assert np.all(s.mu[k:] == 0) and np.all(np.isfinite(s.fc[k:])) and np.all(np.isinf(s.fc[:k]))
    # capacity = 2 d b fc: the restraint's largest push
    assert (2 * s.d[k:] * s.thickness[k:] * s.fc[k:]).sum() == pytest.approx(
        sum(r["capacity"] for r in restraints(b)), rel=1e-12)
    no = structure_from_spec(bridge_spec(b, passive=False), "b")
    assert no.restraints == 0 and no.n_contacts == k


def test_restraints_survive_writing_the_structure_back():
    b = bridge()
    spec = bridge_spec(b)
    s = structure_from_spec(spec, "b")
    s.live = s.cases["x=0"].live          # a structure with one live pattern writes back
    s.live_m = s.cases["x=0"].live_m
    s.cases = {}
    again = structure_from_spec(structure_to_json(s), "again")
    assert again.restraints == s.restraints
    for name in ("centre", "normal", "d", "mu", "fc", "thickness"):
        assert np.allclose(getattr(again, name), getattr(s, name), rtol=1e-12, atol=1e-12), name


@pytest.mark.parametrize("change, field", [
    ({"span": -1}, "'span'"), ({"rise": 4.0}, "'rise'"), ({"ring": {"voussoirs": 2}}, "'voussoirs'"),
    ({"ring": {"thickness": "thick"}}, "'thickness'"), ({"fill": {"phi": 95}}, "'phi'"),
    ({"fill": {"lateral": "sideways"}}, "'lateral'"), ({"fill": {"spread": 90}}, "'spread'"),
    ({"load": {"positions": []}}, "'positions'"), ({"width": 0}, "'width'"), ({"skew": 95}, "'skew'"),
    ({"abutments": {"kind": "floating"}}, "'kind'"), ({"fill": {"dispersal": "elastic"}}, "'dispersal'")])
def test_bad_values_name_their_field(change, field):
    with pytest.raises(InputError, match=field):
        bridge(**change)


def test_a_bad_restraint_names_its_field():
    spec = bridge_spec(bridge())
    spec["restraints"][0]["capacity"] = -1
    with pytest.raises(InputError, match=r"restraints\[0\].*'capacity'"):
        structure_from_spec(spec, "f")
    spec["restraints"][0].update(capacity=1.0, support="v3")
    with pytest.raises(InputError, match="expected the id of a support"):
        structure_from_spec(spec, "f")


def _cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "lamodel.cli", *args], capture_output=True, text=True, cwd=cwd,
                          env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"}, timeout=300)


def test_the_command_builds_a_structure_and_a_picture_and_refuses_bad_input(tmp_path):
    spec = dict(BASE, extra_field=1)
    (tmp_path / "b.json").write_text(json.dumps(spec))
    run = _cli("bridge", "b.json", "out.json", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert "unknown" in run.stderr and "extra_field" in run.stderr   # a warning, not an error
    assert (tmp_path / "out.png").stat().st_size > 0
    built = json.loads((tmp_path / "out.json").read_text())
    assert built["restraints"] and any(x.get("case") == "x=0" for x in built["loads"])
    (tmp_path / "bad.json").write_text(json.dumps(dict(BASE, rise="high")))
    run = _cli("bridge", "bad.json", cwd=tmp_path)
    assert run.returncode == 2
    assert "'rise'" in run.stderr and len(run.stderr.strip().splitlines()) == 1 and "Traceback" not in run.stderr
    for command in (("solve", "b.json", "--out", "out"), ("build", "b.json")):  # a description is not blocks:
        run = _cli(*command, cwd=tmp_path)                                       # one line, no field warnings
        assert run.returncode == 2 and "a bridge description, not blocks" in run.stderr
        assert len(run.stderr.strip().splitlines()) == 1, run.stderr


def test_skew_is_recorded_not_modelled():
    skewed = bridge_spec(bridge(skew=20.0))
    assert "skew 20 deg (not modelled)" in skewed["description"]
    assert skewed["blocks"] == bridge_spec(bridge())["blocks"]


def test_the_example_builds():
    b = read_bridge(INSTANCES / "bridge_demo.json")
    s = structure_from_spec(bridge_spec(b), "demo")
    assert len(s.cases) == 21 and s.restraints == 24


def test_backing_blocks_carry_the_fill_above_them():
    from lamodel.bridges.backing import backing_blocks, bed
    b = bridge(backing={"height": 1.0})
    blocks = backing_blocks(b)
    assert {"backing_left", "backing_right"} <= {x["id"] for x in blocks}
    s = structure_from_spec(bridge_spec(b), "b")
    ids = set(s.blocks)
    assert all(x["id"] in ids for x in blocks)
    # every backing block touches its voussoir or a neighbour; the ends stand on the abutments
    pairs = set(zip(s.block_a, s.block_b))
    assert ("abutment_left", "backing_left") in pairs and ("abutment_right", "backing_right") in pairs
    # the whole dead load: ring and backing (masonry) and the fill between the road and the bed
    seg = bed(b)
    xs = np.array([p[0] for _, p, _ in seg] + [seg[-1][2][0]])
    ys = np.array([p[1] for _, p, _ in seg] + [seg[-1][2][1]])
    fill_area = b.road * (xs[-1] - xs[0]) - np.trapezoid(ys, xs)
    masonry = sum(_area(s.polygons[k]) for k in s.blocks)
    assert s.dead[:, 1].sum() == pytest.approx(-(20.0 * masonry + 18.0 * fill_area) * 2.0, rel=1e-9)
    # no passive restraint on the chords the backing covers
    assert len(restraints(b)) < len(restraints(bridge()))
    with pytest.raises(InputError, match="backing: 'height'"):
        bridge(backing={"height": 5.0})


def test_a_solved_bridge_is_rebuilt_from_its_tables_by_the_oracle(tmp_path):
    """The fill's forces (blocks.csv) and the passive restraints (contacts.csv, with their
    capacity as fc and thickness) are all an external checker needs."""
    import pandas as pd
    from oracle import check_folder
    spec = json.loads(json.dumps(BASE))
    spec["load"]["positions"] = [-1.5]
    (tmp_path / "b.json").write_text(json.dumps(spec))
    assert _cli("bridge", "b.json", "built.json", cwd=tmp_path).returncode == 0
    run = _cli("solve", "built.json", "--starts", "0", "--out", "out", "--quiet", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    alpha = check_folder(tmp_path / "out")
    contacts = pd.read_csv(tmp_path / "out" / "contacts.csv")
    passive = contacts[contacts["mu"] == 0]
    assert len(passive) == len(restraints(bridge())) and np.isfinite(passive["fc"]).all()
    assert (passive["N"] >= -2 * passive["d"] * passive["thickness"] * passive["fc"] * (1 + 1e-7)).all()
    assert alpha > 0


def test_an_elliptical_arch_as_high_as_half_its_span_is_the_semicircle():
    from lamodel.bridges.ring import voussoirs
    circle = voussoirs(bridge(rise=3.0))
    ellipse = voussoirs(bridge(rise=3.0, shape="elliptical"))
    assert np.allclose([v["vertices"] for v in circle], [v["vertices"] for v in ellipse], atol=1e-12)


def test_a_pointed_arch_has_a_vertical_joint_at_its_apex():
    from lamodel.bridges.ring import intrados
    b = bridge(rise=4.0, shape="pointed")
    points, normal = intrados(b)
    mid = len(points) // 2
    assert np.allclose(points[mid], [0.0, 4.0]) and np.allclose(normal[mid], [0.0, 1.0])
    assert np.allclose(points[:, 0], -points[::-1, 0]) and np.allclose(points[:, 1], points[::-1, 1])
    s = structure_from_spec(bridge_spec(b), "pointed")
    assert len(s.blocks) == 16
    with pytest.raises(InputError, match="even number"):
        bridge(rise=4.0, shape="pointed", ring={"voussoirs": 15})
    with pytest.raises(InputError, match="'rise'.*pointed"):
        bridge(rise=2.0, shape="pointed")
    with pytest.raises(InputError, match="'shape'"):
        bridge(shape="gothic")


def test_the_command_takes_other_positions_and_says_which_load_nothing(tmp_path):
    (tmp_path / "b.json").write_text(json.dumps(BASE))
    run = _cli("bridge", "b.json", "out.json", "--positions=-1,0.5,40", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert "2 load positions" in run.stdout
    assert "position(s) 40 load no block" in run.stderr and len(run.stderr.strip().splitlines()) == 1
    built = json.loads((tmp_path / "out.json").read_text())
    assert sorted({x["case"] for x in built["loads"] if x.get("case")}) == ["x=-1", "x=0.5"]
    run = _cli("bridge", "b.json", "off.json", "--positions", "40,50", "--adequacy", "a", cwd=tmp_path)
    assert run.returncode == 2 and "no lead-axle position loads the bridge" in run.stderr, run.stderr
    assert not (tmp_path / "off.json").exists() and not (tmp_path / "a").exists()


def test_what_ifs_change_the_joints_and_leave_the_restraints_alone():
    """--fc, --ft, --cohesion, a friction study and random friction change the masonry's
    joints; the passive restraints (the last contacts) keep their capacity and no friction."""
    from lamodel.loads import case_structure
    from lamodel.parametric import study_from_dict, variant_structure
    from lamodel.variants import with_friction, with_strengths
    built = structure_from_spec(bridge_spec(bridge()), "b")
    s = case_structure(built, next(iter(built.cases)))
    n, r = s.n_contacts - s.restraints, s.restraints
    assert r > 0
    for t in (with_strengths(s, fc=1e6, ft=5.0, cohesion=2.0), with_friction(s, 0.9)):
        for name in ("mu", "fc", "ft", "cohesion"):
            assert np.array_equal(getattr(t, name)[n:], getattr(s, name)[n:]), name
    t = with_strengths(s, fc=1e6)
    assert np.all(t.fc[:n] == 1e6) and np.all(t.fc[n:] < 1e3)
    assert np.all(with_friction(s, 0.9).mu[:n] == 0.9)
    study = study_from_dict({"random": {"count": 2, "mu": {"sd": 0.2}}}, s)
    t, _ = variant_structure(study, {}, np.random.default_rng(3))
    assert np.all(t.mu[n:] == 0) and not np.allclose(t.mu[:n], s.mu[:n])


@pytest.mark.parametrize("args, change, words", [
    (("b.json", "b.json"), {}, "the bridge description itself"),
    (("b.json", "b.png"), {}, "the picture path"),
    (("b.json", "sub/"), {}, "a folder"),
    (("b.json", "afile/out.json"), {}, "afile: cannot make this folder"),
    (("b.json", "o.json", "--adequacy", "afile"), {}, "afile: cannot make this folder"),
    (("b.json", "o.json", "--positions=1,1.0000001"), {}, "are the same position"),
    (("b.json", "o.json"), {"load": dict(BASE["load"], positions=[0.5, 0.5])}, "are the same position"),
    (("b.json", "o.json"), {"load": dict(BASE["load"], positions=[100.0, -1e300])}, "no lead-axle position loads"),
    (("b.json", "o.json"), {"fill": dict(BASE["fill"], passive=33)}, "'passive' is 33"),
])
def test_the_command_refuses_what_would_lose_a_file_or_give_a_wrong_factor(tmp_path, args, change, words):
    """Before any work, in one line (exit 2), nothing written: an output over the description
    or over its own picture, an output folder that cannot be made, one position given twice
    (it would be two axles in one case), no position on the deck (the file would be solved
    under the default live load), a passive fraction above 1."""
    (tmp_path / "b.json").write_text(json.dumps(dict(BASE, **change)))
    (tmp_path / "afile").write_text("a file")
    before = sorted(p.name for p in tmp_path.iterdir())
    run = _cli("bridge", *args, cwd=tmp_path)
    lines = run.stderr.strip().splitlines()
    assert run.returncode == 2 and words in lines[-1] and "Traceback" not in run.stderr, run.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    assert json.loads((tmp_path / "b.json").read_text())["span"] == BASE["span"]


def test_absurd_sizes_are_built_or_refused_in_a_line_not_run_out_of_memory():
    """A fill a million units deep is built (its spread over the abutments sampled coarser:
    it sampled 5e8 points); a span of 1e200 is one line naming the arch, not an overflow."""
    built = structure_from_spec(bridge_spec(bridge(fill=dict(BASE["fill"], depth=1e6))), "b")
    assert built.cases and np.all(np.isfinite(built.centroid))
    with pytest.raises(InputError, match="overflow its geometry"):
        bridge(span=1e200)
