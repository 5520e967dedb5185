"""The joints' strengths in and out: JSON and .dat fields, the command line's what-ifs,
one-line errors naming the field, contacts.csv's limits and modes, the words."""
import json
import re

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


def test_a_study_over_fc_spanning_decades_plots_on_a_log_axis_with_infinity_apart_and_says_why_alpha_is_missing(
        block_file, tmp_path, monkeypatch):
    """The block (N = -6 kN on a 2 m joint) crushes under its own weight at fc = 1 kN/m²
    (unstable); fc from 1 to 1000 kN/m² and "inf" (no crushing): a log axis, ∞ a tick of its
    own, the missing alpha's status in study.csv, the printed table and the legend."""
    from lamodel.output import figures
    from lamodel.parametric import run_study_into, study_from_dict
    drawn = []

    def keep(path, draw, size=(6.4, 4.2)):  # the figure study.png is drawn from, kept open
        fig = figures._pyplot().figure(figsize=size)
        draw(fig)
        drawn.append(fig)
        return str(path)
    monkeypatch.setattr(figures, "save_figure", keep)
    s = structure_from_json(json.loads(block_file.read_text()))
    study = study_from_dict({"name": "blk_fc", "options": {"starts": 0}, "vary": {"fc": [1, 10, 1000, "inf"]}}, s)
    run = run_study_into(study, tmp_path / "out", workers=1)
    table = pd.read_csv(tmp_path / "out" / "study.csv")
    assert np.isinf(table["fc"].iloc[-1]) and table["alpha"].iloc[-1] == pytest.approx(2 / 3)
    missing = table[table["alpha"].isna()]
    assert list(missing["fc"]) == [1] and list(missing["status"]) == ["unstable"]
    assert "unstable" in run.text().splitlines()[1]
    ax = drawn[0].axes[0]
    assert ax.get_xscale() == "log"
    assert "∞" in [t.get_text() for t in ax.get_xticklabels()]
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "no α: unstable under dead load: fc = 1" in legend
    assert any(t.startswith("fc = ∞: α = 0.6667") for t in legend)
    assert "kN/m²" in ax.get_xlabel()
    # within a decade, a linear axis
    study = study_from_dict({"name": "blk_fc", "vary": {"fc": [4, 8]}}, s)
    figures.plot_study(pd.DataFrame({"fc": [4.0, 8.0], "alpha": [0.5, 0.6], "certified": [True, True],
                                     "alpha_associative": [0.5, 0.6], "status": ["certified"] * 2}), study, "x.png")
    assert drawn[1].axes[0].get_xscale() == "linear"
    with pytest.raises(InputError, match='vary.fc: "soft" is not a number; expected a number or "inf"'):
        study_from_dict({"name": "x", "vary": {"fc": [10, "soft"]}}, s, where="spec")


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


# ================================================================================ report
def test_the_report_states_the_joints_strengths_in_the_structures_units(block_file, tmp_path):
    """Among the report's inputs: each strength in kN/m² (the file's kN and m), the joints a
    body's own value reaches named, and the what-if of the command line said as such."""
    path = tmp_path / "pair.json"
    path.write_text(json.dumps(spec(fc=20.0, units={"length": "m", "force": "kN"}) | {"blocks": [
        {"id": "a", "vertices": rect(0, 0, 2, 3), "fc": 12.5}, {"id": "b", "vertices": rect(2, 0, 4, 3)},
        {"id": "ground", "support": True, "vertices": rect(-1, -1, 5, 0)}]}))
    report = tmp_path / "report.html"
    assert command("solve", [str(path), "--cohesion", "0.1", "--out", str(tmp_path / "o"), "--report", str(report),
                             "--workers", "1", "--quiet"]) == 0
    inputs = report.read_text().split("<h2>Inputs and units</h2>")[1]
    assert "<td>stress unit</td><td>kN/m²</td>" in inputs
    mu = spec(fc=20.0)["mu"]
    assert f"<td>friction mu</td><td>{mu:.4g}</td>" in inputs    # one friction: one value, not "x to x"
    assert ("<td>compressive strength fc</td><td>12.5 kN/m² on 2 joints: a|b (c1), ground|a (c2); 20 kN/m² on 1 "
            "joint: ground|b (c3)</td>") in inputs
    assert "<td>cohesion c0</td><td>0.1 kN/m² on every joint (3)</td>" in inputs
    assert "<td>tensile strength ft</td><td>0 kN/m² on every joint (3): no tension</td>" in inputs
    assert "--cohesion 0.1 (kN/m²) on every joint, replacing the file" in inputs
    # a dry structure: one line, no strengths
    dry = tmp_path / "dry.html"
    assert command("solve", [str(block_file), "--out", str(tmp_path / "d"), "--report", str(dry), "--workers", "1",
                             "--quiet"]) == 0
    inputs = dry.read_text().split("<h2>Inputs and units</h2>")[1]
    assert "<td>joint strengths</td><td>dry joints (eq. 4)" in inputs and "kN/m²" not in inputs


def test_the_view_in_space_states_the_joints_strengths(tmp_path):
    def cuboid(x0, y0, z0, x1, y1, z1):
        return [[x, y, z] for z in (z0, z1) for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]
    path = tmp_path / "box.json"
    path.write_text(json.dumps({"name": "box", "dimension": 3, "mu": 5.0, "fc": 50.0,
                                "units": {"length": "m", "force": "kN"}, "blocks": [
                                    {"id": "ground", "support": True, "vertices": cuboid(-2, -1, -0.5, 2, 1, 0)},
                                    {"id": "B", "vertices": cuboid(-1, -0.5, 0, 1, 0.5, 4)}]}))
    view = tmp_path / "view.html"
    assert command("solve", [str(path), "--cohesion", "0.5", "--out", str(tmp_path / "o"), "--view", str(view),
                             "--no-plot", "--quiet"]) == 0
    text = view.read_text().replace("\\u002f", "/").replace("\\u00b2", "²")
    unwrapped = text.replace("\\u003cbr\\u003e&nbsp;&nbsp;", " ")  # long rows wrap onto indented lines
    assert "compressive strength fc: 50 kN/m² on every interface (1)" in unwrapped
    assert "--cohesion 0.5 (kN/m²) on every interface" in unwrapped
    # the box sits in a column of its own, right of the scene (over it, it hid the axes' labels)
    scene = re.search(r'"scene":\{"domain":\{"x":\[([0-9.]+),([0-9.]+)\]', text)
    box = re.search(r'"annotations":\[\{[^]]*"x":([0-9.]+),"xanchor":"right"', text)
    assert scene and box and float(scene.group(2)) < 0.8 and float(box.group(1)) == 1.0
