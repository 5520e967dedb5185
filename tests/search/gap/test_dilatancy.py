"""The dilatancy continuation: the fictitious systems whose sliding dilates by t mu, from the
associative one (t = 1) to the seed's (t = 0), in the plane and in space."""
import numpy as np
import pytest

from builders3d import box_on_ground, stack_of_boxes
from lamodel.formulation.matrices import dilatant_flows, flow_matrix
from lamodel.search.gap import GapSearch
from lamodel.search.gap.problem import ScaledProblem
from lamodel.search.gap.problem3d import ConeProblem

from .helpers import bond, collapse_violation, wall
from lamodel.search.gap.dilatancy import Dilatancy
from lamodel.search.gap.lanes import Start
from lamodel.search.gap.phases import associative


@pytest.mark.parametrize("t", [0.0, 0.3, 1.0])
def test_the_flows_rebuild_the_strains_of_their_flow_rule(t):
    """q = G_t^T xi with G_t the flow rows of dilatancy t (slides open by t mu |slip|):
    flows of one sign a pair, drawn at random, come back from their strains."""
    s = wall(6)
    nc = s.n_contacts
    rng = np.random.default_rng(1)
    slide = rng.random(nc) * (rng.random(nc) < 0.5)
    hinge = rng.random(nc) * (rng.random(nc) < 0.5)
    sign_s, sign_h = rng.random(nc) < 0.5, rng.random(nc) < 0.5
    xi = np.concatenate([np.where(sign_s, slide, 0), np.where(sign_s, 0, slide),
                         np.where(sign_h, hinge, 0), np.where(sign_h, 0, hinge)])
    G = flow_matrix(s).toarray()
    G[:2 * nc, :nc] = t * np.tile(np.diag(s.mu), (2, 1))  # the slides' dilatancy
    assert dilatant_flows(s, G.T @ xi, t) == pytest.approx(xi, abs=1e-12)
    if t == 0.0:
        assert np.allclose(G, flow_matrix(s).toarray())


@pytest.mark.parametrize("t", [0.2, 0.5, 0.9])
def test_a_dilatant_mechanism_keeps_the_gap_of_eq_5(t):
    """For every statics of S and the mechanism of dilatancy t at cohesions -(1 - t) mu N,
    alpha_K - alpha = slack^T xi, the weights the gap step minimises (virtual work)."""
    p = ScaledProblem(wall(6))
    for cost in (None, np.random.default_rng(2).random(p.nl)):
        status, x = p.statics(cost_lam=cost, maximize=cost is None)
        assert status == "optimal"
        status, a_k, _, u, xi = p.mechanism(-(1 - t) * p.mu * p.N_of(x), dilatancy=t)
        assert status == "optimal" and p.fbar @ u == pytest.approx(1.0) and (xi >= 0).all()
        assert p.gap(x, xi, u) == pytest.approx(a_k - x[-1], abs=1e-8)
        assert p.gap(x, xi, u) >= -1e-10


def test_at_full_dilatancy_the_system_is_the_associative_one():
    p = ScaledProblem(bond(4, width=6, mu=0.9))
    status, x = p.statics(maximize=True)
    status, a_k, _, u, xi = p.mechanism(np.zeros(p.nc), dilatancy=1.0)
    assert status == "optimal" and a_k == pytest.approx(x[-1], abs=1e-9)
    assert p.gap(x, xi, u) == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("t", [0.3, 0.8])
def test_in_space_a_dilatant_mechanism_keeps_the_gap(t):
    p = ConeProblem(stack_of_boxes(3, 1.0, 0.8, 0.6, mu=0.5))
    status, x = p.statics(maximize=True)
    assert status == "optimal"
    status, a_k, _, u, xi = p.mechanism(-(1 - t) * p.mu * p.N_of(x), dilatancy=t)
    assert status == "optimal" and p.form.fbar @ u == pytest.approx(1.0)
    assert p.gap(x, xi, u) == pytest.approx(a_k - x[-1], abs=1e-6) and p.gap(x, xi, u) >= -1e-7


@pytest.mark.parametrize("structure", [wall(6), bond(6, width=8, mu=1.0)], ids=["wall33", "bond6x8_mu1"])
def test_the_continuation_certifies_exact_collapse_states(structure):
    e = GapSearch(structure)
    _, _, x0 = associative(e)
    st = Dilatancy().run(e, Start(x0))
    assert st is not None and st.source.startswith("dilatancy")
    assert collapse_violation(structure, e.problem.to_user(st)) <= 1e-7
    assert Dilatancy().run(e, Start(x0)) is st  # once a search


def test_where_the_continuation_stalls_the_chain_from_its_stall_certifies():
    """At t = 0 the continuation can stall below every state it certified (a 10 x 10
    running-bond wall at mu = 0.9: no mechanism on the rows its statics holds); the seed's
    fixed-point chain from that stall then certifies an exact collapse state."""
    s = bond(10, width=10, mu=0.9)
    e = GapSearch(s)
    _, _, x0 = associative(e)
    st = Dilatancy().run(e, Start(x0))
    assert st is not None and st.source.startswith("dilatancy-fixed")
    assert collapse_violation(s, e.problem.to_user(st)) <= 1e-7


def test_the_continuation_in_space():
    s = box_on_ground(1.0, 0.5, 2.0, 0.6, (0.0, 1.0, 0.0))
    e = GapSearch(s)
    _, _, x0 = associative(e)
    st = Dilatancy().run(e, Start(x0))
    assert st is not None and st.alpha == pytest.approx(0.25, abs=1e-6)
