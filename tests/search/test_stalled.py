"""A search that certifies nothing says how near it came: the alpha of its step nearest a
collapse state and that step's relative complementarity gap (summary.csv's alpha_stalled
and gap_stalled), and the joints that hold the gap, in words; alpha itself stays empty."""
import dataclasses

import numpy as np
import pytest

from lamodel.output.extras import words_of
from lamodel.output.report import outcome_results
from lamodel.search.driver import SolveOptions, solve
from lamodel.search.gap import GapSearch


def test_the_alternation_keeps_its_step_of_least_relative_gap(wall33):
    engine = GapSearch(wall33)
    status, x = engine.problem.statics(maximize=True)  # the associative statics
    assert status == "optimal"
    seen = []
    note = engine.record.note_gap
    engine.record.note_gap = lambda alpha, gap, rows: (seen.append((alpha, gap)), note(alpha, gap, rows))
    engine.alternation.alternate(x, max_steps=3)
    assert seen
    alpha, alpha_k, rel, rows = engine.record.stall
    rels = [g / (a + g) for a, g in seen]
    assert rel == pytest.approx(min(rels)) and alpha_k == pytest.approx(alpha + rel * alpha_k)
    assert 0.0 <= rel < 1.0 and np.all((0 <= rows) & (rows < 4 * wall33.n_contacts))


def test_an_uncertified_outcome_reports_the_stall_never_as_alpha(wall33):
    out = solve(wall33, SolveOptions(starts=0, time_limit=1e-3))  # stopped before any certificate
    assert out.best is None
    rows = np.array([1, 4 * wall33.n_contacts + 1, 2])  # two rows of the second contact, one of the third
    out = dataclasses.replace(out, stalled=(0.61, 0.65, 0.04 / 0.65, rows))
    results = outcome_results(out)
    row = results.summary.iloc[0]
    assert np.isnan(row["alpha"]) and not row["certified"]
    assert row["alpha_stalled"] == 0.61 and row["gap_stalled"] == pytest.approx(0.04 / 0.65)
    words = " ".join(words_of(out, results))
    assert "alpha = 0.61 " in words and "alpha_K = 0.65" in words
    assert f"{wall33.contacts[1]}, {wall33.contacts[2]} (2)" in words
    assert "never reported as alpha" in words


def test_a_certified_outcome_has_no_stall(wall33):
    out = solve(wall33, SolveOptions(starts=0))
    row = outcome_results(out).summary.iloc[0]
    assert row["certified"] and np.isnan(row["alpha_stalled"]) and np.isnan(row["gap_stalled"])
