"""Certificates that hold for every block, whatever the sizes; bad input refused in one line
before any solve: seeds, deep JSON, study names, .dat vertices, oversized compare inputs,
the mode of an animation."""
import json
import os
import stat
import subprocess
import sys

import pandas as pd
import pytest

from conftest import INSTANCES, ROOT, rect
from oracle import check_folder


def lamodel(*args, cwd=ROOT, timeout=600):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "lamodel.cli", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, cwd=cwd, env=env)


def small_on_big(ratio: float) -> dict:
    """A b x 4b block on the middle of a 4Lb x Lb block (L = ``ratio``), on the ground.

    Closed form: the small block overturns about its toe at alpha = b / h = 0.25; the big
    block would need 4, the whole stack more than 1, sliding mu = 0.6."""
    b = ratio ** -0.5  # the two sizes straddle 1
    big_w, big_h = 4 * ratio * b, ratio * b
    return {"name": f"ratio{ratio:g}", "mu": 0.6, "live_load": [1, 0], "blocks": [
        {"id": "ground", "vertices": rect(-2 * big_w, -big_h, 2 * big_w, 0), "support": True},
        {"id": "big", "vertices": rect(-big_w / 2, 0, big_w / 2, big_h)},
        {"id": "small", "vertices": rect(-b / 2, big_h, b / 2, big_h + 4 * b)}]}


def issue_geometry() -> dict:
    """A 1e-3 x 4e-3 block standing on a 1e3 x 1e3 block."""
    return {"name": "tiny_on_huge", "mu": 0.6, "live_load": [1, 0], "blocks": [
        {"id": "ground", "vertices": rect(-1e3, -1e3, 1e3, 0), "support": True},
        {"id": "big", "vertices": rect(-500, 0, 500, 1e3)},
        {"id": "small", "vertices": rect(-0.5e-3, 1e3, 0.5e-3, 1e3 + 4e-3)}]}


@pytest.mark.slow
@pytest.mark.parametrize("ratio", [1.0, 1e2, 1e4, 1e5, 1e6, 1e8, 1e12])
def test_a_small_block_on_a_big_one_certifies_the_closed_form_or_is_refused(tmp_path, ratio):
    spec = tmp_path / "s.json"
    spec.write_text(json.dumps(small_on_big(ratio)))
    res = lamodel("solve", spec, "--out", tmp_path / "o", "--no-plot", "--quiet", "--starts", "0")
    if res.returncode == 0:
        summary = pd.read_csv(tmp_path / "o" / "summary.csv")
        assert summary.alpha[0] == pytest.approx(0.25, abs=1e-6), res.stdout
        assert check_folder(tmp_path / "o") == pytest.approx(0.25, abs=1e-6)  # every block in equilibrium
    else:  # never a wrong certificate: refused, naming the block and why
        assert res.returncode == 2, res.stdout + res.stderr
        assert "'small'" in res.stderr and ("double precision" in res.stderr or "tolerance" in res.stderr), res.stderr
        assert res.stderr.count("\n") == 1
    if ratio <= 1e6:  # loads down to 1e-12 of the largest are certified (light blocks are scaled)
        assert res.returncode == 0, res.stderr


@pytest.mark.slow
def test_the_tiny_block_on_a_huge_one_overturns_at_0_25(tmp_path):
    """Loads 4e-12 of the big block's: the small block's rows and contacts get scales of
    their own, and the closed form is certified (not the big block's sliding at 0.6)."""
    spec = tmp_path / "s.json"
    spec.write_text(json.dumps(issue_geometry()))
    res = lamodel("solve", spec, "--out", tmp_path / "o", "--no-plot", "--quiet")
    assert res.returncode == 0, res.stderr
    assert "alpha = 0.250000" in res.stdout and "associative bound 0.250000" in res.stdout
    assert check_folder(tmp_path / "o") == pytest.approx(0.25, abs=1e-9)  # every block in equilibrium


