"""Issue 14, what an engineer expects: point loads where they act, load cases, a rolling
load, units, the mechanism in words, pictures (loads, thrust line), a report, a GIF, the
blocks that move under dead load."""
import json
import os
import subprocess
import sys
from html.parser import HTMLParser

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402

from conftest import INSTANCES, ROOT, rect  # noqa: E402
from oracle import check_folder, check_state  # noqa: E402

from lamodel.io.datfile import read_dat, write_dat  # noqa: E402
from lamodel.io.jsonspec import structure_from_json  # noqa: E402
from lamodel.search.driver import SolveOptions, solve  # noqa: E402

LP_ONLY = SolveOptions(starts=0, progress=False)


def lamodel(*args, timeout=300):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "lamodel.cli", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, cwd=ROOT, env=env)


def block_spec(b, h, loads, mu=5.0, **extra):
    return {"name": "block", "mu": mu, "blocks": [
        {"id": "ground", "vertices": rect(-5, -1, 5, 0), "support": True},
        {"id": "b1", "vertices": rect(0, 0, b, h)}], "loads": loads, **extra}


# ------------------------------------------------------------------ point loads
@pytest.mark.parametrize("b, h, P, x", [(1.0, 2.0, 3.0, 0.3), (2.0, 1.0, 0.5, 0.0), (0.5, 3.0, 2.0, 0.5)])
def test_point_load_at_the_top_overturns_at_the_closed_form(b, h, P, x, tmp_path):
    """A b x h block (weight W = b h) with a horizontal live point load P on its top edge
    overturns about its toe at alpha = W b / (2 h P) (friction ample)."""
    s = structure_from_json(block_spec(b, h, [{"block": "b1", "at": [x, h], "force": [P, 0.0]}]))
    assert s.live_m[0] == pytest.approx(-P * h / 2)    # (at - centroid) ^ f
    out = solve(s, LP_ONLY)
    W = b * h
    assert out.best.alpha == pytest.approx(W * b / (2 * h * P), rel=1e-9)
    check_state(s, out.best)
    # the same through a .dat file with the optional moment table, and in the Pyomo model
    dat = tmp_path / "block.dat"
    write_dat(s, dat)
    again = read_dat(dat)
    assert np.array_equal(again.live_m, s.live_m) and np.array_equal(again.dead_m, s.dead_m)
    assert solve(again, LP_ONLY).best.alpha == pytest.approx(out.best.alpha, rel=1e-12)
    from lamodel.formulation.model import create_abstract_model
    inst = create_abstract_model().create_instance(str(dat))
    assert inst._formulation.fbar[2] == pytest.approx(-P * h / 2)


def test_dat_files_without_moments_stay_valid():
    s = read_dat(INSTANCES / "wall33.dat")
    assert not s.dead_m.any() and not s.live_m.any()
    assert "dead_m" not in (INSTANCES / "wall33.dat").read_text()


def test_a_dead_point_load_off_the_centroid_adds_its_moment():
    """A dead point load on the heel of the block shifts its resultant: the overturning
    multiplier about the toe grows by exactly the load's lever arm."""
    b, h, P, D = 1.0, 2.0, 1.0, 0.5
    loads = [{"block": "b1", "at": [0.0, h], "force": [P, 0.0]},
             {"block": "b1", "at": [0.0, h], "force": [0.0, -D], "kind": "dead"}]
    s = structure_from_json(block_spec(b, h, loads))
    assert s.dead_m[0] == pytest.approx(D * b / 2)
    # about the toe (b, 0): P h alpha = W b / 2 + D b
    assert solve(s, LP_ONLY).best.alpha == pytest.approx((b * h * b / 2 + D * b) / (P * h), rel=1e-9)


