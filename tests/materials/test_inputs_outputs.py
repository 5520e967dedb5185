"""The joints' strengths in and out: JSON and .dat fields, the command line's what-ifs,
one-line errors naming the field, contacts.csv's limits and modes, the words."""
import json

import numpy as np
import pandas as pd
import pytest

from conftest import INSTANCES, rect
from oracle import check_folder
from lamodel.cli import command
from lamodel.errors import InputError
from lamodel.io.datfile import read_dat, write_dat
from lamodel.io.jsonspec import structure_from_json, structure_to_json
from lamodel.output.modes import classify


def spec(**top):
    """Two 2 x 3 blocks side by side on the ground (contacts: ground|a, ground|b, a|b)."""
    return {"name": "pair", "mu": 5.0, **top, "blocks": [
        {"id": "a", "vertices": rect(0, 0, 2, 3)}, {"id": "b", "vertices": rect(2, 0, 4, 3)},
        {"id": "ground", "support": True, "vertices": rect(-1, -1, 5, 0)}]}


def contact(s, x, y):
    return next(k for k in range(s.n_contacts) if {s.block_a[k], s.block_b[k]} == {x, y})


# ================================================================================ JSON
def test_json_strengths_top_body_and_joint():
    d = spec(fc=50.0, cohesion=0.2)
    d["blocks"][1]["fc"] = 30.0                      # b's contacts take the smaller fc
    d["joints"] = [{"between": ["a", "b"], "ft": 0.5, "thickness": 0.8}]
    s = structure_from_json(d)
    ga, gb, ab = contact(s, "ground", "a"), contact(s, "ground", "b"), contact(s, "a", "b")
    assert s.fc[ga] == 50 and s.fc[gb] == 30 and s.fc[ab] == 30
    assert np.all(s.cohesion == 0.2) and s.ft[ab] == 0.5 and s.ft[ga] == 0 and s.thickness[ab] == 0.8
    back = structure_from_json(structure_to_json(s))
    for name in ("fc", "ft", "cohesion", "thickness"):
        assert np.array_equal(getattr(back, name), getattr(s, name)), name


def test_json_without_strengths_is_dry():
    s = structure_from_json(spec())
    assert not s.has_materials and np.all(np.isinf(s.fc)) and "fc" not in structure_to_json(s)


@pytest.mark.parametrize("change, field", [
    ({"fc": -1.0}, "'fc'"), ({"fc": "strong"}, "'fc'"), ({"fc": 0}, "'fc'"), ({"cohesion": -0.1}, "'cohesion'"),
    ({"ft": True}, "'ft'"), ({"fc": 1.0, "ft": 2.0}, "ft"), ({"thickness": 0}, "'thickness'"),
    ({"joints": [{"between": ["a", "ground2"], "fc": 1}]}, "joints[0]"), ({"joints": {"a": 1}}, "'joints'")])
def test_json_bad_strengths_name_the_field(change, field):
    with pytest.raises(InputError) as err:
        structure_from_json(spec(**change))
    message = str(err.value)
    assert field in message and "\n" not in message and "expected" in message


# ================================================================================= .dat
def test_dat_round_trip_and_errors(tmp_path):
    d = spec(fc=40.0)
    d["joints"] = [{"between": ["a", "b"], "cohesion": 0.3, "ft": 0.1}]
    s = structure_from_json(d)
    back = read_dat(write_dat(s, tmp_path / "pair.dat"))
    for name in ("fc", "ft", "cohesion", "thickness"):
        assert np.array_equal(getattr(back, name), getattr(s, name)), name
    dry = read_dat(INSTANCES / "arch.dat")
    write_dat(dry, tmp_path / "dry.dat")
    assert not dry.has_materials and "fc" not in (tmp_path / "dry.dat").read_text()  # as it was
    ab = s.contacts[contact(s, "a", "b")]
    text = (tmp_path / "pair.dat").read_text()
    line = f"param: cohesion :=\n  {ab} 0.3\n"
    assert line in text
    (tmp_path / "bad.dat").write_text(text.replace(line, line.replace("0.3", "-0.3")))
    with pytest.raises(InputError, match=f"cohesion of contact '{ab}' is -0.3; expected a finite cohesion >= 0"):
        read_dat(tmp_path / "bad.dat")
    (tmp_path / "bad.dat").write_text(text.replace(line, line.replace("0.3", "soft")))
    with pytest.raises(InputError, match=f"parameter cohesion of contact '{ab}' is 'soft'; expected a number"):
        read_dat(tmp_path / "bad.dat")


