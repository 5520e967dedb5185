"""The Pyomo model of eq. (5): components, .dat round trip, agreement with the numpy
matrices, a solved state checked independently, and the Block inside a user's model."""
import numpy as np
import pyomo.environ as pe
import pytest

import lamodel
from lamodel.io.datfile import read_dat, write_dat
from lamodel.formulation.model import create_abstract_model, create_model, get_state, set_state
from lamodel.structure import YIELD_ROWS
from oracle import equilibrium_residual
from lamodel.formulation.matrices import equilibrium_matrix, flow_matrix, load_vectors, yield_matrix

from conftest import INSTANCES, assert_same_structure


def test_wall33_component_counts(wall33):
    m = create_model(wall33)
    nb, nc = 33, 83
    assert (len(m.BLOCKS), len(m.CONTACTS), len(m.SUPPORTS)) == (nb, nc, 1)
    assert len(m.N) == len(m.V) == len(m.M) == nc
    assert len(m.xi) == 4 * nc
    assert len(m.ux) == len(m.uy) == len(m.theta) == nb
    assert len(m.equilibrium_x) + len(m.equilibrium_y) + len(m.equilibrium_moment) == 3 * nb
    assert len(m.yield_condition) == 4 * nc
    assert len(m.flow_opening) + len(m.flow_slip) + len(m.flow_rotation) == 3 * nc
    n_cons = len(list(m.component_data_objects(pe.Constraint, active=True)))
    assert n_cons == 3 * nb + 4 * nc + 3 * nc + 2  # + normalisation + bilinear condition
    assert m.alpha.lb == 0  # collapse under the given load, not its reverse
    assert all(v.ub is not None and v.ub > 0 for v in m.xi.values())


def test_dat_round_trip(tmp_path, wall33):
    path = tmp_path / "again.dat"
    write_dat(wall33, path)
    again = read_dat(path)
    assert_same_structure(again, wall33)
    assert set(again.polygons) == set(wall33.polygons)


def test_abstract_model_from_dat_equals_concrete_model(wall33):
    a = create_abstract_model().create_instance(str(INSTANCES / "wall33.dat"))
    c = create_model(wall33)
    assert list(a.CONTACTS) == list(c.CONTACTS)
    for name in ("cx", "cy", "nx", "ny", "d", "mu", "block_a", "block_b"):
        pa, pc = getattr(a, name), getattr(c, name)
        assert all(pa[k] == pc[k] for k in a.CONTACTS), name
    for name in ("x", "y", "dead_x", "dead_y", "live_x", "live_y"):
        pa, pc = getattr(a, name), getattr(c, name)
        assert all(pa[j] == pc[j] for j in a.BLOCKS), name


def _body(con):
    """The residual of an equality, body - rhs, whatever side Pyomo moved terms to."""
    return pe.value(con.body) - pe.value(con.upper) if con.equality else pe.value(con.body)


@pytest.mark.slow
def test_model_rows_agree_with_numpy_matrices(wall33):
    """Two writings of eq. (1)-(5): Pyomo expressions and the sparse matrices of Structure."""
    s = wall33
    m = create_model(s)
    rng = np.random.default_rng(3)
    nb, nc = s.n_blocks, s.n_contacts
    N, V, M = -rng.random(nc), rng.normal(size=nc), rng.normal(size=nc)
    alpha, u, xi = 0.3, rng.normal(size=3 * nb), rng.random(4 * nc)
    set_state(m, s, N, V, M, alpha, u, xi)
    A = equilibrium_matrix(s)
    f0, fb = load_vectors(s)
    eq = A @ np.concatenate([N, V, M]) + f0 + alpha * fb
    for i, con in enumerate((m.equilibrium_x, m.equilibrium_y, m.equilibrium_moment)):
        assert np.allclose(np.abs([_body(con[j]) for j in s.blocks]), np.abs(eq[i::3]), atol=1e-12)
    Y = yield_matrix(s) @ np.concatenate([N, V, M])
    got = np.array([_body(m.yield_condition[k, r]) for r in YIELD_ROWS for k in s.contacts])
    assert np.allclose(got, Y)
    # compatibility: relative displacements (-A^T u) equal the flow G^T xi row by row
    q = -(A.T @ u)
    flow = flow_matrix(s).T @ xi
    from lamodel.formulation.model import relative_displacement
    rel = np.array([[pe.value(x) for x in relative_displacement(m, k)] for k in s.contacts])
    assert np.allclose(rel.T.ravel(), q, atol=1e-12)
    for i, con in enumerate((m.flow_opening, m.flow_slip, m.flow_rotation)):
        got = np.abs([_body(con[k]) for k in s.contacts])
        assert np.allclose(got, np.abs(q[i * nc:(i + 1) * nc] - flow[i * nc:(i + 1) * nc]), atol=1e-12), con.name
    assert get_state(m, s)[4] == pytest.approx(u)


