"""Hostile 3D inputs through `lamodel solve` (not only `lamodel build`): each is one line on
stderr naming the file and the block or field, exit status 2, no traceback, no result folder."""
import copy
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from lamodel.cli import main

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "geometry3d"))
from test_contacts3d import cube  # noqa: E402

#: Outward faces of ``cube``'s 8 corners.
FACES = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
#: A 1 x 0.5 x 2 block on a ground slab (alpha = 0.25 along y).
BLOCK = {"name": "block", "mu": 0.6, "live_load": [0, 1, 0],
         "blocks": [{"id": "ground", "support": True, "vertices": cube(-2, -2, -0.5, 4, 4, 0.5)},
                    {"id": "B", "vertices": cube(-0.5, -0.25, 0, 1, 0.5, 2), "faces": FACES}]}


def edited(change):
    spec = copy.deepcopy(BLOCK)
    change(spec)
    return json.dumps(spec, allow_nan=True)


def block(**fields):
    return lambda spec: spec["blocks"][1].update(fields)


def corner(k, value):
    return lambda spec: spec["blocks"][1]["vertices"][k].__setitem__(2, value)


#: case -> (the file's text, or a function of the folder making the input; words of the error)
CASES = {
    "open surface": (edited(block(faces=FACES[:-1])), ["block 'B'", "open", "expected a closed surface"]),
    "overlapping blocks": (edited(lambda s: s["blocks"].append({"id": "C", "vertices": cube(0, 0, 0.5)})),
                           ["blocks 'B' and 'C' overlap", "expected blocks that touch"]),
    "no support": (edited(lambda s: s["blocks"][0].update(support=False)), ["no block is a support"]),
    "every body a support": (edited(block(support=True)), ["every body is a support"]),
    "zero volume": (edited(block(vertices=cube(-0.5, -0.25, 0, 1, 0.5, 0), faces=None)),
                    ["block 'B'", "zero volume"]),
    "NaN coordinate": (edited(corner(3, float("nan"))), ["block 'B'", "not a finite number"]),
    "infinite coordinate": (edited(corner(3, float("inf"))), ["block 'B'", "not a finite number"]),
    "true as a coordinate": (edited(corner(3, True)), ["block 'B'", "'vertices' is not a list of [x, y, z]"]),
    "negative mu": (edited(lambda s: s.update(mu=-0.3)), ["'mu' is -0.3", "expected a number >= 0"]),
    "negative mu of a block": (edited(block(mu=-0.3)), ["block 'B': 'mu' is -0.3"]),
    "NaN live load": (edited(lambda s: s.update(live_load=[0, float("nan"), 0])), ["'live_load' is NaN"]),
    "zero live load": (edited(lambda s: s.update(live_load=[0, 0, 0])), ["every live load is zero"]),
    "face naming no vertex": (edited(block(faces=FACES[:-1] + [[1, 5, 7, 99]])), ["block 'B'", "vertex 99"]),
    "duplicate id": (edited(lambda s: s["blocks"].append({"id": "B", "vertices": cube(5, 5, 0)})),
                     ["block 'B' is declared twice"]),
    "free block": (edited(lambda s: s["blocks"].append({"id": "far", "vertices": cube(9, 9, 9)})),
                   ["block 'far' touches nothing"]),
    "unknown contact points": (edited(lambda s: s.update(contact_points="bogus")),
                               ["'contact_points' is 'bogus'", "expected \"vertices\" or \"grid:n\""]),
    "unknown dimension": (edited(lambda s: s.update(dimension=4)), ["'dimension' is 4", "expected 2", "or 3"]),
    "empty file": ("", ["the file is empty", "expected a JSON object"]),
    "JSON null": ("null", ["the file holds a JSON null", "expected a JSON object"]),
    "no blocks": ("{}", ["'blocks' is missing or empty"]),
    "a folder": (lambda folder: made(folder / "dir.json", folder=True), ["is a folder", "expected"]),
    "a missing file": (lambda folder: folder / "missing.json", ["no such file", "expected"]),
    "an empty mesh": (lambda folder: made(folder / "empty.obj"), ["holds no triangles"]),
}


def made(path, folder=False):
    """``path``, made an empty folder or an empty file."""
    path.mkdir() if folder else path.write_text("")
    return path


def make(folder, case):
    source = CASES[case][0]
    if callable(source):
        return source(folder)
    path = folder / "bad.json"
    path.write_text(source)
    return path


@pytest.mark.parametrize("case", list(CASES))
def test_a_hostile_3d_input_is_one_line_exit_2_in_solve(tmp_path, capsys, case):
    path = make(tmp_path, case)
    status = main(["solve", str(path), "--out", str(tmp_path / "r")])
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert status == 2 and len(lines) == 1 and lines[0].startswith(f"lamodel solve: error: {path}: "), err
    for words in CASES[case][1]:
        assert words in lines[0], (words, lines[0])
    assert out == "" and not (tmp_path / "r").exists()


def test_a_block_floating_above_the_ground_is_a_free_block(tmp_path, capsys):
    path = tmp_path / "float.json"
    path.write_text(edited(block(vertices=cube(-0.5, -0.25, 0.1, 1, 0.5, 2))))
    status = main(["solve", str(path), "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err
    assert status == 2 and "block 'B' touches nothing" in err, err


def test_unknown_fields_warn_in_one_line_each_and_the_solve_goes_on(tmp_path, capsys):
    path = tmp_path / "extra.json"
    path.write_text(edited(lambda s: (s.update(colour="red"), s["blocks"][1].update(weight=3))))
    status = main(["solve", str(path), "--out", str(tmp_path / "r"), "--quiet", "--no-plot"])
    out, err = capsys.readouterr()
    assert status == 0 and "alpha = 0.250000" in out
    assert err.strip().splitlines() == [
        f"lamodel solve: warning: {path}: unknown top-level field(s) 'colour' ignored; known fields are name, "
        "description, dimension, mu, unit_weight, live_load, tolerance, blocks, loads, units, contact_points, meta, joints, fc, ft, cohesion",
        f"lamodel solve: warning: {path}: unknown block field(s) 'weight' ignored; known fields are id, vertices, "
        "faces, support, dead, live, dead_m, live_m, mu, description, fc, ft, cohesion"]


def test_in_a_process_of_its_own_the_status_is_2_and_no_traceback(tmp_path):
    path = make(tmp_path, "overlapping blocks")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    p = subprocess.run([sys.executable, "-m", "lamodel.cli", "solve", str(path), "--out", str(tmp_path / "r")],
                       capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 2 and p.stdout == "" and "Traceback" not in p.stderr
    assert p.stderr.strip().splitlines() == [p.stderr.strip()] and "overlap" in p.stderr
