"""compare: differences between two result folders, and the exit codes of scripts/compare.py."""
import os
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from lamodel.cli import command
from lamodel.output.compare import compare_results
from lamodel.output.results import Results

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(REPO, "scripts", "compare.py")


def toy(alpha=0.64, certified=True, modes=("hinging", "closed", "sliding", "open"), N_scale=1.0,
        ux_shift=0.0, contacts=("c1", "c2", "c3", "c4")) -> Results:
    """Three blocks in a row on the ground, built by hand: 4 contacts, one mechanism."""
    summary = dict(instance="row3", alpha=alpha, certified=certified, alpha_associative=0.7,
                   n_blocks=3, n_contacts=len(contacts), n_starts=1, n_certified=int(certified),
                   wall_time_s=0.5)
    blocks = pd.DataFrame(dict(
        block=["b1", "b2", "b3"], x=[1.0, 3.0, 5.0], y=[0.875] * 3, dead_x=[0.0] * 3, dead_y=[-1.0] * 3,
        live_x=[1.0] * 3, live_y=[0.0] * 3, ux=np.array([0.2, 0.3, 0.5]) + ux_shift, uy=[0.0, 0.01, 0.02],
        theta=[0.0, 0.1, -0.1]))
    k = len(contacts)
    contacts_df = pd.DataFrame(dict(
        contact=list(contacts), block_a=["ground", "b1", "b2", "ground"][:k], block_b=["b1", "b2", "b3", "b3"][:k],
        cx=[1.0, 2.0, 4.0, 5.0][:k], cy=[0.0, 0.875, 0.875, 0.0][:k], nx=[0.0, 1.0, 1.0, 0.0][:k],
        ny=[1.0, 0.0, 0.0, 1.0][:k], d=[2.0, 0.875, 0.875, 2.0][:k], mu=[0.65] * k,
        N=(np.array([-3.0, -0.4, -0.2, -1.0]) * N_scale)[:k], V=[0.6, 0.1, -0.13, 0.0][:k],
        M=[1.2, 0.0, 0.05, 0.0][:k], mode=list(modes)[:k]))
    runs = pd.DataFrame(dict(start=[0], source=["lp"], alpha_ipopt=[alpha], status=["optimal"],
                             alpha_certified=[alpha], iterations=[20], seconds=[0.4]))
    return Results.from_frames(summary, blocks, contacts_df, runs)


def run_main(capsys, a, b, *extra):
    code = command("compare", [str(a), str(b), *extra], prog="compare.py")
    out, err = capsys.readouterr()
    return code, out, err


# ------------------------------------------------------------------------------ compare_results
def test_equal_results_agree():
    table, differ = compare_results(toy(), toy(), 1e-5)
    assert not differ
    assert not table["differs"].any()
    assert table.loc["alpha", "difference"] == 0.0
    assert table.loc["mode changes", "difference"] == 0


def test_alpha_difference_beyond_atol(tmp_path, capsys):
    a, b = toy().write(tmp_path / "a"), toy(alpha=0.64 + 1e-3).write(tmp_path / "b")
    table, differ = compare_results(Results.read(a), Results.read(b), 1e-5)
    assert differ
    assert table.loc["alpha", "differs"]
    assert table.loc["alpha", "difference"] == pytest.approx(1e-3)
    assert list(table.index[table["differs"].astype(bool)]) == ["alpha"]
    code, out, err = run_main(capsys, a, b)
    assert code == 1 and err == ""
    assert "alpha" in out and "0.001" in out and "differ" in out


def test_mode_change_names_the_contact(tmp_path, capsys):
    a = toy().write(tmp_path / "a")
    b = toy(modes=("hinging", "closed", "sliding+hinging", "open")).write(tmp_path / "b")
    code, out, err = run_main(capsys, a, b)
    assert code == 1
    assert "c3 (sliding -> sliding+hinging)" in out
    table, differ = compare_results(Results.read(a), Results.read(b), 1e-5)
    assert differ and list(table.index[table["differs"].astype(bool)]) == ["mode changes"]
    assert table.loc["mode changes", "difference"] == 1


def test_difference_below_atol_agrees(tmp_path, capsys):
    a = toy().write(tmp_path / "a")
    b = toy(alpha=0.64 + 4e-6, N_scale=1 + 1e-6, ux_shift=5e-6).write(tmp_path / "b")
    code, out, err = run_main(capsys, a, b, "--atol", "1e-5")
    assert code == 0, out
    assert "agree" in out
    # the same differences fail a tighter tolerance
    code, out, _ = run_main(capsys, a, b, "--atol", "1e-6")
    assert code == 1
    assert "alpha" in out and "max |dN|" in out and "max |dux|" in out


