"""The linear programs around eq. (5), solved with HiGHS (warm-started between calls).

* :meth:`LimitLPs.associative` — max alpha over the statically admissible set S (eq. 1-4).
  It is the collapse multiplier of the associative (dilatant) assembly: an upper bound on
  every collapse multiplier of the frictional one.
* :meth:`LimitLPs.cohesive` — for given cohesions c, max alpha of the fictitious system
  (|V| <= c, |M| <= -d N): the multiplier alpha_as(c) of the seed. Its duals are a
  mechanism (u, xi) of that system. When c = -mu N of its own solution, it is a collapse
  state of the real system (the seed's second theorem).
* :meth:`LimitLPs.statics` — min (or max) alpha over S with chosen yield rows held at
  equality: the statics half of the certification.
* :meth:`LimitLPs.mechanism` — a mechanism (u, xi) of the fictitious system with fbar^T u = 1
  that flows only on chosen rows: the kinematics half of the certification.

Variables of the statics LPs are (N, V, M, alpha) in the order of eq. (3).
"""
from __future__ import annotations

from dataclasses import dataclass

import highspy
import numpy as np
import scipy.sparse as sp

from ..formulation.matrices import Formulation
from ..structure import Structure
from .highs import QuietHighs
from .options import Deadline

INF = highspy.kHighsInf
#: Feasibility tolerance of the LPs whose alpha is reported. HiGHS's default 1e-7 moves
#: alpha by ~2e-6 on a 200-block wall (measured); 1e-9 agrees across simplex and IPM to 1e-10.
#: The GA's screening LPs keep the faster default (``tolerance=None``).
TIGHT_TOLERANCE = 1e-9
#: LPs with more columns than this start with the interior point method
IPM_COLUMNS = 3000


@dataclass
class LPResult:
    status: str                    # 'optimal', 'infeasible', 'unbounded' or HiGHS's word
    alpha: float = np.nan
    x: np.ndarray | None = None    # primal columns
    row_dual: np.ndarray | None = None
    col_dual: np.ndarray | None = None

    @property
    def ok(self) -> bool:
        return self.status == "optimal"


class _HighsLP:
    """min c^T x, row_lo <= A x <= row_hi, col_lo <= x <= col_hi; kept for warm starts."""

    def __init__(self, cost, A, row_lo, row_hi, col_lo, col_hi, tolerance=None):
        A = sp.csc_matrix(A)
        self.h = QuietHighs()
        if tolerance is not None:
            for option in ("primal_feasibility_tolerance", "dual_feasibility_tolerance"):
                self.h.setOptionValue(option, float(tolerance))
        lp = highspy.HighsLp()
        lp.num_col_, lp.num_row_ = A.shape[1], A.shape[0]
        lp.col_cost_ = np.asarray(cost, dtype=float)
        lp.col_lower_, lp.col_upper_ = np.asarray(col_lo, dtype=float), np.asarray(col_hi, dtype=float)
        lp.row_lower_, lp.row_upper_ = np.asarray(row_lo, dtype=float), np.asarray(row_hi, dtype=float)
        lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
        lp.a_matrix_.start_ = A.indptr.astype(np.int32)
        lp.a_matrix_.index_ = A.indices.astype(np.int32)
        lp.a_matrix_.value_ = A.data.astype(float)
        self.h.passModel(lp)
        self.n, self.m = A.shape[1], A.shape[0]
        self.cold = True

    def set_col_bounds(self, idx, lo, hi):
        idx = np.asarray(idx, dtype=np.int32)
        self.h.changeColsBounds(idx.size, idx, np.asarray(lo, dtype=float), np.asarray(hi, dtype=float))

    def set_row_bounds(self, idx, lo, hi):
        idx = np.asarray(idx, dtype=np.int32)
        self.h.changeRowsBounds(idx.size, idx, np.asarray(lo, dtype=float), np.asarray(hi, dtype=float))

    def set_cost(self, cost):
        idx = np.arange(self.n, dtype=np.int32)
        self.h.changeColsCost(self.n, idx, np.asarray(cost, dtype=float))

    def solve(self):
        if self.cold and self.n > IPM_COLUMNS:
            # A cold simplex start on a large, degenerate statics LP takes minutes (820-block
            # wall: 104 s); the interior point method with crossover takes seconds (7.5 s)
            # and leaves a basis for the warm-started simplex re-solves that follow.
            self.h.setOptionValue("solver", "ipm")
            self.h.run()
            self.h.setOptionValue("solver", "simplex")
        else:
            self.h.run()
        self.cold = False
        status = self.h.getModelStatus()
        if status == highspy.HighsModelStatus.kOptimal:
            sol = self.h.getSolution()
            return "optimal", np.array(sol.col_value), np.array(sol.row_dual), np.array(sol.col_dual)
        if status == highspy.HighsModelStatus.kInfeasible:
            return "infeasible", None, None, None
        if status in (highspy.HighsModelStatus.kUnbounded, highspy.HighsModelStatus.kUnboundedOrInfeasible):
            # Tell the two apart: a basis-free re-solve settles it.
            return "unbounded" if status == highspy.HighsModelStatus.kUnbounded else "unbounded_or_infeasible", None, None, None
        if status == highspy.HighsModelStatus.kTimeLimit:
            return "time limit", None, None, None
        return self.h.modelStatusToString(status), None, None, None


