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

import numpy as np
import scipy.sparse as sp

from ..formulation.matrices import Formulation
from ..structure import Structure
from .highs import INF, HighsLP
from .options import Deadline, Stopped


@dataclass
class LPResult:
    status: str                    # 'optimal', 'infeasible', 'unbounded', 'time limit' or HiGHS's word
    alpha: float = np.nan
    x: np.ndarray | None = None    # primal columns
    row_dual: np.ndarray | None = None
    col_dual: np.ndarray | None = None

    @property
    def ok(self) -> bool:
        return self.status == "optimal"


def methods_lp(cost, A, row_lo, row_hi, col_lo, col_hi) -> HighsLP:
    """An LP of the published methods: min cost^T x, row_lo <= A x <= row_hi,
    col_lo <= x <= col_hi, warm re-solves by HiGHS's dual simplex."""
    return HighsLP(A, row_lo, cost, col_lo, col_hi, name="methods", b_hi=row_hi, warm="dual")


class LimitLPs:
    """The LPs of one structure, built once and re-solved with new data."""

    def __init__(self, structure: Structure, formulation: Formulation | None = None):
        self.structure = s = structure
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
        self._statics = methods_lp(cost, sp.vstack([E, Yrows]), np.concatenate([-self.f0, np.full(4 * nc, -INF)]),
                                   np.concatenate([-self.f0, np.zeros(4 * nc)]), col_lo, col_hi)
        # Fictitious cohesive statics: equilibrium and the hinge rows; |V| <= c as column bounds.
        self._cohesive = methods_lp(cost, sp.vstack([E, Yrows[2 * nc:]]),
                                    np.concatenate([-self.f0, np.full(2 * nc, -INF)]),
                                    np.concatenate([-self.f0, np.zeros(2 * nc)]), col_lo, col_hi)
        # Mechanisms: columns (u, xi); compatibility -A^T u - G^T xi = 0 and fbar^T u = 1.
        K = sp.vstack([sp.hstack([-self.A.T, -self.G.T]),
                       sp.hstack([sp.csr_matrix(self.fbar.reshape(1, -1)), sp.csr_matrix((1, 4 * nc))])])
        self._mech = methods_lp(np.zeros(3 * nb + 4 * nc), K, np.append(np.zeros(3 * nc), 1.0),
                                np.append(np.zeros(3 * nc), 1.0),
                                np.concatenate([np.full(3 * nb, -INF), np.zeros(4 * nc)]),
                                np.concatenate([np.full(3 * nb, INF), np.full(4 * nc, INF)]))
        self.n_solves = 0
        self.work = 0  # LP work of the solves (HighsLP.work: iterations x rows), counted as a search counts it

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
        self._statics.set_row_bounds(np.full(4 * self.nc, -INF), np.zeros(4 * self.nc),
                                     np.arange(3 * self.nb, 3 * self.nb + 4 * self.nc))
        cost = np.zeros(self.nvar)
        cost[-1] = -1.0
        self._statics.set_cost(cost)
        return self.run(self._statics)

    def statics(self, active, minimize: bool = True) -> LPResult:
        """min (max) alpha over S with the yield rows `active` (indices into 4 nc) at equality."""
        active = np.zeros(4 * self.nc, dtype=bool) if active is None else np.asarray(active)
        if active.dtype != bool:
            mask = np.zeros(4 * self.nc, dtype=bool)
            mask[active] = True
            active = mask
        lo = np.where(active, 0.0, -INF)
        self._statics.set_row_bounds(lo, np.zeros(4 * self.nc), np.arange(3 * self.nb, 3 * self.nb + 4 * self.nc))
        cost = np.zeros(self.nvar)
        cost[-1] = 1.0 if minimize else -1.0
        self._statics.set_cost(cost)
        return self.run(self._statics)

    def cohesive(self, c) -> tuple[LPResult, np.ndarray | None, np.ndarray | None]:
        """alpha_as(c): max alpha with |V| <= c; returns (result, u, xi) with (u, xi) its mechanism.

        The mechanism comes from the duals (HiGHS: col_dual = cost - A^T row_dual):
        u = -(equilibrium duals), hinge xi = -(hinge row duals), sliding xi from the reduced
        costs of V at its bounds.
        """
        nc, nb = self.nc, self.nb
        c = np.maximum(np.asarray(c, dtype=float), 0.0)
        self._cohesive.set_bounds(-c, c, np.arange(nc, 2 * nc))
        res = self.run(self._cohesive)
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
        self._mech.set_bounds(np.zeros(4 * nc), hi, np.arange(3 * nb, 3 * nb + 4 * nc))
        mu_n = self.structure.mu * np.asarray(N_hat, dtype=float)
        cost = np.concatenate([-self.f0, -mu_n, -mu_n, np.zeros(2 * nc)])
        self._mech.set_cost(cost)
        res = self.run(self._mech)
        if not res.ok:
            return res, None, None
        return res, res.x[:3 * nb], np.maximum(res.x[3 * nb:], 0.0)

    def run(self, lp: HighsLP) -> LPResult:
        """Solve ``lp`` (one of these LPs, or a method's own) within this object's
        deadline ("time limit" after it), counting the solve and its work."""
        self.n_solves += 1
        before = lp.work
        try:
            status = lp.solve(deadline=self.deadline)
        except Stopped:
            return LPResult(status="time limit")
        finally:
            self.work += lp.work - before
        if status != "optimal":
            return LPResult(status=status)
        x = lp.x()
        yr, yc = lp.duals()
        alpha = float(x[-1]) if lp is not self._mech else lp.objective()
        return LPResult(status=status, alpha=alpha, x=x, row_dual=yr, col_dual=yc)

    # ------------------------------------------------------------------ virtual work
    def kinematic_multiplier(self, u, xi, N):
        """alpha_K = -u^T f0 - xi^T N_mu s_N (eq. 5)."""
        return self.formulation.kinematic_multiplier(u, xi, N)
