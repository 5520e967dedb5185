"""The one HiGHS wrapper: an LP that is warm-started, interruptible, and gives exact duals.

``min c^T x, A x = b, lo <= x <= hi`` (rows as equalities; a range row is a column more).
Every solve of the search and of the published methods goes through :class:`HighsLP`:

* warm re-solves by the primal simplex, a cold start of a large LP by the interior point
  method with crossover (IPM_COLUMNS);
* a solve stops at its :class:`~lamodel.search.options.Deadline`, inside HiGHS (its
  interrupt callback) and, for LPs run in a worker thread, within WAIT_SLICE s even where
  HiGHS calls no callback, and at the work its deadline leaves; iteration caps (counted);
* the primal and the duals recomputed exactly from the final basis (an LU solve), so that
  certified states satisfy equilibrium and compatibility to round-off.
"""
from __future__ import annotations

import atexit
import threading
import time

import highspy
import numpy as np
import scipy.sparse as sp

from .basis import solve as basis_solve
from .options import Deadline, Stopped
from .pace import Pace
from .tuning import (ABANDONED_EXIT_WAIT, BASIS_TOLERANCE, CAP_BACKSTOP, CAP_BACKSTOP_MIN, CAP_BACKSTOP_SAMPLE,
                     HIGHS_THREADS, INLINE_COLUMNS, IPM_COLUMNS, IPM_TOLERANCE, LP_TOLERANCE, WAIT_SLICE)

INF = highspy.kHighsInf
_NEVER = Deadline()


class QuietHighs(highspy.Highs):
    """highspy's Highs that prints nothing. highspy 1.16 logs its banner to stdout when
    its constructor enables the Python callbacks, before an option can be set (it broke
    ``--quiet`` and any stdout a user parses); the option goes first here."""

    def enableCallbacks(self):
        self.setOptionValue("output_flag", False)
        super().enableCallbacks()

    def __init__(self):
        super().__init__()
        self.setOptionValue("output_flag", False)  # highspy versions without enableCallbacks
        # before any solve of the process: its first sets the scheduler's threads for good
        self.setOptionValue("threads", HIGHS_THREADS)


_abandoned: list[threading.Thread] = []


@atexit.register
def _join_abandoned():
    """An abandoned solve whose thread returns from HiGHS while the interpreter finalises
    aborts the process (exit 134, in pybind11's GIL re-acquisition). Before finalising,
    give those solves (interrupted: they stop at HiGHS's next callback) a bounded time."""
    end = time.monotonic() + ABANDONED_EXIT_WAIT
    for t in _abandoned:
        t.join(max(0.0, end - time.monotonic()))