def test_a_point_load_on_a_rounded_coordinate_is_on_its_block_and_one_clearly_off_is_not():
    """A coordinate rounded to four digits (0.02 % of the block's size above its top) is on
    the block, as in space; 2 % above it is refused (LOAD_POINT_SLACK, 0.1 %)."""
    from lamodel.errors import InputError
    s = structure_from_json(block_spec(1.0, 1.0, [{"block": "b1", "at": [0.5, 1.0003], "force": [1, 0]}]))
    assert s.point_loads[0].at == (0.5, 1.0003)
    with pytest.raises(InputError, match="is not on block 'b1'"):
        structure_from_json(block_spec(1.0, 1.0, [{"block": "b1", "at": [0.5, 1.03], "force": [1, 0]}]))


@pytest.mark.parametrize("load, message", [
    ({"block": "b1", "at": [3.0, 0.5], "force": [1, 0]}, "is not on block 'b1'"),
    ({"block": "ground", "at": [0.5, 0.5], "force": [1, 0]}, "not a movable block"),
    ({"block": "b1", "at": [0.5, 0.5], "force": [1, 0], "kind": "wind"}, "expected \"live\" or \"dead\""),
    ({"block": "b1", "at": [0.5, 0.5], "force": [0, -1], "kind": "dead", "case": "x"}, "without a case"),
    ({"block": "b1", "force": [1, 0]}, "has no 'at'"),
])
@pytest.mark.slow
def test_bad_point_loads_are_one_line_exit_2(load, message, tmp_path):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(block_spec(1.0, 1.0, [load])))
    r = lamodel("solve", path, "--starts", "0", "--out", tmp_path / "out")
    assert r.returncode == 2 and message in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "out").exists()


# ------------------------------------------------------------------ load cases, units, report
def two_block_cases():
    return {"name": "stack", "mu": 0.6, "units": {"length": "m", "force": "kN"},
            "blocks": [{"id": "ground", "vertices": rect(-2, -1, 3, 0), "support": True},
                       {"id": "b1", "vertices": rect(0, 0, 1, 1)}, {"id": "b2", "vertices": rect(0, 1, 1, 2)}],
            "loads": [{"block": "b2", "at": [0, 2], "force": [1, 0], "case": "wind_top"},
                      {"block": "b1", "at": [0, 0.5], "force": [1, 0], "case": "wind_low"},
                      {"block": "b2", "at": [0.5, 2], "force": [0, -0.5], "kind": "dead"}]}


class _Collect(HTMLParser):
    def __init__(self):
        super().__init__()
        self.tags, self.text = [], []

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)

    def handle_data(self, data):
        self.text.append(data)


@pytest.mark.slow
def test_load_cases_give_one_alpha_each_and_the_governing_one(tmp_path):
    path = tmp_path / "cases.json"
    path.write_text(json.dumps(two_block_cases()))
    s = structure_from_json(path)
    assert list(s.cases) == ["wind_top", "wind_low"]
    out = tmp_path / "out"
    r = lamodel("solve", path, "--starts", "0", "--out", out, "--report", tmp_path / "r.html", "--no-plot")
    assert r.returncode == 0, r.stderr
    cases = pd.read_csv(out / "cases.csv")
    assert list(cases["case"]) == ["wind_top", "wind_low"]
    # wind_top overturns the stack about the toe (1, 0): 2 P alpha = 0.5 + 0.5 + 0.5 * 0.5
    # wind_low pushes b1 out: it slides at mu (W + D) = 0.6 * 2.5 (overturning would need 2.5)
    assert cases["alpha_c"].tolist() == pytest.approx([1.25 / 2, 1.5], rel=1e-9)
    assert cases["governing"].tolist() == [True, False]
    summary = pd.read_csv(out / "summary.csv")
    assert summary["case"][0] == "wind_top" and summary["alpha"][0] == pytest.approx(0.625)
    assert (summary["length_unit"][0], summary["force_unit"][0]) == ("m", "kN")
    # the reported state's largest residual and which condition it is
    assert 0.0 <= summary["residual"][0] <= 1e-7
    assert summary["residual_condition"][0] in ("equilibrium", "yield", "compatibility", "normalisation",
                                                "nonnegative_flow", "complementarity", "virtual_work",
                                                "block_equilibrium", "contact_yield", "contact_complementarity")
    assert check_folder(out) == pytest.approx(0.625)   # with the moments of blocks.csv
    assert "wind_low" in r.stdout and "hinge at the right end of joint ground|b1" in r.stdout
    last = r.stdout.strip().splitlines()[-1]  # the governing case, and the whole study's time
    assert last.startswith("stack: alpha = 0.625000 (certified collapse state;"), last
    assert "case 'wind_top' governs) in " in last and last.endswith(" s for 2 cases")

    # the report: one file, parsable, with the picture as SVG and the tables
    text = (tmp_path / "r.html").read_text()
    parser = _Collect()
    parser.feed(text)
    assert parser.tags.count("svg") == 2 and parser.tags.count("table") >= 4
    words = " ".join(parser.text)
    for needed in ("wind_top", "wind_low", "hinge at the right end", "kN", "Inputs and units", "lamodel 0."):
        assert needed in words, needed
    assert "http" not in text.split("<svg", 1)[0]  # nothing fetched from elsewhere