# ========================================================================= command line
@pytest.fixture
def block_file(tmp_path):
    path = tmp_path / "blk.json"
    path.write_text(json.dumps({"name": "blk", "mu": 5.0, "units": {"length": "m", "force": "kN"}, "blocks": [
        {"id": "a", "vertices": rect(0, 0, 2, 3)},
        {"id": "ground", "support": True, "vertices": rect(-1, -1, 3, 0)}]}))
    return path


def test_cli_fc_what_if(block_file, tmp_path, capsys):
    out = tmp_path / "out"
    assert command("solve", [str(block_file), "--fc", "10", "--out", str(out), "--no-plot", "--workers", "1",
                             "--quiet"]) == 0
    contacts = pd.read_csv(out / "contacts.csv")
    assert contacts.loc[0, "fc"] == 10 and contacts.loc[0, "ft"] == 0 and contacts.loc[0, "mode"] == "crushing"
    # the stress block under N = -6 kN, f_c = 10 kPa, b = 1 m is 0.6 m deep (at the toe, the right end)
    assert check_folder(out) == pytest.approx((1 - 6 / 20) / 1.5, rel=0.01)
    command("solve", [str(block_file), "--fc", "10", "--out", str(out), "--no-plot", "--workers", "1"])
    assert "the joint crushes over its last 0.6 m at the right end" in capsys.readouterr().out


def test_the_picture_marks_the_crushed_joint(block_file):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from lamodel.output.extras import picture_of
    from lamodel.output.plot import plot_mechanism
    from lamodel.output.report import outcome_results
    from lamodel.search.driver import SolveOptions, solve
    s = structure_from_json(json.loads(block_file.read_text()) | {"fc": 10.0})
    outcome = solve(s, SolveOptions(workers=1))
    fig, ax = plt.subplots()
    plot_mechanism(s, path=None, ax=ax, **picture_of(outcome, outcome_results(outcome), None))
    # the block turns about the toe of its crushed base, drawn on the ground (not displaced)
    diamonds = [line for line in ax.lines if line.get_marker() == "D"]
    assert len(diamonds) == 1 and diamonds[0].get_xydata()[0, 1] == pytest.approx(0.0, abs=1e-9)
    assert not [line for line in ax.lines if line.get_marker() == "o"]
    assert "crushing (joint at its crushing cap)" in [t.get_text() for t in ax.get_legend().get_texts()]
    plt.close(fig)


def test_cli_cohesion_what_if_slides(block_file, tmp_path):
    out = tmp_path / "out"
    path = block_file.with_name("slide.json")
    path.write_text(block_file.read_text().replace('"mu": 5.0', '"mu": 0.3'))
    assert command("solve", [str(path), "--cohesion", "0.1", "--out", str(out), "--no-plot", "--workers", "1",
                             "--quiet"]) == 0
    assert check_folder(out) == pytest.approx(0.3 + 0.1 * 2 / 6, rel=1e-9)
    assert pd.read_csv(out / "contacts.csv").loc[0, "mode"] == "sliding"


@pytest.mark.parametrize("argv, words", [(["--fc", "-1"], "--fc"), (["--cohesion", "x"], "--cohesion"),
                                         (["--fc", "1", "--ft", "2"], "--ft is 2, above --fc 1")])
def test_cli_bad_strengths_one_line(block_file, tmp_path, capsys, argv, words):
    assert command("solve", [str(block_file), *argv, "--out", str(tmp_path / "o"), "--no-plot"]) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and len(err.splitlines()) == 1
    assert not (tmp_path / "o").exists()


def test_other_methods_refuse_strengths(block_file, tmp_path, capsys):
    assert command("solve", [str(block_file), "--fc", "10", "--method", "associative", "--out",
                             str(tmp_path / "o"), "--no-plot"]) == 2
    assert "lamodel" in capsys.readouterr().err


