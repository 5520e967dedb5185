"""`lamodel solve` on 3D inputs: the result folder (summary, blocks, contacts per point, runs,
picture, view), checked by the independent oracle; --method all; input options; hostile
inputs and planar-only options refused in one line, exit 2."""
import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "tests" / "geometry3d"))
from oracle3d import check_folder, live_load_gap, uncertified, violations  # noqa: E402
from test_contacts3d import cube, stack_spec  # noqa: E402


def run_cli(*args, cwd=None, timeout=300):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "lamodel.cli", *map(str, args)], capture_output=True, text=True,
                          env=env, cwd=cwd, timeout=timeout)


def block_spec(a=1.0, b=0.5, h=2.0, mu=0.6, live=(0.0, 1.0, 0.0)):
    """A block a x b x h on a ground slab (closed form: alpha = min(mu, a/(h|cos|), b/(h|sin|)))."""
    return {"name": "block", "mu": mu, "live_load": list(live),
            "blocks": [{"id": "ground", "support": True, "vertices": cube(-2, -2, -0.5, 4, 4, 0.5)},
                       {"id": "B", "vertices": cube(-a / 2, -b / 2, 0, a, b, h)}]}


def write(tmp_path, name, spec):
    path = tmp_path / name
    path.write_text(json.dumps(spec))
    return path


def one_line_error(out):
    assert out.returncode == 2, (out.returncode, out.stderr[-2000:])
    assert "Traceback" not in out.stderr
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("lamodel solve: error: "), out.stderr
    return lines[0]


def test_cubes_solve_writes_the_3d_result_folder(tmp_path):
    out = run_cli("solve", write(tmp_path, "cubes.json", stack_spec()), "--out", tmp_path / "r")
    assert out.returncode == 0, out.stderr
    r = tmp_path / "r"
    assert sorted(p.name for p in r.iterdir()) == ["blocks.csv", "contacts.csv", "mechanism.png", "runs.csv",
                                                   "summary.csv"]
    summary = pd.read_csv(r / "summary.csv")
    assert len(summary) == 1 and bool(summary.certified[0]) and summary.status[0] == "certified"
    # each 1 x 1 column of two cubes tips about its toe: alpha = width / height = 0.5
    assert summary.alpha[0] == pytest.approx(0.5, abs=1e-9)
    assert summary.residual[0] < 1e-7 and summary.path[0].endswith(("certify-lp", "certify-cone"))
    assert (summary.n_blocks[0], summary.n_interfaces[0], summary.n_contacts[0]) == (8, 16, 64)
    contacts = pd.read_csv(r / "contacts.csv")
    assert len(contacts) == 64 and set(contacts["mode"]) <= {"stuck", "opening", "sliding"}
    assert list(contacts.columns[:3]) == ["interface", "block_a", "block_b"]
    assert {"ux", "uy", "uz", "rx", "ry", "rz"} <= set(pd.read_csv(r / "blocks.csv").columns)
    runs = pd.read_csv(r / "runs.csv")
    assert list(runs["method"]) == ["lamodel"] and runs["path"].notna().all()
    assert violations(r) == []
    assert "alpha = 0.500000" in out.stdout and "macro-block" in out.stdout and "Opening interfaces" in out.stdout
    assert "results written to" in out.stdout


def test_block_with_a_closed_form_and_its_view(tmp_path):
    view = tmp_path / "r" / "view.html"
    out = run_cli("solve", write(tmp_path, "block.json", block_spec()), "--out", tmp_path / "r", "--view", view,
                  "--quiet")
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines() == [out.stdout.strip()]          # --quiet: one line
    summary = pd.read_csv(tmp_path / "r" / "summary.csv")
    assert summary.alpha[0] == pytest.approx(0.25, abs=1e-9)                # b / h
    assert summary.view[0] == "view.html"
    assert check_folder(tmp_path / "r")["virtual_work"] < 1e-9
    assert summary.live_load[0] == "0 1 0" and live_load_gap(tmp_path / "r") < 1e-15   # the file's, applied
    text = view.read_text()
    assert "Plotly.newPlot" in text and len(text) > 1_000_000               # plotly.js inside the file
    assert not re.search(r"<(script|link|img|iframe)[^>]+(src|href)\s*=\s*[\"']?(https?:)?//", text)
    # a second run replaces the folder as a whole and knows the view as its own file
    again = run_cli("solve", tmp_path / "block.json", "--out", tmp_path / "r", "--quiet", "--no-plot")
    assert again.returncode == 0, again.stderr
    assert sorted(p.name for p in (tmp_path / "r").iterdir()) == ["blocks.csv", "contacts.csv", "runs.csv",
                                                                  "summary.csv"]
    # the oracle sees a live_load that the blocks do not carry, and one that is no vector
    summary = pd.read_csv(tmp_path / "r" / "summary.csv", keep_default_na=False)
    for told, seen in (("1 0 0", None), ("0 1", "live_load '0 1' is not three numbers")):
        summary.loc[0, "live_load"] = told
        summary.to_csv(tmp_path / "r" / "summary.csv", index=False)
        if seen is None:
            assert live_load_gap(tmp_path / "r") == pytest.approx(1.0)
        else:
            assert seen in violations(tmp_path / "r")


