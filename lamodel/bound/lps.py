"""The linear programs of the lower bound, on the scaled structure, solved by HiGHS.

* :meth:`BoundLPs.normal_force` — ``min`` (or ``max``) ``-N_k`` over the statics admissible
  for the real Coulomb law (eq. 1-4) with ``alpha`` in ``[a, b]`` and the normal forces in a
  box ``lo <= -N <= hi``: the Nmin LPs. Friction-cone generator form (four ``lambda >= 0``
  per contact, :func:`lamodel.formulation.matrices.generator_matrix`), so only the 3 nb
  equilibrium rows and one row per contact for the box. One HiGHS object, warm-started
  from one LP to the next.
* :meth:`BoundLPs.cohesive` — ``alpha_coh(c)``: max alpha of the fictitious cohesive system
  (``|V| <= c``, both end compressions ``>= 0``: the hinge rows of eq. 4), with cohesions
  and half-lengths shrunk by a relative margin so that its statics, rebuilt exactly, has
  room inside the true rows (:mod:`.exact`).
* :meth:`BoundLPs.opening_motion` — a motion opening every contact strictly inside the
  associative flow cone; it corrects a floating-point dual point into an exactly feasible
  one (:func:`lamodel.bound.exact.dual_bound`).

Forces are divided by F and lengths by L (:func:`lamodel.formulation.scaling.scales`); every
value that leaves this module is in the user's units. Duals follow the sign convention of
:mod:`.exact`: ``-N_k >= y^T f0 + (c + A^T y + Y^T w)^T s + (y^T fbar) alpha``.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import highspy
import numpy as np
import scipy.sparse as sp

from ..formulation.matrices import cohesive_matrix, equilibrium_matrix, generator_matrix, load_vectors
from ..formulation.scaling import scaled as _scaled
from ..formulation.scaling import scales as _scales
from ..search.highs import QuietHighs
from ..structure import Structure
from .exact import weights

INF = highspy.kHighsInf
#: HiGHS's feasibility tolerances on the scaled LPs (their answers are re-checked exactly).
TOLERANCE = 1e-9


@dataclass
class LPAnswer:
    """One LP's answer in the user's units: status, value, the certificate's raw material."""

    status: str                   # "optimal", "infeasible" or HiGHS's word
    value: float = np.nan         # -N_k (normal_force) or alpha (cohesive)
    y: np.ndarray | None = None   # equilibrium-row multipliers (user units), or a Farkas ray
    x: np.ndarray | None = None   # cohesive: (n1, n2, V) per contact then alpha, user units
    basic: np.ndarray | None = None  # cohesive: which columns are basic
    at_upper: np.ndarray | None = None  # cohesive: nonbasic columns at their upper bound
    slide_rate: np.ndarray | None = None  # cohesive: d alpha / d c_k (user units), >= 0


def _highs(A, cost, col_lo, col_hi, row_lo, row_hi) -> highspy.Highs:
    A = sp.csc_matrix(A)
    h = QuietHighs()
    h.setOptionValue("primal_feasibility_tolerance", TOLERANCE)
    h.setOptionValue("dual_feasibility_tolerance", TOLERANCE)
    lp = highspy.HighsLp()
    lp.num_col_, lp.num_row_ = A.shape[1], A.shape[0]
    lp.col_cost_, lp.col_lower_, lp.col_upper_ = cost, col_lo, col_hi
    lp.row_lower_, lp.row_upper_ = row_lo, row_hi
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.start_ = A.indptr.astype(np.int32)
    lp.a_matrix_.index_ = A.indices.astype(np.int32)
    lp.a_matrix_.value_ = A.data.astype(float)
    h.passModel(lp)
    return h


def _status(h) -> str:
    st = h.getModelStatus()
    if st == highspy.HighsModelStatus.kOptimal:
        return "optimal"
    if st == highspy.HighsModelStatus.kInfeasible:
        return "infeasible"
    return h.modelStatusToString(st).lower()