@pytest.mark.slow
def test_report_and_animation_need_their_suffix(tmp_path):
    r = lamodel("solve", INSTANCES / "wall33.dat", "--starts", "0", "--report", tmp_path / "r.txt")
    assert r.returncode == 2 and "expected a file name ending in .html" in r.stderr


# ------------------------------------------------------------------ rolling load
@pytest.mark.slow
def test_rolling_load_worst_position_equals_a_separate_solve(tmp_path):
    from lamodel.loads import RollingLoad, rolling_structure, top_positions
    from lamodel.studies import governing, rolling_study
    spec = json.loads((INSTANCES / "arch.json").read_text())
    del spec["live_load"]
    spec["rolling_load"] = {"force": [0.0, -1.0]}
    s = structure_from_json(spec)
    assert not s.live.any()  # the rolling load is the live load
    positions = top_positions(s)
    assert len(positions) == 13  # one on each voussoir's extrados
    df, outcomes = rolling_study(s, LP_ONLY)
    worst = governing(df, "position")
    certified = df[df["certified"]]
    assert worst is not None and len(certified) >= 5
    alone = solve(rolling_structure(s, worst), LP_ONLY)
    assert alone.best.alpha == pytest.approx(certified["alpha_c"].min(), rel=1e-9)
    assert alone.best.alpha == pytest.approx(df.loc[df["governing"], "alpha_c"].iloc[0], rel=1e-9)
    # an axle group: two axles carry twice the load of one at the crown region
    two = rolling_structure(s, -0.2, RollingLoad((0.0, -1.0), (0.0, 0.4)))
    assert -two.live[:, 1].sum() == pytest.approx(2.0)


@pytest.mark.slow
def test_rolling_load_from_the_command_line(tmp_path):
    out = tmp_path / "arch"
    r = lamodel("solve", INSTANCES / "arch.json", "--starts", "0", "--rolling=0,-1",
                "--positions=-3,-1.5,0,1.5", "--out", out)  # '=': values starting with '-' are not options
    assert r.returncode == 0, r.stderr
    rolling = pd.read_csv(out / "rolling.csv")
    assert rolling["position"].tolist() == [-3, -1.5, 0, 1.5]
    assert rolling["governing"].sum() == 1 and (out / "rolling.png").stat().st_size > 1000
    summary = pd.read_csv(out / "summary.csv")
    assert summary["alpha"][0] == pytest.approx(rolling["alpha_c"].min(), rel=1e-12)
    assert summary["position"][0] == rolling.loc[rolling["governing"], "position"].iloc[0]
    check_folder(out)


