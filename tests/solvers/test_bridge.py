"""The Pyomo -> Ipopt bridge on small QCQPs with known optima and duals."""
import math

import pyomo.environ as pe
import pytest
from pyomo.opt import TerminationCondition

import lamodel.solvers.bridge  # noqa: F401  registers the plugin
from lamodel.errors import SolverError


def solve(m, **options):
    opt = pe.SolverFactory("lamodel_ipopt")
    opt.options.update(options)
    return opt.solve(m)


def test_plugin_is_registered_and_available():
    opt = pe.SolverFactory("lamodel_ipopt")
    assert opt.available()


def test_qcqp_on_the_unit_disc_optimum_and_duals():
    # max x + 2y on the unit disc: x = 1/sqrt5, y = 2/sqrt5; the disc's multiplier is sqrt5/2
    m = pe.ConcreteModel()
    m.x = pe.Var(initialize=0.1)
    m.y = pe.Var(initialize=0.1)
    m.disc = pe.Constraint(expr=m.x ** 2 + m.y ** 2 <= 1)
    m.half = pe.Constraint(expr=m.x + m.y >= 0.5)
    m.obj = pe.Objective(expr=m.x + 2 * m.y, sense=pe.maximize)
    m.dual = pe.Suffix(direction=pe.Suffix.IMPORT)
    res = solve(m, tol=1e-10)
    assert res.solver.termination_condition == TerminationCondition.optimal
    assert pe.value(m.x) == pytest.approx(1 / math.sqrt(5), abs=1e-7)
    assert pe.value(m.y) == pytest.approx(2 / math.sqrt(5), abs=1e-7)
    # Pyomo's convention: d(objective)/d(upper bound of the disc) = +sqrt5/2 for a max
    assert m.dual[m.disc] == pytest.approx(math.sqrt(5) / 2, rel=1e-6)
    assert m.dual[m.half] == pytest.approx(0.0, abs=1e-7)


def test_bilinear_equality_and_bounds():
    # min x + y with x y = 4, x, y in [1, 10]: x = y = 2, multiplier of x y = 4 is -1/2 ... (d obj / d 4)
    m = pe.ConcreteModel()
    m.x = pe.Var(bounds=(1, 10), initialize=5)
    m.y = pe.Var(bounds=(1, 10), initialize=1)
    m.prod = pe.Constraint(expr=m.x * m.y == 4)
    m.obj = pe.Objective(expr=m.x + m.y)
    m.dual = pe.Suffix(direction=pe.Suffix.IMPORT)
    solve(m, tol=1e-10)
    assert (pe.value(m.x), pe.value(m.y)) == (pytest.approx(2, abs=1e-6), pytest.approx(2, abs=1e-6))
    # objective 2 sqrt(c): derivative 1/sqrt(c) = 1/2 at c = 4
    assert m.dual[m.prod] == pytest.approx(0.5, rel=1e-5)


def test_linear_program_duals_and_reduced_costs():
    m = pe.ConcreteModel()
    m.x = pe.Var(bounds=(0, None))
    m.y = pe.Var(bounds=(0, None))
    m.c1 = pe.Constraint(expr=m.x + m.y >= 2)
    m.c2 = pe.Constraint(expr=m.x - m.y <= 1)
    m.obj = pe.Objective(expr=2 * m.x + 3 * m.y)
    m.dual = pe.Suffix(direction=pe.Suffix.IMPORT)
    m.rc = pe.Suffix(direction=pe.Suffix.IMPORT)
    solve(m, tol=1e-10)
    # optimum x = 1.5, y = 0.5; duals 2.5 and -0.5
    assert pe.value(m.x) == pytest.approx(1.5, abs=1e-6)
    assert m.dual[m.c1] == pytest.approx(2.5, rel=1e-5)
    assert m.dual[m.c2] == pytest.approx(-0.5, rel=1e-5)
    assert m.rc[m.x] == pytest.approx(0.0, abs=1e-6)


def test_infeasible_model_is_reported():
    m = pe.ConcreteModel()
    m.x = pe.Var(initialize=0)
    m.y = pe.Var(initialize=0)
    m.disc = pe.Constraint(expr=m.x ** 2 + m.y ** 2 <= 1)
    m.far = pe.Constraint(expr=m.x >= 2)
    m.obj = pe.Objective(expr=m.y)
    res = solve(m, max_iter=500)
    assert res.solver.termination_condition == TerminationCondition.infeasible


def test_non_quadratic_term_names_the_constraint():
    m = pe.ConcreteModel()
    m.x = pe.Var(initialize=1)
    m.cubic = pe.Constraint(expr=m.x ** 3 <= 2)
    m.obj = pe.Objective(expr=m.x)
    with pytest.raises(SolverError, match="cubic"):
        solve(m)


def ellipse_model():
    """min (x - 3)^2 + x y on the ellipse x^2 + 2 y^2 <= 1, from far outside: a few iterations."""
    m = pe.ConcreteModel()
    m.x = pe.Var(initialize=3)
    m.y = pe.Var(initialize=-2)
    m.c = pe.Constraint(expr=m.x ** 2 + 2 * m.y ** 2 <= 1)
    m.obj = pe.Objective(expr=(m.x - 3) ** 2 + m.x * m.y)
    return m


def test_ipopt_options_pass_through():
    res = solve(ellipse_model(), max_iter=1)
    assert res.solver.termination_condition == TerminationCondition.maxIterations


def test_fixed_variables_are_held():
    m = pe.ConcreteModel()
    m.x = pe.Var(initialize=0)
    m.y = pe.Var(initialize=0)
    m.c = pe.Constraint(expr=m.x + m.y >= 3)
    m.obj = pe.Objective(expr=m.x ** 2 + m.y ** 2)
    m.y.fix(2.5)
    solve(m)
    assert pe.value(m.y) == 2.5
    assert pe.value(m.x) == pytest.approx(0.5, abs=1e-6)


def test_max_wall_time_stops_the_solve_in_wall_time():
    """Debian's Ipopt 3.11 has only max_cpu_time; max_wall_time (3.14's name) is honoured by
    asking the clock at every iteration."""
    m = ellipse_model()
    res = solve(m, max_wall_time=0.0)
    assert res.solver.termination_condition == TerminationCondition.maxTimeLimit
    assert res.solver.iterations == 0
    assert solve(m, max_wall_time=60.0).solver.termination_condition == TerminationCondition.optimal


def test_an_ipopt_start_ends_at_its_deadline_in_wall_time(wall33):
    """The polish's ladder asks the deadline at every Ipopt iteration: one that expires after
    a few questions ends the start there, said as the time limit."""
    from lamodel.formulation.model import create_model
    from lamodel.search.driver import solve as lamodel_solve
    from lamodel.search.ipopt import ipopt_ladder
    from lamodel.search.options import Deadline, SolveOptions
    from lamodel.solvers.bridge import QuadraticNLP
    start = lamodel_solve(wall33, SolveOptions(starts=0)).best
    asked = []
    deadline = Deadline(at=None, stop=lambda: asked.append(1) or len(asked) > 3)
    model = create_model(wall33)
    state, message, iterations = ipopt_ladder(model, QuadraticNLP(model), wall33, start, deadline=deadline)
    assert message == "time limit" and iterations <= 3
