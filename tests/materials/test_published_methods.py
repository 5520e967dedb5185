"""The published methods with the joints' strengths (lamodel.search.lp: rows ``Y s <= b``, the
fictitious cohesion the joint's own plus -mu N, every flow dissipating ``xi b``): the closed
forms of test_joints.py by each method, ``--method all`` on the command line, and the default
search beside them."""
import dataclasses
import json

import numpy as np
import pandas as pd
import pytest

from conftest import INSTANCES, rect
from oracle import check_folder, check_state
from lamodel.cli import command
from lamodel.formulation.joints import relative_error_bound
from lamodel.io.datfile import read_dat
from lamodel.io.jsonspec import structure_from_json
from lamodel.search.driver import SolveOptions, solve
from lamodel.search.methods import run_method
from lamodel.search.tuning import CRUSHING_FACETS
from lamodel.variants import with_strengths

B, H, W = 2.0, 3.0, 6.0
EPS = relative_error_bound(CRUSHING_FACETS)
OPTIONS = SolveOptions(workers=1, starts=0)


def block(mu=5.0, **strengths):
    """The 2 x 3 block (W = 6, thickness 1) on the ground, with strengths."""
    s = structure_from_json({"name": "block", "mu": mu, "blocks": [
        {"id": "a", "vertices": rect(0, 0, B, H)},
        {"id": "ground", "support": True, "vertices": rect(-1, -1, 3, 0)}]})
    return dataclasses.replace(s, **{k: np.full(s.n_contacts, float(v)) for k, v in strengths.items()})


def overturning(fc, ft):
    """The stress blocks' moment over W H / 2 (test_joints.py derives it)."""
    if np.isinf(fc):
        return (W + ft * B) * B / 2 / (W * H / 2)
    y = (W + ft * B) / (fc + ft)
    return (fc + ft) * y * (B - y) / 2 / (W * H / 2)


# (structure, exact alpha of the parabola, the polygon's relative loss at most)
CASES = {
    "crushing": (lambda: block(fc=10.0), (B / 2 - W / (2 * 10.0)) / (H / 2), EPS),
    "glued sliding": (lambda: block(mu=0.3, cohesion=0.1), 0.3 + 0.1 * B / W, 0.0),
    "tension, rigid": (lambda: block(ft=0.5, cohesion=5.0), overturning(np.inf, 0.5), 0.0),
    "tension and crushing": (lambda: block(fc=20.0, ft=2.0, cohesion=5.0), overturning(20.0, 2.0), EPS),
}


@pytest.mark.parametrize("method", ["associative", "successive-lp", "mpec", "seed"])
@pytest.mark.parametrize("case", CASES)
def test_each_published_method_certifies_the_closed_forms(case, method):
    """Crushing, cohesion and tension on one block, by every published method: each answer
    certified within the inscribed polygon's bound of the stress block's alpha, and exact
    for its polygonal joint (the oracle's rebuild)."""
    make, exact, loss = CASES[case]
    s = make()
    result = run_method(method, s, OPTIONS, seed_budget=(4, 2))
    assert result.certified, result.notes
    assert exact * (1 - loss) - 1e-9 <= result.alpha_certified <= exact + 1e-9
    check_state(s, result.state)


def test_the_methods_see_a_joint_crush_under_the_dead_load():
    """W = 6 > B b f_c = 5.8: unstable, and the words say the joints crush (as the search's)."""
    result = run_method("successive-lp", block(fc=2.9), OPTIONS)
    assert result.status == "unstable" and not result.certified
    assert "crush" in result.notes and "with dry joints it stands" in result.notes


def test_method_all_with_strengths_on_the_command_line(tmp_path):
    """``--fc`` with ``--method all``: every method in methods.csv certified within the
    polygon's bound of the closed form, the folder that of the least (the oracle rebuilds it
    from the CSVs, the joints' limits included)."""
    path = tmp_path / "blk.json"
    path.write_text(json.dumps({"name": "blk", "mu": 5.0, "units": {"length": "m", "force": "kN"}, "blocks": [
        {"id": "a", "vertices": rect(0, 0, 2, 3)}, {"id": "ground", "support": True, "vertices": rect(-1, -1, 3, 0)}]}))
    out = tmp_path / "out"
    assert command("solve", [str(path), "--fc", "10", "--method", "all", "--out", str(out), "--no-plot",
                             "--workers", "1", "--quiet", "--pop-size", "4", "--generations", "2"]) == 0
    table = pd.read_csv(out / "methods.csv")
    exact = (B / 2 - W / (2 * 10.0)) / (H / 2)
    assert list(table.method) == ["associative", "successive-lp", "mpec", "seed", "lamodel"]
    assert table.certified.all()
    assert (table.alpha_certified >= exact * (1 - EPS) - 1e-9).all() and (table.alpha_certified <= exact + 1e-9).all()
    assert check_folder(out) == pytest.approx(table.alpha_certified.min(), abs=1e-9)


@pytest.mark.slow
@pytest.mark.parametrize("strengths", [{"fc": 20.0}, {"cohesion": 0.02, "ft": 0.01}])
def test_the_default_run_with_strengths_is_never_above_the_fixed_point_methods(strengths):
    """Table 1's wall with crushing, or a mortar: the default run's alpha at most each of the
    associative bound's and the successive LP's certified ones (each method's state exact
    for the oracle)."""
    s = with_strengths(read_dat(INSTANCES / "wall33.dat"), **strengths)
    out = solve(s, OPTIONS)
    assert out.best is not None
    check_state(s, out.best)
    for name in ("associative", "successive-lp"):
        other = run_method(name, s, OPTIONS)
        if other.certified:
            check_state(s, other.state)
            assert out.best.alpha <= other.alpha_certified + 1e-9, name
