"""A bad value given on the command line is refused as the option's, never the file's: one
line naming the option (``--mu is nan; expected ...``), exit 2, for a 3D JSON, a mesh and a
planar file alike; an ft above an fc names the option that set it (and the file, when the
other strength is the file's)."""
import json
import sys
from pathlib import Path

import pytest

from lamodel.cli import main
from lamodel.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "geometry3d"))
from test_contacts3d import cube  # noqa: E402

BLOCK3D = {"name": "block", "mu": 0.6, "live_load": [0, 1, 0],
           "blocks": [{"id": "ground", "support": True, "vertices": cube(-2, -2, -0.5, 4, 4, 0.5)},
                      {"id": "B", "vertices": cube(-0.5, -0.25, 0, 1, 0.5, 2)}]}
BLOCK2D = {"name": "block2", "mu": 0.6, "unit_weight": 1.0, "live_load": [1.0, 0.0],
           "blocks": [{"id": "ground", "vertices": [[-2, -1], [2, -1], [2, 0], [-2, 0]], "support": True},
                      {"id": "B", "vertices": [[-0.5, 0], [0.5, 0], [0.5, 1], [-0.5, 1]]}]}


def inputs(folder):
    """The three kinds of input: a 3D JSON, a mesh (its supports given), a planar JSON."""
    import trimesh
    (folder / "block3d.json").write_text(json.dumps(BLOCK3D))
    (folder / "block2d.json").write_text(json.dumps(BLOCK2D))
    ground = trimesh.creation.box(extents=[4, 4, 1]).apply_translation([0, 0, -0.5])
    box = trimesh.creation.box(extents=[1, 1, 1]).apply_translation([0, 0, 0.5])
    trimesh.Scene([ground, box]).export(folder / "block.glb")
    return {"3d": [folder / "block3d.json"], "mesh": [folder / "block.glb", "--supports-below", "-0.5"],
            "planar": [folder / "block2d.json"]}


#: option values -> the words of the one line
BAD = {
    ("--mu", "-1"): "--mu is -1; expected a finite friction coefficient >= 0",
    ("--mu", "nan"): "--mu is nan; expected a finite friction coefficient >= 0",
    ("--mu", "inf"): "--mu is inf; expected",
    ("--unit-weight", "-1"): "--unit-weight is -1; expected a finite weight per unit volume > 0",
    ("--unit-weight", "0"): "--unit-weight is 0; expected",
    ("--unit-weight", "nan"): "--unit-weight is nan; expected",
    ("--live-load", "nan", "0", "0"): "--live-load is nan 0 0; expected three finite numbers",
    ("--live-load", "0", "0", "0"): "--live-load is 0 0 0; expected three finite numbers X Y Z, not all zero",
    ("--tolerance", "-1"): "--tolerance is -1; expected a finite tolerance >= 0",
    ("--tolerance", "nan"): "--tolerance is nan; expected",
    ("--supports-below", "nan"): "--supports-below is nan; expected a finite height Z",
    ("--contact-points", "grid:0"): "--contact-points is 'grid:0'; expected \"vertices\" or \"grid:n\"",
    ("--contact-points", "bogus"): "--contact-points is 'bogus'; expected",
    ("--fc", "1", "--ft", "2"): "--ft is 2, above --fc 1; expected a tensile strength at most the compressive one",
}


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    return inputs(tmp_path_factory.mktemp("inputs"))


def one_line(capsys, args, command="solve"):
    status = main([command, *map(str, args)])
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert status == 2 and len(lines) == 1 and out == "", err
    return lines[0]


@pytest.mark.parametrize("kind", ["3d", "mesh", "planar"])
@pytest.mark.parametrize("option", list(BAD), ids=" ".join)
def test_a_bad_option_value_names_the_option_not_the_file(files, tmp_path, capsys, kind, option):
    line = one_line(capsys, [*files[kind], "--out", tmp_path / "r", "--no-plot", *option])
    assert line.startswith("lamodel solve: error: --") and BAD[option] in line, line
    assert str(files[kind][0]) not in line and not (tmp_path / "r").exists()


@pytest.mark.parametrize("option", [("--tolerance", "nan"), ("--contact-points", "grid:0"), ("--mu", "-1")],
                         ids=" ".join)
def test_build_names_the_option_too(files, capsys, option):
    line = one_line(capsys, [*files["mesh"], *option], command="build")
    assert line.startswith(f"lamodel build: error: {option[0]} is "), line


def test_an_unknown_support_is_the_options_and_the_3d_json_refuses_mesh_options(files, tmp_path, capsys):
    line = one_line(capsys, [files["mesh"][0], "--supports", "b1,x", "--out", tmp_path / "r"])
    assert line == f"lamodel solve: error: --supports: 'x' is not a block of {files['mesh'][0]}; expected ids " \
                   "among b1, b2", line
    line = one_line(capsys, [*files["3d"], "--unit-weight", "2", "--out", tmp_path / "r"])
    assert line.startswith("lamodel solve: error: --unit-weight: applies to COMPAS assemblies and meshes only"), line


@pytest.mark.parametrize("kind, owner", [("3d", "interface 'i1'"), ("planar", "contact 'c1'")])
def test_an_ft_above_an_fc_names_the_option_and_the_files_strength(tmp_path, capsys, kind, owner):
    spec = dict(BLOCK3D if kind == "3d" else BLOCK2D, fc=1.0, ft=0.5)
    path = tmp_path / "strong.json"
    path.write_text(json.dumps(spec))
    line = one_line(capsys, [path, "--ft", "2", "--out", tmp_path / "r"])
    assert line == f"lamodel solve: error: --ft is 2, above the fc 1 that {path} gives {owner}; expected a tensile " \
                   "strength at most the compressive one (give --fc too)", line
    line = one_line(capsys, [path, "--fc", "0.2", "--out", tmp_path / "r"])
    assert line.startswith(f"lamodel solve: error: --fc is 0.2, below the ft 0.5 that {path} gives {owner}"), line
    assert not (tmp_path / "r").exists()


def test_read_refuses_a_callers_value_as_the_callers(files):
    from lamodel.io import read
    for options, words in (({"tolerance": -1.0}, "--tolerance is -1"), ({"mu": float("nan")}, "--mu is nan"),
                           ({"contact_points": "grid:0"}, "--contact-points is 'grid:0'")):
        with pytest.raises(InputError) as e:
            read(files["mesh"][0], supports_below=-0.5, **options)
        assert str(e.value).startswith(words), str(e.value)
    assert read(files["mesh"][0], supports_below=-0.5, live_load=(0.0, 1.0, 0.0), tolerance=0.0).n_blocks == 1
