"""The plane's LPs for joints with strengths: crushing, tension, cohesion.

A joint with the strengths of :mod:`lamodel.formulation.joints` has a bounded domain
``Y s_f <= b`` (the slides with cohesion, the facets of its inscribed N-M polygon), no
longer a cone: the statics are written with explicit slacks instead of friction-cone
generators.

* **Statics**: columns ``(sigma, N, V, M, alpha)``, rows ``A s_f + alpha fbar = -f0`` and
  ``Y s_f + w sigma = b``, ``sigma >= 0``: the slack ``w sigma`` of a yield row is its own
  column (``w = max(1, |b|)``: a far facet's slack, of the size of the joint's crushing
  force, stays a number of the size of the forces in sigma, which the search measures
  tolerances against: unscaled, f_c = 1e9 made every row "active"), so a
  row is held by bounding its sigma at 0 (as the generator form holds a row by zeroing
  its lambdas), the gap ``xi^T sigma`` is linear, and every equality LP of the search
  (the certificate's two, the pressure step's) works unchanged
  (:class:`~.problem.ScaledProblem`'s methods run on these columns).
* **Mechanism**: the fictitious system of cohesion ``c0 A - mu N`` (N of the real
  statics, given as ``c = -mu N`` by the search) with the facets unchanged and
  associative: columns ``(N, V, M, alpha)``, rows of equilibrium and ``G s_f <= (c + c0 A,
  beta)``, max alpha. The duals of its yield rows are the flows xi, of its equilibrium
  rows the motion u, exact from the final basis.
* **Facets in force**: at a joint's N only the facets near it bind. The LPs begin with
  the slides and each half's facets at the tension end (eq. 4's hinge rows as f_c grows)
  and at the crushing end (N bounded from the start), and take in the facets an optimum
  violates, each joint's most violated a round, re-solving warm until none is: every LP
  gets them as appended rows (the statics' sigma of a facet out of force is an empty
  column at 0, its slack filled in from the forces after the solve). Each optimum is that
  of the whole polygon; every vector the search sees has all nr rows. A 1,020-block wall's
  statics begins with 20,796 rows where it had 127,212.
* **One row of each**: a joint of infinite f_c has eq. 4's rows only; the layout's copies
  of its hinge rows (:func:`~lamodel.formulation.matrices.row_origins`) are not in the
  LPs: their slacks and flows are those of the row they copy (``row_of_pair`` maps the
  sigma columns to the rows). One crushing joint among many dry ones (a bridge's passive
  restraint) no longer multiplies every joint's rows.
* **Far strengths**: a row of infinite right-hand side (:func:`~lamodel.formulation.matrices.far_bounds`)
  is in no LP and has no sigma column; its slack is infinite, its flow 0.

A structure without strengths never comes here: :func:`lamodel.search.gap.formulation_of`
keeps :class:`~.problem.ScaledProblem`, whose LPs are those of eq. (4).
"""
from __future__ import annotations

from dataclasses import replace

import highspy
import numpy as np
import scipy.sparse as sp

from ...formulation.matrices import row_origins
from ...structure import Structure
from ..highs import INF, HighsLP
from ..options import Deadline
from ..tuning import CAP_FAR, FLOW_TOL, LP_TOLERANCE
from .problem import ScaledProblem
from .program import CAPPED

BASIC = int(highspy.HighsBasisStatus.kBasic)


