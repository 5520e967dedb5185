"""The examples (tie force in a user's Pyomo model, friction study), scripts/table1.py and
lamodel.studies, run as a user would."""
import os
import re
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from conftest import ROOT, run_script

TABLE1_REFERENCE = pd.read_csv(ROOT / "lamodel" / "data" / "table1.csv")


def run_example(script, *args, cwd=None, timeout=600):
    """Run one of examples/ as a user would, with this interpreter."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, str(ROOT / "examples" / script), *map(str, args)], capture_output=True,
                          text=True, cwd=cwd or ROOT, env=env, timeout=timeout)


RESULT = re.compile(r"result: tie force T = (?P<T>[-0-9.e]+) at (?P<block>\w+), cost [-0-9.e]+; "
                    r"certified alpha of the tied wall = (?P<alpha>[-0-9.e]+), target (?P<target>[-0-9.e]+): "
                    r"(?P<verdict>target (NOT )?met)")


def _result(proc):
    m = RESULT.search(proc.stdout)
    assert m, proc.stdout + proc.stderr
    return float(m["T"]), m["block"], float(m["alpha"]), m["verdict"]


# ------------------------------------------------------------------------- tie force
@pytest.mark.slow
def test_tie_force_example_meets_its_target(tmp_path):
    target = 0.645
    proc = run_example("tie_force.py", "--target", target, "--checks", 1, "--csv", tmp_path / "tie.csv")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    T, block, alpha, verdict = _result(proc)
    assert block == "b33"  # the right end block of the top course
    assert T > 0
    assert alpha >= target - 1e-6
    assert verdict == "target met"
    table = pd.read_csv(tmp_path / "tie.csv")
    untied = table["alpha"].iloc[0]
    assert untied == pytest.approx(0.638982, abs=1e-6)  # Table 1
    assert alpha > untied  # the tie raises the collapse load
    # every check ran on the tied wall with the T found, and certified a state
    checks = table[table["step"].str.startswith("tied wall")]
    assert len(checks) == 2 and checks["certified"].all()
    assert np.allclose(checks["T"], T, rtol=0, atol=1e-6)  # T as printed: 6 decimals
    # the least certified alpha of the tied wall is not above the collapse state Ipopt found
    ipopt = table[table["step"].str.startswith("Ipopt's point")]["alpha"].iloc[0]
    assert alpha <= ipopt + 1e-9


@pytest.mark.slow
def test_tie_force_example_says_when_the_target_is_out_of_reach():
    """A target of 0.70: Ipopt finds T = 1.5 and a collapse state at 0.70, but with that
    tie a half block at the right end (b28 below b33, or b17: equal multipliers) slides
    out alone, unloaded, at alpha = mu = 0.65."""
    proc = run_example("tie_force.py", "--target", 0.70, "--checks", 1)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    T, _, alpha, verdict = _result(proc)
    assert verdict == "target NOT met"
    assert T == pytest.approx(1.5, abs=1e-4)
    assert alpha == pytest.approx(0.65, abs=1e-6)
    assert "not the least one" in proc.stdout
    moving = re.search(r"1 moving block\(s\) \((b\d+)\)", proc.stdout)
    assert moving and moving[1] in ("b6", "b17", "b28"), proc.stdout
    assert "b33 does not move in that mechanism" in proc.stdout


# ------------------------------------------------------------------------- friction
@pytest.mark.slow
def test_friction_study_example(tmp_path):
    proc = run_example("friction_study.py", "--mus", "0.4,0.65,0.9", "--out", tmp_path / "a.png")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    df = pd.read_csv(tmp_path / "a.csv")
    assert list(df.columns[:7]) == ["mu", "alpha_c", "alpha_associative", "certified", "n_sliding", "n_hinging",
                                    "seconds"]
    assert df["mu"].tolist() == [0.4, 0.65, 0.9]
    assert df["certified"].all()
    assert (df["alpha_c"] <= df["alpha_associative"] + 1e-9).all()
    # the statically admissible set grows with mu, so the associative bound cannot drop
    assert (np.diff(df["alpha_associative"]) >= -1e-9).all()
    a = dict(zip(df["mu"], df["alpha_c"]))
    assert a[0.4] == pytest.approx(0.4, abs=1e-7)          # low friction: the wall slides, alpha = mu
    assert a[0.65] == pytest.approx(0.638982, abs=1e-6)    # Table 1
    # alpha_c is NOT monotone in mu: measured on wall33 (every seed tried, 0.3..0.9), the
    # same rocking mechanism with a few slipping joints governs from mu = 0.65 up, and its
    # certified multiplier falls as mu grows (0.6390, 0.6371, 0.6303, 0.6174 at mu = 0.65,
    # 0.7, 0.8, 0.9): more friction lets the statics unload the slipping joints.
    assert a[0.9] < a[0.65] - 0.01
    assert a[0.9] == pytest.approx(0.617364, abs=1e-5)
    assert "alpha_c decreases with mu" in proc.stdout
    rows = df.set_index("mu")
    assert rows.loc[0.4, "n_sliding"] > 0 and rows.loc[0.4, "n_hinging"] == 0
    assert rows.loc[0.65, "n_hinging"] > 0

    png = (tmp_path / "a.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    other = run_example("friction_study.py", "--mus", "0.5,0.9", "--out", tmp_path / "b.png")
    assert other.returncode == 0, other.stdout + other.stderr
    assert (tmp_path / "b.png").read_bytes() != png
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]


def test_friction_study_rejects_bad_mus(tmp_path):
    proc = run_example("friction_study.py", "--mus", "0.4,abc", "--out", tmp_path / "a.png")
    assert proc.returncode == 2
    assert "expected comma-separated numbers" in proc.stderr
    assert not (tmp_path / "a.png").exists()


# ------------------------------------------------------------------------- Table 1
@pytest.mark.slow
def test_table1_script(tmp_path):
    out = tmp_path / "sub" / "table1.csv"
    proc = run_script("table1.py", "--starts", 0, "--out", out)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "wall33" in proc.stdout and "wall55" in proc.stdout
    df = pd.read_csv(out)
    assert df["wall"].tolist() == ["wall33", "wall55"]
    pd.testing.assert_frame_equal(df[TABLE1_REFERENCE.columns], TABLE1_REFERENCE)
    assert df["certified"].all()
    alpha = dict(zip(df["wall"], df["lamodel"]))
    assert alpha["wall33"] <= 0.63900
    assert alpha["wall55"] <= 0.55745
    assert (df["lamodel"] <= df["alpha_associative"] + 1e-9).all()
    assert "0.638982" in proc.stdout and "0.557416" in proc.stdout


# ------------------------------------------------------------------------- lamodel.studies
def test_friction_study_on_a_stack(stack):
    """Two unit blocks stacked: they slide at alpha = mu or overturn at alpha = 1/2."""
    from lamodel.search.driver import SolveOptions
    from lamodel.studies import friction_study
    mu0 = stack.mu.copy()
    df = friction_study(stack, [0.3, 0.8], SolveOptions(starts=0))
    assert df["certified"].all()
    assert df["alpha_c"].tolist() == pytest.approx([0.3, 0.5], abs=1e-9)
    assert df.loc[0, "n_sliding"] > 0 and df.loc[1, "n_hinging"] > 0
    assert np.array_equal(stack.mu, mu0)  # the structure passed in is untouched


def test_with_dead_force_copies(stack):
    from lamodel.errors import InputError
    from lamodel.variants import with_dead_force
    tied = with_dead_force(stack, "b2", fx=-0.4)
    assert tied.dead[1].tolist() == pytest.approx([stack.dead[1, 0] - 0.4, stack.dead[1, 1]])
    assert stack.dead[1, 0] == 0.0
    with pytest.raises(InputError, match="no movable block 'nope'"):
        with_dead_force(stack, "nope", fx=1.0)


def test_write_csv_is_atomic_and_exact(tmp_path):
    from lamodel.io.files import write_csv
    x = np.random.default_rng(0).random(50)
    path = tmp_path / "deep" / "t.csv"
    write_csv(pd.DataFrame({"x": x}), path)
    assert np.array_equal(pd.read_csv(path)["x"].to_numpy(), x)
    assert [p.name for p in path.parent.iterdir()] == ["t.csv"]
