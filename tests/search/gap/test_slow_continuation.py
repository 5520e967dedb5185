"""The slow continuation (lamodel/search/gap/continuation.py: SlowContinuation, plan.SLOW,
run after the published methods): where the quick penalty ladders jump past a family of mechanisms, the
slow ladder follows it down to a lower collapse state, which the default run reports and
names in runs.csv; elsewhere it leaves alpha as it was."""
import numpy as np
import pytest

from conftest import INSTANCES
from lamodel.geometry import running_bond_wall, stone_wall
from lamodel.io.datfile import read_dat
from lamodel.io.jsonspec import structure_from_json
from lamodel.search import plan
from lamodel.search.gap.lanes import Lane
from lamodel.search.driver import SolveOptions, path_of, solve

from .helpers import collapse_violation

OPTIONS = SolveOptions(workers=1)


def bond(courses, blocks, mu, degrees=0.0):
    """The families benchmark's running-bond wall, its live load inclined ``degrees`` up."""
    rows = [[0.5] + [1] * (blocks - 1) + [0.5] if r % 2 == 0 else [1] * blocks for r in range(courses)]
    a = np.radians(degrees)
    return structure_from_json(running_bond_wall(rows, mu=mu, live_load=(float(np.cos(a)), float(np.sin(a)))))


def stones(n, seed, mu):
    width = 2.0 * np.sqrt(n / 10.0)
    return structure_from_json(stone_wall(n, width=width, height=width / 2, seed=seed, mu=mu, name=f"stones{n}"))


def solved(structure, slow, monkeypatch):
    with monkeypatch.context() as m:
        m.setattr(plan, "MPEC_LANE", Lane(()))  # the phase alone (the MPEC's lane after it: test_mpec_lane.py)
        if not slow:
            m.setattr(plan, "SLOW", Lane(()))
        return solve(structure, OPTIONS)


@pytest.mark.slow
def test_the_slow_continuation_gives_the_best_where_the_quick_ladders_jump_past_it(monkeypatch):
    # measured (benchmarks/lanes.py --lane "slow continuation"): on this wall pushed 30
    # degrees up at mu 0.9 the default run without the lane certifies 0.513849, with it a
    # state below, near Ferris & Tin-Loi's MPEC (0.497872) at a fraction of its time
    s = bond(10, 10, 0.9, degrees=30.0)
    off, on = solved(s, False, monkeypatch), solved(s, True, monkeypatch)
    assert on.best.alpha < off.best.alpha - 1e-6
    assert path_of(on.best) == "slow continuation"
    assert collapse_violation(s, on.best) <= 1e-7
    assert on.best.alpha <= on.alpha_associative + 1e-9


@pytest.mark.slow
@pytest.mark.parametrize("make", [lambda: read_dat(INSTANCES / "wall33.dat"), lambda: stones(40, 1, 0.65),
                                  lambda: bond(5, 10, 0.9), lambda: bond(5, 10, 0.65, degrees=-30.0)],
                         ids=["wall33", "stones40_s1", "bond5x10", "bond5x10_down30"])
def test_the_slow_continuation_never_raises_alpha(make, monkeypatch):
    s = make()
    off, on = solved(s, False, monkeypatch), solved(s, True, monkeypatch)
    assert on.best.alpha <= off.best.alpha + 1e-12


@pytest.mark.parametrize("bound, runs", [(33, True), (32, False)])
def test_the_slow_continuation_runs_on_structures_of_at_most_slow_blocks(bound, runs, monkeypatch):
    # it lowered alpha on walls of 80 to 135 blocks, on none of 160 to 320, by 5e-7 on 1 of 23 of 500-520; it
    # took up to a tenth of the run (docs/method/evidence.md, "The slow continuation")
    s = read_dat(INSTANCES / "wall33.dat")
    called = []
    slow = plan.phases.slow
    monkeypatch.setattr(plan, "SLOW_BLOCKS", bound)
    monkeypatch.setattr(plan.phases, "slow", lambda *a, **k: called.append(1) or slow(*a, **k))
    out = solve(s, OPTIONS)
    assert bool(called) is runs
    assert abs(out.best.alpha - 0.638982) < 1e-6  # Table 1's wall: its state comes before the phase
