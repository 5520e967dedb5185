"""The plan of the search (lamodel/search/plan.py): its lanes named as runs.csv's paths,
objects that pickle, and one screen long."""
import pickle
from pathlib import Path

from lamodel.search import plan
from lamodel.search.driver import PATHS


def _lanes():
    return (plan.IF_STALLED, *plan.BESIDE_STALLED, *plan.CONTINUATIONS, plan.PUBLISHED, plan.SLOW)


def test_every_strategy_of_the_plan_is_named_as_a_path_of_runs_csv():
    names = {name for lane in _lanes() for name in lane.names}
    assert names == {"single block", "rescue", "chain from zero cohesion", "fixed-point fallback",
                     "dilatancy continuation", "continuation", "slow continuation", "successive LP",
                     "successive cone"}
    assert names <= set(PATHS.values())


def test_the_lanes_pickle_and_come_back_equal():
    for lane in _lanes():
        assert pickle.loads(pickle.dumps(lane)) == lane


def test_a_once_a_search_strategy_that_ran_is_left_out_of_a_lane():
    lane = plan.CONTINUATIONS[0].without({"from zero": (None,)})
    assert lane.names == ["continuation"]
    assert plan.CONTINUATIONS[1].without({}) == plan.CONTINUATIONS[1]


def test_the_plan_reads_in_one_screen():
    assert len(Path(plan.__file__).read_text(encoding="utf-8").splitlines()) <= 120