class LimitLPs:
    """The LPs of one structure, built once and re-solved with new data."""

    def __init__(self, structure: Structure, tolerance: float | None = TIGHT_TOLERANCE,
                 formulation: Formulation | None = None):
        self.structure = s = structure
        self.tolerance = tolerance
        self.deadline = Deadline()  # after it, LPs stop with status "time limit"
        self.nb, self.nc = nb, nc = s.n_blocks, s.n_contacts
        self.formulation = F = formulation or Formulation.of(s)
        self.A, self.f0, self.fbar, self.Y, self.G = F.A, F.f0, F.fbar, F.Y, F.G
        self.nvar = 3 * nc + 1  # N, V, M, alpha
        E = sp.hstack([self.A, sp.csr_matrix(self.fbar.reshape(-1, 1))])
        Yrows = sp.hstack([self.Y, sp.csr_matrix((4 * nc, 1))])
        free = np.full(3 * nc, -INF), np.full(3 * nc, INF)
        # alpha >= 0 (collapse under the given live load, not under its reverse)
        col_lo, col_hi = np.append(free[0], 0.0), np.append(free[1], INF)
        cost = np.zeros(self.nvar)
        cost[-1] = -1.0  # max alpha
        # Real statics: equilibrium (= -f0) and all four yield rows (<= 0).
        self._statics = _HighsLP(cost, sp.vstack([E, Yrows]),
                                 np.concatenate([-self.f0, np.full(4 * nc, -INF)]),
                                 np.concatenate([-self.f0, np.zeros(4 * nc)]), col_lo, col_hi, tolerance)
        # Fictitious cohesive statics: equilibrium and the hinge rows; |V| <= c as column bounds.
        self._cohesive = _HighsLP(cost, sp.vstack([E, Yrows[2 * nc:]]),
                                  np.concatenate([-self.f0, np.full(2 * nc, -INF)]),
                                  np.concatenate([-self.f0, np.zeros(2 * nc)]), col_lo, col_hi, tolerance)
        # Mechanisms: columns (u, xi); compatibility -A^T u - G^T xi = 0 and fbar^T u = 1.
        K = sp.vstack([sp.hstack([-self.A.T, -self.G.T]),
                       sp.hstack([sp.csr_matrix(self.fbar.reshape(1, -1)), sp.csr_matrix((1, 4 * nc))])])
        self._mech = _HighsLP(np.zeros(3 * nb + 4 * nc), K, np.append(np.zeros(3 * nc), 1.0),
                              np.append(np.zeros(3 * nc), 1.0),
                              np.concatenate([np.full(3 * nb, -INF), np.zeros(4 * nc)]),
                              np.concatenate([np.full(3 * nb, INF), np.full(4 * nc, INF)]), tolerance)
        self.n_solves = 0

    # ------------------------------------------------------------------------ pieces
    def split(self, x):
        nc = self.nc
        return x[:nc], x[nc:2 * nc], x[2 * nc:3 * nc], x[3 * nc]

    def slack(self, x):
        """-(Y s): the four yield slacks per contact (>= 0 when admissible), stacked by row."""
        return self.formulation.slack(x)

    # -------------------------------------------------------------------------- LPs
    def associative(self) -> LPResult:
        """max alpha over S: the associative multiplier, an upper bound on alpha_c."""
        self._statics.set_row_bounds(np.arange(3 * self.nb, 3 * self.nb + 4 * self.nc),
                                     np.full(4 * self.nc, -INF), np.zeros(4 * self.nc))
        cost = np.zeros(self.nvar)
        cost[-1] = -1.0
        self._statics.set_cost(cost)
        return self._run(self._statics)

    def statics(self, active, minimize: bool = True) -> LPResult:
        """min (max) alpha over S with the yield rows `active` (indices into 4 nc) at equality."""
        active = np.zeros(4 * self.nc, dtype=bool) if active is None else np.asarray(active)
        if active.dtype != bool:
            mask = np.zeros(4 * self.nc, dtype=bool)
            mask[active] = True
            active = mask
        lo = np.where(active, 0.0, -INF)
        self._statics.set_row_bounds(np.arange(3 * self.nb, 3 * self.nb + 4 * self.nc), lo, np.zeros(4 * self.nc))
        cost = np.zeros(self.nvar)
        cost[-1] = 1.0 if minimize else -1.0
        self._statics.set_cost(cost)
        return self._run(self._statics)

    def cohesive(self, c) -> tuple[LPResult, np.ndarray | None, np.ndarray | None]:
        """alpha_as(c): max alpha with |V| <= c; returns (result, u, xi) with (u, xi) its mechanism.

        The mechanism comes from the duals (HiGHS: col_dual = cost - A^T row_dual):
        u = -(equilibrium duals), hinge xi = -(hinge row duals), sliding xi from the reduced
        costs of V at its bounds.
        """
        nc, nb = self.nc, self.nb
        c = np.maximum(np.asarray(c, dtype=float), 0.0)
        self._cohesive.set_col_bounds(np.arange(nc, 2 * nc), -c, c)
        res = self._run(self._cohesive)
        if not res.ok:
            return res, None, None
        u = -res.row_dual[:3 * nb]
        zV = res.col_dual[nc:2 * nc]
        yH = -res.row_dual[3 * nb:]
        xi = np.concatenate([np.maximum(-zV, 0.0), np.maximum(zV, 0.0), np.maximum(yH, 0.0)])
        return res, u, xi

    def mechanism(self, allowed, N_hat, xi_max=None) -> tuple[LPResult, np.ndarray | None, np.ndarray | None]:
        """A mechanism flowing only on `allowed` rows (bool, 4 nc), fbar^T u = 1.

        Among them, the one of least kinematic multiplier alpha_K(u, xi; N_hat) =
        -f0^T u - mu N_hat (xi_slide+ + xi_slide-): the mechanism that the statics N_hat
        would do least work against.
        """
        nb, nc = self.nb, self.nc
        allowed = np.asarray(allowed, dtype=bool)
        hi = np.where(allowed, INF if xi_max is None else xi_max, 0.0)
        self._mech.set_col_bounds(np.arange(3 * nb, 3 * nb + 4 * nc), np.zeros(4 * nc), hi)
        mu_n = self.structure.mu * np.asarray(N_hat, dtype=float)
        cost = np.concatenate([-self.f0, -mu_n, -mu_n, np.zeros(2 * nc)])
        self._mech.set_cost(cost)
        res = self._run(self._mech)
        if not res.ok:
            return res, None, None
        return res, res.x[:3 * nb], np.maximum(res.x[3 * nb:], 0.0)

    def _run(self, lp: _HighsLP) -> LPResult:
        self.n_solves += 1
        if self.deadline.at is not None:  # one LP of a large model can take minutes
            lp.h.setOptionValue("time_limit", max(self.deadline.left(), 1e-3))
        status, x, yr, yc = lp.solve()
        if status != "optimal" and status.startswith("unbounded_or"):
            lp.h.clearSolver()  # start cold to tell infeasible from unbounded
            status, x, yr, yc = lp.solve()
        alpha = float(x[-1]) if (x is not None and lp is not self._mech) else (
            float(lp.h.getInfo().objective_function_value) if x is not None else np.nan)
        return LPResult(status=status, alpha=alpha, x=x, row_dual=yr, col_dual=yc)

    # ------------------------------------------------------------------ virtual work
    def kinematic_multiplier(self, u, xi, N):
        """alpha_K = -u^T f0 - xi^T N_mu s_N (eq. 5)."""
        return self.formulation.kinematic_multiplier(u, xi, N)
