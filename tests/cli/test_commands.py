"""The one command line: lamodel solve | compare | build | table1, and what loads when."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import INSTANCES, ROOT

LAMODEL = Path(sys.executable).with_name("lamodel")


def lamodel(*args, timeout=300):
    cmd = [str(LAMODEL)] if LAMODEL.exists() else [sys.executable, "-m", "lamodel.cli"]
    return subprocess.run([*cmd, *map(str, args)], capture_output=True, text=True, timeout=timeout, cwd=ROOT)


def loaded_after(code):
    """The heavy modules a fresh interpreter holds after running ``code``."""
    probe = code + "\nimport sys; print(sorted(m for m in ('pyomo', 'highspy', 'matplotlib', 'cyipopt') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stdout.strip().splitlines()[-1]


@pytest.mark.slow
def test_reading_results_and_comparing_load_no_solver():
    assert loaded_after("import lamodel") == "[]"
    assert loaded_after("import lamodel.output.results, lamodel.output.compare, lamodel.cli") == "[]"
    assert loaded_after("from lamodel.cli import _parser; _parser().format_help()") == "[]"


@pytest.mark.slow
def test_the_model_registers_the_ipopt_bridge():
    code = ("import lamodel\nm = lamodel.create_model\nfrom pyomo.environ import SolverFactory\n"
            "print(SolverFactory('lamodel_ipopt').available())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert out.stdout.strip() == "True", out.stderr


@pytest.mark.slow
def test_help_lists_the_commands():
    res = lamodel("--help")
    assert res.returncode == 0
    for name in ("solve", "compare", "build", "table1"):
        assert name in res.stdout


@pytest.mark.slow
def test_solve_build_compare_through_the_console_script(tmp_path):
    dat = tmp_path / "stack.dat"
    spec = tmp_path / "stack.json"
    spec.write_text((INSTANCES / "wall33.json").read_text())
    built = lamodel("build", spec, "-o", dat)
    assert built.returncode == 0, built.stderr
    a = lamodel("solve", dat, "--out", tmp_path / "a", "--starts", "0", "--no-plot", "--quiet")
    assert a.returncode == 0, a.stderr
    b = lamodel("solve", spec, "--out", tmp_path / "b", "--starts", "0", "--no-plot", "--quiet")
    assert b.returncode == 0, b.stderr
    same = lamodel("compare", tmp_path / "a", tmp_path / "b")
    assert same.returncode == 0, same.stdout + same.stderr


@pytest.mark.parametrize("args, prefix, text", [
    (("solve", "nowhere.dat"), "lamodel solve: error: ", "nowhere.dat: no such file"),
    (("solve", "instances/wall33.dat", "--starts", "-1"), "lamodel solve: error: ", "argument --starts"),
    (("compare", "x"), "lamodel compare: error: ", "required: B"),
    (("build", "nowhere.json"), "lamodel build: error: ", "nowhere.json"),
    (("frobnicate",), "lamodel: error: ", "invalid choice"),
])
@pytest.mark.slow
def test_bad_input_is_one_line_exit_2(args, prefix, text):
    res = lamodel(*args)
    lines = res.stderr.strip().splitlines()
    assert res.returncode == 2 and len(lines) == 1, res.stderr
    assert lines[0].startswith(prefix) and text in lines[0], lines[0]


def test_table1_reference_data_ship_with_the_package():
    from lamodel.studies import read_table1
    ref = read_table1()
    assert list(ref.wall) == ["wall33", "wall55"] and ref.ferris_tin_loi_2.tolist() == [0.63898, 0.55742]
    import lamodel.studies
    assert Path(lamodel.studies.DATA).is_relative_to(Path(lamodel.studies.__file__).parent)
    assert not os.fspath(lamodel.studies.DATA).startswith(os.fspath(ROOT / "references"))
