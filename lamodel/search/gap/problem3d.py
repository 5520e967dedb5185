"""The search's programs in space: the seed's method on the Coulomb cone (eq. 1-5 in 3D),
the space's :class:`~.program.GapProgram`.

Columns are the statics ``x = (N, T1, T2, alpha)`` of :mod:`lamodel.formulation.space`
on the non-dimensional structure; the programs are Clarabel's second-order cone programs
(:mod:`lamodel.search.cone`), the certificates exact LPs on fixed cones with HiGHS
(:mod:`lamodel.search.certify3d`). Rows (what a mechanism flows on) are two a contact
point: ``p`` its opening (``N = 0``, any slip) and ``np + p`` its sliding (on the cone,
along the tangential force); a mechanism's flows ``xi`` are its openings and slips there.

* **statics**: max alpha over S (the associative bound), min ``alpha + w^T x`` (the gap
  step), min alpha with rows held: opening points at ``N = T = 0``, sliding points at
  ``T = -mu N s_hat`` along the slip of the mechanism u given;
* **mechanism**: the cohesive program for cohesions c (``||T|| <= c``); its equilibrium
  duals are the mechanism of least alpha_K;
* **gap**: ``alpha_K(N) - alpha = w(q)^T x`` with the strains ``q = -A^T u``
  (:func:`lamodel.formulation.space.gap_weights`);
* **certificate**: at thresholds of the strains in turn, the nearest exact motion with
  those points moving (:func:`~lamodel.search.certify3d.project_mechanism`), polished to
  the least alpha_K for its cohesions (:func:`~lamodel.search.certify3d.polish_mechanism`),
  then the least alpha with the points held: the exact LP on fixed cones
  (:func:`~lamodel.search.certify3d.statics_lp`) and the held cone program's statics;
  where none holds, the same with the sliding directions aligned
  (:func:`~lamodel.search.certify3d.align`).

With the joints' strengths: :class:`~.capped3d.CappedConeProblem`.

No warm bases: an interior-point program starts cold (``lps`` is empty).
"""
from __future__ import annotations

import logging
import math
import time

import numpy as np

from ...formulation.space import Formulation3D, scaled, scales
from ...structure3d import Structure3D
from ..certify3d import (CollapseState3D, align, mechanism_lp, passes, polish_mechanism, project_mechanism, residuals,
                         statics_lp)
from ..cone import ConePrograms
from ..options import Deadline
from ..tuning import (ALIGN_CAP_ROWS, ALIGN_IPM_CAP, CONE_ACTIVE, CONE_DIRECTION_DECIMALS, CONE_FLOW_TOLS,
                      CONE_LP_FIRST_POINTS, MECHANISMS_REMEMBERED, STABLE_ALPHA_CONE, WORK_FLOOR_CONE,
                      WORK_PER_BLOCK_CONE)

log = logging.getLogger(__name__)