def test_method_all_puts_the_methods_side_by_side(tmp_path):
    import lamodel
    a = lamodel.analyse(write(tmp_path, "cubes.json", stack_spec()), lamodel.SolveOptions(), tmp_path / "r",
                        method="all", picture=False)
    methods = pd.read_csv(tmp_path / "r" / "methods.csv")
    assert list(methods["method"]) == ["associative", "successive-lp", "lamodel"]     # as --method names them
    assert methods.alpha_raw[0] >= a.alpha - 1e-9                           # the associative bound
    certified = methods[methods.certified]
    assert len(certified) >= 2 and a.alpha == pytest.approx(certified.alpha_certified.min(), abs=1e-12)
    assert pd.read_csv(tmp_path / "r" / "summary.csv").method[0] in set(certified["method"])
    assert list(pd.read_csv(tmp_path / "r" / "runs.csv")["method"]) == list(methods["method"])
    assert "Methods on 'stack'" in a.text() and violations(tmp_path / "r") == []
    # the one-line result: the whole comparison's time, not the kept method's alone
    assert a.line().endswith(f"in {methods.seconds.sum():.1f} s for 3 methods")


def test_a_mesh_takes_the_input_options_and_records_the_defaults(tmp_path):
    import trimesh

    import lamodel
    meshes = [trimesh.convex.convex_hull(np.asarray(b["vertices"])) for b in block_spec()["blocks"]]
    path = tmp_path / "block.glb"
    trimesh.Scene(meshes).export(path)
    a = lamodel.analyse(path, lamodel.SolveOptions(), tmp_path / "r", picture=False,
                        inputs={"supports_below": -0.25, "mu": 0.6, "live_load": (0.0, 1.0, 0.0)})
    summary = pd.read_csv(tmp_path / "r" / "summary.csv")
    assert a.alpha == pytest.approx(0.25, abs=1e-9)
    assert summary.defaults_applied[0] == "unit_weight" and summary.unit_weight[0] == 1.0
    assert summary.live_load[0] == "0 1 0" and summary.mu[0] == 0.6
    assert "defaults applied" in a.text()


@pytest.mark.parametrize("case", ["overlap", "duplicate", "free", "no-support", "non-planar"])
def test_hostile_3d_inputs_give_one_line_errors_in_solve(tmp_path, case):
    spec = stack_spec()
    words = {"overlap": "overlap", "duplicate": "declared twice", "free": "touches nothing",
             "no-support": "no block is a support", "non-planar": "not planar"}[case]
    if case == "overlap":
        spec["blocks"][3]["vertices"] = cube(0.5, 0, 0)
    elif case == "duplicate":
        spec["blocks"].append({"id": "b000", "vertices": cube(5, 5, 0)})
    elif case == "free":
        spec["blocks"].append({"id": "far", "vertices": cube(9, 9, 9)})
    elif case == "no-support":
        spec["blocks"][0]["support"] = False
    else:
        faces = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
        v = cube(0, 0, 0, 1, 1, 1)
        v[7] = [1, 1, 1.3]
        spec["blocks"][1] = {"id": "b000", "vertices": v, "faces": faces}
    out = run_cli("solve", write(tmp_path, "bad.json", spec), "--out", tmp_path / "r")
    assert words in one_line_error(out)
    assert not (tmp_path / "r").exists()


def test_an_open_mesh_is_refused_by_solve(tmp_path):
    import trimesh
    ground = trimesh.creation.box(extents=[4, 4, 1]).apply_translation([0, 0, -0.5])
    box = trimesh.creation.box(extents=[1, 1, 1]).apply_translation([0, 0, 0.5])
    box = trimesh.Trimesh(box.vertices, box.faces[:-1], process=False)
    trimesh.Scene([ground, box]).export(tmp_path / "open.glb")
    out = run_cli("solve", tmp_path / "open.glb", "--supports-below", "-0.5", "--out", tmp_path / "r")
    assert "open" in one_line_error(out)