@pytest.mark.slow
@pytest.mark.parametrize("b, certified", [(1e-6, True), (1e-10, False)])
def test_a_block_below_what_double_precision_geometry_resolves_is_refused(tmp_path, b, certified):
    """A b x 4b block beside a 1 x 0.5 one, both on the ground (closed form 0.25): at 1e-6
    of the structure's size it is certified; at 1e-10 its contacts are computed to about
    1e-6 of its size, and it is refused by name, in one line."""
    spec = tmp_path / "s.json"
    spec.write_text(json.dumps({"name": "side", "mu": 0.6, "live_load": [1, 0], "tolerance": 1e-30, "blocks": [
        {"id": "ground", "vertices": rect(-2, -1, 4, 0), "support": True},
        {"id": "big", "vertices": rect(1, 0, 2, 0.5)},
        {"id": "small", "vertices": rect(0, 0, b, 4 * b)}]}))
    res = lamodel("solve", spec, "--out", tmp_path / "o", "--no-plot", "--quiet", "--starts", "0")
    if certified:
        assert res.returncode == 0 and "alpha = 0.250000" in res.stdout, res.stderr
        assert check_folder(tmp_path / "o") == pytest.approx(0.25, abs=1e-7)
    else:
        assert res.returncode == 2 and not (tmp_path / "o").exists(), res.stdout
        assert "block 'small' is smaller than 1e-08 times the structure's size" in res.stderr, res.stderr
        assert res.stderr.count("\n") == 1


@pytest.mark.slow
@pytest.mark.parametrize("tolerance", [0, 1e-15, 1e-26])
def test_a_user_tolerance_does_not_let_a_light_block_certify_a_wrong_alpha(tmp_path, tolerance):
    spec = tmp_path / "s.json"
    spec.write_text(json.dumps(dict(small_on_big(1e6), tolerance=tolerance)))  # a 1e-3 block on a 1e3 one
    res = lamodel("solve", spec, "--out", tmp_path / "o", "--no-plot", "--quiet")
    assert res.returncode == 0, res.stderr
    assert "alpha = 0.250000" in res.stdout


def test_a_state_that_leaves_a_light_block_out_of_equilibrium_is_no_collapse_state():
    """The residual test holds each block to its own loads: the statics of the whole
    structure with the small block carrying 42 % of its live load fails, however light."""
    import numpy as np

    from lamodel.io.jsonspec import structure_from_json
    from lamodel.search.certify import residuals
    from lamodel.search.lp import LimitLPs
    lps = LimitLPs(structure_from_json(issue_geometry()))
    st = lps.associative()  # exact statics at alpha = 0.25 (in the user's units, without scaling)
    N, V, M, alpha = lps.split(st.x)
    assert residuals(lps, N, V, M, alpha, np.zeros(3 * lps.nb), np.zeros(4 * lps.nc))["block_equilibrium"] < 1e-12
    small = lps.structure.block_index()["small"]
    on_small = [k for k, (a, b) in enumerate(zip(lps.structure.block_a, lps.structure.block_b)) if "small" in (a, b)]
    V = V.copy()
    V[on_small] += 0.58 * abs(lps.structure.live[small, 0])  # the shear the small block misses
    u, xi = np.zeros(3 * lps.nb), np.zeros(4 * lps.nc)
    res = residuals(lps, N, V, M, alpha, u, xi)
    assert res["equilibrium"] < 1e-7  # globally, the miss is below round-off of the big block
    assert res["block_equilibrium"] > 0.1  # against the small block's own load it is 58 %


@pytest.mark.slow
def test_a_block_smaller_than_the_tolerance_names_the_relative_tolerance(tmp_path):
    spec = tmp_path / "s.json"
    spec.write_text(json.dumps(small_on_big(1e24)))
    res = lamodel("build", spec, "-o", tmp_path / "s.dat")
    assert res.returncode == 2
    assert "block 'small'" in res.stderr and "'tolerance' 1e-09 times the model's size" in res.stderr, res.stderr


@pytest.mark.slow
@pytest.mark.parametrize("seed", ["-1", str(2**70), "1.5", "x"])
def test_a_seed_out_of_range_is_refused_before_solving(tmp_path, seed):
    res = lamodel("solve", INSTANCES / "wall33.dat", "--seed", seed, "--out", tmp_path / "o")
    assert res.returncode == 2 and res.stdout == "", res.stdout + res.stderr
    assert res.stderr.startswith("lamodel solve: error: argument --seed: expected a whole number >= 0")
    assert res.stderr.count("\n") == 1 and not (tmp_path / "o").exists()