# ------------------------------------------------------------------ words, pictures
def test_words_for_wall33_name_the_hinges_the_picture_marks(wall33):
    from lamodel.output.modes import modes_from_flow
    from lamodel.output.plot import plot_mechanism, pivots
    from lamodel.output.words import describe, joint_marks
    out = solve(wall33, LP_ONLY)
    u, modes = out.best.u.reshape(-1, 3), modes_from_flow(wall33, out.best.xi)
    words = "\n".join(describe(wall33, u, modes, out.best.alpha))
    hinged = [k for k, m in enumerate(modes) if "hinging" in m]
    assert hinged
    piv = pivots(wall33, u)
    for k in hinged:  # every hinge named, with its joint and end
        c = wall33.contacts[k]
        line = next(x for x in words.splitlines() if f"hinge at the" in x and f"({c})" in x)
        assert f"joint {wall33.block_a[k]}|{wall33.block_b[k]}" in line
        assert any(end in line for end in ("left end", "right end", "top", "bottom"))
    marks = [m for m in joint_marks(wall33, u, modes) if m.kind == "hinge"]
    assert sorted(m.contact for m in marks) == sorted(wall33.contacts[k] for k in hinged)
    assert all(np.allclose(m.point, piv[wall33.contacts.index(m.contact)]) for m in marks)
    # the picture: a dot per hinge, and next to each the number the words give it
    fig, ax = plt.subplots()
    plot_mechanism(wall33, u, modes=modes, alpha=out.best.alpha, ax=ax, path=None)
    dots = [line for line in ax.lines if line.get_marker() == "o"][0].get_xydata()
    assert len(dots) == len(hinged)
    labels = {t.get_text() for t in ax.texts}
    for m in marks:
        assert str(m.number) in labels and f"  {m.number}. hinge" in words
    assert "displacements drawn ×" in ax.get_xlabel()
    plt.close(fig)


def test_a_mechanism_with_more_marks_than_the_picture_can_number_draws_them_unnumbered():
    from lamodel.geometry.generators import running_bond_wall
    from lamodel.output.kinematics import contact_modes
    from lamodel.output.plot import plot_mechanism
    from lamodel.output.words import PICTURE_NUMBERS, describe, joint_marks
    rows = [[0.5] + [1] * 5 + [0.5] if k % 2 == 0 else [1] * 6 for k in range(12)]
    s = structure_from_json(running_bond_wall(rows))
    rng = np.random.default_rng(0)
    u = 1e-3 * rng.standard_normal((s.n_blocks, 3))  # every block its own motion
    modes = contact_modes(s, u)
    marks = joint_marks(s, u, modes)
    assert len(marks) > PICTURE_NUMBERS
    fig, ax = plt.subplots()
    plot_mechanism(s, u, modes=modes, ax=ax, path=None)
    assert not ax.texts                                       # no numbers over the drawing
    assert [line for line in ax.lines if line.get_marker() == "o"]  # the hinges still marked
    plt.close(fig)
    words = describe(s, u, modes)
    assert "Joints:" in words and f"  {marks[-1].number}. " in "\n".join(words)  # the words keep every joint


def test_thrust_line_of_a_certified_arch_stays_within_the_ring():
    from lamodel.output.words import ring_centre, thrust_line
    s = structure_from_json(INSTANCES / "arch.json")
    out = solve(s, LP_ONLY)
    check_state(s, out.best)
    centre = ring_centre(s)
    assert np.allclose(centre, [0.0, 0.0], atol=1e-9)  # the arch's centre, from its joints alone
    points, ratio, joints = thrust_line(s, out.best.N, out.best.M)
    assert len(points) >= 10 and (ratio <= 1 + 1e-7).all()
    radius = np.hypot(*(points - centre).T)
    assert (radius >= 5.0 - 1e-7).all() and (radius <= 6.5 + 1e-7).all()  # intrados 5, extrados 6.5
    assert ratio.max() > 0.999  # a collapse state touches the ring where it hinges


def test_arch_words_use_intrados_and_extrados():
    from lamodel.output.modes import modes_from_flow
    from lamodel.output.words import describe
    s = structure_from_json(INSTANCES / "arch.json")
    out = solve(s, LP_ONLY)
    words = "\n".join(describe(s, out.best.u, modes_from_flow(s, out.best.xi), out.best.alpha))
    assert "trados of joint" in words and "macro-block" in words


