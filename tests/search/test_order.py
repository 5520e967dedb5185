"""Whether a wall is certified does not depend on how its file is written: the same
running-bond wall with its blocks shuffled, the ground first, or other ids is certified
every time, at the same multiplier (the LPs are degenerate: which vertex a solve returns
depends on the order of rows and columns, so this is a property of the search, not of
the mechanics)."""
import numpy as np
import pytest

from lamodel.geometry import running_bond_wall
from lamodel.io.jsonspec import structure_from_json
from lamodel.search.driver import SolveOptions, solve

pytestmark = pytest.mark.slow


def wall(mu, how):
    rows = [[0.5] + [1] * 9 + [0.5] if r % 2 == 0 else [1] * 10 for r in range(10)]
    spec = running_bond_wall(rows, mu=mu, name="bond10x10")
    bodies = spec["blocks"]
    rng = np.random.default_rng(7)
    if how == "shuffled":
        spec["blocks"] = [bodies[i] for i in rng.permutation(len(bodies))]
    elif how == "ground first":
        ground = [b for b in bodies if b.get("support")]
        spec["blocks"] = ground + [b for b in bodies if not b.get("support")]
    elif how == "renamed":
        for k, b in zip(rng.permutation(len(bodies)), bodies):
            b["id"] = f"{'support' if b.get('support') else 'stone'}-{k:05d}"
    return structure_from_json(spec)


@pytest.mark.parametrize("mu", [0.65, 0.9])  # 0.9: the gap alternation stalls on running bond
def test_every_order_of_the_file_is_certified(mu):
    alphas = {}
    for how in ("as written", "shuffled", "ground first", "renamed"):
        o = solve(wall(mu, how), SolveOptions(starts=0, progress=False))
        assert o.certified, (how, o.message)
        alphas[how] = o.best.alpha
    if mu == 0.65:  # where the alternation certifies, every order gives the same state
        assert max(alphas.values()) == pytest.approx(min(alphas.values()), rel=1e-9), alphas
    # where it stalls the lanes after it may end in other collapse states: measured over 10
    # shuffles at mu 0.9, 7 give 0.565625 and 3 up to 6.7 % above (docs/benchmarks/families.md)
    assert max(alphas.values()) <= 1.07 * min(alphas.values()), alphas