@pytest.mark.slow
def test_the_largest_seed_is_written(tmp_path):
    from lamodel.search.options import SolveOptions
    with pytest.raises(ValueError, match="seed"):
        SolveOptions(seed=-1)
    res = lamodel("solve", INSTANCES / "wall33.dat", "--seed", 2**63 - 1, "--out", tmp_path / "o", "--quiet",
                  "--no-plot", "--starts", "0", "--generations", "1")
    assert res.returncode == 0, res.stderr
    assert pd.read_csv(tmp_path / "o" / "summary.csv").seed[0] == 2**63 - 1


@pytest.mark.slow
@pytest.mark.parametrize("command", ["solve", "study"])
def test_json_nested_ten_thousand_deep_is_bad_input(tmp_path, command):
    deep = tmp_path / "deep.json"
    deep.write_text("[" * 10000 + "]" * 10000)
    res = lamodel(command, deep)
    assert res.returncode == 2 and "nested too deeply" in res.stderr and "Traceback" not in res.stderr, res.stderr


@pytest.mark.slow
@pytest.mark.parametrize("name", ["../../../../x", "/tmp/elsewhere", "a/../../b"])
def test_a_study_name_never_leaves_results(tmp_path, name):
    (tmp_path / "work").mkdir()
    spec = tmp_path / "work" / "spec.json"
    spec.write_text(json.dumps({"name": name, "structure": str(INSTANCES / "wall33.json"),
                                "options": {"starts": 0, "generations": 1}, "vary": {"mu": [0.5]}}))
    res = lamodel("study", spec, "--no-plot", "--quiet", cwd=tmp_path / "work")
    assert res.returncode == 0, res.stderr
    written = [p for p in tmp_path.rglob("study.csv")]
    assert len(written) == 1 and written[0].parent.parent == tmp_path / "work" / "results", written


@pytest.mark.slow
def test_dat_vertices_of_an_unknown_block_are_refused(tmp_path):
    text = (INSTANCES / "wall33.dat").read_text()
    assert "param: VERTICES" in text
    bad = tmp_path / "bad.dat"
    bad.write_text(text.replace("param: VERTICES: vx vy :=", "param: VERTICES: vx vy :=\n  nowhere 1 0 0\n"
                                "  nowhere 2 1 0\n  nowhere 3 1 1", 1))
    res = lamodel("solve", bad, "--out", tmp_path / "o")
    assert res.returncode == 2 and "'nowhere'" in res.stderr and "VERTICES" in res.stderr, res.stderr


@pytest.mark.slow
def test_compare_refuses_a_device_and_an_oversized_table_before_reading(tmp_path, monkeypatch):
    res = lamodel("solve", INSTANCES / "wall33.dat", "--out", tmp_path / "a", "--no-plot", "--quiet", "--starts", "0")
    assert res.returncode == 0, res.stderr
    (tmp_path / "z").mkdir()
    os.symlink("/dev/zero", tmp_path / "z" / "summary.csv")
    res = lamodel("compare", tmp_path / "a", tmp_path / "z" / "summary.csv", timeout=60)
    assert res.returncode == 2 and "not a regular file" in res.stderr, res.stderr
    import lamodel.output.tablefiles as tablefiles
    from lamodel.errors import InputError
    from lamodel.output.results import Results
    monkeypatch.setattr(tablefiles, "MAX_TABLE_BYTES", 100)
    with pytest.raises(InputError, match="MB; expected a result table of at most"):
        Results.read(tmp_path / "a")


@pytest.mark.slow
def test_an_animation_follows_the_umask(tmp_path):
    old = os.umask(0o022)
    try:
        res = lamodel("solve", INSTANCES / "wall33.dat", "--out", tmp_path / "o", "--animate", tmp_path / "m.gif",
                      "--quiet", "--starts", "0")
    finally:
        os.umask(old)
    assert res.returncode == 0, res.stderr
    modes = {p.name: stat.S_IMODE(p.stat().st_mode) for p in [tmp_path / "m.gif", tmp_path / "o" / "summary.csv"]}
    assert modes == {"m.gif": 0o644, "summary.csv": 0o644}