# ------------------------------------------------------------------ dead-load instability, GIF
@pytest.mark.slow
def test_unstable_under_dead_load_names_the_blocks_that_move(tmp_path):
    spec = {"name": "overhang", "mu": 0.6, "live_load": [1.0, 0.0], "blocks": [
        {"id": "ground", "vertices": rect(-2, -1, 4, 0), "support": True},
        {"id": "b1", "vertices": rect(0, 0, 1, 1)}, {"id": "b2", "vertices": rect(0.8, 1, 1.8, 2)}]}
    path = tmp_path / "overhang.json"
    path.write_text(json.dumps(spec))
    r = lamodel("solve", path, "--starts", "0", "--out", tmp_path / "out", "--animate", tmp_path / "m.gif")
    assert r.returncode == 3, r.stderr
    assert "blocks that move under dead load alone: b2" in r.stdout and "b1," not in r.stdout
    summary = pd.read_csv(tmp_path / "out" / "summary.csv")
    assert "b2" in summary["message"][0]
    from lamodel.search.unstable import dead_load_mechanism
    s = structure_from_json(spec)
    u = dead_load_mechanism(s)
    assert u is not None and np.allclose(u[0], 0) and np.dot(s.dead[1], u[1, :2]) > 0
    assert dead_load_mechanism(structure_from_json(block_spec(1, 1, [], live_load=[1, 0]))) is None
    from PIL import Image
    with Image.open(tmp_path / "m.gif") as gif:
        assert gif.n_frames > 5


def test_picture_draws_point_loads_where_they_act():
    from lamodel.output.plot import plot_mechanism
    s = structure_from_json(block_spec(1.0, 2.0, [{"block": "b1", "at": [0.0, 2.0], "force": [1.0, 0.0]}],
                                       units={"length": "m", "force": "kN"}))
    fig, ax = plt.subplots()
    plot_mechanism(s, np.zeros((1, 3)), ax=ax, path=None)
    from matplotlib.patches import FancyArrowPatch
    from matplotlib.quiver import Quiver
    # the arrows' tips in data units: point loads are patches (matplotlib keeps no public
    # getter for their ends), the loads at the centroids one quiver a kind
    tips = [np.array(a._posA_posB[1]) for a in ax.get_children() if isinstance(a, FancyArrowPatch)]
    tips += [np.array(t) for q in ax.collections if isinstance(q, Quiver)
             for t in zip(q.X + q.U, q.Y + q.V)]
    assert any(np.allclose(t, (0.0, 2.0)) for t in tips)          # the live arrow ends at its point
    assert any(np.allclose(t[0], 0.5) and t[1] < 1.0 for t in tips)  # the weight from the centroid, down
    assert ax.get_xlabel().startswith("x [m]")
    assert any("[kN]" in t.get_text() for t in ax.get_legend().get_texts())
    plt.close(fig)


def test_a_signal_during_one_load_case_ends_the_cases(monkeypatch):
    """A stop signal that ends one case's search (its status ``interrupted``) ends the
    study of the cases: the rest are marked ``not run``, and the analysis says so."""
    import lamodel.solve_all as solve_all
    import lamodel.studies as studies
    real, calls = solve_all.solve, []

    def stopped_first(structure, options):
        outcome = real(structure, options)
        calls.append(structure.name)
        if len(calls) == 1:
            outcome.status = "interrupted"
        return outcome
    monkeypatch.setattr(solve_all, "solve", stopped_first)
    s = structure_from_json(two_block_cases())
    study, outcome, extra = studies.governing_study(s, SolveOptions(starts=0, workers=1))
    assert len(calls) == 1 and study["interrupted"]
    assert study["table"]["status"].tolist() == ["interrupted", "not run"]
    assert extra["case"] == "wind_top"



def test_the_last_line_of_a_stopped_study_says_how_many_were_not_run(monkeypatch, tmp_path):
    import lamodel
    import lamodel.solve_all as solve_all
    real = solve_all.solve

    def stopped_first(structure, options):
        outcome = real(structure, options)
        outcome.status = "interrupted"
        return outcome
    monkeypatch.setattr(solve_all, "solve", stopped_first)
    a = lamodel.analyse(structure_from_json(two_block_cases()), SolveOptions(starts=0, workers=1),
                        out=tmp_path / "r", picture=False)
    assert a.interrupted
    assert a.line().endswith("for 2 cases; stopped: 1 of 2 cases not run"), a.line()