class StrengthProblem(ScaledProblem):
    """The :class:`~.program.GapProgram` of a planar structure whose joints have strengths
    (module doc). ``stat``: the statics LP; ``coh`` and ``coh_r``: the fictitious LP (every
    row may flow; some only); ``dilatant``: (t, that LP with sliding dilating by t mu)."""

    #: the Pyomo model of eq. (5) polished by Ipopt knows no strengths
    polish = False

    def __init__(self, structure: Structure, deadline: Deadline | None = None):
        s = self._formulate(structure, deadline)
        nb, nc = self.nb, self.nc
        self.b = self.form.b_far  # the programs' (module doc: far strengths)
        self.far = ~np.isfinite(self.b)
        self.opens = np.isfinite(self.b[2 * nc:3 * nc])  # far tension: the joint never opens
        self.cohesion_area = self.b[:nc]  # c0 A: the real joint's own cohesion (inf: it never slides)
        self.nr = nr = self.Y.shape[0]
        self.R, self.C = np.ones(3 * nb), np.ones(nc)  # forces already bounded: no light-block scales
        self.row_scale = np.ones(nr)
        # one sigma column a distinct row (module doc); they play the generator form's lambdas
        origin = row_origins(s)
        self.is_kept = (origin == np.arange(nr)) & ~self.far
        self.kept = np.flatnonzero(self.is_kept)
        self.nl = self.kept.size
        column = np.full(nr, -1)
        column[self.kept] = np.arange(self.nl)
        has = column[origin] >= 0  # a far row (and its copies) has none
        self.row_of_pair = sp.csr_matrix((np.ones(has.sum()), (np.flatnonzero(has), column[origin][has])),
                                         shape=(nr, self.nl))
        self.w = np.where(self.far, 1.0, np.maximum(1.0, np.abs(self.b)))  # a row's slack is w sigma (module doc)
        self.w_kept = self.w[self.kept]
        self.column = column  # the sigma column of each kept yield row
        # the rows in force (module doc): the slides and each half's facet at the tension
        # end (eq. 4's hinge rows) to begin with, in every LP in this order
        self.in_force = np.zeros(nr, bool)
        self.in_force[:3 * nc] = True
        self.in_force[(2 + self.n_facets) * nc:(3 + self.n_facets) * nc] = True
        # and each half's facet at the crushing end: a crushing joint's N bounded from the
        # start, so that no LP runs unbounded for want of it (HiGHS took 1.6 million
        # iterations to say so on bond10x10 at f_c = 1e9)
        m = self.n_facets
        self.in_force[(1 + m) * nc:(2 + m) * nc] = True
        self.in_force[(1 + 2 * m) * nc:(2 + 2 * m) * nc] = True
        self.in_force &= self.is_kept
        self.fict_rows = np.flatnonzero(self.in_force)
        # --- statics: columns sigma (one a distinct row), s_f (3 nc), alpha; rows the
        # equilibrium and the yield rows in force (a sigma out of force: an empty column at 0)
        k = self.fict_rows
        A = sp.bmat([[sp.csr_matrix((3 * nb, self.nl)), self.A, self.fbar.reshape(-1, 1)],
                     [self._sigma_of(k), self.Y[k], None]], format="csc")
        self.free = np.r_[np.zeros(self.nl), np.full(3 * nc, -INF), 0.0]
        self.stat = HighsLP(A, np.concatenate([-self.f0, self.b[k]]), np.zeros(A.shape[1]), self.free,
                            np.full(A.shape[1], INF), "statics")
        #: the statics' rows with every yield row in it: the work bound's scale (:meth:`work_bound`),
        #: and what a statics iteration counts (the search's iterations as with every row in)
        self.rows_all = self.stat.rows_counted = 3 * nb + self.nl
        self.obj_scale = float(nb)
        self.facet_rounds = 0  # re-solves that brought violated facets into force
        self.coh = self._fictitious(0.0, "cohesive")
        self.coh_r = self._fictitious(0.0, "cohesive-r")
        self.lps = {"stat": self.stat, "coh": self.coh, "coh_r": self.coh_r}
        for lp in self.lps.values():
            self._trace(lp)
        self.lps_elsewhere = 0
        self.work_elsewhere = 0
        self.dilatant = None
        self.dilatant_done = [0, 0]

    @property
    def n_facets(self):
        """Facets a half of each joint's N-M polygon."""
        return (self.nr // self.nc - 2) // 2

    def work_bound(self):
        """The generator form's bound times how many more rows these LPs have: the work
        counts iterations times rows (:attr:`~lamodel.search.highs.HighsLP.work`), and the
        search should get as many iterations as on the dry joints' LPs (3 nb rows)."""
        return super().work_bound() * self.rows_all / (3 * self.nb)

    # ------------------------------------------------ bases of LPs whose rows grow
    GROWING = ("stat", "coh", "coh_r")  # the LPs whose rows grow

    def bases(self):
        """As :meth:`ScaledProblem.bases`, the row statuses of the LPs whose rows grow in the order of
        all the yield rows (a row not in force: basic), with the rows in force: another
        copy of this problem, whose facets came into force in another order, restarts
        from them (:meth:`restart`)."""
        out = super().bases()
        for name in self.GROWING:
            if out[name] is not None:
                cols, rows = out[name]
                full = np.full(3 * self.nb + self.nr, BASIC, np.int8)
                full[:3 * self.nb] = rows[:3 * self.nb]
                full[3 * self.nb + self.fict_rows] = rows[3 * self.nb:]
                out[name] = cols, full
        out["in_force"] = self.in_force.copy()
        return out

    def restart(self, bases):
        self._bring_into_force(bases.get("in_force", self.in_force))
        own = dict(bases)
        for name in self.GROWING:
            if own.get(name) is not None:
                cols, full = own[name]
                own[name] = cols, np.r_[full[:3 * self.nb], full[3 * self.nb + self.fict_rows]]
        super().restart(own)

    def load_bases(self, saved, restart_cold=True):
        """As :meth:`ScaledProblem.load_bases`; a fictitious LP's basis saved before facets
        came into force gets their slacks basic (what adding them did)."""
        for name, basis in saved.items():
            lp = self.lps[name]
            if basis is not None and len(basis.row_status) < lp.m:
                basis.row_status = list(basis.row_status) + [highspy.HighsBasisStatus.kBasic] * (lp.m - len(basis.row_status))
        super().load_bases(saved, restart_cold)

    def crushing_message(self) -> str:
        """Why the structure cannot stand, when its joints' strengths are the reason: the
        same structure with dry, infinitely strong joints stands (its statics LP is
        solved once, here); '' otherwise."""
        dry = replace(self.user, fc=None, ft=None, cohesion=None)
        status, x = ScaledProblem(dry, self.deadline).statics()
        if status == "optimal" and x[-1] <= self.stable_alpha:
            return ("; with dry joints it stands: the joints crush under the dead load "
                    "(compressive strength fc too small for the forces they carry)")
        return ""

    def glued_message(self) -> str:
        """Why no mechanism follows the load when far strengths glue joints; '' if none is."""
        return "" if not self.far.any() else (f" (joints' tensile strength or cohesion beyond {CAP_FAR:g} times "
                                              "the loads glue them: such a joint never opens, or never slides)")

    def _fictitious(self, t, name):
        """The fictitious LP (module doc) whose sliding dilates by t mu: rows equilibrium
        (3 nb) and ``G_t s_f <= bounds`` (nr), columns s_f (3 nc) and alpha; max alpha."""
        nc = self.nc
        G = self.G
        if t > 0:  # a joint that never opens (far tension) slides without dilating
            tmu = np.where(self.opens, t * self.mu, 0.0)
            tmu = sp.csr_matrix((np.tile(tmu, 2), (np.arange(2 * nc), np.tile(np.arange(nc), 2))), shape=G.shape)
            G = (G + tmu).tocsr()
        k = self.fict_rows
        A = sp.bmat([[self.A, self.fbar.reshape(-1, 1)], [G[k], None]], format="csc")
        n = 3 * nc + 1
        cost = np.zeros(n)
        cost[-1] = -self.obj_scale
        lo = np.concatenate([-self.f0, np.full(k.size, -INF)])
        hi = np.concatenate([-self.f0, self.b[k]])
        return HighsLP(A, lo, cost, self.free[self.nl:], np.full(n, INF), name, b_hi=hi)

    def _fictitious_lps(self):
        return [self.coh, self.coh_r] + ([self.dilatant[1]] if self.dilatant is not None else [])

    def _sigma_of(self, rows):
        """The sigma columns (w on the diagonal) of the yield rows ``rows`` (indices)."""
        return sp.csr_matrix((self.w[rows], (np.arange(rows.size), self.column[rows])), shape=(rows.size, self.nl))

    def _bring_into_force(self, rows):
        """Append the facets ``rows`` (a mask of the yield rows; copies are left out) to
        every fictitious LP (their bounds are set by the next solve) and to the statics,
        whose basis takes each one's sigma as basic (its row at its value): the basis stays
        a basis and the solution the same until sigma is bounded at 0."""
        rows = np.flatnonzero(np.asarray(rows, bool) & ~self.in_force & self.is_kept)
        if not rows.size:
            return
        self.in_force[rows] = True
        self.fict_rows = np.r_[self.fict_rows, rows]
        facets = sp.hstack([self.G[rows], sp.csr_matrix((rows.size, 1))], format="csr")
        for lp in self._fictitious_lps():
            lp.add_rows(facets, np.full(rows.size, -INF), self.b[rows])
        stat = self.stat
        m0 = stat.m
        stat.add_rows(sp.hstack([self._sigma_of(rows), self.Y[rows], sp.csr_matrix((rows.size, 1))], format="csr"),
                      self.b[rows], self.b[rows])
        if not stat.cold and not stat.abandoned:
            basis = stat.h.getBasis()
            cols, status = list(basis.col_status), list(basis.row_status)
            for i, r in enumerate(rows):
                cols[self.column[r]] = highspy.HighsBasisStatus.kBasic
                status[m0 + i] = highspy.HighsBasisStatus.kLower
            basis.col_status, basis.row_status = cols, status
            stat.h.setBasis(basis)

    # ------------------------------------------------------------------- statics
    def forces(self, x):
        return x[self.nl:self.nl + 3 * self.nc]

    def N_of(self, x):
        return x[self.nl:self.nl + self.nc]

    def statics(self, cost_lam=None, held=None, maximize=False, cap=None, alpha_cost=1.0, u=None):
        """Optimise over S: min (max) alpha_cost alpha + cost_lam^T sigma with the yield rows
        ``held`` at equality (their sigma bounded at 0). Returns (status, x)."""
        n = self.stat.n
        cost = np.zeros(n)
        cost[-1] = -alpha_cost if maximize else alpha_cost
        if cost_lam is not None:
            cost[:self.nl] = cost_lam
        hi = np.full(n, INF)
        if held is not None and held.any():
            hi[:self.nl][self.zeroed(held)] = 0.0
        # a row held or priced must be in force (a free sigma with a cost is unbounded)
        self._bring_into_force(self._rows_of((hi[:self.nl] == 0.0) | (cost[:self.nl] != 0.0)))
        self.stat.set_cost(cost)
        while True:
            # a facet not in force is not in the LP: its sigma an empty column at 0
            out = ~self.in_force[self.kept]
            h = hi.copy()
            h[:self.nl][out] = 0.0
            self.stat.set_bounds(self.free, h)
            status = self.stat.solve(cap, self.deadline)
            if status == "unbounded" and out.any():
                # the facets left out may be what bounds it: all of them, once
                self._bring_into_force(self.is_kept)
                self.facet_rounds += 1
                continue
            if status != "optimal":
                return status, None
            x = self._filled(self.stat.x())
            late, excess = np.zeros(self.nr, bool), np.zeros(self.nr)
            late[self.kept] = out & (x[:self.nl] < -LP_TOLERANCE)
            if not late.any():
                break
            excess[self.kept] = -self.w_kept * x[:self.nl]  # by how much each row is violated
            self._bring_into_force(self._most_violated(late, excess))
            self.facet_rounds += 1
        x[:self.nl] = np.maximum(x[:self.nl], 0.0)
        x[-1] = max(x[-1], 0.0)
        return status, x

    def _filled(self, x):
        """A statics of the LP with the sigma of each facet out of force set to its slack
        (``(b - Y s_f) / w``, negative where the forces violate it): every statics the
        search sees has all its columns."""
        out = ~self.in_force[self.kept]
        if out.any():
            rows = self.kept[out]
            x = x.copy()
            x[:self.nl][out] = (self.b[rows] - self.Y[rows] @ self.forces(x)) / self.w[rows]
        return x

    def certificates(self, u, xi, flow, cap):
        """:meth:`ScaledProblem.certificates`, each statics with all its columns (:meth:`_filled`)."""
        for out in super().certificates(u, xi, flow, cap):
            yield out if out is CAPPED else (self._filled(out[0]), *out[1:])

    def _most_violated(self, late, excess):
        """Of the violated facets ``late`` (a mask of the yield rows), each joint's most
        violated (``excess``: by how much, a row): a point far outside a joint's polygon
        violates many of its facets, and the one of them that binds at the new optimum is
        near the joint's N (bringing in all doubled the rows in force on wall33 at f_c 3)."""
        rows = np.flatnonzero(late)
        joint = rows % self.nc
        order = np.lexsort((-excess[rows], joint))  # by joint, the largest excess first
        first = np.r_[True, joint[order][1:] != joint[order][:-1]]
        out = np.zeros(self.nr, bool)
        out[rows[order][first]] = True
        return out

    def _rows_of(self, columns):
        """The yield rows (a mask) of the sigma columns ``columns`` (a mask)."""
        rows = np.zeros(self.nr, bool)
        rows[self.kept[np.asarray(columns, bool)]] = True
        return rows

    def zeroed(self, held):
        """The sigma columns that holding the rows ``held`` bounds at 0: theirs (a copy's
        is the row's it copies)."""
        return self.row_of_pair.T @ np.asarray(held, float) > 0

    def slack(self, x):
        out = self.row_of_pair @ (self.w_kept * x[:self.nl])
        out[self.far] = np.inf
        return out

    def gap_weights(self, xi, u=None):
        """The weights of x = (sigma, ...) in alpha_K - alpha = xi^T (w sigma) (virtual work)."""
        return self.w_kept * (self.row_of_pair.T @ np.asarray(xi, float))

    def cohesive_N(self, xc):
        return xc[:self.nc]

    # ----------------------------------------------------------------- mechanism
    def mechanism(self, c, allowed=None, dilatancy=0.0):
        """The fictitious LP for cohesions c (the search's ``-mu N``; the joint's own
        ``c0 A`` is added), flow allowed on rows ``allowed`` only (a row that may not flow
        is dropped). Returns (status, alpha_as, x, u, xi); ``dilatancy`` t > 0: the LP
        whose sliding dilates by t mu, every row allowed, its flows those of the seed's
        system (:meth:`_seed_flows`)."""
        nc = self.nc
        c = np.maximum(np.asarray(c, float), 0.0) + self.cohesion_area
        hi = self.b.copy()
        hi[:2 * nc] = np.tile(c, 2)
        if dilatancy > 0:
            lp = self._dilatant_lp(dilatancy)
        else:
            if allowed is not None:
                hi[~np.asarray(allowed, bool)] = INF
            lp = self.coh if allowed is None else self.coh_r
            if lp.cold and not self.coh.cold:
                lp.h.setBasis(self.coh.h.getBasis())
                lp.cold = False
        status = self._solve_in_force(lp, hi)
        if status != "optimal":
            return status, np.nan, None, None, None
        y, _ = lp.exact_duals()
        u = -y[:3 * self.nb] / self.obj_scale
        fu = self.fbar @ u
        if not fu > 0:
            return "degenerate", np.nan, None, None, None
        u /= fu
        xi = np.zeros(self.nr)
        xi[self.fict_rows] = np.maximum(-y[3 * self.nb:] / (self.obj_scale * fu), 0.0)
        if dilatancy > 0:
            xi = self._seed_flows(xi, dilatancy)
        elif allowed is not None:
            xi[~np.asarray(allowed, bool)] = 0.0
        x = lp.x()
        return status, float(x[-1]), x, u, self._significant(xi, u)

    def _significant(self, xi, u=None):
        """xi without the flows below FLOW_TOL of the largest flow or of the largest block
        motion, whichever is smaller (slips and motions as they are, rotations times the
        structure's size, as the residual test measures them). Two facets at a joint's
        crushing end that close it without turning flow ~1/d times its closure, and nearly
        cancel: a bridge's fill restraint (d 0.1 m of 27 m) flowed 224 where the blocks
        moved 1, and its flows alone would have set what counts as zero elsewhere (flows
        of 2e-7 dropped at joints carrying the arch's thrust: a virtual-work residual of
        1.7e-6 on an exact collapse state)."""
        if u is None:
            return super()._significant(xi)
        L = self.form.structure.size()
        flows = np.abs(np.concatenate([xi[:2 * self.nc], L * xi[2 * self.nc:]]))
        motion = np.abs(np.concatenate([u[0::3], u[1::3], L * u[2::3]]))
        largest = min(flows.max() if flows.size else 0.0, motion.max() if motion.size else 0.0)
        xi[flows <= FLOW_TOL * largest] = 0.0
        return xi

    def _solve_in_force(self, lp, hi):
        """Solve the fictitious LP ``lp`` (yield rows' bounds ``hi``, all nr) with only the
        facets in force; the facets its optimum violates come into force and it is
        re-solved warm, until none is violated: then it is the optimum over the whole
        polygon (the rows left out are slack, their flows 0), the same LP as with every
        facet, at the cost of the few facets near each joint's N (with f_c large, eq. 4's
        rows alone)."""
        out = ~self.in_force & (hi < INF) & self.is_kept  # rows that may flow and are not in the LP
        while True:
            k = self.fict_rows
            lp.set_row_bounds(np.concatenate([-self.f0, np.full(k.size, -INF)]), np.concatenate([-self.f0, hi[k]]))
            status = lp.solve(deadline=self.deadline)
            if status == "unbounded" and out.any():
                # the facets left out may be what bounds it: all of them, once
                self._bring_into_force(out)
                out[:] = False
                self.facet_rounds += 1
                continue
            if status != "optimal":
                return status
            s_f = lp.x()[:3 * self.nc]
            late = np.zeros(self.nr, bool)
            excess = np.zeros(self.nr)
            rows = np.flatnonzero(out)
            excess[rows] = self.G[rows] @ s_f - hi[rows]
            late[rows] = excess[rows] > LP_TOLERANCE * np.maximum(1.0, np.abs(hi[rows]))
            if not late.any():
                return status
            late = self._most_violated(late, excess)
            self._bring_into_force(late)
            out &= ~late
            self.facet_rounds += 1

    def _dilatant_lp(self, t):
        """The fictitious LP of dilatancy t, one at a time (as the generator form's)."""
        if self.dilatant is None or self.dilatant[0] != t:
            if self.dilatant is not None:
                old = self.dilatant[1]
                self.dilatant_done = [self.dilatant_done[0] + old.n_solves, self.dilatant_done[1] + old.work]
            self.dilatant = (t, self._fictitious(t, "dilatant"))
        return self.dilatant[1]

    def _seed_flows(self, xi, t):
        """Flows of the dilatant system as flows of the seed's: a slip s there also opens
        the joint by t mu |s|; that opening is given to the two facets at the tension end
        (gradients (a, -/+1), a > 0), so that ``q = G^T xi`` holds with the seed's G."""
        nc, m = self.nc, (self.nr // self.nc - 2) // 2
        a0 = self.Y[2 * nc:3 * nc][:, :nc].diagonal()
        opening = np.where(self.opens, t * self.mu * (xi[:nc] + xi[nc:2 * nc]), 0.0)
        out = xi.copy()
        out[2 * nc:3 * nc] += opening / (2 * a0)
        out[(2 + m) * nc:(3 + m) * nc] += opening / (2 * a0)
        return out
