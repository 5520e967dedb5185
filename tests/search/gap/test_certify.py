"""The two-LP certificate of a mechanism."""
import numpy as np

from lamodel.search.gap import GapSearch

from .helpers import collapse_violation, wall
from lamodel.search.gap.phases import associative


def test_certification_needs_the_held_lambdas_at_zero_not_a_small_gap():
    """A mechanism flowing on rows no statics can hold all at once is refused, and one
    that the certification holds gives a state whose held lambdas are exactly zero."""
    e = GapSearch(wall(6))
    p = e.problem
    _, _, x0 = associative(e)
    best, _ = e.alternation.alternate(x0)
    assert best is not None
    lam = best.lam[:p.nl]
    assert np.all(lam[p.held_lams[best.flow].ravel()] == 0.0)
    # every row of the associative statics' rows allowed to flow at once: not holdable
    status, _, _, u, xi = p.mechanism(-p.mu * p.N_of(x0))
    flow_all = np.ones_like(xi, bool)
    assert e.certifier.held(u, np.where(flow_all, np.maximum(xi, 1e-3 * xi.max()), 0.0), flow_all, "t") is None


def test_a_certificate_is_cached_by_flow_pattern_and_told_to_the_record():
    s = wall(6)
    e = GapSearch(s)
    seen = []
    e.record.on_state = seen.append
    _, _, x0 = associative(e)
    best, _ = e.alternation.alternate(x0)
    n = len(seen)
    assert n >= 1 and e.record.best is not None
    lps = e.n_lps()
    again = e.certifier.certify(best.u, best.xi, "again")
    assert again is best and e.n_lps() == lps and len(seen) == n  # from the cache: no LP
    assert collapse_violation(s, e.record.best_user) <= 1e-7
