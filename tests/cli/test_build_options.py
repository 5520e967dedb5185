"""`lamodel build`: a planar JSON gives its .dat instance, a 3D input its contacts summary;
options that do not apply to the input are refused in one line (exit 2), never ignored."""
import json
import sys
from pathlib import Path

import pytest

from lamodel.cli import main

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "geometry3d"))
from test_contacts3d import stack_spec  # noqa: E402


@pytest.fixture
def cubes(tmp_path):
    path = tmp_path / "cubes.json"
    path.write_text(json.dumps(stack_spec()))
    return path


def test_a_3d_input_prints_its_contacts_summary(cubes, capsys):
    assert main(["build", str(cubes)]) == 0
    assert capsys.readouterr().out.strip() == (f"{cubes}: 8 blocks, 1 supports, 16 interfaces, 64 contact points, "
                                               "total interface area 16")
    assert sorted(p.name for p in cubes.parent.iterdir()) == ["cubes.json"]


def test_a_planar_input_writes_its_instance(tmp_path, capsys):
    out = tmp_path / "w.dat"
    assert main(["build", str(ROOT / "instances" / "wall33.json"), "-o", str(out), "--name", "w"]) == 0
    assert capsys.readouterr().out.strip() == f"{out}: 33 blocks, 1 supports, 83 contacts"
    assert "set BLOCKS" in out.read_text()


@pytest.mark.parametrize("geometry, args, words", [
    ("cubes", ["-o", "x.dat"], "lamodel build: error: --output: a structure in space has no .dat instance"),
    ("cubes", ["--name", "x"], "lamodel build: error: --name: a structure in space has no .dat instance"),
    ("wall33.json", ["--mu", "0.3"], "lamodel build: error: --mu: applies to 3D inputs"),
    ("wall33.json", ["--contact-points", "grid:2"], "lamodel build: error: --contact-points: applies to 3D inputs"),
    ("wall33.dat", [], "wall33.dat: not a .json file; expected a JSON polygon geometry"),
])
def test_what_build_cannot_honour_is_refused(cubes, tmp_path, capsys, geometry, args, words):
    path = cubes if geometry == "cubes" else ROOT / "instances" / geometry
    assert main(["build", str(path), *args]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.strip().splitlines()) == 1 and words in err, err
    assert not Path("x.dat").exists() and not (ROOT / "instances" / "x.dat").exists()


def test_a_dat_that_cannot_hold_the_file_is_refused_or_said(tmp_path, capsys):
    """A .dat holds one live load, no units, and takes its name from its file: load cases or
    a rolling load are refused (exit 2, nothing written), units and a --name it cannot keep
    are said; a folder or '-' as the output is refused; missing parent folders are made."""
    stack = {"name": "s", "mu": 0.6, "units": {"length": "m", "force": "kN"},
             "blocks": [{"id": "ground", "vertices": [[-2, -1], [2, -1], [2, 0], [-2, 0]], "support": True},
                        {"id": "b1", "vertices": [[-0.5, 0], [0.5, 0], [0.5, 1], [-0.5, 1]]}]}
    cases = {**stack, "loads": [{"block": "b1", "at": [0, 1], "force": [1, 0], "case": "top"}]}
    rolling = {**stack, "rolling_load": {"force": [0, -1]}}
    for spec, words in ((cases, "has load cases"), (rolling, "has a rolling load")):
        path = tmp_path / "g.json"
        path.write_text(json.dumps(spec))
        assert main(["build", str(path), "-o", str(tmp_path / "g.dat")]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and words in err[0] and "cannot hold" in err[0]
        assert not (tmp_path / "g.dat").exists()
    path = tmp_path / "g.json"
    path.write_text(json.dumps(stack))
    for out, words in ((tmp_path, "a folder"), ("-", "not a file name")):
        assert main(["build", str(path), "-o", str(out)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and words in err[0]
    out = tmp_path / "new" / "x.dat"
    assert main(["build", str(path), "-o", str(out), "--name", "wall"]) == 0
    err = capsys.readouterr().err
    assert out.exists() and "keeps no units (length m, force kN)" in err and "call it 'x', not 'wall'" in err
