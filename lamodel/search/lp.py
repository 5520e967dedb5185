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

With the joints' strengths (:func:`lamodel.formulation.matrices.strength_rows`) the yield
rows are ``Y s <= b``: slides with the joint's cohesion, the N-M facets of crushing and
tension (``nr`` rows, a block of nc a kind); the fictitious system's cohesion is the
joint's own plus -mu N, its facets those of the real joint (associative), and every row
of a mechanism dissipates ``xi b``. A row of far strength (``b`` taken as +inf,
:func:`~lamodel.formulation.matrices.far_bounds`) is left out of the statics and never
flows. Without strengths b = 0 and nr = 4 nc: eq. (4).
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
        self.nr = nr = self.Y.shape[0]  # yield rows: 4 nc (eq. 4), more with the joints' strengths
        #: the rows' right-hand sides: what a flow dissipates (b), and as the LPs take them (+inf: far)
        self.b = np.zeros(nr) if F.b is None else np.asarray(F.b, dtype=float)
        self.b_lp = np.zeros(nr) if F.b_far is None else np.asarray(F.b_far, dtype=float)
        E = sp.hstack([self.A, sp.csr_matrix(self.fbar.reshape(-1, 1))])
        Yrows = sp.hstack([self.Y, sp.csr_matrix((nr, 1))])
        free = np.full(3 * nc, -INF), np.full(3 * nc, INF)
        # alpha >= 0 (collapse under the given live load, not under its reverse)
        col_lo, col_hi = np.append(free[0], 0.0), np.append(free[1], INF)
        cost = np.zeros(self.nvar)
        cost[-1] = -1.0  # max alpha
        # Real statics: equilibrium (= -f0) and all the yield rows (<= b).
        self._statics = methods_lp(cost, sp.vstack([E, Yrows]), np.concatenate([-self.f0, np.full(nr, -INF)]),
                                   np.concatenate([-self.f0, self.b_lp]), col_lo, col_hi)
        # Fictitious cohesive statics: equilibrium and the hinge rows (facets); |V| <= c as column bounds.
        self._cohesive = methods_lp(cost, sp.vstack([E, Yrows[2 * nc:]]),
                                    np.concatenate([-self.f0, np.full(nr - 2 * nc, -INF)]),
                                    np.concatenate([-self.f0, self.b_lp[2 * nc:]]), col_lo, col_hi)
        # Mechanisms: columns (u, xi); compatibility -A^T u - G^T xi = 0 and fbar^T u = 1.
        K = sp.vstack([sp.hstack([-self.A.T, -self.G.T]),
                       sp.hstack([sp.csr_matrix(self.fbar.reshape(1, -1)), sp.csr_matrix((1, nr))])])
        self._mech = methods_lp(np.zeros(3 * nb + nr), K, np.append(np.zeros(3 * nc), 1.0),
                                np.append(np.zeros(3 * nc), 1.0),
                                np.concatenate([np.full(3 * nb, -INF), np.zeros(nr)]),
                                np.concatenate([np.full(3 * nb, INF), self._flows_hi()]))
        self.n_solves = 0
        self.work = 0  # LP work of the solves (HighsLP.work: iterations x rows), counted as a search counts it

    # ------------------------------------------------------------------------ pieces
    def split(self, x):
        nc = self.nc
        return x[:nc], x[nc:2 * nc], x[2 * nc:3 * nc], x[3 * nc]

    def slack(self, x):
        """b - Y s: the yield slacks (>= 0 when admissible), stacked by row."""
        return self.formulation.slack(x)

    def _flows_hi(self, hi=INF):
        """The flows' upper bounds: ``hi``, and 0 on the rows left out (far strengths)."""
        return np.where(np.isfinite(self.b_lp), hi, 0.0)

    def _rows(self):
        return np.arange(3 * self.nb, 3 * self.nb + self.nr)

    # -------------------------------------------------------------------------- LPs
    def associative(self) -> LPResult:
        """max alpha over S: the associative multiplier, an upper bound on alpha_c."""
        self._statics.set_row_bounds(np.full(self.nr, -INF), self.b_lp, self._rows())
        cost = np.zeros(self.nvar)
        cost[-1] = -1.0
        self._statics.set_cost(cost)
        return self.run(self._statics)

    def statics(self, active, minimize: bool = True) -> LPResult:
        """min (max) alpha over S with the yield rows `active` (indices into nr) at equality."""
        active = np.zeros(self.nr, dtype=bool) if active is None else np.asarray(active)
        if active.dtype != bool:
            mask = np.zeros(self.nr, dtype=bool)
            mask[active] = True
            active = mask
        lo = np.where(active & np.isfinite(self.b_lp), self.b_lp, -INF)
        self._statics.set_row_bounds(lo, self.b_lp, self._rows())
        cost = np.zeros(self.nvar)
        cost[-1] = 1.0 if minimize else -1.0
        self._statics.set_cost(cost)
        return self.run(self._statics)

    def cohesive(self, c) -> tuple[LPResult, np.ndarray | None, np.ndarray | None]:
        """alpha_as(c): max alpha with |V| <= c (plus the joints' own cohesion c0 A, when
        they have it); returns (result, u, xi) with (u, xi) its mechanism.

        The mechanism comes from the duals (HiGHS: col_dual = cost - A^T row_dual):
        u = -(equilibrium duals), hinge xi = -(hinge row duals), sliding xi from the reduced
        costs of V at its bounds.
        """
        nc, nb = self.nc, self.nb
        c = np.maximum(np.asarray(c, dtype=float), 0.0) + self.b_lp[:nc]
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
        """A mechanism flowing only on `allowed` rows (bool, nr), fbar^T u = 1.

        Among them, the one of least kinematic multiplier alpha_K(u, xi; N_hat) =
        -f0^T u - mu N_hat (xi_slide+ + xi_slide-) + xi^T b: the mechanism that the statics
        N_hat would do least work against.
        """
        nb, nc, nr = self.nb, self.nc, self.nr
        allowed = np.asarray(allowed, dtype=bool)
        hi = np.where(allowed, self._flows_hi(INF if xi_max is None else xi_max), 0.0)
        self._mech.set_bounds(np.zeros(nr), hi, np.arange(3 * nb, 3 * nb + nr))
        mu_n = self.structure.mu * np.asarray(N_hat, dtype=float)
        cost = np.concatenate([-self.f0, -mu_n, -mu_n, np.zeros(nr - 2 * nc)]) + np.append(np.zeros(3 * nb), self.b)
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
