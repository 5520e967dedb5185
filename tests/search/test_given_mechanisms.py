"""Mechanisms of the same blocks under other loads (a study's other load cases or positions):
certified first where a statics holds their rows, else the search goes on as without them;
a study solves again, from the certified variants' mechanisms, a variant it left uncertified."""
import dataclasses

import numpy as np
import pytest

from oracle import check_state

import lamodel.studies as studies
from lamodel.io.jsonspec import structure_from_json
from lamodel.loads import case_structure
from lamodel.search.canonical import canonical, mechanism_from_user, to_user
from lamodel.search.driver import SolveOptions, solve
from lamodel.search.state import CERTIFIED, NOT_CERTIFIED
from lamodel.search.tuning import RETRY_WORK

LP_ONLY = SolveOptions(starts=0, progress=False)


def rect(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


def stack(shuffled=False):
    """Two blocks on the ground (weights 1), a dead load of 0.5 on the top; three live
    loads (cases) along +x: at the top, at mid-height of the top block, at the lower one."""
    blocks = [{"id": "ground", "vertices": rect(-2, -1, 3, 0), "support": True},
              {"id": "b1", "vertices": rect(0, 0, 1, 1)}, {"id": "b2", "vertices": rect(0, 1, 1, 2)}]
    if shuffled:
        blocks = blocks[::-1]
    return structure_from_json({
        "name": "stack", "mu": 0.6, "blocks": blocks,
        "loads": [{"block": "b2", "at": [0, 2], "force": [1, 0], "case": "top"},
                  {"block": "b2", "at": [0, 1.5], "force": [1, 0], "case": "mid"},
                  {"block": "b1", "at": [0, 0.5], "force": [1, 0], "case": "low"},
                  {"block": "b2", "at": [0.5, 2], "force": [0, -0.5], "kind": "dead"}]})


def first_source(outcome):
    return outcome.history[0][2]


@pytest.mark.parametrize("shuffled", [False, True])
def test_the_overturning_of_one_load_certifies_another_load_at_once(shuffled):
    s = stack(shuffled)
    top = solve(case_structure(s, "top"), LP_ONLY)
    assert top.best.alpha == pytest.approx(1.25 / 2, rel=1e-9)   # 2 alpha = 0.5 + 0.5 + 0.25 about the toe
    mid = solve(case_structure(s, "mid"), LP_ONLY, mechanisms=[top.best])
    # the same mechanism (the stack about its toe) under the load 0.5 lower: 1.5 alpha = 1.25
    assert mid.best.alpha == pytest.approx(1.25 / 1.5, rel=1e-9)
    assert first_source(mid).startswith("given")
    assert mid.lps_first < solve(case_structure(s, "mid"), LP_ONLY).lps_first
    check_state(mid.structure, mid.best)


def test_a_mechanism_no_statics_holds_leaves_the_search_as_without_it():
    s = stack()
    top = solve(case_structure(s, "top"), LP_ONLY)
    alone = solve(case_structure(s, "low"), LP_ONLY)
    given = solve(case_structure(s, "low"), LP_ONLY, mechanisms=[top.best])
    # the stack overturning under a load at 0.5 needs alpha 2.5, beyond b1's friction (1.5)
    assert given.best.alpha == pytest.approx(alone.best.alpha, rel=1e-9) == pytest.approx(1.5, rel=1e-9)
    assert not first_source(given).startswith("given")


def test_a_mechanism_goes_to_the_canonical_order_and_back():
    s, order = canonical(stack(shuffled=True))
    assert order is not None
    o = solve(case_structure(stack(shuffled=True), "top"), LP_ONLY)
    u, xi = mechanism_from_user(o.best.u, o.best.xi, order)
    back = to_user(dataclasses.replace(o.best, u=u, xi=xi), order)
    assert np.array_equal(back.u, o.best.u) and np.array_equal(back.xi, o.best.xi)


def test_a_study_solves_an_uncertified_variant_again_from_the_others(monkeypatch):
    import lamodel.solve_all
    real, calls = studies.solve, []

    def solve_failing_once(structure, options=None, mechanisms=(), work_scale=1.0):
        calls.append((len(mechanisms), work_scale))
        out = real(structure, options, mechanisms=mechanisms, work_scale=work_scale)
        if len(calls) == 1:  # the first variant, first pass: as if the search had stalled
            return dataclasses.replace(out, status=NOT_CERTIFIED, best=None)
        return out

    monkeypatch.setattr(studies, "solve", solve_failing_once)
    monkeypatch.setattr(lamodel.solve_all, "solve", solve_failing_once)
    # (one variant after another, in this process: the patched solve runs here)
    df, outcomes = studies.load_case_study(stack(), dataclasses.replace(LP_ONLY, workers=1))
    # the second pass: the two certified variants' mechanisms, and more work
    assert calls == [(0, 1.0), (0, 1.0), (0, 1.0), (2, RETRY_WORK)] and RETRY_WORK > 1
    assert df["certified"].all() and outcomes["top"].status == CERTIFIED
    assert df.set_index("case").loc["top", "alpha_c"] == pytest.approx(0.625, rel=1e-9)


def test_more_work_is_more_work_bound():
    from lamodel.search.budget import Budget
    from lamodel.search.gap.problem import ScaledProblem
    p = ScaledProblem(case_structure(stack(), "top"))
    one, two = Budget.for_solve().count(p), Budget.for_solve(work_scale=2.0).count(p)
    assert two.whole_bound() == 2 * one.whole_bound() == 2 * p.work_bound()
    assert two.first_bound == 2 * one.first_bound and two.rule.total == 2 * one.rule.total
    assert Budget.for_solve(time_limit=5.0, work_scale=2.0).rule is None   # a time limit has no work bounds


def test_variants_side_by_side_give_what_one_after_another_gives():
    """A study's variants solved two at once in worker processes (each search on one core):
    the same multipliers, statuses and mechanisms as one after another in this process, in
    the variants' order; each outcome re-checked by the independent oracle."""
    import json

    from conftest import INSTANCES
    from lamodel.bridges import read_bridge
    from lamodel.bridges.adequacy import structure_of
    from lamodel.solve_all import solve_all
    spec = json.loads((INSTANCES / "bridge_demo.json").read_text())
    spec["load"]["positions"] = [-2.0, 0.4, 2.0]
    for structure in (stack(), structure_of(read_bridge(spec))):
        variants = [case_structure(structure, name) for name in structure.cases]
        seen = []
        side = solve_all(variants, dataclasses.replace(LP_ONLY, workers=2), lambda i, o: seen.append(i))
        one = solve_all(variants, dataclasses.replace(LP_ONLY, workers=1))
        assert sorted(seen) == list(range(len(variants)))
        for v, a, b in zip(variants, side, one):
            assert a.structure.name == v.name and a.status == b.status == CERTIFIED
            assert a.best.alpha == pytest.approx(b.best.alpha, rel=1e-9)
            assert np.array_equal(a.best.xi > 0, b.best.xi > 0)
            check_state(v, a.best)


def test_a_worker_that_dies_costs_its_variants_a_second_solve_not_the_study(caplog):
    """kill -9 of a worker process in the middle of a study side by side: the variants it
    took with it are solved again on new workers; every outcome is certified, as one after
    another."""
    import json
    import os
    import signal
    from pathlib import Path

    from conftest import INSTANCES, descendants
    from lamodel.bridges import read_bridge
    from lamodel.bridges.adequacy import structure_of
    from lamodel.solve_all import solve_all

    spec = json.loads((INSTANCES / "bridge_demo.json").read_text())
    spec["load"]["positions"] = [-2.4, -1.2, 0.4, 1.6, 2.8]
    s = structure_of(read_bridge(spec))
    variants = [case_structure(s, name) for name in s.cases]
    killed = []

    def kill_one(i, outcome):
        if not killed:  # a worker: a child of the forkserver (never the resource tracker beside it)
            servers = [p for p in descendants(os.getpid()) if b"forkserver" in Path(f"/proc/{p}/cmdline").read_bytes()]
            workers = sorted(set().union(*(descendants(p) for p in servers)))
            os.kill(workers[0], signal.SIGKILL)
            killed.append(i)
    side = solve_all(variants, dataclasses.replace(LP_ONLY, workers=2), kill_one)
    one = solve_all(variants, dataclasses.replace(LP_ONLY, workers=1))
    assert killed and "a worker process died; solving" in caplog.text
    for a, b in zip(side, one):
        assert a.status == b.status == CERTIFIED
        assert a.best.alpha == pytest.approx(b.best.alpha, rel=1e-9)


SCRIPT = '''
import json
from lamodel.io.jsonspec import structure_from_json
from lamodel.search.driver import SolveOptions
from lamodel.studies import load_case_study
{body}
'''
STUDY = ("df, _ = load_case_study(structure_from_json(json.loads(open({spec!r}).read())), "
         "SolveOptions(starts=0, progress=False, workers=2))\nprint(df['status'].tolist())")


@pytest.mark.parametrize("guarded", [True, False])
def test_a_script_that_solves_side_by_side_is_told_to_guard_its_main(tmp_path, guarded):
    """A user's script run as ``python script.py`` that starts a study side by side: under
    ``if __name__ == "__main__":`` it is solved; unguarded, its workers run the script again
    and cannot start, and the error names the cases and says why (not only "out of memory")."""
    import subprocess
    import sys
    import textwrap

    from lamodel.io.jsonspec import structure_to_json

    spec = tmp_path / "stack.json"
    structure_to_json(stack(), spec)
    study = STUDY.format(spec=str(spec))
    body = ("if __name__ == '__main__':\n" + textwrap.indent(study, "    ")) if guarded else study
    script = tmp_path / "study.py"
    script.write_text(SCRIPT.format(body=body))
    run = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300)
    if guarded:
        assert run.returncode == 0, run.stderr[-2000:]
        assert run.stdout.strip() == str([CERTIFIED] * 3)
    else:
        assert run.returncode != 0
        error = [line for line in run.stderr.splitlines() if line.startswith("RuntimeError: the worker")]
        assert error, run.stderr[-2000:]
        assert "died 2 times" in error[-1] and "case top" in error[-1] and "if __name__ ==" in error[-1]
