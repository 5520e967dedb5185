"""A bridge from Pyomo to Ipopt (through cyipopt) for quadratically constrained models.

Debian's ``coinor-libipopt-dev`` ships Ipopt as a library only: no ``ipopt`` executable and
no AMPL Solver Library, so Pyomo's own ``SolverFactory('ipopt')`` finds nothing here. This
module compiles a Pyomo model whose objective and constraints are at most quadratic into
sparse matrices, hands Ipopt exact first and second derivatives, and loads the primal
solution and the multipliers back into the model.

It is registered as the Pyomo solver ``'lamodel_ipopt'``::

    from pyomo.environ import SolverFactory
    import lamodel.solvers.bridge  # registers the plugin
    opt = SolverFactory('lamodel_ipopt')
    opt.options['tol'] = 1e-8           # any Ipopt option passes through
    results = opt.solve(model)

Duals follow Pyomo's convention (``model.dual[c]`` is d(objective)/d(bound) at the
optimum); bound multipliers go to ``model.rc`` when that Suffix exists.
"""
from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp
from pyomo.core.base.block import BlockData
from pyomo.environ import Constraint, Objective, Suffix, maximize, value
from pyomo.opt import SolverFactory, SolverResults, SolverStatus, TerminationCondition
from pyomo.repn import generate_standard_repn

from ..errors import SolverError

INF = 1e20  # Ipopt takes |bound| >= 1e19 as no bound

# Ipopt's ApplicationReturnStatus -> (Pyomo solver status, termination condition)
_STATUS = {
    0: (SolverStatus.ok, TerminationCondition.optimal),
    1: (SolverStatus.warning, TerminationCondition.locallyOptimal),  # solved to acceptable level
    2: (SolverStatus.warning, TerminationCondition.infeasible),
    3: (SolverStatus.warning, TerminationCondition.other),  # search direction too small
    4: (SolverStatus.warning, TerminationCondition.unbounded),  # diverging iterates
    5: (SolverStatus.aborted, TerminationCondition.userInterrupt),
    6: (SolverStatus.warning, TerminationCondition.other),  # feasible point found
    -1: (SolverStatus.warning, TerminationCondition.maxIterations),
    -2: (SolverStatus.warning, TerminationCondition.other),  # restoration failed
    -3: (SolverStatus.error, TerminationCondition.error),
    -4: (SolverStatus.warning, TerminationCondition.maxTimeLimit),
    -5: (SolverStatus.warning, TerminationCondition.maxTimeLimit),  # max_wall_time (Ipopt 3.14's code)
    -10: (SolverStatus.error, TerminationCondition.error),  # not enough degrees of freedom
    -11: (SolverStatus.error, TerminationCondition.error),  # invalid problem definition
    -12: (SolverStatus.error, TerminationCondition.error),  # invalid option
    -13: (SolverStatus.error, TerminationCondition.error),  # invalid number detected
}


def ipopt_available() -> bool:
    try:
        import cyipopt  # noqa: F401
    except ImportError:
        return False
    return True


