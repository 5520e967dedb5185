"""The one budget of a search (lamodel/search/budget.py): the time cap made once from
--time-limit, the work bounds counted in LP solves and LP work, and the child budgets it
hands out (lanes beside each other, the side lanes of a stalled first certificate, the
search's share when the Ipopt polish keeps its part of the limit)."""
import pickle
import time

import pytest

from lamodel.geometry import running_bond_wall
from lamodel.io.jsonspec import structure_from_json
from lamodel.search.budget import Budget
from lamodel.search.gap import GapSearch
from lamodel.search.gap.continuation import Continuation
from lamodel.search.gap.lanes import Start
from lamodel.search.gap.phases import associative
from lamodel.search.options import Deadline, Stopped
from lamodel.search.plan import first_certificate
from lamodel.search.tuning import FIRST_WORK, POLISH_SHARE, TOTAL_WORK



def bond(courses, width):
    rows = [[0.5] + [1] * (width - 1) + [0.5] if r % 2 == 0 else [1] * width for r in range(courses)]
    return structure_from_json(running_bond_wall(rows, name=f"bond{courses}x{width}"))


def test_a_solve_without_a_time_limit_is_bounded_by_work_alone():
    b = Budget.for_solve(None)
    assert (b.rule.first, b.rule.total) == (FIRST_WORK, TOTAL_WORK)
    assert b.left() == float("inf") and not b.expired() and b.polish_seconds() is None
    assert b.reserve(5.0).cap is b.cap  # nothing to keep for the polish without a limit


def test_a_time_limit_is_the_cap_and_sets_no_work_bound():
    b = Budget.for_solve(10.0)
    assert b.rule is None and 9.0 < b.left() <= 10.0
    assert b.polish_seconds() == POLISH_SHARE * 10.0


def test_the_search_leaves_the_polish_its_reserve_then_gives_it_back():
    b = Budget.for_solve(10.0)
    search = b.reserve(3.0)
    assert 2.5 < b.left() - search.left() <= 3.0 + 1e-6
    most = b.reserve(100.0)  # at most POLISH_SHARE of the limit
    assert b.left() - most.left() == pytest.approx(POLISH_SHARE * 10.0, abs=0.1)
    search.release()
    assert search.cap is b.cap and search.deadline.at == b.cap.at


def test_a_stop_is_told_from_the_time_cap():
    asked = []
    b = Budget.for_solve(None, stop=lambda: bool(asked))
    assert not b.expired() and not b.asked()
    asked.append(1)
    assert b.expired() and b.asked() and b.deadline.expired()
    late = Budget(Deadline(time.monotonic() - 1.0))
    assert late.expired() and not late.asked()


def test_the_deadline_of_the_solves_travels_as_the_seconds_left():
    b = Budget.for_solve(30.0)
    d = pickle.loads(pickle.dumps(b.deadline))
    assert type(d) is Deadline and 25.0 < d.left() <= 30.0


def test_work_bounds_stop_the_solves_and_a_lane_ends_quietly_there():
    """An engine's budget with its work bounds spent stops the next solve before it starts;
    a lane (``Budget.lane``) ends there quietly, while the time cap goes up to the search;
    once the search ended (``Budget.end``) the bounds stop no solve."""
    e = GapSearch(bond(4, width=6))
    _, _, x0 = associative(e)
    first_certificate(e, x0)
    e.budget.bound(e.n_lps())  # spent
    with pytest.raises(Stopped):
        e.problem.statics()
    n = e.n_lps()
    assert Continuation().run(e, Start(x0)) is None and e.n_lps() == n
    e.budget.end()
    assert e.problem.statics()[0] == "optimal"
    e.budget.cap = Deadline(time.monotonic() - 1.0)  # the time limit passed
    with pytest.raises(Stopped):
        with e.budget.lane():
            e.problem.statics()


def test_child_budgets_share_what_is_left_under_the_same_cap():
    e = GapSearch(bond(4, width=6), Budget(Deadline.after(60.0)))
    _, _, x0 = associative(e)
    e.budget.bound(e.n_lps() + 10, e.budget.work() + 1000.0)
    children = e.budget.share(2)
    assert [c.allowance for c in children] == [(5, 500.0)] * 2
    assert all(c.cap is e.budget.cap for c in children)
    other = GapSearch(bond(4, width=6))
    other.budget.run_under(children[0])  # counted from the other engine's own work
    assert other.budget.work_limit == other.n_lps() + 5 and other.budget.cap is e.budget.cap


def test_the_first_certificates_side_lanes_get_its_work_left():
    e = GapSearch(bond(4, width=6), Budget.for_solve(None))
    side = e.budget.side_lane()
    assert side.allowance == (None, e.budget.first_bound - e.budget.work())
    assert side.cap is e.budget.cap
