"""Single-block mechanisms (lamodel.search.gap.single): a block that goes alone is ranked by
its own multiplier and certified at it, in the plane and in space, whatever the direction
of the load; the certificate is checked by the independent oracle."""
import numpy as np
import pytest

from lamodel.io.json3d import structure3d_from_spec
from lamodel.io.jsonspec import structure_from_json
from lamodel.search.gap import GapSearch
from lamodel.search.gap.single import ranked, single_blocks
from oracle import check_state


def cube(x, y, z, a=1.0, b=1.0, c=1.0):
    return [[x + i * a, y + j * b, z + k * c] for i in (0, 1) for j in (0, 1) for k in (0, 1)]


def pyramid(levels, mu, degrees):
    """A stepped pyramid of unit boxes: level k is (levels - k)^2 boxes, offset by half a box;
    a horizontal live load equal to the weight, ``degrees`` from x."""
    blocks = [{"id": "ground", "support": True, "vertices": cube(-1, -1, -0.5, levels + 2, levels + 2, 0.5)}]
    for k in range(levels):
        m = levels - k
        blocks += [{"id": f"b{k}_{i}_{j}", "vertices": cube(i + k / 2, j + k / 2, k)} for i in range(m) for j in range(m)]
    a = np.radians(degrees)
    return {"name": "pyramid", "mu": mu, "live_load": [float(np.cos(a)), float(np.sin(a)), 0.0], "blocks": blocks}


def run(structure):
    engine = GapSearch(structure)
    status, x = engine.problem.statics(maximize=True)  # the associative statics
    assert status == "optimal"
    return engine, single_blocks(engine.problem, engine.certifier, x)


@pytest.mark.parametrize("degrees", [0.0, 45.0, 120.0])
def test_the_top_box_of_a_stepped_pyramid_slides_at_mu_whatever_the_direction(degrees):
    """Each level's boxes carry the load of those above at alpha = mu exactly: the top box
    sliding alone is a collapse state at alpha = mu (the associative bound too), which the
    gap alternation's blended mechanisms never certify."""
    s = structure3d_from_spec(pyramid(3, 0.5, degrees))
    engine, st = run(s)
    assert st is not None and st.source.startswith("single-block")
    assert st.alpha == pytest.approx(0.5, abs=1e-7)
    assert max(engine.problem.to_user(st).residual.values()) <= 1e-7


def test_a_slender_block_on_a_wide_one_overturns_alone_at_its_closed_form():
    """A 0.5 x 2 block on a 4 x 1 block on the ground, mu 0.9: the top block alone turns
    about its toe at alpha = b / h = 0.25; the pair together would need more."""
    rect = lambda x0, y0, x1, y1: [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]  # noqa: E731
    spec = {"name": "slender", "mu": 0.9, "live_load": [1.0, 0.0], "unit_weight": 1.0,
            "blocks": [{"id": "ground", "support": True, "vertices": rect(-3, -1, 3, 0)},
                       {"id": "base", "vertices": rect(-2, 0, 2, 1)},
                       {"id": "top", "vertices": rect(-0.25, 1, 0.25, 3)}]}
    s = structure_from_json(spec)
    engine, st = run(s)
    own = dict((j, a) for a, j in ranked(engine.problem, -engine.problem.mu * engine.problem.N_of(
        engine.problem.statics(maximize=True)[1])))
    assert own[s.blocks.index("top")] == pytest.approx(0.25, abs=1e-9)
    assert st is not None and st.alpha == pytest.approx(0.25, abs=1e-9)
    assert check_state(s, engine.problem.to_user(st)) == pytest.approx(0.25, abs=1e-9)


@pytest.mark.slow
def test_the_default_search_certifies_a_stepped_pyramid_at_its_top_box():
    """Through the whole search (the single-block lane where the alternation stalls): the
    14-box pyramid pushed at 30 degrees, certified at mu, the state checked by the oracle."""
    from lamodel.search.driver import SolveOptions, solve
    s = structure3d_from_spec(pyramid(3, 0.5, 30.0))
    out = solve(s, SolveOptions())
    assert out.status == "certified" and out.best.alpha == pytest.approx(0.5, abs=1e-7)
    assert max(out.best.residual.values()) <= 1e-7


def test_joints_with_strengths_are_left_to_the_other_lanes():
    """Their rows (the N-M polygon's facets) are not the four a contact the ranking knows:
    the lane steps aside, it never guesses."""
    rect = lambda x0, y0, x1, y1: [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]  # noqa: E731
    spec = {"name": "strong", "mu": 0.9, "live_load": [1.0, 0.0], "unit_weight": 1.0, "fc": 50.0,
            "blocks": [{"id": "ground", "support": True, "vertices": rect(-3, -1, 3, 0)},
                       {"id": "base", "vertices": rect(-2, 0, 2, 1)},
                       {"id": "top", "vertices": rect(-0.25, 1, 0.25, 3)}]}
    engine, st = run(structure_from_json(spec))
    assert type(engine.problem).__name__ == "StrengthProblem" and st is None
