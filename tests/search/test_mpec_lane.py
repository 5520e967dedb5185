"""Ferris & Tin-Loi's MPEC as the default search's last lane (lamodel/search/plan.py:
MPEC_LANE): where its state is lower than the rest of the search's, the default run reports
it, named in runs.csv; elsewhere the lane leaves alpha as it was, and it steps aside where
it does not apply (in space, joints with strengths, more than MPEC_LANE_BLOCKS blocks)."""
import numpy as np
import pytest

from conftest import INSTANCES
from lamodel.geometry import running_bond_wall
from lamodel.io.datfile import read_dat
from lamodel.io.jsonspec import structure_from_json
from lamodel.search import plan
from lamodel.search.driver import SolveOptions, path_of, solve
from lamodel.search.gap.lanes import Lane
from lamodel.search.published import mpec

OPTIONS = SolveOptions(workers=1)


def pushed_up(courses, blocks, mu, degrees):
    """A running-bond wall (the families benchmark's ``direction`` cases) whose live load
    points ``degrees`` above +x."""
    rows = [[0.5] + [1] * (blocks - 1) + [0.5] if r % 2 == 0 else [1] * blocks for r in range(courses)]
    spec = running_bond_wall(rows, mu=mu, name="pushed")
    a = np.radians(degrees)
    spec["live_load"] = [float(np.cos(a)), float(np.sin(a))]
    return structure_from_json(spec)


def solved(structure, monkeypatch, lane_on=True, blocks=None):
    with monkeypatch.context() as m:
        if not lane_on:
            m.setattr(plan, "MPEC_LANE", Lane(()))
        if blocks is not None:
            m.setattr(mpec, "MPEC_LANE_BLOCKS", blocks)
        return solve(structure, OPTIONS)


@pytest.mark.slow
def test_the_mpec_lane_gives_the_answer_where_it_lands_lower(monkeypatch):
    # measured (docs/method/evidence.md, "The MPEC's lane"): on this 105-block wall pushed
    # 30 degrees up at mu 0.9 the rest of the search certifies 0.498276 (the slow
    # continuation, below the phases before it), Ferris & Tin-Loi's MPEC 0.497872
    s = pushed_up(10, 10, 0.9, 30.0)
    off, on = solved(s, monkeypatch, lane_on=False), solved(s, monkeypatch)
    assert on.best.alpha < off.best.alpha - 1e-6
    assert path_of(on.best) == "MPEC" and path_of(off.best) == "slow continuation"
    assert "MPEC" in on.phases and "MPEC" not in off.phases
    assert on.work > off.work  # its start's LPs and its certification count in the search's work
    # above its size bound the lane steps aside: no LP, no Ipopt
    bounded = solved(s, monkeypatch, blocks=s.n_blocks - 1)
    assert bounded.best.alpha == off.best.alpha and bounded.work == off.work


def test_the_lane_runs_only_where_the_slow_continuation_went_lower(monkeypatch):
    s = read_dat(INSTANCES / "wall33.dat")  # the gap alternation certifies the best here
    off, on = solved(s, monkeypatch, lane_on=False), solved(s, monkeypatch)
    assert path_of(on.best) != "slow continuation"
    assert on.best.alpha == off.best.alpha and on.work == off.work
    assert "MPEC" not in on.phases


def test_the_lane_runs_last():
    from lamodel.search.published.mpec import MPEC
    assert [type(s) for s in plan.MPEC_LANE.strategies] == [MPEC]


def test_a_state_lower_only_by_round_off_is_not_below_the_best():
    # the slow continuation's least state on a 129-block wall with doors and windows (mu 0.3:
    # it slides at alpha = mu) matched the best but for round-off and started the MPEC's
    # Ipopt ladder: 10 s where the search took 1.3 s. Below means below as a new best is.
    from types import SimpleNamespace as State
    from lamodel.search.gap.phases import below
    best = State(alpha=0.3)
    assert not below(State(alpha=np.nextafter(0.3, 0.0)), best)
    assert not below(State(alpha=0.3 - 1e-13), best)
    assert below(State(alpha=0.3 - 1e-9), best)
    assert below(State(alpha=0.3), None) and not below(None, best)