class ConeProblem:
    """The cone programs of one 3D structure, scaled (see the module doc)."""

    #: no Ipopt polish in space (the search's states are certified as they are)
    polish = False
    stable_alpha = STABLE_ALPHA_CONE

    def __init__(self, structure: Structure3D, deadline: Deadline | None = None, threads: int = 1):
        self.t0 = time.perf_counter()
        self.user = structure
        self.deadline = deadline or Deadline()
        self.F, self.L = scales(structure)
        self.form = Formulation3D.of(scaled(structure, self.F, self.L))
        self.user_form = Formulation3D.of(structure)
        self.cone = ConePrograms(self.form, threads)
        self.nb, self.np = self.form.nb, self.form.np
        self.nc = self.np            # one cohesion a contact point
        self.mu = self.form.mu
        self.caps = self.form.caps   # (N_c, N_t, k) per point with the joints' strengths, else None
        self.lps = {}                # no warm bases
        self.lps_elsewhere = 0
        self.work_elsewhere = 0      # the cone work of evaluations merged from elsewhere
        self.n_lp = 0                # HiGHS LPs of the certificates
        self._mechanisms = {}        # id(u) -> (u, c): the cohesions u is least-alpha_K for
        self._dilatant = {}          # id(u) -> (u, t): mechanisms of the system of dilatancy t > 0
        self.align_work = 0.0        # work of the direction alignments' LPs (certify3d.lp_work)
        self._unaligned = set()      # patterns (opening, sliding) the alignment found no statics for
        self._solved = {}            # (c, allowed) -> the cohesive program's answer, the last few

    # ------------------------------------------------------------------ bookkeeping
    def elapsed(self):
        """Seconds since the programs were built."""
        return time.perf_counter() - self.t0

    def n_lps(self):
        """Cone programs and certification LPs so far, merged evaluations included."""
        return self.cone.n_solves + self.n_lp + self.lps_elsewhere

    def work(self):
        """The cone programs' work so far (:attr:`lamodel.search.cone.ConePrograms.work`),
        the direction alignments' LPs counted in the same units, merged evaluations included."""
        return self.cone.work + self.align_work + self.work_elsewhere

    def work_bound(self):
        """WORK_PER_BLOCK_CONE a block, at least WORK_FLOOR_CONE."""
        return max(WORK_FLOOR_CONE, WORK_PER_BLOCK_CONE * self.nb)

    def bases(self):
        """No warm bases in space (interior-point programs start cold)."""
        return {}

    def restart(self, bases):
        """Forget the programs solved (a pure evaluation depends on its snapshot alone)."""
        self._solved = {}
        self._unaligned = set()

    def save_bases(self, names=None):
        """Nothing to save (see :meth:`bases`)."""
        return {}

    def load_bases(self, saved, restart_cold=True):
        """Nothing to load (see :meth:`bases`)."""

    def _left(self):
        """Seconds left for a program (None: no limit); Stopped once the deadline passed."""
        self.deadline.check()
        left = self.deadline.left()
        return None if math.isinf(left) else max(left, 1e-3)

    def _ran(self, res, name):
        """A program's result; Stopped if the deadline fired during it."""
        log.debug("%8.2f %s: %s alpha %.7f (%.2f s, %d iterations)", self.elapsed(), name, res.status, res.alpha,
                  res.seconds, res.iterations)
        if not res.ok and res.status not in ("infeasible", "unbounded"):
            self.deadline.check()
        return res

    # ---------------------------------------------------------------------- statics
    def statics(self, cost_lam=None, held=None, maximize=False, cap=None, alpha_cost=1.0, u=None):
        """max alpha over S, or min ``alpha + cost_lam^T x`` with the rows ``held`` at
        equality (sliding ones along the slips of ``u``). ``cap``: none in space.
        Returns (status, x)."""
        if maximize:
            res = self._ran(self.cone.associative(time_limit=self._left()), "associative")
        else:
            opening = sliding = dirs = crushing = None
            if held is not None and held.any():
                opening, sliding, crushing = self._split(held)
                sliding = sliding if self.caps is not None else sliding & ~opening
                dirs = self._directions(u)
            res = self._ran(self.cone.statics(cost_lam, opening=opening, sliding=sliding, slide_dir=dirs,
                                              time_limit=self._left(), crushing=crushing), "statics")
        return res.status, (res.x if res.ok else None)

    def _split(self, rows):
        """(opening, sliding, crushing) rows (crushing: none without the joints' strengths)."""
        rows, n = np.asarray(rows, bool), self.np
        return rows[:n], rows[n:2 * n], (rows[2 * n:] if self.caps is not None else np.zeros(n, bool))

    def _directions(self, u):
        """(np, 2) unit slips of the mechanism u in the points' frames ((1, 0) where none)."""
        n = self.np
        q = self.form.strains(u)
        slip = np.hypot(q[n:2 * n], q[2 * n:])
        safe = np.where(slip > 0, slip, 1.0)
        return np.column_stack([np.where(slip > 0, q[n:2 * n] / safe, 1.0), q[2 * n:] / safe])

    def N_of(self, x):
        """Normal forces (one a contact point) of a statics."""
        return x[:self.np]

    def cohesive_N(self, xc):
        """Normal forces of the cohesive program's statics."""
        return xc[:self.np]

    def slack(self, x):
        """Per point: -N (opening row) and ``-mu N - ||T||`` (sliding row), >= 0 in S."""
        return np.concatenate([-x[:self.np], self.form.cone_slack(x[:3 * self.np])])

    def active_rows(self, x, tol):
        """Rows whose slack is at most ``tol`` (CONE_ACTIVE at least: an interior-point
        statics holds its rows to its tolerance only) times the largest entry (or 1)."""
        return self.slack(x) <= max(tol, CONE_ACTIVE) * max(1.0, np.abs(x).max())

    def gap_weights(self, xi, u=None):
        """w (3 np) with ``w^T x = alpha_K - alpha`` for the mechanism u, at the points xi
        flows at (openings of a conic mechanism are >= 0 up to its tolerance; a mechanism of
        dilatancy t without the opening t mu ||slip|| its slips cause: the same gap)."""
        return self.form.gap_weights(self._moving_strains(xi, u))

    def _moving_strains(self, xi, u):
        """The strains of u at the points xi flows at (openings >= 0; with the caps, the
        normal strain only where an opening or crushing row flows: a cap times a closing
        of the conic tolerance is no dissipation)."""
        n = self.np
        q = self._strains(u)
        if self.caps is None:
            q[:n] = np.maximum(q[:n], 0.0)
        else:
            q[:n] = np.where((xi[:n] > 0) | (xi[2 * n:] > 0), q[:n], 0.0)
        moving = np.tile(xi.reshape(-1, n).sum(axis=0) > 0, 3)
        return np.where(moving, q, 0.0)

    def gap(self, x, xi, u=None):
        """alpha_K - alpha of the statics x for the mechanism (u, xi) (eq. 5)."""
        return float(self.gap_weights(xi, u) @ x[:3 * self.np])

    # -------------------------------------------------------------------- mechanism
    def _strains(self, u):
        """The strains of u; for a mechanism of dilatancy t (:meth:`mechanism`), the
        openings less the dilatancy t mu ||slip|| of its slips."""
        q = self.form.strains(u)
        entry = self._dilatant.get(id(u))
        if entry is not None and entry[0] is u:
            n = self.np
            q[:n] -= entry[1] * self.mu * np.hypot(q[n:2 * n], q[2 * n:])
        return q

    def flows(self, u, tol=CONE_FLOW_TOLS[0]):
        """xi (2 np) of the motion u: openings where a point opens, slips where it slides
        without opening; motions below ``tol`` of the largest strain are none."""
        n = self.np
        q = self._strains(u)
        top = np.abs(q).max() if q.size else 0.0
        qn, slip = q[:n], np.hypot(q[n:2 * n], q[2 * n:])
        opening = qn > tol * top
        sliding = (slip > tol * top) & ~opening
        return np.concatenate([np.where(opening, qn, 0.0), np.where(sliding, slip, 0.0)])

    def mechanism(self, c, allowed=None, dilatancy=0.0):
        """The cohesive program for cohesions c (>= 0), flow allowed on rows ``allowed``
        only: (status, alpha_as, statics, u, xi), ``fbar^T u = 1``. ``dilatancy`` t > 0:
        the system whose slips dilate by t mu, friction t mu besides the cohesions."""
        c = np.asarray(c, float)
        c = np.maximum(c, 0.0) if self.caps is None else np.maximum(c + self.caps[2], 0.0)
        may_open = may_slip = may_crush = None
        if allowed is not None:
            may_open, may_slip, may_crush = self._split(allowed)
        # the same program again (a descent's two tolerances, the chain's first step after
        # a mechanism step): its answer, not another interior-point solve of seconds
        key = c.tobytes() + (b"" if allowed is None else np.asarray(allowed, bool).tobytes()) + bytes(
            np.float64(dilatancy))
        res = self._solved.get(key)
        if res is None:
            res = self._ran(self.cone.cohesive(c, may_open=may_open, may_slip=may_slip, time_limit=self._left(),
                                               dilatancy=dilatancy, **({} if self.caps is None else {"may_crush": may_crush})),
                            "cohesive" if allowed is None else "cohesive-r")
            self._solved = {key: res} | dict(list(self._solved.items())[:MECHANISMS_REMEMBERED - 1])
        if not res.ok:
            return res.status, np.nan, None, None, None
        if res.u is None:
            return "degenerate", np.nan, None, None, None
        u = res.u
        if dilatancy > 0:
            u = u.copy()  # its own object: gap weights and flows look up its dilatancy by identity
            self._dilatant = {id(u): (u, dilatancy)} | dict(list(self._dilatant.items())[-(MECHANISMS_REMEMBERED - 1):])
        xi = self.flows(u)
        if allowed is not None:
            xi[~np.asarray(allowed, bool)] = 0.0
        self._mechanisms = {id(u): (u, c)} | dict(list(self._mechanisms.items())[-(MECHANISMS_REMEMBERED - 1):])
        return "optimal", res.alpha, res.x, u, xi

    # ---------------------------------------------------------------- certification
    def iteration_cap(self):
        """None: Clarabel's programs take a few dozen iterations, uncapped."""
        return None

    def pattern(self, u, flow):
        """The flow pattern and the sliding directions (to CONE_DIRECTION_DECIMALS)."""
        sliding = self._split(flow)[1]
        dirs = np.round(self._directions(u)[sliding], CONE_DIRECTION_DECIMALS) + 0.0
        return flow.tobytes() + dirs.tobytes()

    def pushing_rows(self, state):
        """No pressure step in space (no reduced costs of a held cone program)."""
        return None

    def certificates(self, u, xi, flow, cap):
        """Held statics for the mechanism u flowing on ``flow`` (see the module doc): at
        each threshold of CONE_FLOW_TOLS, its exact (and polished) motion and the held
        statics of each candidate sliding direction; where none holds, those of the first
        pattern's sliding directions aligned (:meth:`_aligned`), once a pattern."""
        n = self.np
        q = self.form.strains(u)
        top = np.abs(q).max()
        if not top > 0:
            return
        entry = self._mechanisms.get(id(u))
        c = entry[1] if entry is not None and entry[0] is u else None
        flow_open, flow_slip, _ = self._split(flow)
        qn, slip = q[:n], np.hypot(q[n:2 * n], q[2 * n:])
        tried = set()
        first = None  # the first pattern whose exact motion keeps its modes
        for tol in CONE_FLOW_TOLS:
            opening = flow_open & (qn > tol * top)
            sliding = flow_slip & (slip > tol * top) & ~opening
            key = opening.tobytes() + sliding.tobytes()
            if key in tried or not (opening.any() or sliding.any()):
                continue
            tried.add(key)
            exact = self._exact_motion(u, opening, sliding, c)
            if exact is None:
                continue
            first = first or (opening, sliding, exact)
            held = np.concatenate([opening, sliding])
            for tag, x in self._held_statics(opening, sliding, self._directions(exact)):
                yield x, exact, np.where(held, self.flows(exact, 0.0)[:held.size], 0.0), held, "+certify-" + tag
        if first is None or c is None or not first[1].any():
            return
        # the alignment's first LP tells in a dozen interior-point iterations that a pattern
        # has no statics near its directions; the chains meet one pattern again and again
        # with directions that differ by the conic tolerance: it is not asked twice
        key = first[0].tobytes() + first[1].tobytes()
        if key not in self._unaligned:
            self._unaligned.add(key)
            for cand in self._aligned(*first, c):
                self._unaligned.discard(key)   # it gave statics: not a pattern without any
                yield cand

    def _aligned(self, opening, sliding, exact, c):
        """The held statics of the sliding directions turned until a statics and a mechanism
        agree (:func:`~lamodel.search.certify3d.align`), about the normal forces ``-c / mu``
        the mechanism is least for: the conic slips are off by about the square root of the
        solver's tolerance, and then no statics holds them. Its LPs count as program solves
        and their work in :meth:`work`."""
        self.deadline.check()
        steps = []

        def tally(work):
            steps.append(work)
            self.align_work += work

        N0 = np.where(self.mu > 0, -np.asarray(c, float) / np.where(self.mu > 0, self.mu, 1.0), 0.0)
        try:
            got = align(self.form, opening, sliding, exact, N0, deadline=self.deadline, ipm_cap=ALIGN_IPM_CAP,
                        cap_rows=ALIGN_CAP_ROWS, tally=tally)
        finally:
            self.n_lp += len(steps)
        log.debug("%8.2f align: %s after %d LPs (work %.2e)", self.elapsed(), "aligned" if got is not None else "none",
                  len(steps), sum(steps))
        moved = None if got is None else project_mechanism(self.form, got[1], ~(opening | sliding), sliding)
        if moved is None:
            return
        held = np.concatenate([opening, sliding])
        for tag, x in self._held_statics(opening, sliding, got[0]):
            yield x, moved, np.where(held, self.flows(moved, 0.0)[:held.size], 0.0), held, "+align-" + tag

    def _exact_motion(self, u, opening, sliding, c):
        """The nearest exact motion with only ``opening`` and ``sliding`` points moving
        (slips of a conic answer are exact to its tolerance only: directions 1e-8 apart on
        one face can leave no exact statics), polished to the least alpha_K for cohesions
        c when known; None if the points do not keep their modes."""
        n = self.np
        stuck = ~(opening | sliding)
        best = None
        for cand in (u, None):
            if cand is None:
                if c is None or best is None:
                    break
                cand = polish_mechanism(self.form, best, stuck, sliding, c)
                if cand is None:
                    break
            v = project_mechanism(self.form, cand, stuck, sliding)
            if v is None:
                continue
            qv = self.form.strains(v)
            if np.any(qv[:n][opening] <= 0) or np.any(np.hypot(qv[n:2 * n], qv[2 * n:])[sliding] <= 0):
                continue
            best = v
        return best

    def _held_statics(self, opening, sliding, sdir):
        """The least alpha with the points held, on fixed cones (HiGHS: exact) and on the
        cone (Clarabel; its forces orient the stuck points' pyramids in the LP); the order
        by size (CONE_LP_FIRST_POINTS). Yields (tag, x). Not remembered here: the
        certifier's cache, part of a GA snapshot, keeps evaluations pure functions of it."""
        n = self.np
        _, x_cone = self._held_cone(opening, sliding, sdir)
        ref = np.column_stack([x_cone[n:2 * n], x_cone[2 * n:3 * n]]) if x_cone is not None else None
        order = ("lp", "cone") if self.np <= CONE_LP_FIRST_POINTS else ("cone", "lp")
        for tag in order:
            if tag == "lp":
                self.deadline.check()
                self.n_lp += 1
                x = statics_lp(self.form, opening, sliding, sdir, ref)
            else:
                x = x_cone
            if x is not None:
                yield tag, x

    def _held_cone(self, opening, sliding, sdir):
        res = self._ran(self.cone.statics(opening=opening, sliding=sliding, slide_dir=sdir, time_limit=self._left()),
                        "held")
        return res.status, (res.x if res.ok else None)

    # -------------------------------------------------------------------- states
    def state(self, x, u, xi, flow, source):
        """The collapse state of statics x with the mechanism u or, if u fails the residual
        test, one fitted to x (:func:`~lamodel.search.certify3d.mechanism_lp`); residuals in
        scaled units. ``flow`` is the flow of its mechanism."""
        N, T1, T2 = self.form.split(x)
        st = self._state(x, u, source)
        if not passes(st.residual):
            self.deadline.check()
            self.n_lp += 1
            mech = mechanism_lp(self.form, N, T1, T2)
            if mech is not None:
                st = self._state(x, mech[0], source)
        st.xi = self.flows(st.u)
        st.flow = st.xi > 0
        return st

    def _state(self, x, u, source):
        N, T1, T2 = self.form.split(x)
        q = self.form.strains(u)
        st = CollapseState3D(alpha=float(x[-1]), N=N.copy(), T1=T1.copy(), T2=T2.copy(), u=np.asarray(u, float),
                             q=q, source=source)
        st.residual = residuals(self.form, N, T1, T2, st.alpha, st.u, q)
        return st

    def to_user(self, st: CollapseState3D) -> CollapseState3D:
        """A scaled state in the user's units (``fbar^T u = 1`` there), re-checked there."""
        F, L = self.F, self.L
        u = st.u.reshape(-1, 6).copy()
        u[:, :3] *= L
        u = u.ravel() / (F * L)
        q = st.q * L / (F * L)
        out = CollapseState3D(alpha=st.alpha, N=st.N * F, T1=st.T1 * F, T2=st.T2 * F, u=u, q=q, source=st.source)
        out.residual = residuals(self.user_form, out.N, out.T1, out.T2, out.alpha, out.u, out.q)
        out.flow, out.xi, out.crushable = st.flow.copy(), st.xi * L / (F * L), st.crushable
        return out

