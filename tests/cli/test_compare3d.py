"""`lamodel compare` on result folders of structures in space: the same rules and exit statuses
as in the plane (0 agree, 1 differ, 2 bad input), per-point forces and per-block motions
matched by id, and a planar result against one in space refused in one line."""
import json
import shutil
import sys
from pathlib import Path

import pandas as pd
import pytest

from lamodel.cli import command
from lamodel.output.compare import compare_results, read_result

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "geometry3d"))
from test_contacts3d import stack_spec  # noqa: E402


@pytest.fixture(scope="module")
def solved(tmp_path_factory):
    """One solve of four columns of two cubes (alpha = 0.5), and one planar solve."""
    import lamodel
    base = tmp_path_factory.mktemp("compare3d")
    path = base / "cubes.json"
    path.write_text(json.dumps(stack_spec()))
    lamodel.analyse(path, lamodel.SolveOptions(), base / "cubes", picture=False)
    lamodel.analyse(ROOT / "instances" / "wall33.dat", lamodel.SolveOptions(starts=0), base / "wall33",
                    picture=False)
    return base


def copy(solved, tmp_path, edit=None, table="contacts.csv"):
    """A copy of the 3D result folder, one of its tables (as text) edited by ``edit``."""
    out = tmp_path / "b"
    shutil.copytree(solved / "cubes", out)
    if edit is not None:
        df = pd.read_csv(out / table, keep_default_na=False, dtype=str)
        edited = edit(df)                      # edits in place, or returns the new table
        df = df if edited is None else edited
        df.to_csv(out / table, index=False)
    return out


def run(capsys, a, b, *extra):
    code = command(None, ["compare", str(a), str(b), *extra])
    out, err = capsys.readouterr()
    return code, out, err


def differing(a, b, atol=1e-5):
    table, differ = compare_results(read_result(a), read_result(b), atol)
    return differ, list(table.index[table["differs"].astype(bool)]), table


def test_a_3d_result_agrees_with_itself(solved, capsys):
    code, out, err = run(capsys, solved / "cubes", solved / "cubes" / "summary.csv")
    assert code == 0 and err == ""
    assert "A and B agree" in out
    for row in ("status", "contact points", "max |dT1|", "max |dT2|", "max |drz|", "8 blocks, 16 interfaces, "
                "64 contact points"):
        assert row in out, row


def test_alpha_and_status_differences_are_named(solved, tmp_path, capsys):
    def alpha(df):
        df.loc[0, "alpha"] = str(float(df.loc[0, "alpha"]) + 1e-3)
    b = copy(solved, tmp_path, alpha, "summary.csv")
    code, out, _ = run(capsys, solved / "cubes", b)
    assert code == 1 and "A and B differ (atol=1e-05): alpha" in out
    assert differing(solved / "cubes", b)[1] == ["alpha"]
    assert run(capsys, solved / "cubes", b, "--atol", "1e-2")[0] == 0

    def status(df):
        df.loc[0, "status"] = "interrupted"
    assert differing(solved / "cubes", copy(solved, tmp_path / "s", status, "summary.csv"))[1] == ["status"]


def test_a_point_force_and_a_block_motion_are_matched_by_id(solved, tmp_path):
    def force(df):  # the third point of interface i2, and the rows in another order (matched by id, not row)
        rows = df.index[df["interface"] == "i2"]
        df.loc[rows[2], "T1"] = str(float(df.loc[rows[2], "T1"]) + 0.01)
        df.loc[rows[2], "mode"] = "sliding" if df.loc[rows[2], "mode"] != "sliding" else "stuck"
    differ, rows, table = differing(solved / "cubes", copy(solved, tmp_path, force))
    assert differ and rows == ["mode changes", "max |dT1|"]
    assert table.loc["max |dT1|", "detail"] == "T1 at contact point i2#3"
    assert table.loc["max |dT1|", "difference"] == pytest.approx(0.01, rel=1e-9)
    assert table.loc["mode changes", "detail"].startswith("i2#3 (")

    def turn(df):
        df.loc[1, "rz"] = str(float(df.loc[1, "rz"]) + 0.5)
        df[:] = df.iloc[::-1].to_numpy()          # reversed rows: still matched by block id
    differ, rows, table = differing(solved / "cubes", copy(solved, tmp_path / "m", turn, "blocks.csv"))
    assert rows == ["max |drz|"] and table.loc["max |drz|", "difference"] == pytest.approx(0.5)


def test_another_structure_is_not_matched_point_by_point(solved, tmp_path, capsys):
    def fewer(df):
        return df.iloc[:-1]
    b = copy(solved, tmp_path, fewer)
    code, out, _ = run(capsys, solved / "cubes", b)
    assert code == 1 and "A and B are different structures (other contact point ids)" in out

    def moved(df):
        df.loc[0, "block_b"] = "b111"
    differ, rows, table = differing(solved / "cubes", copy(solved, tmp_path / "j", moved))
    assert "structure" in rows and table.loc["structure", "detail"].endswith("contact point i1#1 joins other bodies")


@pytest.mark.parametrize("order", ["2d-3d", "3d-2d"])
def test_a_planar_result_and_one_in_space_are_refused_in_one_line(solved, capsys, order):
    a, b = (solved / "wall33", solved / "cubes")[:: 1 if order == "2d-3d" else -1]
    code, out, err = run(capsys, a, b)
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [err.strip()]
    assert err.startswith("lamodel compare: error: A is a ") and "expected two results of the same dimension" in err
    assert ("planar result (2D)" in err) and ("result in space (3D)" in err)


@pytest.mark.parametrize("case, words", [
    ("no status", "column 'status' is missing"),
    ("bad force", "column 'N', row 1, is 'oops'; expected a number"),
    ("no contacts", "contacts.csv: no such file"),
])
def test_a_broken_3d_folder_is_one_line_exit_2(solved, tmp_path, capsys, case, words):
    b = copy(solved, tmp_path)
    if case == "no status":
        df = pd.read_csv(b / "summary.csv").drop(columns="status")
        df.to_csv(b / "summary.csv", index=False)
    elif case == "bad force":
        df = pd.read_csv(b / "contacts.csv", keep_default_na=False, dtype=str)
        df.loc[0, "N"] = "oops"
        df.to_csv(b / "contacts.csv", index=False)
    else:
        (b / "contacts.csv").unlink()
    code, out, err = run(capsys, solved / "cubes", b)
    assert code == 2 and len(err.strip().splitlines()) == 1 and words in err, err
