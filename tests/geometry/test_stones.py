"""Walls of irregular stones (lamodel.geometry.stone_wall): a tessellation of the panel into
convex stones whose joints the contact search finds whole, the same wall for the same
seed, and a certified collapse state however the file lists its blocks."""
import numpy as np
import pytest
from shapely.geometry import Polygon

from lamodel.errors import InputError
from lamodel.geometry import stone_wall
from lamodel.io.jsonspec import structure_from_json
from lamodel.search.driver import SolveOptions, solve
from oracle import check_state


def stones(spec):
    return [Polygon(b["vertices"]) for b in spec["blocks"] if not b.get("support")]


@pytest.mark.parametrize("n, seed", [(12, 0), (40, 3)])
def test_the_stones_tile_the_panel_and_touch_along_whole_edges(n, seed):
    spec = stone_wall(n, width=6.0, height=3.0, seed=seed)
    cells = stones(spec)
    assert len(cells) == n
    assert all(c.is_valid and c.exterior.is_ccw and abs(c.convex_hull.area - c.area) < 1e-9 for c in cells)
    assert sum(c.area for c in cells) == pytest.approx(18.0, rel=1e-9)
    # the joints between stones, as the contact search finds them, are the shared edges
    s = structure_from_json(spec)
    shared = sum(a.intersection(b).length for i, a in enumerate(cells) for b in cells[i + 1:]
                 if a.distance(b) < 1e-9)
    on_ground = np.array(["ground" in (a, b) for a, b in zip(s.block_a, s.block_b)])
    assert 2 * s.d[~on_ground].sum() == pytest.approx(shared, rel=1e-6)
    assert 2 * s.d[on_ground].sum() == pytest.approx(6.0, rel=1e-6)  # the whole base


def test_the_same_seed_gives_the_same_wall_and_another_seed_another():
    assert stone_wall(20, seed=5) == stone_wall(20, seed=5)
    assert stone_wall(20, seed=5)["blocks"] != stone_wall(20, seed=6)["blocks"]


@pytest.mark.parametrize("bad", [dict(n_stones=1), dict(n_stones=2.5), dict(width=0.0), dict(height=-1.0)])
def test_a_wall_that_cannot_be_cut_is_refused_in_one_line(bad):
    with pytest.raises(InputError, match="stone_wall"):
        stone_wall(**{"n_stones": 10, **bad})


def test_the_certificate_does_not_depend_on_how_the_file_lists_the_blocks():
    """The same stone wall with its blocks shuffled, the ground first and every id renamed:
    certified every time at the same alpha (the LPs are degenerate: the vertex a solve
    returns depends on the order of rows and columns; the collapse state must not)."""
    spec = stone_wall(30, width=5.0, height=2.5, seed=2, mu=0.65)
    rng = np.random.default_rng(0)
    shuffled = dict(spec, blocks=[spec["blocks"][i] for i in rng.permutation(len(spec["blocks"]))])
    ground_first = dict(spec, blocks=spec["blocks"][-1:] + spec["blocks"][:-1])
    renamed = dict(spec, blocks=[dict(b, id=f"x{k:03d}") for k, b in zip(rng.permutation(31), spec["blocks"])])
    alphas = []
    for variant in (spec, shuffled, ground_first, renamed):
        s = structure_from_json(variant)
        out = solve(s, SolveOptions(starts=0))
        assert out.status == "certified"
        assert check_state(s, out.best) == pytest.approx(out.best.alpha, abs=1e-9)
        alphas.append(out.best.alpha)
    assert max(alphas) - min(alphas) <= 1e-6 * max(1.0, alphas[0]), alphas
