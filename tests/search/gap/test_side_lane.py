"""The lane beside the first certificate's main lane (plan.BESIDE_STALLED), bounded once the
main lane certifies by SIDE_LANE_SHARE times the LP work the main lane took: counted work,
so the same answer with one worker or two, and on stalled walls no higher alpha than without
the bound."""
import pytest

from lamodel.search import budget as budget_module
from lamodel.search import plan
from lamodel.search.budget import Budget
from lamodel.search.driver import SolveOptions, solve
from lamodel.search.gap import GapSearch
from lamodel.search.gap.phases import associative

from .test_stalled_lane import bond


def _first_certificate(s, workers):
    """LP solves, LP work and the least alpha of the first certificate (the lanes merged)."""
    engine = GapSearch(s, Budget.for_solve(None))
    _, _, x0 = associative(engine)
    plan.first_certificate(engine, x0, workers)
    return engine.n_lps(), engine.problem.work(), engine.record.best.alpha


def test_the_bound_cuts_the_side_lane_and_is_the_same_with_one_worker_or_two(monkeypatch):
    s = bond(12, 8, 0.9)  # stalls: the main lane certifies, the dilatancy continuation runs beside it
    unbounded = _first_certificate(s, 1)
    monkeypatch.setattr(budget_module, "SIDE_LANE_SHARE", 0.3)  # small enough to cut the side lane here
    one, two = _first_certificate(s, 1), _first_certificate(s, 2)
    assert one == two
    assert one[0] < unbounded[0] and one[1] < unbounded[1]
    assert one[2] <= unbounded[2] + 1e-9  # the main lane's state: the side lane found none lower


def test_no_bound_under_a_time_limit():
    e = GapSearch(bond(4, 6, 0.9), Budget.for_solve(60.0))
    assert e.budget.side_lane().main_lane is None
    e = GapSearch(bond(4, 6, 0.9), Budget.for_solve(None))
    side = e.budget.side_lane()
    side.main_lane.ended(certified=False)
    assert not side.main_lane.reached(1e30)  # the main lane certified nothing: its budget alone


@pytest.mark.parametrize("courses, width", [(12, 8), (9, 7)])
def test_the_answer_is_not_above_the_one_without_the_bound(monkeypatch, courses, width):
    s = bond(courses, width, 0.9)
    opt = SolveOptions(starts=0, pop_size=4, generations=2)
    now = solve(s, opt)
    monkeypatch.setattr(budget_module, "SIDE_LANE_SHARE", float("inf"))
    before = solve(s, opt)
    assert now.certified and before.certified
    assert now.best.alpha <= before.best.alpha + 1e-9
