"""Eq. (5) in space as a Pyomo model, solved by Ipopt through SolverFactory('lamodel_ipopt')."""
import numpy as np
import pytest
from pyomo.environ import ConcreteModel, Objective, SolverFactory, value

from builders3d import box_on_ground
from lamodel.formulation.model3d import LimitAnalysisBlock3D, create_model3d, get_state3d, set_state3d
from lamodel.formulation.space import Formulation3D
from lamodel.solvers.bridge import ipopt_available
from lamodel.search.search3d import solve3d

pytestmark = pytest.mark.skipif(not ipopt_available(), reason="cyipopt not installed")


def test_ipopt_polishes_a_perturbed_collapse_state_back_to_the_closed_form():
    s = box_on_ground(1.0, 0.5, 2.0, 0.6, (0.5, np.sqrt(3) / 2, 0.0))
    r = solve3d(s)
    m = create_model3d(s)
    set_state3d(m, r.state)
    m.alpha.set_value(r.alpha * 1.2)             # start away from the answer
    for p in m.POINTS:
        m.N[p].set_value(m.N[p].value * 1.1 - 0.01)
    res = SolverFactory("lamodel_ipopt").solve(m)
    assert str(res.solver.termination_condition) in ("optimal", "locallyOptimal")
    assert value(m.alpha) == pytest.approx(0.288675, abs=1e-5)
    N, T1, T2, alpha, u = get_state3d(m)
    f = Formulation3D.of(s)
    assert np.abs(f.A @ np.concatenate([N, T1, T2]) + f.f0 + alpha * f.fbar).max() < 1e-6
    assert (np.hypot(T1, T2) + 0.6 * N).max() < 1e-6


def test_block_inside_a_users_model():
    s = box_on_ground(1.0, 0.5, 2.0, 0.6, (1.0, 0.0, 0.0))
    m = ConcreteModel()
    m.box = LimitAnalysisBlock3D(structure=s, objective=False)
    m.obj = Objective(expr=m.box.alpha)
    assert len(m.box.equilibrium) == 6 and len(m.box.cone) == 4
    set_state3d(m.box, solve3d(s).state)
    SolverFactory("lamodel_ipopt").solve(m)
    assert value(m.box.alpha) == pytest.approx(0.5, abs=1e-5)