class HighsLP:
    """min c^T x, b <= A x <= b_hi, lo <= x <= hi, warm-started, interruptible, with exact duals.

    Rows are equalities unless ``b_hi`` is given. ``warm``: the simplex of warm re-solves,
    ``"primal"`` (the search's: the dual was 10-100x slower on its LPs) or ``"dual"``
    (HiGHS's default, the published methods' LPs, whose reported values were measured so).

    Each solve is given its deadline. Every HiGHS ``run()`` happens in a worker thread
    (highspy releases the GIL) while the calling thread waits in slices of WAIT_SLICE s
    and checks the deadline (small LPs, at most INLINE_COLUMNS columns, run inline:
    milliseconds each): a stop takes effect within a slice even where HiGHS calls no
    interrupt callback (IPX's crossover, presolve). The abandoned solve goes on in its thread until HiGHS notices the
    interrupt; its object is marked ``abandoned`` and never touched again (every later
    call raises :class:`Stopped`), so a search is unusable after a Stopped.
    """

    def __init__(self, A, b, cost, lo, hi, name="", b_hi=None, warm="primal", ipm=False):
        self.A = sp.csc_matrix(A)
        self.m, self.n = self.A.shape
        self.b = np.asarray(b, float).copy()
        self.b_hi = self.b.copy() if b_hi is None else np.asarray(b_hi, float).copy()
        self.cost = np.asarray(cost, float).copy()
        self.lo, self.hi = np.asarray(lo, float).copy(), np.asarray(hi, float).copy()
        self.deadline = _NEVER  # that of the solve under way (see solve)
        self.name = name
        self.warm_strategy = {"primal": 4, "dual": 1}[warm]  # HiGHS's simplex_strategy of warm solves
        self.ipm = bool(ipm)  # a cold start by the interior point method whatever the size
        self._built = tuple(v.copy() for v in (self.cost, self.lo, self.hi, self.b, self.b_hi))
        self._fresh()
        self.n_solves = 0
        self.seconds = 0.0
        #: simplex and interior-point iterations times rows, summed over the solves: a count
        #: that grows like their time (the search's work bound without a time limit)
        self.work = 0
        #: the rows an iteration counts in :attr:`work` (None: this LP's): an LP that stands for
        #: a larger one (rows brought in only when violated) counts the larger one's
        self.rows_counted = None
        self.trace = None  # a print-like function to log every solve
        self.warm_iterations, self.warm_seconds = 0, 0.0  # of warm solves (see _backstop)
        self.cold_seconds = 0.0  # the longest cold solve (see _backstop)
        self._pace = None  # the simplex of a capped cold interior point run (see :class:`.pace.Pace`)
        self.abandoned = False

    def _fresh(self):
        """A new HiGHS object holding this LP (current costs and bounds), cold."""
        h = self.h = QuietHighs()
        h.setOptionValue("primal_feasibility_tolerance", LP_TOLERANCE)
        h.setOptionValue("dual_feasibility_tolerance", LP_TOLERANCE)
        lp = highspy.HighsLp()
        lp.num_col_, lp.num_row_ = self.n, self.m
        lp.col_cost_, lp.col_lower_, lp.col_upper_ = self.cost, self.lo, self.hi
        lp.row_lower_, lp.row_upper_ = self.b, self.b_hi
        lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
        lp.a_matrix_.start_ = self.A.indptr.astype(np.int32)
        lp.a_matrix_.index_ = self.A.indices.astype(np.int32)
        lp.a_matrix_.value_ = self.A.data.astype(float)
        h.passModel(lp)
        if self.n > INLINE_COLUMNS or self.ipm:
            # HiGHS calls these inside its iterations: the deadline and Ctrl-C reach into a
            # solve (inline solves take milliseconds: the deadline is checked between them)
            h.cbSimplexInterrupt.subscribe(self._interrupt)
            h.cbIpmInterrupt.subscribe(self._interrupt)
        self.cold = True

    def restart(self, basis):
        """Forget every solve so far: a new HiGHS object (options and solver state as
        built), warm from ``basis`` (:meth:`portable_basis`; None: cold)."""
        self._usable()
        self.cost, self.lo, self.hi, self.b, self.b_hi = (v.copy() for v in self._built)
        self._fresh()
        if basis is not None:
            b = highspy.HighsBasis()
            status = highspy.HighsBasisStatus
            b.col_status = list(map(status, basis[0].tolist()))
            b.row_status = list(map(status, basis[1].tolist()))
            b.valid, b.alien = True, False  # as HiGHS left it: taken as is, not repaired
            self.h.setBasis(b)
            self.cold = False

    def portable_basis(self):
        """HiGHS's current basis as two arrays of status codes (columns, rows), which
        pickle (a HighsBasis does not): what :meth:`restart` starts from; None when cold."""
        if self.cold:
            return None
        b = self.h.getBasis()
        return np.array(b.col_status, np.int8), np.array(b.row_status, np.int8)

    def _interrupt(self, e):
        if self.abandoned or self.deadline.expired() or (
                self._pace is not None and self._pace.slow(e.data_out.simplex_iteration_count)):
            e.interrupt()

    def _usable(self):
        if self.abandoned:
            raise Stopped()

    def _run(self):
        """``h.run()`` in a worker thread, waited for in slices; raises Stopped (and
        abandons this HiGHS object) when the deadline fires or the wait is interrupted."""
        self._usable()
        if self.n <= INLINE_COLUMNS:
            self.h.run()
            return
        done = threading.Event()
        failure = []

        def work():
            try:
                self.h.run()
            except BaseException as e:  # pragma: no cover - HiGHS raising is a bug to report
                failure.append(e)
            finally:
                done.set()

        thread = threading.Thread(target=work, name=f"highs-{self.name}", daemon=True)
        thread.start()
        try:
            while not done.wait(WAIT_SLICE):
                if self.deadline.expired():
                    raise Stopped()
        except BaseException:  # Stopped, or KeyboardInterrupt without a handler
            self.abandoned = True
            _abandoned[:] = [t for t in _abandoned if t.is_alive()] + [thread]
            raise
        if failure:
            raise failure[0]

    def set_cost(self, cost):
        self._usable()
        cost = np.asarray(cost, float)
        changed = np.flatnonzero(cost != self.cost)
        if changed.size:
            self.h.changeColsCost(changed.size, changed.astype(np.int32), cost[changed])
            self.cost = cost.copy()

    def set_bounds(self, lo, hi, idx=None):
        """Column bounds: all of them, or those of the columns ``idx``."""
        self.lo, self.hi = self._changed(self.lo, self.hi, lo, hi, idx, self.h.changeColsBounds)

    def set_row_bounds(self, lo, hi, idx=None):
        """Row bounds: all of them, or those of the rows ``idx``."""
        self.b, self.b_hi = self._changed(self.b, self.b_hi, lo, hi, idx, self.h.changeRowsBounds)

    def add_rows(self, rows, lo, hi):
        """Append the rows ``lo <= rows x <= hi``; HiGHS keeps its basis, the new rows'
        slacks basic (warm: the next solve starts where the last ended)."""
        self._usable()
        rows = sp.csr_matrix(rows)
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        self.A = sp.vstack([self.A, rows], format="csc")
        self.m = self.A.shape[0]
        self.b, self.b_hi = np.r_[self.b, lo], np.r_[self.b_hi, hi]
        cost, col_lo, col_hi, b, b_hi = self._built
        self._built = (cost, col_lo, col_hi, np.r_[b, lo], np.r_[b_hi, hi])
        self.h.addRows(rows.shape[0], lo, hi, rows.nnz, rows.indptr[:-1].astype(np.int32),
                       rows.indices.astype(np.int32), rows.data.astype(float))

    def _changed(self, cur_lo, cur_hi, lo, hi, idx, change):
        """New bounds (lo, hi), passed to HiGHS by ``change`` where they differ from (cur_lo, cur_hi)."""
        self._usable()
        lo, hi = _spread(cur_lo, lo, idx), _spread(cur_hi, hi, idx)
        changed = np.flatnonzero((lo != cur_lo) | (hi != cur_hi))
        if not changed.size:
            return cur_lo, cur_hi
        change(changed.size, changed.astype(np.int32), lo[changed], hi[changed])
        return lo, hi

    def solve(self, cap: int | None = None, deadline: Deadline | None = None, ipm_cap: int | None = None) -> str:
        """'optimal', 'infeasible', 'unbounded' or another HiGHS status word; raises Stopped
        when ``deadline`` (None: none) fires, also inside HiGHS.

        ``cap`` (simplex iterations) bounds this warm solve alone: past it the status is
        'iteration limit', the basis is the one it started from, and the search goes on (a
        certification LP that would take minutes is not worth it). Iterations, not
        seconds: the outcome does not depend on the machine or on its load. ``ipm_cap``
        bounds the interior-point iterations of a cold start by the interior point method
        (and ``cap`` its simplex clean-up): past either the status is HiGHS's word for it.
        """
        self._usable()
        self.deadline = deadline or _NEVER
        self.deadline.check()
        h = self.h
        interior = self.cold and (self.n > IPM_COLUMNS or self.ipm)
        # the work bounds cut a solve where they are reached, not after it (iterations: counted)
        by_work = self.deadline.work_left() / max(self.m if self.rows_counted is None else self.rows_counted, 1)
        by_work = int(max(by_work, 1)) if by_work < min((c for c in (cap, ipm_cap) if c is not None), default=INF) \
            else None
        clean_up = cap if interior else None
        start = h.getBasis() if (cap is not None or by_work is not None) and not self.cold else None
        if start is None:
            cap = None
        def limit(c):  # a cap or the work bound's, the less
            c = min((x for x in (c, by_work) if x is not None), default=None)
            return highspy.kHighsIInf if c is None else max(int(min(c, highspy.kHighsIInf)), 1)
        # HiGHS counts simplex_iteration_limit per run (its iteration count restarts at 0)
        h.setOptionValue("simplex_iteration_limit", limit(cap))
        left = self.deadline.remaining()
        backstop = self._backstop(cap)
        if backstop < left:
            left = backstop
        else:
            backstop = None
        # HiGHS compares time_limit with the run time accumulated over all runs of this object
        h.setOptionValue("time_limit", h.getRunTime() + float(max(left, 1e-3)) if left < INF else INF)
        t = time.perf_counter()
        paced = None
        if interior:
            # IPM + crossover at IPM_TOLERANCE, then the warm primal simplex to LP_TOLERANCE
            for option in ("primal_feasibility_tolerance", "dual_feasibility_tolerance"):
                h.setOptionValue(option, IPM_TOLERANCE)
            h.setOptionValue("solver", "ipm")
            h.setOptionValue("run_crossover", "on")
            h.setOptionValue("ipm_iteration_limit", limit(ipm_cap))
            # where the interior point method gives up HiGHS goes on with its simplex in the same
            # run: the clean-up's cap and pace bound that too
            h.setOptionValue("simplex_iteration_limit", limit(clean_up))
            self._pace = None if clean_up is None else Pace(clean_up)
            try:
                self._run()
                for option in ("primal_feasibility_tolerance", "dual_feasibility_tolerance"):
                    h.setOptionValue(option, LP_TOLERANCE)
                if h.getModelStatus() == highspy.HighsModelStatus.kOptimal and not self.deadline.expired():
                    h.setOptionValue("simplex_iteration_limit", limit(clean_up))
                    if clean_up is not None:
                        self._pace = Pace(clean_up)
                    h.setOptionValue("solver", "simplex")
                    h.setOptionValue("simplex_strategy", self.warm_strategy)
                    self._run()
            finally:
                paced, self._pace = self._pace, None
        else:
            h.setOptionValue("solver", "simplex")
            h.setOptionValue("simplex_strategy", 1 if self.cold else self.warm_strategy)
            self._run()
        was_cold, self.cold = self.cold, False
        self.n_solves += 1
        dt = time.perf_counter() - t
        self.seconds += dt
        st = h.getModelStatus()
        if st == highspy.HighsModelStatus.kInterrupt and paced is not None and paced.cut \
                and not self.deadline.expired():
            st = highspy.HighsModelStatus.kIterationLimit  # its pace: capped as if by iterations
        if self.trace is not None:
            info = h.getInfo()
            self.trace(f"    LP {self.name:9s} {dt:7.2f} s  {info.simplex_iteration_count:6d} it  "
                       f"{h.modelStatusToString(st)}")
        S = highspy.HighsModelStatus
        info = h.getInfo()
        iterations = info.simplex_iteration_count
        self.work += (max(iterations, 0) + max(info.ipm_iteration_count, 0) + max(info.crossover_iteration_count, 0)) \
            * (self.m if self.rows_counted is None else self.rows_counted)
        if was_cold:
            self.cold_seconds = max(self.cold_seconds, dt)
        elif iterations > 0 and (st in (S.kOptimal, S.kInfeasible, S.kUnbounded, S.kIterationLimit)
                                 or (st == S.kTimeLimit and backstop is not None)):
            # a solve cut by its backstop ran at this LP's speed too: left out, the sample
            # never grew where every capped solve met the backstop (2,040 blocks)
            self.warm_iterations += iterations
            self.warm_seconds += dt
        if st in (S.kInterrupt, S.kTimeLimit) or self.deadline.expired():
            if st != S.kTimeLimit or backstop is None or self.deadline.expired():
                raise Stopped()
            st = S.kIterationLimit  # the backstop: capped as if by iterations
        if st == S.kIterationLimit and by_work is not None and not (paced is not None and paced.cut):
            if start is not None:
                h.setBasis(start)
            raise Stopped()  # the work bound reached inside the solve, as it is between two
        if st == S.kIterationLimit and cap is not None:
            h.setBasis(start)  # back to the basis the capped solve started from
            return "iteration limit"
        if st == S.kIterationLimit and clean_up is not None:
            return "iteration limit"  # a cold solve's clean-up met its cap or its pace
        if st == S.kOptimal:
            return "optimal"
        if st == S.kInfeasible:
            return "infeasible"
        if st == S.kUnbounded:
            return "unbounded"
        if st == S.kUnboundedOrInfeasible:
            # A warm basis can leave it undecided: a cold re-solve tells the two apart.
            h.clearSolver()
            h.setOptionValue("simplex_iteration_limit", highspy.kHighsIInf)
            h.setOptionValue("solver", "simplex")
            h.setOptionValue("simplex_strategy", 1)
            h.setOptionValue("presolve", "off")
            self._run()
            h.setOptionValue("presolve", "choose")
            st = h.getModelStatus()
            if st in (S.kInterrupt, S.kTimeLimit):
                raise Stopped()
            return {S.kOptimal: "optimal", S.kInfeasible: "infeasible", S.kUnbounded: "unbounded"}.get(
                st, h.modelStatusToString(st))
        return h.modelStatusToString(st)

    def _backstop(self, cap):
        """Seconds after which a capped solve stops even below its iteration cap:
        CAP_BACKSTOP times the cap at this LP's mean warm speed (at least CAP_BACKSTOP_MIN
        s). Only a pathological solve meets it (HiGHS's dual simplex on near-singular
        bases: 241 iterations in 25 s where 6,000 take 4 s), so the answer stays counted in
        iterations in every ordinary case. Before the sample: CAP_BACKSTOP times the
        longest cold solve of this LP, at least CAP_BACKSTOP_MIN * CAP_BACKSTOP s
        (docs/method/evidence.md)."""
        if cap is None:
            return INF
        if self.warm_iterations < CAP_BACKSTOP_SAMPLE:
            return max(CAP_BACKSTOP_MIN, self.cold_seconds) * CAP_BACKSTOP
        return max(CAP_BACKSTOP_MIN, CAP_BACKSTOP * cap * self.warm_seconds / self.warm_iterations)

    def x(self) -> np.ndarray:
        return np.array(self.h.getSolution().col_value)

    def duals(self):
        """(row duals, reduced costs) as HiGHS gives them (exact to its tolerances; see
        :meth:`exact_duals`)."""
        sol = self.h.getSolution()
        return np.array(sol.row_dual), np.array(sol.col_dual)

    def objective(self) -> float:
        return float(self.h.getInfo().objective_function_value)

    def dual_ray(self):
        """HiGHS's Farkas ray of the rows after an 'infeasible' solve (either sign may be
        the certificate: the caller checks), or None when HiGHS has none."""
        _, has, ray = self.h.getDualRay()
        return np.asarray(ray, float) if has else None

    def _basis(self):
        """(cols, rows): the basic columns and basic rows (ascending), or None if HiGHS's
        basis is not a square basis."""
        status, basic = self.h.getBasicVariables()
        if status != highspy.HighsStatus.kOk or basic.size != self.m:
            return None
        return np.sort(basic[basic >= 0]), np.sort(-basic[basic < 0] - 1)

    def _basis_solve(self, cols, rows, rhs, transpose=False):
        """Solve B v = rhs (B^T v = rhs), B = [A_cols | unit columns of rows] (:func:`lamodel.search.basis.solve`)."""
        return basis_solve(self.A, cols, rows, rhs, transpose)

    def exact_x(self) -> np.ndarray:
        """The primal solution recomputed from the final basis: nonbasic columns at their
        bound, ``B x_B = b - A_N x_N`` by an LU solve.

        HiGHS's own solution satisfies the rows to its tolerance on its scaled model only:
        at 1020 blocks a warm statics solve left equilibrium residuals of 5e-7..5e-6
        (relative), which failed the certification of exact collapse states.
        """
        x = self.x()
        basis = self._basis()
        if basis is None or np.any(self.b != self.b_hi):  # range rows: not written for them
            return x
        cols, rows = basis
        xn = np.clip(x, self.lo, self.hi)
        xn[cols] = 0.0
        xb = self._basis_solve(cols, rows, self.b - self.A @ xn)
        if xb is None:
            return x
        tol = BASIS_TOLERANCE * max(1.0, np.abs(xb).max())
        if rows.size and np.abs(xb[cols.size:]).max() > tol:
            return x  # a basic equality row off its value: keep HiGHS's
        xn[cols] = xb[:cols.size]
        if np.any(xn[cols] < self.lo[cols] - tol) or np.any(xn[cols] > self.hi[cols] + tol):
            return x
        return np.clip(xn, self.lo, self.hi)

    def exact_duals(self):
        """(y, z): row duals and reduced costs from the final basis, by an LU solve.

        HiGHS's own duals are exact only to its tolerances; solving ``B^T y = c_B`` on the
        basic columns (and unit columns for basic rows, whose duals are 0) makes
        ``z = c - A^T y`` vanish on basic columns to round-off.
        """
        basis = self._basis()
        y = None
        if basis is not None:
            cols, rows = basis
            y = self._basis_solve(cols, rows, np.concatenate([self.cost[cols], np.zeros(rows.size)]), transpose=True)
        if y is None:  # no square basis, or a singular one: keep HiGHS's duals
            y = np.array(self.h.getSolution().row_dual)
        return y, self.cost - self.A.T @ y


def _spread(current, values, idx):
    """``values`` for all entries (idx None), or ``current`` with those of ``idx`` replaced."""
    if idx is None:
        return np.asarray(values, float).copy()
    out = current.copy()
    out[np.asarray(idx)] = values
    return out