def test_forces_are_scaled_by_the_largest_normal_force():
    a = toy(N_scale=1000.0)
    b = toy(N_scale=1000.0 * (1 + 5e-9))  # |dN| = 1.5e-5 > atol but < atol * 3000
    table, differ = compare_results(a, b, 1e-5)
    assert not differ
    assert table.loc["max |dN|", "tolerance"] == pytest.approx(1e-5 * 3000.0)
    assert table.loc["max |dN|", "detail"] == "N at contact c1"


def test_certified_and_contact_sets():
    table, differ = compare_results(toy(), toy(certified=False), 1e-5)
    assert differ and list(table.index[table["differs"].astype(bool)]) == ["certified"]
    table, differ = compare_results(toy(), toy(contacts=("c1", "c2", "c3", "c9")), 1e-5)
    assert differ
    assert "only in A: c4; only in B: c9" == table.loc["contacts", "detail"]


def test_nan_alpha_on_both_sides_agrees():
    table, differ = compare_results(toy(alpha=np.nan), toy(alpha=np.nan), 1e-5)
    assert not differ
    table, differ = compare_results(toy(), toy(alpha=np.nan), 1e-5)
    assert differ and table.loc["alpha", "differs"]


def test_summary_csv_paths_work(tmp_path, capsys):
    a = toy().write(tmp_path / "a")
    code, _, _ = run_main(capsys, os.path.join(a, "summary.csv"), a)
    assert code == 0


# ------------------------------------------------------------------------------ the script
def script(*args):
    env = dict(os.environ, PYTHONPATH=REPO)
    return subprocess.run([sys.executable, SCRIPT, *map(str, args)], capture_output=True, text=True, env=env,
                          cwd=REPO, timeout=120)


@pytest.mark.slow
def test_script_exit_codes(tmp_path):
    a = toy().write(tmp_path / "a")
    b = toy(alpha=0.65).write(tmp_path / "b")
    same = script(a, a)
    assert same.returncode == 0, same.stderr
    assert "agree" in same.stdout
    diff = script(a, b)
    assert diff.returncode == 1, diff.stderr
    assert "alpha" in diff.stdout


@pytest.mark.slow
def test_script_garbage_summary_is_one_line_error(tmp_path):
    a = toy().write(tmp_path / "a")
    b = toy().write(tmp_path / "b")
    with open(os.path.join(b, "summary.csv"), "w") as fh:
        fh.write("instance,alpha,certified\nrow3,\"oops,1\n,,,,,\n")
    res = script(a, b)
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("compare.py: error: "), res.stderr
    assert "summary.csv" in lines[0]
    assert "Traceback" not in res.stderr and res.stdout == ""


@pytest.mark.slow
@pytest.mark.parametrize("case", ["missing folder", "non-numeric alpha", "missing file", "bad atol"])
def test_script_bad_input_exit_2(tmp_path, case):
    a = toy().write(tmp_path / "a")
    b = toy().write(tmp_path / "b")
    args = [a, b]
    if case == "missing folder":
        args = [a, tmp_path / "nowhere"]
    elif case == "non-numeric alpha":
        path = os.path.join(b, "summary.csv")
        text = open(path).read().replace("0.64000000000000001", "abc")
        open(path, "w").write(text)
    elif case == "missing file":
        os.remove(os.path.join(b, "contacts.csv"))
    else:
        args += ["--atol", "tiny"]
    res = script(*args)
    assert res.returncode == 2, (res.stdout, res.stderr)
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("compare.py: error: "), res.stderr
    assert "Traceback" not in res.stderr


def test_results_in_other_units_differ():
    """The same numbers in kN and m against N and mm, or against no units: not comparable."""
    def in_units(length, force):
        r = toy()
        r.summary["length_unit"], r.summary["force_unit"] = length, force
        return r
    kn, n, bare = in_units("m", "kN"), in_units("mm", "N"), toy()
    table, differ = compare_results(kn, n, 1e-5)
    assert differ and table.loc["units", "differs"] and table.loc["units", "A"] == "length m, force kN"
    assert compare_results(kn, bare, 1e-5)[1] and table.loc["units", "B"] == "length mm, force N"
    assert not compare_results(kn, in_units("m", "kN"), 1e-5)[1]
    assert compare_results(bare, toy(), 1e-5)[0].loc["units", "A"] == "none"


def test_a_half_written_folder_is_bad_input_not_another_structure(tmp_path, capsys):
    toy().write(tmp_path / "a")
    toy().write(tmp_path / "b")
    contacts = tmp_path / "b" / "contacts.csv"
    contacts.write_text("\n".join(contacts.read_text().splitlines()[:3]) + "\n")
    code, out, err = run_main(capsys, tmp_path / "a", tmp_path / "b")
    assert code == 2 and "2 rows where summary.csv says n_contacts = 4" in err