def test_solved_stack_is_in_equilibrium_and_overturns_at_the_known_multiplier(stack):
    m = create_model(stack)
    m.epsilon = 1e-7
    res = pe.SolverFactory("lamodel_ipopt").solve(m, options={"bound_relax_factor": 0.0})
    assert res.solver.termination_condition in (pe.TerminationCondition.optimal,
                                                pe.TerminationCondition.locallyOptimal)
    N, V, M, alpha, u, xi = get_state(m, stack)
    assert equilibrium_residual(stack, N, V, M, alpha) < 1e-6
    assert (N <= 1e-9).all() and (np.abs(V) <= -stack.mu * N + 1e-7).all()
    assert (np.abs(M) <= -stack.d * N + 1e-7).all()
    # two unit blocks overturning together about the toe: alpha = 1 / 2
    assert alpha == pytest.approx(0.5, abs=1e-5)


def test_block_inside_a_users_model(stack):
    """A user's study: a horizontal tie at the top block, whose force T the user pays for,
    must keep the collapse multiplier at or above 0.8."""
    from lamodel.search.certify import certify
    from lamodel.search.lp import LimitLPs
    m = pe.ConcreteModel()
    m.wall = lamodel.LimitAnalysisBlock(structure=stack, objective=False)
    m.T = pe.Var(bounds=(0, 10), initialize=0.0)
    top = stack.blocks[-1]
    w = m.wall
    w.extra_x[top] = -m.T  # the tie pulls the top block against the live load
    m.safe = pe.Constraint(expr=w.alpha >= 0.8)
    m.cost = pe.Objective(expr=m.T)
    w.epsilon = 1e-7
    res = pe.SolverFactory("lamodel_ipopt").solve(m, options={"bound_relax_factor": 0.0, "max_iter": 3000})
    assert res.solver.termination_condition in (pe.TerminationCondition.optimal,
                                                pe.TerminationCondition.locallyOptimal)
    # The stack overturns about its toe when alpha (0.5 + 1.5) = 1 + 1.5 T: alpha = 0.8 needs T = 0.4.
    T = pe.value(m.T)
    assert T == pytest.approx(0.4, abs=1e-4)
    assert pe.value(w.alpha) == pytest.approx(0.8, abs=1e-4)
    # The tie is part of f0: with it in the structure's dead loads, the point is an exact
    # collapse state (its work enters alpha_K, so the flow is complementary).
    tied = lamodel.Structure(**{**stack.__dict__, "dead": stack.dead + np.array([[0.0, 0.0], [-T, 0.0]])})
    N, V, M, alpha, u, xi = get_state(w, stack)
    state = certify(LimitLPs(tied), N, V, M, alpha, u, xi)
    assert state is not None and state.alpha == pytest.approx(0.8, abs=1e-4)


def test_block_rejects_a_missing_structure():
    m = pe.ConcreteModel()
    with pytest.raises(ValueError, match="expected a lamodel Structure"):
        m.wall = lamodel.LimitAnalysisBlock(structure="wall33.dat")
