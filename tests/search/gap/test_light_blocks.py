"""A block far lighter than the rest (a 1e-3 m block on a 1e3 m one) gets scales of its own
in the search's LPs (formulation.scaling.light_scales), and only such a block."""
import numpy as np
import pytest

from conftest import INSTANCES, rect
from lamodel.formulation.scaling import light_scales, scaled, scales
from lamodel.io import read
from lamodel.io.jsonspec import structure_from_json
from lamodel.search.gap import GapSearch
from lamodel.search.tuning import LIGHT_BLOCK
from lamodel.search.gap.phases import associative
from lamodel.search.plan import first_certificate


def tiny_on_huge():
    return structure_from_json({"name": "tiny_on_huge", "mu": 0.6, "live_load": [1, 0], "blocks": [
        {"id": "ground", "vertices": rect(-1e3, -1e3, 1e3, 0), "support": True},
        {"id": "big", "vertices": rect(-500, 0, 500, 1e3)},
        {"id": "small", "vertices": rect(-0.5e-3, 1e3, 0.5e-3, 1e3 + 4e-3)}]})


@pytest.mark.parametrize("name", ["wall33.dat", "arch.dat", "portal_columns.dat"])
def test_a_structure_without_light_blocks_is_solved_unscaled(name):
    s = read(INSTANCES / name)
    rows, contacts = light_scales(scaled(s, *scales(s)), LIGHT_BLOCK)
    assert np.all(rows == 1.0) and np.all(contacts == 1.0)


def test_only_the_light_block_and_its_contacts_are_scaled():
    s = tiny_on_huge()
    sc = scaled(s, *scales(s))
    rows, contacts = light_scales(sc, LIGHT_BLOCK)
    small = s.block_index()["small"]
    weight = np.abs(sc.dead[small]).max()  # 4e-12 of the big block's, in units of the mean
    assert weight < 1e-11
    assert rows[3 * small] == rows[3 * small + 1] == pytest.approx(1 / weight)
    assert rows[3 * small + 2] > rows[3 * small]  # moments by the small block's own size too
    assert np.all(np.delete(rows, [3 * small, 3 * small + 1, 3 * small + 2]) == 1.0)
    touches = np.array(["small" in (a, b) for a, b in zip(s.block_a, s.block_b)])
    assert np.all(contacts[touches] == pytest.approx(weight)) and np.all(contacts[~touches] == 1.0)


def test_the_light_block_decides_the_search(monkeypatch):
    """With its own scales the small block's overturning (0.25) is found and certified; the
    LPs without them see only the big block (it slides at 0.6) and certify nothing."""
    s = tiny_on_huge()
    g = GapSearch(s)
    kind, alpha, x = associative(g)
    assert kind == "ok" and alpha == pytest.approx(0.25, abs=1e-9)
    first_certificate(g, x)
    assert g.record.best_user.alpha == pytest.approx(0.25, abs=1e-9)
    assert max(g.record.best_user.residual.values()) < 1e-7

    import lamodel.search.gap.problem as problem
    monkeypatch.setattr(problem, "LIGHT_BLOCK", 0.0)
    g = GapSearch(s)
    kind, alpha, x = associative(g)
    assert alpha == pytest.approx(0.6, abs=1e-6)
    first_certificate(g, x)
    assert g.record.best is None