class BoundLPs:
    """The LPs of the bound for one structure, built once, warm-started throughout.

    ``margin``: the relative shrink of the cohesions and half-lengths in the cohesive LP.
    """

    def __init__(self, structure: Structure, margin: float = 1e-9):
        s = structure
        self.structure = s
        self.nb, self.nc = s.n_blocks, s.n_contacts
        self.F, self.L = _scales(s)
        ss = _scaled(s, self.F, self.L)
        A = equilibrium_matrix(ss)
        f0, fb = load_vectors(ss)
        self.f0s, self.fbs = f0, fb
        nb, nc = self.nb, self.nc
        # y in user units: force rows keep their value, moment rows are divided by L
        self.y_user = np.tile([1.0, 1.0, 1.0 / self.L], nb)
        self.n_solves = 0
        self.lp_seconds = 0.0
        # ---- statics in generator form: lambda (4 nc), alpha; rows: 3 nb equilibrium, nc box
        E = sp.csc_matrix(A @ generator_matrix(ss))
        box = sp.csr_matrix((np.ones(4 * nc), (np.repeat(np.arange(nc), 4), np.arange(4 * nc))),
                            shape=(nc, 4 * nc))
        M = sp.bmat([[E, sp.csc_matrix(fb.reshape(-1, 1))], [box, None]], format="csc")
        self.stat = _highs(M, np.zeros(4 * nc + 1), np.zeros(4 * nc + 1), np.full(4 * nc + 1, INF),
                           np.concatenate([-f0, np.zeros(nc)]), np.concatenate([-f0, np.full(nc, INF)]))
        self._stat_cost = np.zeros(4 * nc + 1)
        # ---- cohesive LP: (n1, n2, V) per contact, alpha; max alpha
        self.margin = margin
        shrunk = _scaled(s, self.F, self.L)
        shrunk.d = ss.d * (1.0 - margin)
        self.d_shrunk = s.d * (1.0 - margin)  # the half-lengths the exact check rebuilds with
        Ec = sp.csc_matrix(A @ cohesive_matrix(shrunk))
        Mc = sp.hstack([Ec, sp.csc_matrix(fb.reshape(-1, 1))], format="csc")
        cost = np.zeros(3 * nc + 1)
        cost[-1] = -1.0
        lo = np.zeros(3 * nc + 1)
        hi = np.full(3 * nc + 1, INF)
        lo[-1] = -INF
        self.coh = _highs(Mc, cost, lo, hi, -f0, -f0)
        self._Mc = Mc

    # ------------------------------------------------------------------ running HiGHS
    def _run(self, h, deadline: float | None):
        if deadline is not None:
            h.setOptionValue("time_limit", max(1e-3, deadline - time.monotonic()))
        t = time.perf_counter()
        h.run()
        self.lp_seconds += time.perf_counter() - t
        self.n_solves += 1
        return _status(h)

    # ------------------------------------------------------------------ Nmin / Nmax
    def normal_force(self, k, a, b, lo, hi, maximize=False, deadline=None) -> LPAnswer:
        """min (max) ``-N_k`` over S with alpha in [a, b] and lo <= -N <= hi (user units).

        ``k`` a dict {contact: weight}: the weighted sum of the ``-N``. ``k=None``: a
        feasibility LP (zero objective); when infeasible, ``y`` is HiGHS's Farkas ray.
        ``x`` of the answer: ``-N`` of every contact at the optimum."""
        nc = self.nc
        cost = np.zeros(4 * nc + 1)
        for j, w in weights(k).items():
            cost[4 * j:4 * j + 4] = -w if maximize else w
        changed = np.flatnonzero(cost != self._stat_cost)
        if changed.size:
            self.stat.changeColsCost(changed.size, changed.astype(np.int32), cost[changed])
            self._stat_cost = cost
        self.stat.changeColBounds(4 * nc, float(a), float(b))
        rows = np.arange(self.nb * 3, self.nb * 3 + nc, dtype=np.int32)
        hi_s = np.where(np.isfinite(hi), np.asarray(hi, float) / self.F, INF)
        self.stat.changeRowsBounds(nc, rows, np.asarray(lo, float) / self.F, hi_s)
        status = self._run(self.stat, deadline)
        if status == "infeasible":
            ok, has, ray = self.stat.getDualRay()
            y = None
            if has:
                # HiGHS's ray proves infeasibility of its rows; either sign may be ours: the
                # exact check (exact.dual_bound with k=None) decides, trying both
                y = np.asarray(ray, float)[:3 * self.nb] * self.y_user
            return LPAnswer("infeasible", y=y)
        if status != "optimal":
            return LPAnswer(status)
        sol = self.stat.getSolution()
        value = self.stat.getInfo().objective_function_value * self.F
        n = np.asarray(sol.col_value, float)[:4 * nc].reshape(nc, 4).sum(axis=1) * self.F
        y = -np.asarray(sol.row_dual, float)[:3 * self.nb] * self.y_user
        if maximize:
            value, y = -value, -y
        return LPAnswer("optimal", value=value, y=y, x=n)

    # ------------------------------------------------------------------ alpha_coh
    def cohesive(self, c, deadline=None) -> LPAnswer:
        """max alpha of the fictitious cohesive system with cohesions ``c`` (user units),
        each shrunk by the margin. ``x`` in user units; ``slide_rate[k]`` is the rate at
        which alpha grows with c_k (the flow of contact k in the cohesive mechanism)."""
        nc = self.nc
        cs = np.maximum(np.asarray(c, float), 0.0) * (1.0 - self.margin) / self.F
        idx = np.arange(2, 3 * nc, 3, dtype=np.int32)
        self.coh.changeColsBounds(nc, idx, -cs, cs)
        status = self._run(self.coh, deadline)
        if status != "optimal":
            return LPAnswer(status)
        sol = self.coh.getSolution()
        x = np.asarray(sol.col_value, float).copy()
        x[:-1] *= self.F
        basis = self.coh.getBasis()
        st = np.array([int(v) for v in basis.col_status])
        row_basic = np.array([int(v) for v in basis.row_status]) == int(highspy.HighsBasisStatus.kBasic)
        basic = st == int(highspy.HighsBasisStatus.kBasic)
        if row_basic.any():
            basic = None  # a degenerate basis with an equilibrium row's slack basic
        rate = np.abs(np.asarray(sol.col_dual, float)[idx]) / self.F
        return LPAnswer("optimal", value=float(x[-1]), x=x, basic=basic,
                        at_upper=st == int(highspy.HighsBasisStatus.kUpper), slide_rate=rate)

    def cohesive_limits(self, c):
        """The cohesive columns' bounds (user units, shrunk): what a nonbasic column sits on."""
        nc = self.nc
        cs = np.maximum(np.asarray(c, float), 0.0) * (1.0 - self.margin)
        lo = np.zeros(3 * nc + 1)
        hi = np.full(3 * nc + 1, np.inf)
        lo[2::3][:nc], hi[2::3][:nc] = -cs, cs
        lo[-1] = -np.inf
        return lo, hi

    # ------------------------------------------------------------------ correction direction
    def opening_motion(self):
        """A motion y0 (user units) that opens every contact strictly inside the
        associative flow cone (``-N``'s reduced cost strictly negative at every contact),
        or None when there is none (a compressive self-stress exists)."""
        nb, nc = self.nb, self.nc
        ss = _scaled(self.structure, self.F, self.L)
        E = sp.csc_matrix(equilibrium_matrix(ss) @ generator_matrix(ss))
        # variables (y0 (3 nb) in [-1, 1], tau); rows E^T y0 - tau >= 0 (4 nc); max tau
        M = sp.hstack([E.T, -np.ones((4 * nc, 1))], format="csc")
        cost = np.zeros(3 * nb + 1)
        cost[-1] = -1.0
        lo = np.concatenate([-np.ones(3 * nb), [-INF]])
        hi = np.concatenate([np.ones(3 * nb), [1.0]])
        h = _highs(M, cost, lo, hi, np.zeros(4 * nc), np.full(4 * nc, INF))
        if self._run(h, None) != "optimal":
            return None
        x = np.asarray(h.getSolution().col_value, float)
        if not x[-1] > 1e-9:
            return None
        return x[:-1] * self.y_user
