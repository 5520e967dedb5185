"""A 3D point load acts at a point of its block: inside it or on its surface (within the
geometric tolerance and LOAD_POINT_SLACK of the block's size); a point off the block, whose
moment about the block would be meaningless, is refused in one line naming the load and the
block (exit 2 from `lamodel solve`)."""
import copy
import json
import sys
from pathlib import Path

import pytest

from lamodel.errors import InputError
from lamodel.io.json3d import structure3d_from_spec
from lamodel.search.tuning import LOAD_POINT_SLACK

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "geometry3d"))
from test_contacts3d import cube  # noqa: E402

FACES = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
#: A 1 x 0.5 x 2 block on a ground slab (its size, the diagonal, is 2.29).
BLOCK = {"name": "block", "mu": 0.6, "live_load": [0, 1, 0],
         "blocks": [{"id": "ground", "support": True, "vertices": cube(-2, -2, -0.5, 4, 4, 0.5)},
                    {"id": "B", "vertices": cube(-0.5, -0.25, 0, 1, 0.5, 2)}]}
SIZE = (1 + 0.25 + 4) ** 0.5
#: An L-shaped block (2 x 1 x 2 less its upper right quarter) on the ground: non-convex.
L_VERTICES = [[0, 0, 0], [2, 0, 0], [2, 0, 1], [1, 0, 1], [1, 0, 2], [0, 0, 2],
              [0, 1, 0], [2, 1, 0], [2, 1, 1], [1, 1, 1], [1, 1, 2], [0, 1, 2]]
L_FACES = [[0, 1, 2, 3, 4, 5], [11, 10, 9, 8, 7, 6], [6, 7, 1, 0], [7, 8, 2, 1], [8, 9, 3, 2], [9, 10, 4, 3],
           [10, 11, 5, 4], [11, 6, 0, 5]]


def loaded(at, spec=BLOCK, block="B"):
    s = copy.deepcopy(spec)
    s["loads"] = [{"block": block, "at": list(at), "force": [0, 1, 0]}]
    return s


def l_block():
    return {"name": "ell", "mu": 0.6, "live_load": [1, 0, 0],
            "blocks": [{"id": "ground", "support": True, "vertices": cube(-1, -1, -0.5, 4, 3, 0.5)},
                       {"id": "L", "vertices": L_VERTICES, "faces": L_FACES}]}


@pytest.mark.parametrize("at", [(0, 0, 1), (0, 0, 2), (0.5, 0.25, 2), (-0.5, 0, 1), (0.2, -0.25, 0.7),
                                (0, 0, 2 + 1e-2 * LOAD_POINT_SLACK * SIZE),
                                (0.5 + 0.5 * LOAD_POINT_SLACK * SIZE, 0, 1)])
def test_a_point_in_or_on_the_block_is_taken(at):
    s = structure3d_from_spec(loaded(at), "f.json")
    bare = structure3d_from_spec(BLOCK, "f.json")
    assert s.live[0] == pytest.approx(bare.live[0] + [0, 1, 0])


@pytest.mark.parametrize("at", [(0, 0, 2 + 100 * SIZE), (0, 0, 2 + 0.01 * SIZE), (0.5 + 2 * LOAD_POINT_SLACK * SIZE,
                                                                                   0, 1), (3, 3, -0.2)])
def test_a_point_off_the_block_is_refused_naming_the_load_and_the_block(at):
    with pytest.raises(InputError) as e:
        structure3d_from_spec(loaded(at), "f.json")
    msg = str(e.value)
    assert msg.startswith("f.json: loads[0]: point ") and "is not on block 'B'" in msg and "\n" not in msg, msg
    assert "expected a point inside or on the boundary of the block" in msg


def test_a_point_in_the_notch_of_a_non_convex_block_is_refused():
    assert structure3d_from_spec(loaded((1, 0.5, 1), l_block(), "L"), "f.json").n_blocks == 1   # on its step
    assert structure3d_from_spec(loaded((0.5, 0.5, 1.5), l_block(), "L"), "f.json").n_blocks == 1   # inside
    with pytest.raises(InputError, match="is not on block 'L'"):
        structure3d_from_spec(loaded((1.5, 0.5, 1.5), l_block(), "L"), "f.json")   # in its bounding box, not in it


def test_solve_refuses_a_far_point_load_in_one_line_exit_2(tmp_path, capsys):
    from lamodel.cli import main
    path = tmp_path / "far.json"
    path.write_text(json.dumps(loaded((0, 0, 2 + 100 * SIZE))))
    status = main(["solve", str(path), "--out", str(tmp_path / "r"), "--no-plot"])
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert status == 2 and len(lines) == 1 and out == "", err
    assert lines[0].startswith(f"lamodel solve: error: {path}: loads[0]: point [0.0, 0.0, ") and "block 'B'" in lines[0]
    assert not (tmp_path / "r").exists()