@pytest.mark.parametrize("args, words", [
    (("--method", "seed"), "--method seed"),
    (("--rolling", "1,0"), "--rolling"),
    (("--report", "r.html"), "--report"),
    (("--starts", "2"), "--starts"),
    (("--mu", "0.3"), "--mu: applies to COMPAS assemblies and meshes only"),   # the 3D JSON gives its own mu
])
def test_options_a_3d_solve_cannot_honour_are_refused(tmp_path, capsys, args, words):
    from lamodel.cli import main
    status = main(["solve", str(write(tmp_path, "cubes.json", stack_spec())), "--out", str(tmp_path / "r"), *args])
    err = capsys.readouterr().err.strip()
    assert status == 2 and len(err.splitlines()) == 1 and words in err, err


@pytest.mark.parametrize("args, words", [(("--view", "v.html"), "--view"), (("--live-load", "1", "0", "0"),
                                                                            "--live-load")])
def test_3d_options_with_a_planar_input_are_refused(tmp_path, capsys, args, words):
    from lamodel.cli import main
    status = main(["solve", str(ROOT / "instances" / "wall33.dat"), "--out", str(tmp_path / "r"), *args])
    err = capsys.readouterr().err.strip()
    assert status == 2 and len(err.splitlines()) == 1 and words in err, err


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_stop_signal_writes_the_best_certified_3d_state(tmp_path, sig):
    from cases3d import case_specs
    path = write(tmp_path, "building.json", case_specs()["building_mu0.9"])   # certified at 0.6 s, ends at 10 s
    out = tmp_path / "o"
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    p = subprocess.Popen([sys.executable, "-m", "lamodel.cli", "solve", str(path), "--out", str(out), "--no-plot"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                         preexec_fn=lambda: [signal.signal(s, signal.SIG_DFL) for s in (signal.SIGINT, signal.SIGTERM)])
    t = time.monotonic()
    while not any(f.name.startswith(".o.lamodel-new-") for f in tmp_path.iterdir()):
        assert p.poll() is None and time.monotonic() - t < 120, "the solve never started"
        time.sleep(0.05)
    time.sleep(4.0)
    p.send_signal(sig)
    stdout, stderr = p.communicate(timeout=120)
    assert "Traceback" not in stderr, stderr[-2000:]
    if p.returncode == 0:
        pytest.skip("the solve ended before the signal (a fast machine)")
    assert p.returncode == 128 + sig, (p.returncode, stderr[-2000:])
    assert not [f for f in tmp_path.iterdir() if f.name.startswith(".")], "staging folders left behind"
    summary = pd.read_csv(out / "summary.csv")
    assert summary.status[0] == "interrupted"
    if summary.certified[0]:
        assert violations(out) == [] and f"alpha = {summary.alpha[0]:.6f}" in stdout


def test_the_time_limit_and_the_seed_are_honoured_and_recorded(tmp_path):
    import lamodel
    spec = write(tmp_path, "cubes.json", stack_spec())
    a = lamodel.analyse(spec, lamodel.SolveOptions(time_limit=1e-3, seed=7), tmp_path / "r", picture=False)
    summary = pd.read_csv(tmp_path / "r" / "summary.csv")
    assert not a.certified and summary.status[0] == "not_certified"      # stopped before any certificate
    assert summary.time_limit[0] == 1e-3 and summary.seed[0] == 7 and np.isnan(summary.alpha[0])
    assert uncertified(tmp_path / "r") == [] and violations(tmp_path / "r") == []   # NaN, never zeros
    assert "no certified collapse multiplier" in a.line()
    b = lamodel.analyse(spec, lamodel.SolveOptions(seed=7), tmp_path / "r", picture=False)
    assert b.certified and pd.read_csv(tmp_path / "r" / "summary.csv").seed[0] == 7


def test_the_words_name_a_sliding_block_and_a_turning_one(tmp_path):
    import lamodel
    squat = lamodel.analyse(write(tmp_path, "squat.json", block_spec(2.0, 2.0, 0.2, live=(1.0, 0.0, 0.0))),
                            lamodel.SolveOptions(), tmp_path / "squat", picture=False)
    assert squat.alpha == pytest.approx(0.6, abs=1e-9)                      # slides at alpha = mu
    assert "(1 block: B) translates along +x" in squat.text()
    assert "Sliding interfaces (1): ground|B" in squat.text() and "Opening" not in squat.text()
    tall = lamodel.analyse(write(tmp_path, "tall.json", block_spec()), lamodel.SolveOptions(), tmp_path / "tall",
                           picture=False)
    assert "(1 block: B) turns about the axis -x through (0, 0.25, 0)" in tall.text()   # about its toe
    assert "Opening interfaces (1): ground|B" in tall.text()


def test_the_ga_options_reach_the_search_in_space(tmp_path):
    # --pop-size, --generations and --workers drive the same GA as in the plane
    import lamodel
    options = lamodel.SolveOptions(pop_size=4, generations=2, ga_workers=2)
    a = lamodel.analyse(write(tmp_path, "cubes.json", stack_spec()), options, tmp_path / "r", picture=False)
    assert a.certified and a.alpha == pytest.approx(0.5, abs=1e-9)
    runs = pd.read_csv(tmp_path / "r" / "runs.csv")
    summary = pd.read_csv(tmp_path / "r" / "summary.csv")
    assert list(runs["method"]) == ["lamodel"] and runs["path"][0] == summary.path[0] == "gap+certify-lp"
    assert summary.lps[0] >= 1                           # the certification LP that certified it is counted
    with pytest.raises(lamodel.InputError, match="--starts"):
        lamodel.analyse(write(tmp_path, "cubes2.json", stack_spec()), lamodel.SolveOptions(starts=2),
                        tmp_path / "r2", picture=False)


def test_live_point_loads_alone_are_the_live_load_and_summary_says_so(tmp_path):
    """A file with a live point load and no live_load: alpha multiplies the point load
    alone, and summary.csv's live_load is empty, not the default 1 0 0 it did not apply."""
    spec = block_spec()
    del spec["live_load"]
    spec["loads"] = [{"block": "B", "at": [0.0, 0.0, 2.0], "force": [0.0, 1.0, 0.0]}]
    out = run_cli("solve", write(tmp_path, "pushed.json", spec), "--out", tmp_path / "r", "--no-plot")
    assert out.returncode == 0, out.stderr
    r = tmp_path / "r"
    summary = pd.read_csv(r / "summary.csv", keep_default_na=False)
    assert summary.live_load[0] == "" and np.isnan(live_load_gap(r))
    # a unit push at the top of a 1 x 0.5 x 2 block of weight 1 tips it about its edge: 0.25 / 2
    assert float(summary.alpha[0]) == pytest.approx(0.125, abs=1e-9) and violations(r) == []
    blocks = pd.read_csv(r / "blocks.csv")
    assert (blocks.live_x[0], blocks.live_y[0], blocks.live_z[0]) == (0.0, 1.0, 0.0)
    runs = pd.read_csv(r / "runs.csv")
    assert runs.path[0] == summary.path[0] and runs.method[0] == summary.method[0] == "lamodel"
    assert "-0," not in (r / "blocks.csv").read_text() + (r / "contacts.csv").read_text()


def test_method_all_gives_each_method_an_equal_share_of_the_time_left(tmp_path, monkeypatch):
    """Under --time-limit every method of --method all is given a share (in the plane too):
    before, each was given the whole limit, so three methods could take three times it."""
    import lamodel
    import lamodel.search.search3d as search3d
    given, solve3d = [], search3d.solve3d

    def recording(*args, time_limit=None, **kw):
        given.append((time_limit, None if kw.get("options") is None else kw["options"].time_limit))
        return solve3d(*args, time_limit=time_limit, **kw)
    monkeypatch.setattr(search3d, "solve3d", recording)
    lamodel.analyse(write(tmp_path, "cubes.json", stack_spec()), lamodel.SolveOptions(time_limit=60.0),
                    tmp_path / "r", method="all", picture=False)
    limits = [limit for limit, _ in given]
    assert len(limits) == 3 and 19.0 < limits[0] <= 20.0        # a third of the limit, then of what is left
    assert limits[0] <= limits[1] <= 30.0 and limits[1] <= limits[2] <= 60.0  # a half, then all that is left
    assert given[2][1] == limits[2]                               # the search's own options say the same


def test_a_published_method_in_space_ends_at_the_searchs_work_bound(monkeypatch):
    """Successive cone programming ran 896 s on a tower: a method alone may spend the default
    search's counted work bound, no more; what it certified stands, and it says why it ended."""
    from lamodel.io.json3d import structure3d_from_spec
    from lamodel.search.gap.problem3d import ConeProblem
    from lamodel.search.search3d import solve3d
    s = structure3d_from_spec(stack_spec())
    full = solve3d(s, method="successive", explore=False)
    assert full.status == "certified" and "work bound" not in full.message
    monkeypatch.setattr(ConeProblem, "work_bound", lambda self: 1.0)  # spent by the associative program
    bounded = solve3d(s, method="successive", explore=False)
    assert bounded.status == "not_certified" and bounded.state is None
    assert "within its work bound" in bounded.message and bounded.n_cone < full.n_cone
