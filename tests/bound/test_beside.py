"""The default lower bound beside the search: the same bound and proofs as after it, and
a search that ends without a state to bound stops it."""
from __future__ import annotations

import math
import time

import pytest

from lamodel.bound.beside import BoundBeside
from lamodel.bound.lower import default_budget, lower_bound, proves
from lamodel.io import read
from lamodel.output.report import bound_columns
from lamodel.search.driver import SolveOptions, solve

from conftest import INSTANCES

OPTIONS = SolveOptions(starts=0, pop_size=4, generations=2, progress=False)


@pytest.mark.parametrize("name", ["arch", "portal", "wall33"])
def test_beside_the_search_the_bound_is_the_bound_after_it(name):
    s = read(INSTANCES / f"{name}.dat")
    beside = BoundBeside(s)
    seen = []
    o = solve(s, OPTIONS, on_associative=lambda a: (seen.append(a), beside.start(a)))
    assert beside.started and seen == [o.alpha_associative]
    lb = beside.finish(o.wall_time_s)
    after = lower_bound(s, o.best.alpha, **default_budget(o.wall_time_s, s))
    assert lb.alpha_lower == pytest.approx(after.alpha_lower, rel=1e-12, abs=1e-12)
    assert proves(lb.alpha_lower, o.best.alpha) == after.proven_global
    assert lb.alpha_lower <= o.best.alpha
    # the summary's columns take it as they take the bound after the search
    cols = bound_columns(s, o.best.alpha, True, o.wall_time_s, beside=beside)
    assert cols["proven_global"] == after.proven_global
    assert (name != "wall33") == after.proven_global  # the arch and portal are proven, wall33 not


def test_a_bound_never_started_is_computed_after_the_search():
    s = read(INSTANCES / "portal.dat")
    o = solve(s, OPTIONS)
    beside = BoundBeside(s)
    assert beside.finish(o.wall_time_s) is None
    cols = bound_columns(s, o.best.alpha, True, o.wall_time_s, beside=beside)
    assert cols["proven_global"] and cols["alpha_lower"] <= o.best.alpha


def test_stop_ends_the_bound_and_no_state_means_no_bound():
    s = read(INSTANCES / "arch.dat")
    beside = BoundBeside(s)
    beside.start(0.5)
    t = time.perf_counter()
    cols = bound_columns(s, math.nan, False, 1.0, beside=beside)  # e.g. an unstable structure
    assert math.isnan(cols["alpha_lower"]) and not cols["proven_global"]
    assert not beside._thread.is_alive() and time.perf_counter() - t < 5.0
    for top in (math.inf, math.nan, -1.0):  # no finite multiplier: nothing starts
        b = BoundBeside(s)
        b.start(top)
        assert not b.started
    off = BoundBeside(s, enabled=False)  # --prove: the bound runs after the search
    off.start(0.5)
    assert not off.started


def test_a_failed_search_stops_the_bound():
    s = read(INSTANCES / "arch.dat")
    beside = BoundBeside(s)
    with pytest.raises(KeyboardInterrupt):
        with beside:
            beside.start(0.5)
            raise KeyboardInterrupt
    assert beside._stop.is_set() and not beside._thread.is_alive()
