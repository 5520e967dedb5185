"""--time-limit reaches every part of a solve through its one budget: the LPs of a planar
search (its lanes in threads too), the cone programs in space, the GA's evaluations in
worker threads, and the Ipopt starts (their limit in wall time). Each run
is stopped within 2 s of the limit (1 s more of slack for a loaded test machine), with a
certified state or an honest status."""
import os
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from lamodel.geometry import running_bond_wall
from lamodel.io.jsonspec import structure_from_json
from lamodel.search.driver import SolveOptions, solve

pytestmark = pytest.mark.slow
SLACK = 2.0 + 1.0


def bond(courses, width):
    rows = [[0.5] + [1] * (width - 1) + [0.5] if r % 2 == 0 else [1] * width for r in range(courses)]
    return structure_from_json(running_bond_wall(rows, name=f"bond{courses}x{width}"))


def timed(structure, **options):
    t = time.perf_counter()
    o = solve(structure, SolveOptions(progress=False, **options))
    return o, time.perf_counter() - t


def test_a_solve_in_space_stops_at_its_limit():
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "space"))
    from cases3d import case_specs
    from lamodel.io.json3d import structure3d_from_spec
    s = structure3d_from_spec(case_specs()["building_mu0.9"])  # certified at 0.6 s, ends at 10 s
    o, took = timed(s, time_limit=2.0)
    assert took < 2.0 + SLACK, took
    assert o.status in ("certified", "not_certified") and "time limit" in o.message, o.message


def test_a_planar_solve_stops_at_its_limit():
    """A 488-block running-bond wall, whose search runs for longer than 2 s (its
    continuation lanes in worker threads at 2 s, idle or loaded), stopped at the limit by
    the LPs' interrupt callback."""
    o, took = timed(bond(16, 30), time_limit=2.0, starts=0, generations=10_000)
    assert took < 2.0 + SLACK, took
    assert o.status in ("certified", "not_certified") and "time limit" in o.message, o.message
    assert o.runs[0].status.endswith("time limit"), o.runs[0].status


def test_the_ga_in_worker_threads_stops_at_the_limit():
    """A GA of 80 individuals a generation on a 255-block wall (7.5 s of evaluations after
    2-5 s of the search's other phases, idle or loaded), stopped at 8 s while it runs."""
    s = bond(10, 25)
    o, took = timed(s, time_limit=8.0, starts=0, ga_workers=2, generations=10_000, pop_size=80)
    assert took < 8.0 + SLACK, took
    assert o.status in ("certified", "not_certified") and "time limit" in o.message, o.message
    assert o.phases.get("ga", 0.0) > 0.0  # stopped in the GA's evaluations


def test_an_ipopt_start_stops_at_the_limit_in_wall_time():
    """An Ipopt start told to converge to 1e-30 (it never does) on an 84-block wall: given
    its share of the limit (its estimated cost fits in half of it), it is stopped inside its
    iterations at the limit, not after its own CPU seconds."""
    never = {"tol": 1e-30, "acceptable_tol": 1e-30, "acceptable_iter": 10**6, "max_iter": 10**7,
             "constr_viol_tol": 1e-30, "acceptable_constr_viol_tol": 1e-30}
    o, took = timed(bond(8, 10), time_limit=15.0, starts=2, workers=1, ipopt_options=never)
    assert took < 15.0 + SLACK, took
    assert o.status == "certified", o.message  # the search's own certificate stands
    assert [r.status for r in o.runs if r.source.startswith("ipopt from")] == ["time limit"], o.runs


def test_an_ipopt_executable_is_stopped_at_the_limit_in_wall_time(tmp_path, monkeypatch):
    """Pyomo's path to an ``ipopt`` executable: Ipopt 3.11's own limit counts CPU seconds,
    which an executable blocked (here: one that sleeps, spending none) never reaches; the
    process is ended at the wall time left."""
    from lamodel.formulation.model import create_model
    from lamodel.search.ipopt import ipopt_ladder
    from lamodel.search.options import Deadline
    from lamodel.search.state import CollapseState
    exe = tmp_path / "ipopt"
    exe.write_text('#!/bin/sh\nif [ "$1" = "-v" ]; then echo "Ipopt 3.11.9 (x86_64-pc-linux-gnu)"; exit 0; fi\n'
                   'exec sleep 60\n')
    exe.chmod(0o755)
    monkeypatch.setenv("PATH", f"{tmp_path}:{os.environ['PATH']}")
    s = bond(3, 4)
    model = create_model(s)
    nc, nb = s.n_contacts, s.n_blocks
    start = CollapseState(0.0, np.zeros(nc), np.zeros(nc), np.zeros(nc), np.zeros(3 * nb), np.zeros(4 * nc),
                          np.zeros(4 * nc, bool))
    t = time.perf_counter()
    _, message, _ = ipopt_ladder(model, None, s, start, deadline=Deadline.after(1.5))
    took = time.perf_counter() - t
    assert message == "time limit", message
    assert took < 1.5 + SLACK, took
