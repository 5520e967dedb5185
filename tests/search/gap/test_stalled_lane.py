"""The lane that runs where the gap alternation stalls (plan.IF_STALLED): on running bond at
high friction its chain from zero cohesion comes before the rescue, whose ladders stay at
the alternation's partial optimum; the first certificate then costs fewer LP solves, and
the search's answer is not above the one of the other order."""
import pytest

from lamodel.geometry import running_bond_wall
from lamodel.io.jsonspec import structure_from_json
from lamodel.search import plan
from lamodel.search.driver import SolveOptions, solve
from lamodel.search.gap import GapSearch
from lamodel.search.gap.chains import FixedPoint, FromZero
from lamodel.search.gap.lanes import Lane, Start
from lamodel.search.gap.phases import associative
from lamodel.search.gap.rescue import Rescue
from lamodel.search.gap.single import SingleBlocks

from .helpers import collapse_violation

#: the other order of the same strategies: the rescue before the chain from zero
RESCUE_FIRST = Lane((SingleBlocks(), Rescue(), FromZero(cold=True), FixedPoint()), until_certified=True)


def bond(courses, width, mu):
    rows = [[0.5] + [1] * (width - 1) + [0.5] if r % 2 == 0 else [1] * width for r in range(courses)]
    return structure_from_json(running_bond_wall(rows, mu=mu, name=f"bond{courses}x{width}"))


def _stalled(s):
    """An engine whose gap alternation from the associative statics certified nothing, and
    where it started and stalled."""
    engine = GapSearch(s)
    kind, _, x0 = associative(engine)
    assert kind == "ok"
    _, x = engine.alternation.alternate(x0, source="gap")
    return engine, Start(x0, x)


def test_the_lane_certifies_a_stalled_wall_with_fewer_lp_solves_than_the_rescue_first():
    s = bond(12, 8, 0.9)  # 102 blocks: the alternation stalls at a partial optimum
    counts, alphas = [], []
    for lane in (plan.IF_STALLED, RESCUE_FIRST):
        engine, start = _stalled(s)
        assert engine.record.best is None
        before = engine.n_lps()
        lane.run(engine, start)
        best = engine.record.best
        assert best is not None
        assert collapse_violation(engine.problem.s, best) < 1e-6
        counts.append(engine.n_lps() - before)
        alphas.append(best.alpha)
    assert counts[0] < counts[1]
    assert alphas[0] <= alphas[1] + 1e-9


# walls where the alternation stalls (the others do not reach the lane)
@pytest.mark.parametrize("courses, width, mu", [(6, 5, 0.9), (9, 7, 0.9), (12, 6, 0.9), (14, 8, 1.0), (12, 10, 0.8)])
def test_the_answer_is_not_above_the_one_with_the_rescue_first(monkeypatch, courses, width, mu):
    s = bond(courses, width, mu)
    assert _stalled(s)[0].record.best is None  # the lane runs here
    opt = SolveOptions(starts=0, pop_size=4, generations=2)
    now = solve(s, opt)
    monkeypatch.setattr(plan, "IF_STALLED", RESCUE_FIRST)
    other = solve(s, opt)
    assert now.certified and other.certified
    assert now.best.alpha <= other.best.alpha + 1e-9