class _Quadratic:
    """sum_l a_l x_{i_l} + sum_q c_q x_{j_q} x_{k_q} + constant, for many rows at once."""

    def __init__(self, nrows, nvars, lin_rows, lin_cols, lin_vals, q_rows, q_i, q_j, q_c):
        self.nrows, self.nvars = nrows, nvars
        self.A = sp.csr_matrix((lin_vals, (lin_rows, lin_cols)), shape=(nrows, nvars))
        self.q_rows = np.asarray(q_rows, dtype=np.int64)
        self.q_i = np.asarray(q_i, dtype=np.int64)
        self.q_j = np.asarray(q_j, dtype=np.int64)
        self.q_c = np.asarray(q_c, dtype=float)
        # Jacobian pattern: linear part plus d/dx_i (c x_i x_j) = c x_j and d/dx_j = c x_i.
        A = self.A.tocoo()
        rows = np.concatenate([A.row, self.q_rows, self.q_rows])
        cols = np.concatenate([A.col, self.q_i, self.q_j])
        keys = rows * nvars + cols
        self.jac_keys, self._jac_pos = np.unique(keys, return_inverse=True)
        self.jac_rows = self.jac_keys // nvars
        self.jac_cols = self.jac_keys % nvars
        self._jac_lin = A.data
        # Hessian of row r: c (e_i e_j^T + e_j e_i^T); lower triangle holds c once (i != j)
        # or 2c (i == j).
        lo = np.maximum(self.q_i, self.q_j)
        hi = np.minimum(self.q_i, self.q_j)
        self.h_keys = lo * nvars + hi
        self.h_coef = np.where(self.q_i == self.q_j, 2.0, 1.0) * self.q_c

    def values(self, x):
        v = self.A @ x
        if self.q_c.size:
            v += np.bincount(self.q_rows, self.q_c * x[self.q_i] * x[self.q_j], minlength=self.nrows)
        return v

    def jacobian_values(self, x):
        vals = np.concatenate([self._jac_lin, self.q_c * x[self.q_j], self.q_c * x[self.q_i]])
        return np.bincount(self._jac_pos, vals, minlength=self.jac_keys.size)


