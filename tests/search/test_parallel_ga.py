"""The GA's generations in parallel (issue 12): every evaluation a pure function of the
generation's snapshot and its genome, merged in task order, so the answer is the same
for any number of workers."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from lamodel.io import read
from lamodel.search.driver import solve
from lamodel.search.engine import GapSearch
from lamodel.search.options import SolveOptions

ROOT = Path(__file__).resolve().parents[2]
INSTANCES = ROOT / "instances"


def _after_first_certificate(name):
    e = GapSearch(read(INSTANCES / name), seed=0)
    _, _, x0 = e.start()
    e.N_assoc = e.N_of(x0)
    e.alternate(x0)
    assert e.best is not None
    return e


def test_an_evaluation_does_not_depend_on_what_its_engine_did_before():
    e = _after_first_certificate("wall55.dat")
    snap = e.snapshot()
    rng = np.random.default_rng(3)
    genomes = [s * rng.standard_normal(e.nc) for s in (0.1, 0.3, 1.0, 0.3, 1.0)]
    forward, backward = e.evaluator(), e.evaluator()
    a = [forward.evaluate_pure(snap, g) for g in genomes]
    b = [backward.evaluate_pure(snap, g) for g in genomes[::-1]][::-1]
    for (alpha_a, states_a, lps_a, _), (alpha_b, states_b, lps_b, _) in zip(a, b):
        assert alpha_a == alpha_b and lps_a == lps_b
        assert [s.alpha for s in states_a] == [s.alpha for s in states_b]
        for sa, sb in zip(states_a, states_b):
            assert np.array_equal(sa.N, sb.N) and np.array_equal(sa.u, sb.u)
    # and the snapshot belongs to the search: evaluating leaves it untouched
    assert e.snapshot()["reference_N"].tobytes() == snap["reference_N"].tobytes()


def test_merged_states_are_recorded_as_if_found_here():
    e = _after_first_certificate("wall55.dat")
    before, lps = e.best.alpha, e.n_lps()
    seen = []
    e.on_state = seen.append
    alpha, states, n, learned = e.evaluator().evaluate_pure(e.snapshot(), np.zeros(e.nc))
    e.merge(states, n, learned)
    assert e.n_lps() == lps + n and len(seen) == len(states)
    assert e.best.alpha <= min([before] + [s.alpha for s in states]) + 1e-15
    assert e.best_user is not None and max(e.best_user.residual.values()) <= 1e-7


@pytest.mark.parametrize("name", ["wall33.dat", "wall55.dat"])
def test_same_answer_for_any_number_of_workers(name):
    structure = read(INSTANCES / name)
    outs = [solve(structure, SolveOptions(seed=0, starts=0, ga_workers=w, pop_size=6, generations=3))
            for w in (1, 2, 3)]
    ref = outs[0]
    assert ref.status == "certified"
    for o in outs[1:]:
        assert o.best.alpha == ref.best.alpha
        assert [(a, src) for _, a, src in o.history] == [(a, src) for _, a, src in ref.history]
        assert o.runs[0].iterations == ref.runs[0].iterations  # the same LPs, counted
        for field in ("N", "V", "M", "u", "xi"):
            assert np.array_equal(getattr(o.best, field), getattr(ref.best, field)), field


def test_command_line_tables_identical_for_one_and_two_workers(tmp_path):
    """What a user compares: the CSV tables of `solve --workers 1` and `--workers 2`."""
    outs = []
    for w in (1, 2):
        out = tmp_path / f"w{w}"
        p = subprocess.run([sys.executable, str(ROOT / "scripts" / "solve.py"), str(INSTANCES / "wall33.dat"),
                            "--workers", str(w), "--starts", "0", "--out", str(out), "--no-plot", "--quiet"],
                           capture_output=True, text=True, timeout=300, cwd=ROOT)
        assert p.returncode == 0, p.stderr
        outs.append(out)
    for table in ("blocks.csv", "contacts.csv"):
        assert (outs[0] / table).read_bytes() == (outs[1] / table).read_bytes(), table
