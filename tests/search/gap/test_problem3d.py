"""The cone formulation: statics, the cohesive mechanism, the gap, certificates in space."""
import numpy as np
import pytest

from builders3d import box_on_ground
from lamodel.search.certify3d import RESIDUAL_TOLERANCE
from lamodel.search.gap.problem3d import ConeProblem
from lamodel.search.options import Deadline, Stopped


def _tall_block(phi=90.0):
    p = np.radians(phi)
    return box_on_ground(1.0, 0.5, 2.0, 0.6, (np.cos(p), np.sin(p), 0.0))


def test_the_associative_statics_and_its_mechanism():
    """max alpha over S bounds alpha; the cohesive program for its normal forces gives a
    mechanism with fbar^T u = 1, flows >= 0 on rows of two kinds a point, and a gap >= 0
    equal to alpha_K - alpha (virtual work)."""
    p = ConeProblem(_tall_block())
    status, x = p.statics(maximize=True)
    assert status == "optimal" and x[-1] >= 0.25 - 1e-7
    N = p.N_of(x)
    status, a_as, xc, u, xi = p.mechanism(-p.mu * N)
    assert status == "optimal" and a_as <= x[-1] + 1e-6
    assert p.form.fbar @ u == pytest.approx(1.0) and xi.shape == (2 * p.np,) and (xi >= 0).all() and xi.any()
    q = p.form.strains(u)
    q[:p.np] = np.maximum(q[:p.np], 0.0)
    alpha_K = p.form.kinematic_multiplier(u, q, N)
    assert p.gap(x, xi, u) == pytest.approx(alpha_K - x[-1], abs=1e-6)
    assert p.gap(x, xi, u) >= -1e-7


def test_rows_are_openings_and_slides_and_held_rows_hold():
    p = ConeProblem(_tall_block())
    _, x = p.statics(maximize=True)
    slack = p.slack(x)
    assert slack.shape == (2 * p.np,) and slack.min() >= -1e-7
    _, _, _, u, xi = p.mechanism(-p.mu * p.N_of(x))
    held = xi > 0
    status, xh = p.statics(held=held, u=u)
    assert status == "optimal"
    assert p.slack(xh)[held].max() <= 1e-6 * max(1.0, np.abs(xh).max())


def test_a_certificate_is_exact_and_back_in_user_units():
    s = box_on_ground(2.0, 1.0, 4.0, 0.6, (0.0, 1.0, 0.0), weight=9.81)  # other units: same alpha
    p = ConeProblem(s)
    _, x = p.statics(maximize=True)
    _, _, _, u, xi = p.mechanism(-p.mu * p.N_of(x))
    found = None
    for xs, uc, xic, flow, tag in p.certificates(u, xi, xi > 0, None):
        st = p.state(xs, uc, xic, flow, "test" + tag)
        if max(st.residual.values()) <= RESIDUAL_TOLERANCE:
            found = st
            break
    assert found is not None and found.alpha == pytest.approx(0.25, abs=1e-9)
    assert found.flow.any() and tag in ("+certify-lp", "+certify-cone")
    user = p.to_user(found)
    assert user.alpha == found.alpha and max(user.residual.values()) <= RESIDUAL_TOLERANCE
    assert p.n_lps() >= 3 and p.lps == {} and p.bases() == {}


def test_the_pattern_tells_sliding_directions_apart():
    p = ConeProblem(box_on_ground(1.0, 1.0, 0.5, 0.6, (1.0, 0.0, 0.0)))
    flow = np.zeros(2 * p.np, bool)
    flow[p.np:] = True   # every point slides
    u = np.zeros(6 * p.nb)
    u[0] = 1.0
    v = np.zeros(6 * p.nb)
    v[1] = 1.0
    assert p.pattern(u, flow) != p.pattern(v, flow)
    assert p.pattern(u, flow) == p.pattern(u * 2.0, flow)


def test_a_fired_deadline_stops_a_program():
    d = Deadline.after(0.0)
    p = ConeProblem(_tall_block(), deadline=d)
    with pytest.raises(Stopped):
        p.statics(maximize=True)
