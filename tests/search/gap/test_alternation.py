"""The gap alternation from the associative statics."""
import numpy as np

from lamodel.search.gap import GapSearch

from .helpers import collapse_violation, wall
from lamodel.search.gap.phases import associative


def test_the_alternation_reaches_a_certified_state_below_the_associative_bound():
    s = wall(10)
    e = GapSearch(s)
    p = e.problem
    _, a_assoc, x0 = associative(e)
    best, x = e.alternation.alternate(x0)
    assert best is not None and best.alpha <= a_assoc + 1e-9
    assert collapse_violation(s, p.to_user(best)) <= 1e-7
    # the last statics is admissible (lambda >= 0) and its gap for its own mechanism small
    assert (x >= 0).all()
    status, _, _, u, xi = p.mechanism(-p.mu * p.N_of(x))
    assert status == "optimal" and p.gap_weights(xi) @ x[:p.nl] <= 1e-6 * max(1.0, x[-1])
    assert "alternate" in e.record.phases


def test_flow_on_slack_rows_forbidden_still_certifies():
    s = wall(6)
    e = GapSearch(s)
    _, a_assoc, x0 = associative(e)
    best, _ = e.alternation.alternate(x0, forbid_slack=True)
    assert best is None or (best.alpha <= a_assoc + 1e-9 and collapse_violation(s, e.problem.to_user(best)) <= 1e-7)
    assert np.isfinite(a_assoc)
