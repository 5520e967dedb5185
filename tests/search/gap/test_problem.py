"""The scaled LPs: statics in generator form, the mechanism, the way back to user units."""
import pytest

from lamodel.search.gap import GapSearch
from lamodel.search.gap.problem import ScaledProblem

from .helpers import bond, collapse_violation, wall
from lamodel.search.gap.phases import associative
from lamodel.search.plan import first_certificate


def _first_certificate(structure):
    e = GapSearch(structure)
    _, _, x0 = associative(e)
    first_certificate(e, x0)
    assert e.record.best is not None
    return e


def test_the_associative_statics_and_its_mechanism():
    """max alpha over S is the associative bound; the cohesive LP for its normal forces
    gives a mechanism with fbar^T u = 1 and flows >= 0."""
    p = ScaledProblem(wall(6))
    status, x = p.statics(maximize=True)
    assert status == "optimal" and x[-1] > 0
    status, a_as, _, u, xi = p.mechanism(-p.mu * p.N_of(x))
    assert status == "optimal" and a_as <= x[-1] + 1e-9
    assert p.fbar @ u == pytest.approx(1.0) and (xi >= 0).all() and xi.any()
    assert p.gap_weights(xi) @ x[:p.nl] >= -1e-12  # alpha_K - alpha >= 0 (virtual work)


def test_a_state_in_user_units_is_a_collapse_state_there():
    s = bond(4, width=6)
    e = _first_certificate(s)
    user = e.problem.to_user(e.record.best)
    assert user.alpha == e.record.best.alpha
    assert collapse_violation(s, user) <= 1e-7
    assert max(user.residual.values()) <= 1e-7