# ================================================================================ modes
def test_modes_of_a_crushed_joint():
    """An end that closes (overlap) crushes, with or without slip; dry mechanisms never do."""
    d = np.ones(4)
    modes = classify(d, opening=[0.5, 0.5, 2.0, -0.1], slip=[0, 1, 0, 0], rotation=[1, 1, 1, 0])
    assert modes == ["crushing", "crushing+sliding", "open", "crushing"]
    assert classify(d[:1], [1.0], [0.0], [1.0]) == ["hinging"]


# ================================================================================ study
def test_study_varies_the_compressive_strength():
    from lamodel.parametric import study_from_dict, variant_structure
    s = read_dat(INSTANCES / "arch.dat")
    study = study_from_dict({"name": "arch_fc", "vary": {"fc": [40, 20]}}, s, where="spec")
    params = study.variants()
    assert [p["fc"] for p in params] == [40, 20]
    variant, _ = variant_structure(study, params[1], np.random.default_rng(0))
    assert np.all(variant.fc == 20) and not s.has_materials
    with pytest.raises(InputError, match="vary.fc has -1; expected compressive strengths > 0"):
        study_from_dict({"name": "x", "vary": {"fc": [10, -1]}}, s, where="spec")


def test_a_joint_takes_the_weaker_of_its_bodies_with_the_files_values_as_theirs():
    """A body without its own strength has the file's: a stronger neighbour does not lend
    it its strength (b1's file values 10, 0.05, 0.1 against b2's own 50, 0.4, 1)."""
    d = spec(fc=10.0, ft=0.05, cohesion=0.1)
    d["blocks"][1].update(fc=50.0, ft=0.4, cohesion=1.0)
    s = structure_from_json(d)
    ab, gb = contact(s, "a", "b"), contact(s, "ground", "b")
    assert (s.fc[ab], s.ft[ab], s.cohesion[ab]) == (10.0, 0.05, 0.1)
    assert (s.fc[gb], s.ft[gb], s.cohesion[gb]) == (10.0, 0.05, 0.1)   # the ground has the file's too
    d = spec()
    d["blocks"][0]["cohesion"] = 0.3   # mortar on a's joints only where both sides have it
    s = structure_from_json(d)
    assert s.cohesion[contact(s, "a", "b")] == 0.0


def test_a_joint_given_twice_is_refused_and_one_without_strengths_is_said():
    with pytest.raises(InputError, match=r"joints\[1\]: the joint between 'b' and 'a' again \(joints\[0\]\)"):
        structure_from_json(spec(joints=[{"between": ["a", "b"], "fc": 10}, {"between": ["b", "a"], "fc": 1}]))
    with pytest.warns(UserWarning, match=r"joints\[0\]: no strength given"):
        structure_from_json(spec(joints=[{"between": ["a", "b"]}]))


def test_a_dat_table_that_gives_a_contact_twice_on_one_line_is_refused(tmp_path):
    path = tmp_path / "p.dat"
    path.write_text((INSTANCES / "portal.dat").read_text() + "param: fc := c1 20 c1 5 ;\n")
    with pytest.raises(InputError, match="'c1' is given twice in the table of fc"):
        read_dat(path)


def test_ipopt_starts_and_the_lower_bound_asked_for_with_strengths_are_said_not_dropped(block_file, tmp_path,
                                                                                      capsys):
    """The Pyomo model of eq. 5 and the proven lower bound know dry joints only: with
    strengths each asked start has its runs.csv row saying why it did not run, and --prove
    is a warning (alpha_lower empty), not silence."""
    out = tmp_path / "out"
    assert command("solve", [str(block_file), "--fc", "10", "--starts", "2", "--prove", "5", "--out", str(out),
                             "--no-plot", "--workers", "1", "--quiet"]) == 0
    runs = pd.read_csv(out / "runs.csv")
    assert len(runs) == 3 and runs["status"].iloc[1:].str.startswith("skipped: no Ipopt polish for joints").all()
    assert "--prove: the proven lower bound knows dry joints only" in capsys.readouterr().err
