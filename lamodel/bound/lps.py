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
from ..search.highs import INF, HighsLP
from ..search.options import Deadline, Stopped
from ..search.tuning import BOUND_MARGIN
from ..structure import Structure
from .exact import weights

#: HiGHS's basis status codes of a basic column and of one at its upper bound
_BASIC, _UPPER = int(highspy.HighsBasisStatus.kBasic), int(highspy.HighsBasisStatus.kUpper)


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


def _lp(A, cost, col_lo, col_hi, row_lo, row_hi, name) -> HighsLP:
    """The project's HiGHS wrapper at its tolerance (1e-9, what the exact checks were
    tuned on), warm re-solves by HiGHS's default dual simplex."""
    return HighsLP(A, row_lo, cost, col_lo, col_hi, name=name, b_hi=row_hi, warm="dual")


class BoundLPs:
    """The LPs of the bound for one structure, built once, warm-started throughout.

    ``margin``: the relative shrink of the cohesions and half-lengths in the cohesive LP.
    """

    def __init__(self, structure: Structure, margin: float = BOUND_MARGIN):
        self.structure = structure
        self.margin = margin
        self.n_solves = 0
        self.lp_seconds = 0.0
        self._setup()

    def _setup(self):
        """The plane: eq. (1)-(4) on contacts (N, V, M), four generators per contact."""
        s = self.structure
        self.nc = s.n_contacts
        ss, A, f0, fb = self._scaled(_scales, _scaled, equilibrium_matrix, load_vectors, 2)
        shrunk = _scaled(s, self.F, self.L)
        shrunk.d = ss.d * (1.0 - self.margin)
        self.d_shrunk = s.d * (1.0 - self.margin)  # the half-lengths the exact check rebuilds with
        nc = self.nc
        # cohesive columns (n1, n2, V) per contact, alpha: n >= 0, |V| <= c, alpha free
        lo, hi = np.zeros(3 * nc + 1), np.full(3 * nc + 1, INF)
        lo[-1] = -INF
        self._build(A, f0, fb, generator_matrix(ss), 4, cohesive_matrix(shrunk), lo, hi,
                    np.arange(2, 3 * nc, 3), np.arange(nc), 1.0)

    def _scaled(self, scales, scaled, equilibrium, loads, dim):
        """The non-dimensional structure (forces by F, lengths by L) and its (A, f0, fbar),
        from the plane's or space's formulation functions; ``y_user`` maps multipliers of
        its equilibrium rows to the user's units (moment rows divided by L)."""
        s = self.structure
        self.nb = s.n_blocks
        self.F, self.L = scales(s)
        ss = scaled(s, self.F, self.L)
        f0, fb = loads(ss)
        per_block = [1.0] * dim + [1.0 / self.L] * (1 if dim == 2 else 3)
        self.y_user = np.tile(per_block, self.nb)
        return ss, equilibrium(ss), f0, fb

    def _build(self, A, f0, fb, G, g, C, coh_lo, coh_hi, coh_idx, coh_point, coh_coef):
        """The two LPs on the scaled matrices: A (equilibrium), f0, fb; G the cone's
        generators (g per contact, contiguous); C the cohesive LP's columns (alpha after
        them), with bounds coh_lo/coh_hi (alpha's included) except the cohesion columns
        coh_idx (of the contacts coh_point), whose bounds are ``+/- coh_coef c``."""
        nc, neq = self.nc, A.shape[0]
        self.g, self.neq = g, neq
        # ---- statics in generator form: lambda (g nc), alpha; rows: equilibrium, nc box
        self._E = E = sp.csc_matrix(A @ G)
        box = sp.csr_matrix((np.ones(g * nc), (np.repeat(np.arange(nc), g), np.arange(g * nc))),
                            shape=(nc, g * nc))
        M = sp.bmat([[E, sp.csc_matrix(fb.reshape(-1, 1))], [box, None]], format="csc")
        self.stat = _lp(M, np.zeros(g * nc + 1), np.zeros(g * nc + 1), np.full(g * nc + 1, INF),
                        np.concatenate([-f0, np.zeros(nc)]), np.concatenate([-f0, np.full(nc, INF)]), "bound-N")
        # ---- cohesive LP: max alpha
        Mc = sp.hstack([sp.csc_matrix(A @ C), sp.csc_matrix(fb.reshape(-1, 1))], format="csc")
        cost = np.zeros(Mc.shape[1])
        cost[-1] = -1.0
        self._coh_lo, self._coh_hi = np.asarray(coh_lo, float), np.asarray(coh_hi, float)
        self._coh_idx, self._coh_point, self._coh_coef = np.asarray(coh_idx), np.asarray(coh_point), coh_coef
        self.coh = _lp(Mc, cost, self._coh_lo, self._coh_hi, -f0, -f0, "bound-coh")

    # ------------------------------------------------------------------ running HiGHS
    def _run(self, lp: HighsLP, deadline: Deadline | None) -> str:
        """Solve; "stopped" when the deadline expired (the caller ends)."""
        t = time.perf_counter()
        self.n_solves += 1
        try:
            return lp.solve(deadline=deadline)
        except Stopped:
            return "stopped"
        finally:
            self.lp_seconds += time.perf_counter() - t

    # ------------------------------------------------------------------ Nmin / Nmax
    def normal_force(self, k, a, b, lo, hi, maximize=False, deadline=None) -> LPAnswer:
        """min (max) ``-N_k`` over S with alpha in [a, b] and lo <= -N <= hi (user units).

        ``k`` a dict {contact: weight}: the weighted sum of the ``-N``. ``k=None``: a
        feasibility LP (zero objective); when infeasible, ``y`` is HiGHS's Farkas ray.
        ``x`` of the answer: ``-N`` of every contact at the optimum."""
        nc, g = self.nc, self.g
        cost = np.zeros(g * nc + 1)
        for j, w in weights(k).items():
            cost[g * j:g * j + g] = -w if maximize else w
        self.stat.set_cost(cost)
        self.stat.set_bounds([float(a)], [float(b)], idx=[g * nc])
        rows = np.arange(self.neq, self.neq + nc)
        hi_s = np.where(np.isfinite(hi), np.asarray(hi, float) / self.F, INF)
        self.stat.set_row_bounds(np.asarray(lo, float) / self.F, hi_s, idx=rows)
        status = self._run(self.stat, deadline)
        if status == "infeasible":
            ray = self.stat.dual_ray()
            # HiGHS's ray proves infeasibility of its rows; either sign may be ours: the
            # exact check (exact.dual_bound with k=None) decides, trying both
            y = None if ray is None else ray[:self.neq] * self.y_user
            return LPAnswer("infeasible", y=y)
        if status != "optimal":
            return LPAnswer(status)
        value = self.stat.objective() * self.F
        n = self.stat.x()[:g * nc].reshape(nc, g).sum(axis=1) * self.F
        y = -self.stat.duals()[0][:self.neq] * self.y_user
        if maximize:
            value, y = -value, -y
        return LPAnswer("optimal", value=value, y=y, x=n)

    # ------------------------------------------------------------------ alpha_coh
    def cohesive(self, c, deadline=None) -> LPAnswer:
        """max alpha of the fictitious cohesive system with cohesions ``c`` (user units),
        each shrunk by the margin. ``x`` in user units; ``slide_rate[k]`` is the rate at
        which alpha grows with c_k (the flow of contact k in the cohesive mechanism)."""
        idx = self._coh_idx
        cs = self._coh_coef * np.maximum(np.asarray(c, float), 0.0)[self._coh_point] * (1.0 - self.margin) / self.F
        self.coh.set_bounds(-cs, cs, idx=idx)
        status = self._run(self.coh, deadline)
        if status != "optimal":
            return LPAnswer(status)
        x = self.coh.x()
        x[:-1] *= self.F
        col_status, row_status = self.coh.portable_basis()
        basic = col_status == _BASIC  # an equilibrium row's slack may be basic too (degenerate)
        rate = np.bincount(self._coh_point, self._coh_coef * np.abs(self.coh.duals()[1][idx]),
                           minlength=self.nc) / self.F
        return LPAnswer("optimal", value=float(x[-1]), x=x, basic=basic, at_upper=col_status == _UPPER,
                        slide_rate=rate)

    def cohesive_limits(self, c):
        """The cohesive columns' bounds (user units, shrunk): what a nonbasic column sits on."""
        cs = self._coh_coef * np.maximum(np.asarray(c, float), 0.0)[self._coh_point] * (1.0 - self.margin)
        lo = np.where(self._coh_lo <= -INF, -np.inf, self._coh_lo * self.F)
        hi = np.where(self._coh_hi >= INF, np.inf, self._coh_hi * self.F)
        lo[self._coh_idx], hi[self._coh_idx] = -cs, cs
        return lo, hi

    # ------------------------------------------------------------------ correction direction
    def opening_motion(self):
        """A motion y0 (user units) that opens every contact strictly inside the
        associative flow cone (``-N``'s reduced cost strictly negative at every contact),
        or None when there is none (a compressive self-stress exists)."""
        neq, ng = self._E.shape
        # variables (y0 (one per equilibrium row) in [-1, 1], tau); rows E^T y0 - tau >= 0
        # (one per generator: with generators spanning a cone that holds the Coulomb
        # cone, this opens every contact strictly inside its flow cone); max tau
        M = sp.hstack([self._E.T, -np.ones((ng, 1))], format="csc")
        cost = np.zeros(neq + 1)
        cost[-1] = -1.0
        lo = np.concatenate([-np.ones(neq), [-INF]])
        hi = np.concatenate([np.ones(neq), [1.0]])
        lp = _lp(M, cost, lo, hi, np.zeros(ng), np.full(ng, INF), "bound-open")
        if self._run(lp, None) != "optimal":
            return None
        x = lp.x()
        if not x[-1] > 1e-9:
            return None
        return x[:-1] * self.y_user
