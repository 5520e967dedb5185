"""The scaled LPs of the search: statics in friction-cone generator form, the fictitious
cohesive LP and its mechanism, and the way back to the user's units.

* **Statics**: per contact four unknowns lambda >= 0, the forces ``-n +/- mu t`` at its two
  end points (:func:`~lamodel.formulation.matrices.generator_matrix`), so that the admissible
  set S of eq. (1)-(4) is ``A T lambda + alpha fbar = -f0``, ``lambda >= 0``, ``alpha >= 0``:
  only 3 nb rows. A yield row of eq. (4) is held at equality exactly when the two lambdas of
  its slack are zero.
* **Mechanism**: the fictitious cohesive LP of the seed (``|V| <= c`` with ``c = -mu N``,
  normal force >= 0 at both ends of a contact, max alpha). Its duals are the mechanism of
  least alpha_K for that N, recomputed exactly from HiGHS's final basis.

Numbers are non-dimensional (:mod:`lamodel.formulation.scaling`); :meth:`ScaledProblem.to_user`
takes a state back to the user's units, re-checked there. A light block's equilibrium rows
and its contacts' columns are scaled further (:func:`~lamodel.formulation.scaling.light_scales`):
the LPs' columns, and so every statics ``x`` of this class, are lambdas in units of their
contact's scale; forces, normal forces, slacks in those units, and mechanisms, come out in
the non-dimensional units.
"""
from __future__ import annotations

import logging
import time

import numpy as np
import scipy.sparse as sp

from ...formulation.matrices import (Formulation, cohesive_matrix, dilatant_flows, generator_matrix, held_generators,
                                     shear_matrix)
from ...formulation.scaling import light_scales, scaled, scales
from ...structure import Structure
from ..certify import residuals
from ..highs import INF, HighsLP
from ..options import Deadline
from ..state import CollapseState
from ..tuning import CERTIFY_CAP_ROWS, FLOW_TOL, LIGHT_BLOCK, LP_TOLERANCE, PUSH, STABLE_ALPHA, WORK_PER_BLOCK
from .program import CAPPED

log = logging.getLogger(__name__)


def state_residuals(form: Formulation, state: CollapseState) -> dict:
    """:func:`lamodel.search.certify.residuals` of a state against a formulation."""
    return residuals(form, state.N, state.V, state.M, state.alpha, state.u, state.xi)