class QuadraticNLP:
    """A Pyomo model compiled once into sparse arrays; solved with Ipopt many times.

    The body of every active constraint and the objective are read with Pyomo's
    ``generate_standard_repn`` (mutable parameters in bodies take their values at compile
    time); variable bounds, constraint bounds and fixed values are re-read at every
    :meth:`solve`, so warm-started sequences that move bounds need no recompilation.
    """

    def __init__(self, model: BlockData):
        self.model = model
        objs = list(model.component_data_objects(Objective, active=True, descend_into=True))
        if len(objs) != 1:
            raise SolverError(f"model '{model.name}' has {len(objs)} active objectives; expected exactly one")
        self.objective = objs[0]
        self.sense = -1.0 if self.objective.sense == maximize else 1.0
        self.constraints = list(model.component_data_objects(Constraint, active=True, descend_into=True))

        var_index = {}
        self.variables = []

        def col(v):
            i = var_index.get(id(v))
            if i is None:
                i = var_index[id(v)] = len(self.variables)
                self.variables.append(v)
            return i

        def read(expr, where):
            repn = generate_standard_repn(expr, quadratic=True, compute_values=True)
            if repn.nonlinear_expr is not None:
                raise SolverError(f"{where} has terms beyond quadratic; lamodel_ipopt solves linear and quadratic models only")
            lin = [(col(v), float(c)) for v, c in zip(repn.linear_vars, repn.linear_coefs)]
            quad = [(col(v1), col(v2), float(c)) for (v1, v2), c in zip(repn.quadratic_vars, repn.quadratic_coefs)]
            return lin, quad, float(value(repn.constant))

        lin_r, lin_c, lin_v, q_r, q_i, q_j, q_c, const = [], [], [], [], [], [], [], []
        for r, con in enumerate(self.constraints):
            lin, quad, c0 = read(con.body, f"constraint '{con.name}'")
            for i, a in lin:
                lin_r.append(r), lin_c.append(i), lin_v.append(a)
            for i, j, a in quad:
                q_r.append(r), q_i.append(i), q_j.append(j), q_c.append(a)
            const.append(c0)
        olin, oquad, self.obj_const = read(self.objective.expr, f"objective '{self.objective.name}'")
        n = len(self.variables)
        self.g = _Quadratic(len(self.constraints), n, lin_r, lin_c, lin_v, q_r, q_i, q_j, q_c)
        self.g_const = np.asarray(const, dtype=float)
        self.f = _Quadratic(1, n, [0] * len(olin), [i for i, _ in olin], [a for _, a in olin],
                            [0] * len(oquad), [i for i, _, _ in oquad], [j for _, j, _ in oquad],
                            [a for _, _, a in oquad])
        # Hessian of the Lagrangian: objective terms then constraint terms, merged.
        keys = np.concatenate([self.f.h_keys, self.g.h_keys])
        self.h_keys, self._h_pos = np.unique(keys, return_inverse=True)
        self.h_rows, self.h_cols = self.h_keys // max(n, 1), self.h_keys % max(n, 1)

    # ------------------------------------------------------------------ Ipopt callbacks
    def objective_value(self, x):
        return self.sense * (self.f.values(x)[0] + self.obj_const)

    def gradient(self, x):
        grad = np.zeros(len(self.variables))
        np.add.at(grad, self.f.jac_cols, self.f.jacobian_values(x))
        return self.sense * grad

    def constraint_values(self, x):
        return self.g.values(x)

    def jacobianstructure(self):
        return self.g.jac_rows, self.g.jac_cols

    def jacobian(self, x):
        return self.g.jacobian_values(x)

    def hessianstructure(self):
        return self.h_rows, self.h_cols

    def hessian(self, x, lagrange, obj_factor):
        w = np.concatenate([obj_factor * self.sense * self.f.h_coef, lagrange[self.g.q_rows] * self.g.h_coef])
        return np.bincount(self._h_pos, w, minlength=self.h_keys.size)

    # --------------------------------------------------------------------------- solve
    def bounds(self):
        def num(v, default):
            return default if v is None else float(value(v))

        xl = np.array([num(v.lb, -INF) for v in self.variables])
        xu = np.array([num(v.ub, INF) for v in self.variables])
        for i, v in enumerate(self.variables):
            if v.fixed:  # a fixed variable after compilation: pin it with equal bounds
                xl[i] = xu[i] = float(v.value)
        cl = np.array([num(c.lower, -INF) for c in self.constraints]) - self.g_const
        cu = np.array([num(c.upper, INF) for c in self.constraints]) - self.g_const
        return xl, xu, cl, cu

    def start_point(self):
        xl, xu, _, _ = self.bounds()
        x = np.array([0.0 if v.value is None else float(v.value) for v in self.variables])
        return np.clip(x, xl, xu)

    def solve(self, x0=None, options=None, tee=False, load=True, multipliers=None, stop=None):
        """Run Ipopt from x0 (default: the variables' current values).

        ``multipliers`` = (mult_g, mult_x_L, mult_x_U) of an earlier solve warm-starts the
        duals too (with Ipopt's ``warm_start_init_point yes``). ``stop``: a callable asked
        at every iteration; True ends the solve there (Ipopt's status 5, "user stop"): the
        way to a limit in wall time, which Debian's Ipopt 3.11 lacks (its ``max_cpu_time``
        counts CPU seconds, fewer than the wall's on a loaded machine). The option
        ``max_wall_time`` (Ipopt 3.14's name) is honoured so.

        Returns a dict with x, status (Ipopt's code), message, objective, iterations,
        seconds, mult_g (Ipopt's sign: L = f + mult_g^T g), mult_x_L, mult_x_U.
        """
        import cyipopt

        xl, xu, cl, cu = self.bounds()
        x0 = self.start_point() if x0 is None else np.clip(np.asarray(x0, dtype=float), xl, xu)
        options = dict(options or {})
        wall = options.pop("max_wall_time", None)
        start = time.perf_counter()
        if wall is not None:
            stop = _within(start + float(wall), stop)
        nlp = _Callbacks(self, stop)
        problem = cyipopt.Problem(n=len(x0), m=len(cl), problem_obj=nlp, lb=xl, ub=xu, cl=cl, cu=cu)
        problem.add_option("print_level", 5 if tee else 0)
        problem.add_option("sb", "yes")  # no banner
        for k, v in options.items():
            problem.add_option(k, v)
        if multipliers is None:
            x, info = problem.solve(x0)
        else:
            lam, zl, zu = multipliers
            x, info = problem.solve(x0, lagrange=np.asarray(lam), zl=np.asarray(zl), zu=np.asarray(zu))
        seconds = time.perf_counter() - start
        status = int(info["status"])
        message = info["status_msg"].decode() if isinstance(info["status_msg"], bytes) else str(info["status_msg"])
        if status == 5 and wall is not None and seconds > float(wall):
            status, message = -5, "Maximum wall time exceeded."
        out = dict(x=np.asarray(x), status=status, message=message,
                   objective=self.sense * float(info["obj_val"]), iterations=nlp.iterations, seconds=seconds,
                   mult_g=np.asarray(info["mult_g"]), mult_x_L=np.asarray(info["mult_x_L"]),
                   mult_x_U=np.asarray(info["mult_x_U"]), g=np.asarray(info["g"]))
        if load:
            self.load(out)
        return out

    def load(self, out):
        """Write the primal point, and duals/reduced costs where Suffixes ask for them."""
        for v, xv in zip(self.variables, out["x"]):
            if not v.fixed:
                v.set_value(float(xv), skip_validation=True)
        duals = _import_suffix(self.model, "dual")
        if duals is not None:
            for c, lam in zip(self.constraints, out["mult_g"]):
                duals[c] = -self.sense * float(lam)
        rc = _import_suffix(self.model, "rc")
        if rc is not None:
            for v, zl, zu in zip(self.variables, out["mult_x_L"], out["mult_x_U"]):
                rc[v] = self.sense * float(zl - zu)


