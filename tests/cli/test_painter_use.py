"""`lamodel solve` starts the planar picture's helper process (lamodel.output.painter) only for
a planar structure: a structure in space draws its own picture, and bad input starts nothing."""
import json
import sys
from pathlib import Path

import pytest

import lamodel.output.painter as painter_mod
from lamodel.cli import main

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "geometry3d"))
from test_contacts3d import stack_spec  # noqa: E402


@pytest.fixture
def started(monkeypatch):
    """The helpers started during the test (each a real one, counted)."""
    seen = []

    class Counted(painter_mod.Painter):
        def __init__(self):
            super().__init__()
            seen.append(self)
    monkeypatch.setattr(painter_mod, "Painter", Counted)
    return seen


def test_a_3d_solve_starts_no_painter_and_still_draws_its_picture(tmp_path, started, capsys):
    path = tmp_path / "cubes.json"
    path.write_text(json.dumps(stack_spec()))
    assert main(["solve", str(path), "--out", str(tmp_path / "r"), "--quiet"]) == 0
    assert started == []
    assert (tmp_path / "r" / "mechanism.png").stat().st_size > 10_000


def test_a_planar_solve_starts_one(tmp_path, started, capsys):
    assert main(["solve", str(ROOT / "instances" / "wall33.dat"), "--out", str(tmp_path / "r"), "--quiet",
                 "--starts", "0"]) == 0
    assert len(started) == 1 and started[0]._proc is None          # used, then stopped
    assert (tmp_path / "r" / "mechanism.png").stat().st_size > 10_000


def test_bad_input_starts_no_painter(tmp_path, started, capsys):
    assert main(["solve", str(tmp_path / "missing.json"), "--out", str(tmp_path / "r")]) == 2
    assert started == [] and "no such file" in capsys.readouterr().err


def test_a_planar_json_starts_one_and_a_mesh_none(tmp_path, started, capsys):
    import trimesh
    assert main(["solve", str(ROOT / "instances" / "wall33.json"), "--out", str(tmp_path / "w"), "--quiet",
                 "--starts", "0"]) == 0
    assert len(started) == 1
    box = trimesh.creation.box(extents=[1, 1, 1])                                     # z from -0.5 to 0.5
    ground = trimesh.creation.box(extents=[4, 4, 1]).apply_translation([0, 0, -1])   # z from -1.5 to -0.5
    trimesh.Scene([ground, box]).export(tmp_path / "box.glb")
    assert main(["solve", str(tmp_path / "box.glb"), "--supports-below", "-1", "--out", str(tmp_path / "m"),
                 "--quiet"]) == 0
    assert len(started) == 1 and (tmp_path / "m" / "mechanism.png").exists()