class ScaledProblem:
    """The LPs of one planar structure, scaled, built once and warm-started from solve to
    solve: the plane's :class:`~.program.GapProgram`.

    ``stat`` is the statics LP (columns lambda, alpha), ``coh`` the cohesive LP (columns
    n1, n2, V per contact, alpha) and ``coh_r`` a copy of it for mechanisms restricted to
    some rows. Every solve is given ``deadline`` (its engine's budget's, read at the call);
    methods raise :class:`~lamodel.search.options.Stopped` when it fires.
    """

    #: Ipopt polishes the search's states on eq. (5) (:mod:`lamodel.search.ipopt`)
    polish = True
    #: least alpha over S at or below this counts as zero (an exact LP vertex)
    stable_alpha = STABLE_ALPHA

    def __init__(self, structure: Structure, deadline: Deadline | None = None):
        s = self._formulate(structure, deadline)
        nb, nc = self.nb, self.nc
        # light blocks: their equilibrium rows times R, their contacts' forces in units of C
        self.R, self.C = light_scales(s, LIGHT_BLOCK)
        self.row_scale = np.tile(self.C, 4)  # a yield row's slack, and its flow's force, in its contact's units
        # --- statics in generator form: columns lambda (4 nc), alpha
        T_unit = generator_matrix(s)
        self.T = self._columns(T_unit, 4)  # lambdas in their contact's units
        self.Slam = (-(self.Y @ T_unit)).tocsr()  # yield slacks = Slam @ lambda (>= 0), in the contact's units
        assert self.Slam.min() >= 0
        self.held_lams = held_generators(nc)
        self.Slam.sort_indices()
        on = (self.mu > 0)[np.arange(4 * nc) % nc] | (np.arange(4 * nc) >= 2 * nc)
        check = self.Slam[np.flatnonzero(on)]
        assert np.all(np.diff(check.indptr) == 2) and np.array_equal(check.indices.reshape(-1, 2),
                                                                     self.held_lams[on])
        rows = np.repeat(np.arange(4 * nc), 2)
        self.row_of_pair = sp.csr_matrix((np.ones(8 * nc), (rows, self.held_lams.ravel())), shape=self.Slam.shape)
        Ag = self._rows(sp.hstack([self.A @ self.T, self.fbar.reshape(-1, 1)])).tocsc()
        self.nl = 4 * nc
        lo = np.zeros(self.nl + 1)
        hi = np.full(self.nl + 1, INF)
        self.stat = HighsLP(Ag, -self.R * self.f0, np.zeros(self.nl + 1), lo, hi, "statics")
        # --- fictitious cohesive LP: columns (n1, n2, V) per contact, alpha
        self.Tc = self._columns(cohesive_matrix(s), 3)
        Ac = self._rows(sp.hstack([self.A @ self.Tc, self.fbar.reshape(-1, 1)])).tocsc()
        # Flow rows of the cohesive system in its own columns: one nonzero per row.
        self.Gc = (self.G @ self.Tc).tocsr()
        self.Gc.eliminate_zeros()
        assert np.all(np.diff(self.Gc.indptr) == 1)
        self.gc_col = self.Gc.indices.copy()   # column of each flow row
        self.gc_val = self.Gc.data.copy()      # its coefficient
        self.obj_scale = float(nb)  # objective scaled: duals (the mechanism) well above HiGHS's tolerance
        cost = np.zeros(3 * nc + 1)
        cost[-1] = -self.obj_scale
        clo = np.zeros(3 * nc + 1)
        chi = np.full(3 * nc + 1, INF)
        self.coh = HighsLP(Ac, -self.R * self.f0, cost, clo, chi, "cohesive")
        # Restricted mechanisms (flow allowed on some rows only) get their own copy: switching
        # one LP between the two kinds cost 10-17 s a re-solve at 2040 blocks.
        self.coh_r = HighsLP(Ac, -self.R * self.f0, cost, clo, chi, "cohesive-r")
        self.lps = {"stat": self.stat, "coh": self.coh, "coh_r": self.coh_r}  # (snapshots name them)
        for lp in self.lps.values():
            self._trace(lp)
        self.lps_elsewhere = 0  # LPs solved for this search by evaluator engines (see Fitness.merge)
        self.work_elsewhere = 0  # and their work
        self.dilatant = None  # (t, HighsLP): the cohesive LP of dilatancy t (see mechanism)
        self.dilatant_done = [0, 0]  # solves and work of the dilatant LPs of other t

    def _formulate(self, structure, deadline):
        """The scaled structure and its matrices (and the user's, for :meth:`to_user`);
        returns the scaled structure."""
        self.t0 = time.perf_counter()
        self.user = structure
        self.deadline = deadline or Deadline()
        self.F, self.L = scales(structure)
        s = self.s = scaled(structure, self.F, self.L)
        self.nb, self.nc = s.n_blocks, s.n_contacts
        self.form = Formulation.of(s)
        self.user_form = Formulation.of(structure)
        self.A, self.f0, self.fbar, self.Y, self.G = self.form.A, self.form.f0, self.form.fbar, self.form.Y, self.form.G
        self.mu = s.mu
        return s

    def _rows(self, M):
        """M (equilibrium rows) with a light block's rows times R; M itself, the same matrix
        entry for entry, where no block is light."""
        return sp.diags(self.R) @ M if np.any(self.R != 1.0) else M

    def _columns(self, M, per):
        """M with the ``per`` columns of each contact times its scale C (M itself where no
        block is light)."""
        return M @ sp.diags(np.repeat(self.C, per)) if np.any(self.C != 1.0) else M

    # ------------------------------------------------------------------ bookkeeping
    def elapsed(self):
        return time.perf_counter() - self.t0

    def _trace(self, lp):
        """Every solve of ``lp`` logged at DEBUG, where the log shows DEBUG (a trace costs
        HiGHS a query a solve)."""
        if log.isEnabledFor(logging.DEBUG):
            lp.trace = lambda m: log.debug("%8.2f %s", self.elapsed(), m)

    def n_lps(self):
        """LP solves so far, those of evaluations merged from elsewhere included."""
        return sum(lp.n_solves for lp in self._all_lps()) + self.lps_elsewhere + self.dilatant_done[0]

    def _all_lps(self):
        return list(self.lps.values()) + ([self.dilatant[1]] if self.dilatant is not None else [])

    def work(self):
        """The LP work so far (:attr:`lamodel.search.highs.HighsLP.work`), merged evaluations
        included."""
        return sum(lp.work for lp in self._all_lps()) + self.work_elsewhere + self.dilatant_done[1]

    def work_bound(self):
        """WORK_PER_BLOCK a block (about a minute per thousand blocks)."""
        return WORK_PER_BLOCK * self.nb

    def bases(self):
        """The LPs' current bases (portable: they pickle), by name."""
        return {name: lp.portable_basis() for name, lp in self.lps.items()}

    def restart(self, bases):
        """Every LP on a new HiGHS object, warm from ``bases`` (:meth:`bases`); the dilatant
        LP forgotten (the next one starts from the statics LP's basis, as a search's first)."""
        for name, lp in self.lps.items():
            lp.restart(bases[name])
        if self.dilatant is not None:
            old = self.dilatant[1]
            self.dilatant_done = [self.dilatant_done[0] + old.n_solves, self.dilatant_done[1] + old.work]
            self.dilatant = None

    def save_bases(self, names=None):
        """The LPs' current bases (None: cold), by name (``names``: those only)."""
        return {name: None if lp.cold else lp.h.getBasis() for name, lp in self.lps.items()
                if names is None or name in names}

    def load_bases(self, saved, restart_cold=True):
        """Back to bases of :meth:`save_bases` (a cold one restarts cold if ``restart_cold``)."""
        for name, basis in saved.items():
            lp = self.lps[name]
            if basis is None:
                if restart_cold:
                    lp.restart(None)
            elif not lp.abandoned:
                lp.h.setBasis(basis)

    # ------------------------------------------------------------------- statics
    def forces(self, lam):
        return self.T @ lam[:self.nl]

    def N_of(self, lam):
        return (self.T @ lam[:self.nl])[:self.nc]

    def statics(self, cost_lam=None, held=None, maximize=False, cap=None, alpha_cost=1.0, u=None):
        """Optimise over S in generator form: min (max) alpha_cost alpha + cost_lam^T lambda
        with the yield rows ``held`` (bool, 4 nc) at equality (``u`` is not needed: a held
        row fixes its force). Returns (status, x)."""
        cost = np.zeros(self.nl + 1)
        cost[-1] = -alpha_cost if maximize else alpha_cost
        if cost_lam is not None:
            cost[:self.nl] = cost_lam
        hi = np.full(self.nl + 1, INF)
        if held is not None and held.any():
            hi[:self.nl][self.zeroed(held)] = 0.0
        self.stat.set_cost(cost)
        self.stat.set_bounds(np.zeros(self.nl + 1), hi)
        status = self.stat.solve(cap, self.deadline)
        if status != "optimal":
            return status, None
        x = np.maximum(self.stat.x(), 0.0)
        return status, x

    def zeroed(self, held):
        """The lambdas (bool, 4 nc) that holding the yield rows ``held`` sets to zero."""
        out = np.zeros(self.nl, bool)
        out[self.held_lams[held].ravel()] = True
        return out

    def slack(self, lam):
        """The yield slacks (4 nc, >= 0) of a statics in generator form, each in its
        contact's units (a light block's contacts in theirs)."""
        return self.Slam @ lam[:self.nl]

    def active_rows(self, lam, tol):
        """Yield rows whose slack is at most ``tol`` times the statics' largest entry (or 1)."""
        return self.slack(lam) <= tol * max(1.0, np.abs(lam).max())

    def gap_weights(self, xi, u=None):
        """w with w^T lambda = alpha_K(N(lambda)) - alpha = slack^T xi (virtual work)."""
        return self.Slam.T @ (self.row_scale * xi)

    def gap(self, x, xi, u=None):
        """alpha_K - alpha of the statics x for the mechanism's flows xi (eq. 5)."""
        return float(self.gap_weights(xi) @ x[:self.nl])

    # ----------------------------------------------------------------- mechanism
    def mechanism(self, c, allowed=None, dilatancy=0.0):
        """The cohesive LP for cohesions c (>= 0), flow allowed on rows ``allowed`` only.

        Returns (status, alpha_as, x, u, xi): its statics x (n1, n2, V, alpha) and its
        mechanism (u, xi) of least alpha_K, exact from the final basis, fbar^T u = 1.
        ``dilatancy`` t > 0: the fictitious system whose sliding also dilates, friction
        t mu besides the cohesions (:meth:`_dilatant`; every row may flow).
        """
        if dilatancy > 0:
            return self._dilatant(c, dilatancy)
        nc = self.nc
        c = np.maximum(np.asarray(c, float), 0.0)
        lo = np.zeros(3 * nc + 1)
        hi = np.full(3 * nc + 1, INF)
        lo[2::3][:nc], hi[2::3][:nc] = -c / self.C, c / self.C
        if allowed is not None:
            # a row that may not flow is a constraint dropped from the primal
            off = np.flatnonzero(~np.asarray(allowed, bool))
            kind, col = off // nc, self.gc_col[off]
            hi[col[kind == 0]] = INF       # slide+: V <= c
            lo[col[kind == 1]] = -INF      # slide-: V >= -c
            lo[col[kind >= 2]] = -INF      # hinge: compression >= 0 at that end
        lp = self.coh if allowed is None else self.coh_r
        if lp.cold and not self.coh.cold:
            lp.h.setBasis(self.coh.h.getBasis())  # start from the unrestricted one's basis
            lp.cold = False
        status, u, z = self._motion(lp, lo, hi)
        if status != "optimal":
            return status, np.nan, None, None, None
        # compatibility in the cohesive columns: Gc^T xi = -(A Tc)^T u = -z on the (n, V) columns
        xi = np.maximum(-z[self.gc_col] / self.gc_val, 0.0)
        if allowed is not None:
            xi[~allowed] = 0.0
        x = lp.x()
        return status, float(x[-1]), x, u, self._significant(xi)

    def _motion(self, lp, lo, hi):
        """A cohesive LP solved with column bounds (lo, hi): (status, u, z), the mechanism
        u from its exact row duals (``fbar^T u = 1``) and the reduced costs z in the same
        normalisation ('degenerate' where the duals move no live load)."""
        lp.set_bounds(lo, hi)
        status = lp.solve(deadline=self.deadline)
        if status != "optimal":
            return status, None, None
        y, z = lp.exact_duals()
        u = -self.R * y / self.obj_scale
        fu = self.fbar @ u
        if not fu > 0:
            return "degenerate", None, None
        return status, u / fu, z / (self.obj_scale * fu)

    def _significant(self, xi):
        """xi without the flows below FLOW_TOL of the largest, each measured against its
        contact's forces (a light block's in its own units)."""
        work = xi * self.row_scale
        xi[work <= FLOW_TOL * (work.max() if work.size else 0.0)] = 0.0
        return xi

    def _dilatant(self, c, t):
        """The cohesive LP of dilatancy t: per contact the four generators of the cone of
        friction t mu and a cohesive shear within +-c (columns in the contact's units), max
        alpha. Its mechanism's flows follow that system's flow rule
        (:func:`~lamodel.formulation.matrices.dilatant_flows`). One LP per t, warm from the
        last t's basis, the first from the statics LP's (at t = 1 and c = 0 it is the
        associative LP)."""
        nc = self.nc
        if self.dilatant is None or self.dilatant[0] != t:
            T = sp.hstack([self._columns(generator_matrix(self.s, t * self.mu), 4),
                           self._columns(shear_matrix(self.s), 1)])
            A = sp.hstack([self.A @ T, self.fbar.reshape(-1, 1)])
            n = 5 * nc + 1
            cost = np.zeros(n)
            cost[-1] = -self.obj_scale
            lp = HighsLP(self._rows(A).tocsc(), -self.R * self.f0, cost, np.zeros(n), np.full(n, INF),
                         "dilatant")
            if self.dilatant is not None:
                old = self.dilatant[1]
                basis = old.portable_basis()
                self.dilatant_done = [self.dilatant_done[0] + old.n_solves, self.dilatant_done[1] + old.work]
            else:  # the statics LP's columns, the shears nonbasic at their bound
                basis = self.stat.portable_basis()
                if basis is not None:
                    lower = np.zeros(nc, np.int8)  # HiGHS's kLower
                    basis = (np.concatenate([basis[0][:self.nl], lower, basis[0][self.nl:]]), basis[1])
            if basis is not None:
                lp.restart(basis)
            self._trace(lp)
            self.dilatant = (t, lp)
        lp = self.dilatant[1]
        c = np.maximum(np.asarray(c, float), 0.0) / self.C
        lo = np.zeros(5 * nc + 1)
        hi = np.full(5 * nc + 1, INF)
        lo[4 * nc:5 * nc], hi[4 * nc:5 * nc] = -c, c
        status, u, _ = self._motion(lp, lo, hi)
        if status != "optimal":
            return status, np.nan, None, None, None
        return status, float(lp.x()[-1]), None, u, self._significant(dilatant_flows(self.s, -(self.A.T @ u), t))

    # ------------------------------------------------------------- certification
    def iteration_cap(self):
        """CERTIFY_CAP_ROWS simplex iterations a row of the statics (3 nb rows)."""
        return int(CERTIFY_CAP_ROWS * self.stat.m)

    def pattern(self, u, flow):
        """A certificate depends on the flow pattern alone (its rows held, min alpha; any
        mechanism with that pattern is then compatible with the statics)."""
        return flow.tobytes()

    def certificates(self, u, xi, flow, cap):
        """The two LPs of a certificate (see :class:`~.certify.Certifier`), yielding the
        held statics (exact to round-off), or CAPPED.

        Holding the rows by bounds makes the warm basis infeasible, and the primal phase 1
        took minutes at 2040 blocks. Instead: (1) min of the sum of the lambdas the held
        rows set to zero, from the current (feasible) basis; zero means the rows can be
        held; (2) then those lambdas are zero, so bounding them keeps the basis feasible,
        and min alpha is a warm primal solve. Each is capped (iterations, ``cap``): a
        certification that hard is not worth it now. Unit weights, not the gap's
        virtual-work weights w: a row flowing 1e-9 of the largest flow weighs its lambdas
        so little that w^T lambda ~ 1e-10 left them at 0.1 (1020 blocks), and the held LP
        then started infeasible (primal phase 1 gave up, HiGHS's dual simplex ran on
        singular bases for minutes)."""
        zeroed = self.zeroed(flow)
        status, x = self.statics(cost_lam=zeroed.astype(float), alpha_cost=0.0, cap=cap)
        if status == "iteration limit":
            yield CAPPED
            return
        if status != "optimal" or x[:self.nl][zeroed].max() > LP_TOLERANCE * max(1.0, np.abs(x).max()):
            return
        status, x = self.statics(held=flow, cap=cap)
        if status == "iteration limit":
            yield CAPPED
            return
        if status != "optimal":
            return
        yield self.stat.exact_x(), u, xi, flow, ""  # equilibrium to round-off, not to HiGHS's tolerance

    def pushing_rows(self, state):
        """Reduced costs of the held lambdas (min alpha with the state's flow rows held):
        per yield row, how much its lambdas push alpha up (None: none pushes)."""
        status, x = self.statics(held=state.flow)
        if status != "optimal":
            return None
        _, z = self.stat.exact_duals()
        zl = z[:self.nl]
        push = np.where(self.zeroed(state.flow) & (zl < -PUSH), -zl, 0.0)
        if not push.any():
            return None
        row_push = self.row_of_pair @ push  # per yield row: how much its lambdas push
        row_push[~state.flow] = 0.0
        return row_push

    def cohesive_N(self, xc):
        """Normal forces of a cohesive LP's statics (columns n1, n2, V per contact)."""
        return (self.Tc @ xc[:3 * self.nc])[:self.nc]

    # ---------------------------------------------------------------- user units
    def state(self, x, u, xi, flow, source) -> CollapseState:
        """The collapse state of statics x (generator form) and mechanism (u, xi) flowing on
        ``flow``, with its residuals (scaled units)."""
        s = self.forces(x)
        nc = self.nc
        state = CollapseState(alpha=float(x[-1]), N=s[:nc].copy(), V=s[nc:2 * nc].copy(), M=s[2 * nc:].copy(),
                              u=u.copy(), xi=np.where(flow, xi, 0.0), flow=flow.copy(), source=source)
        state.residual = state_residuals(self.form, state)
        return state

    def mechanism_from_user(self, u, xi):
        """A mechanism in the user's units (the inverse of :meth:`to_user`'s), normalised
        by this structure's live load (``fbar^T u = 1``): another load's mechanism of the
        same blocks and contacts, to certify here. (None, None) if the live load does no
        positive work on it."""
        F, L, nc = self.F, self.L, self.nc
        u = np.array(u, float) * (F * L)
        u[0::3] /= L
        u[1::3] /= L
        xi = np.array(xi, float) * (F * L)
        xi[:2 * nc] /= L
        fu = float(self.fbar @ u)
        if not fu > 0:
            return None, None
        return u / fu, xi / fu

    def to_user(self, st: CollapseState) -> CollapseState:
        """A scaled state in the user's units (re-checked there)."""
        F, L, nc = self.F, self.L, self.nc
        u = st.u.copy()
        u[0::3] *= L
        u[1::3] *= L
        u /= F * L          # fbar^T u = 1 in user units
        xi = st.xi.copy()
        xi[:2 * nc] *= L    # slips are lengths, hinge flows rotations
        xi /= F * L
        out = CollapseState(alpha=st.alpha, N=st.N * F, V=st.V * F, M=st.M * F * L, u=u, xi=xi,
                            flow=st.flow.copy(), source=st.source)
        out.residual = state_residuals(self.user_form, out)
        return out