def _within(end: float, stop=None):
    """A stop that is True past ``end`` (on ``time.perf_counter``) or when ``stop`` is."""
    return lambda: time.perf_counter() > end or (stop is not None and bool(stop()))


class _Callbacks:
    """The object cyipopt calls; counts iterations, and ends the solve when ``stop()``."""

    def __init__(self, nlp: QuadraticNLP, stop=None):
        self.nlp = nlp
        self.stop = stop
        self.iterations = 0
        self.objective = nlp.objective_value
        self.gradient = nlp.gradient
        self.constraints = nlp.constraint_values
        self.jacobian = nlp.jacobian
        self.jacobianstructure = nlp.jacobianstructure
        self.hessianstructure = nlp.hessianstructure
        self.hessian = nlp.hessian

    def intermediate(self, alg_mod, iter_count, *args):
        self.iterations = int(iter_count)
        return self.stop is None or not self.stop()


def _import_suffix(block, name):
    """The Suffix `name` declared for import on the block or one of its parents."""
    b = block
    while b is not None:
        s = b.component(name)
        if isinstance(s, Suffix) and s.import_enabled():
            return s
        b = b.parent_block()
    return None


@SolverFactory.register("lamodel_ipopt", doc="Ipopt through cyipopt for linear and quadratic Pyomo models (lamodel)")
class LamodelIpopt:
    """Pyomo solver plugin: ``SolverFactory('lamodel_ipopt').solve(model)``."""

    def __init__(self, **kwds):
        self.options = dict(kwds.pop("options", None) or {})
        self.name = "lamodel_ipopt"

    def available(self, exception_flag=False):
        ok = ipopt_available()
        if not ok and exception_flag:
            raise SolverError("cyipopt is not installed; run 'make setup'")
        return ok

    def license_is_valid(self):
        return True

    def version(self):
        import cyipopt
        return tuple(int(p) for p in cyipopt.__version__.split(".")[:3] if p.isdigit())

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def solve(self, model, tee=False, load_solutions=True, options=None, **kwds):
        nlp = QuadraticNLP(model)
        opts = dict(self.options)
        opts.update(options or {})
        out = nlp.solve(options=opts, tee=tee, load=False)
        status, term = _STATUS.get(out["status"], (SolverStatus.error, TerminationCondition.error))
        results = SolverResults()
        results.solver.name = self.name
        results.solver.status = status
        results.solver.termination_condition = term
        results.solver.message = out["message"]
        results.solver.return_code = out["status"]
        results.solver.time = out["seconds"]
        results.solver.iterations = out["iterations"]
        results.problem.number_of_variables = len(nlp.variables)
        results.problem.number_of_constraints = len(nlp.constraints)
        results.problem.lower_bound = results.problem.upper_bound = out["objective"]
        if load_solutions and term not in (TerminationCondition.error,):
            nlp.load(out)
        return results
