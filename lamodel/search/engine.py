"""The certified search at scale: LPs on the complementarity gap of eq. (5) (issue 10).

Every step is a linear program solved by HiGHS and warm-started:

* **Statics** in friction-cone generator form: per contact four unknowns lambda >= 0, the
  forces ``-n +/- mu t`` at its two end points (:func:`generator_matrix`), so that the
  admissible set S of eq. (1)-(4) is ``A T lambda + alpha fbar = -f0``, ``lambda >= 0``,
  ``alpha >= 0``: only 3 nb rows. A yield row of eq. (4) is held at equality exactly when
  the two lambdas of its slack are zero.
* **Mechanism**: the fictitious cohesive LP of the seed (``|V| <= c`` with ``c = -mu N``,
  normal force >= 0 at both ends of a contact, max alpha). Its duals are the mechanism of
  least alpha_K for that N; they are recomputed exactly from HiGHS's final basis.
* **Gap step**: for a mechanism (u, xi), ``alpha_K(N) - alpha = w^T lambda >= 0`` with
  ``w = -(Y T)^T xi``; min ``alpha + rho w^T lambda`` over S pulls the statics towards a
  collapse state.
* **Certification**: with the rows a mechanism flows on held at equality, min alpha over S.
  Feasible means an exact collapse state (the seed's second theorem): statics admissible,
  mechanism compatible with ``fbar^T u = 1``, flow only on held rows, ``alpha = alpha_K``.

* **Hold step** (when the gap stalls near 1e-8 with a few rows flowing while slack):
  min alpha with the rows the mechanism flows on that the statics already holds kept
  at equality; the next mechanism often flows on tight rows only.
* Certified statics are recomputed exactly from HiGHS's final basis (equilibrium to
  round-off), and every long HiGHS run happens in a worker thread so that a stop takes
  effect within WAIT_SLICE s (an engine is unusable after it raised Stopped).

The search alternates the two from the associative solution (rho 1e3 then 1e4, and again
with rho raised from 10 and from 30: :meth:`GapSearch.continuations`), descends from every
certified state, and explores perturbed cohesions ``c exp(sigma z)`` and the seed's
fixed-point chain until its budget or its stopping rule. Numbers are non-dimensional
inside (forces by the dead load, lengths by the structure's size); states come back in
the user's units, each re-checked by :func:`lamodel.search.certify.residuals`.
"""
from __future__ import annotations

import atexit
import threading
import time
from dataclasses import dataclass, field

import highspy
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..formulation.matrices import equilibrium_matrix, flow_matrix, load_vectors, yield_matrix
from ..structure import Structure
from .certify import RESIDUAL_TOLERANCE, residuals
from .lp import QuietHighs
from .options import Deadline, Stopped, catch_sigint, restore_sigint
from .state import CollapseState

INF = highspy.kHighsInf
#: HiGHS feasibility tolerances (non-dimensional problem; see :func:`_scales`).
LP_TOLERANCE = 1e-9
#: LPs with more columns than this start with the interior point method plus crossover.
IPM_COLUMNS = 1500
#: A gap below GAP_CERTIFY * max(1, alpha) is worth a certification LP.
GAP_CERTIFY = 1e-6
#: rho ladders of the gap step: the main one, and the low one tried when the main one stalls.
RHO_MAIN = (1e3, 1e4)
RHO_LOW = (2.0, 10.0, 100.0, 1e3)
#: ... and the one that goes on from where the main one stalled.
RHO_HIGH = (1e5, 1e6, 1e7)
#: The continuation starts (GapSearch.continuation): the penalty raised from a low rho, so
#: that the statics can first move far from the associative state's mechanism. Measured at
#: 1020 blocks: the main ladder certifies 0.445755; these stall near 0.4448 and, pushed on
#: with RHO_HIGH, certify 0.444911-0.444968 about half of the time (the degenerate LPs'
#: vertices depend on their warm bases), hence two ladders.
RHO_CONTS = ((10.0, 100.0, 1e3, 1e4), (30.0, 300.0, 1e3, 1e4))
#: Below this gap (times max(1, alpha)) a mechanism step forbids flow on slack rows.
GAP_FORBID = 1e-6
#: Below this gap (times max(1, alpha)) a mechanism flowing on slack rows triggers a hold
#: step (see GapSearch.alternate).
GAP_HOLD = 1e-6
#: Flows below this fraction of the largest are zero (they cost compatibility <= this).
FLOW_TOL = 1e-9
#: A stalled mechanism whose flows on slack rows are all below this fraction of its largest
#: is certified without them (its compatibility then errs by about that much, within
#: RESIDUAL_TOLERANCE; the residual check decides).
NEAR_FLOW = 1e-7
#: Relative thresholds on slack used to call a row active when restricting mechanisms.
ACTIVE_TOLS = (1e-9, 1e-7, 1e-5, 1e-3)
#: Cap of a statics LP that may be hard (certification, hold and first gap steps): this many
#: simplex iterations a row. Counted, not timed, so that a seed gives the same answer on any
#: machine and with any number of workers (see GapSearch._cap).
CERTIFY_CAP_ROWS = 2.0
#: A capped solve also stops after CAP_BACKSTOP times the time its cap takes at the LP's
#: mean warm speed (measured over CAP_BACKSTOP_SAMPLE iterations; CAP_BACKSTOP_MIN s at
#: least): a backstop against pathological solves only (see _LP._backstop).
CAP_BACKSTOP, CAP_BACKSTOP_MIN, CAP_BACKSTOP_SAMPLE = 2.0, 2.0, 200
#: Pressure step: how many of the most pushing held rows are tried one by one.
PRESSURE_SINGLE = 8
#: While HiGHS runs (in a worker thread) the caller checks the deadline this often (s).
WAIT_SLICE = 0.05
#: LPs with at most this many columns run in the calling thread: every solve takes
#: milliseconds and HiGHS's interrupt callback suffices, where a thread costs ~1 ms a solve.
INLINE_COLUMNS = IPM_COLUMNS
#: At interpreter exit, wait at most this long (s) for abandoned HiGHS solves to end.
ABANDONED_EXIT_WAIT = 5.0

_abandoned: list[threading.Thread] = []


@atexit.register
def _join_abandoned():
    """An abandoned solve whose thread returns from HiGHS while the interpreter finalises
    is killed inside pybind11's GIL re-acquisition and aborts the process ("terminate
    called without an active exception", exit 134). Before finalising, give those solves
    (interrupted: they stop at HiGHS's next callback) a bounded time to end."""
    end = time.monotonic() + ABANDONED_EXIT_WAIT
    for t in _abandoned:
        t.join(max(0.0, end - time.monotonic()))


_CAPPED = object()  # a certification cut short by its iteration cap: not an answer to remember


# ======================================================================= the LP algebra
def generator_matrix(structure: Structure) -> sp.csr_matrix:
    """T (3 nc x 4 nc): the four friction-cone generators of a contact as (N, V, M).

    Generator ``(j, +/-)`` is the unit-compression force ``-n +/- mu t`` at end point j of
    the contact (j = 1: centre + d t; j = 2: centre - d t). Moved to the contact centre
    it is ``N = -1``, ``V = +/- mu`` and the couple ``(+/- d t) x (-n) = +/- d``. Columns
    are ordered 1+, 1-, 2+, 2- contact after contact. With it, the admissible set of
    eq. (1)-(4) is ``A T lambda + alpha fbar = -f0`` with lambda >= 0 (every (N, V, M) of
    the cone is such a combination and vice versa).
    """
    nc = structure.n_contacts
    mu, d = structure.mu, structure.d
    k = np.arange(nc)
    rows, cols, vals = [], [], []
    for g, (sv, sm) in enumerate(((1, 1), (-1, 1), (1, -1), (-1, -1))):
        col = 4 * k + g
        rows += [k, nc + k, 2 * nc + k]
        cols += [col, col, col]
        vals += [-np.ones(nc), sv * mu, sm * d]
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(3 * nc, 4 * nc))


def cohesive_matrix(structure: Structure) -> sp.csr_matrix:
    """Tc (3 nc x 3 nc): columns (n1, n2, V) per contact for the fictitious cohesive LP.

    n1, n2 >= 0 are the compressions at the two end points (``N = -(n1 + n2)``,
    ``M = d (n1 - n2)``: the hinge rows of eq. (4) as signs), V the shear, bounded by the
    cohesion. Columns ordered n1, n2, V contact after contact.
    """
    nc = structure.n_contacts
    d = structure.d
    k = np.arange(nc)
    rows = [k, 2 * nc + k, k, 2 * nc + k, nc + k]
    cols = [3 * k, 3 * k, 3 * k + 1, 3 * k + 1, 3 * k + 2]
    vals = [-np.ones(nc), d, -np.ones(nc), -d, np.ones(nc)]
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(3 * nc, 3 * nc))


def _scales(structure: Structure):
    """(force, length) units of the non-dimensional problem.

    Forces by the mean dead load of a block (the total dead load over the number of
    blocks; the largest live load if there is no dead load): block loads stay O(1) at
    every size, so HiGHS's absolute tolerances mean the same thing on 30 and 3000 blocks.
    Lengths by the size of the structure (diagonal of its bounding box).
    """
    dead = np.hypot(structure.dead[:, 0], structure.dead[:, 1])
    F = dead.sum() / structure.n_blocks
    if not F > 0:
        F = float(np.hypot(structure.live[:, 0], structure.live[:, 1]).max())
    return float(F), float(structure.size())


def _scaled(structure: Structure, F: float, L: float) -> Structure:
    return Structure(name=structure.name, blocks=structure.blocks, centroid=structure.centroid / L,
                     dead=structure.dead / F, live=structure.live / F, supports=structure.supports,
                     contacts=structure.contacts, block_a=structure.block_a, block_b=structure.block_b,
                     centre=structure.centre / L, normal=structure.normal, d=structure.d / L, mu=structure.mu,
                     dead_m=structure.dead_m / (F * L), live_m=structure.live_m / (F * L),
                     polygons={k: v / L for k, v in structure.polygons.items()})  # size() 1, as L


class Checker:
    """What :func:`lamodel.search.certify.residuals` needs, straight from a Structure's matrices."""

    def __init__(self, structure: Structure):
        self.structure = structure
        self.nc = structure.n_contacts
        self.A = equilibrium_matrix(structure)
        self.f0, self.fbar = load_vectors(structure)
        self.Y = yield_matrix(structure)
        self.G = flow_matrix(structure)

    def slack(self, x):
        return -(self.Y @ x[:3 * self.nc])

    def kinematic_multiplier(self, u, xi, N):
        """alpha_K = -u^T f0 - xi^T N_mu s_N (eq. 5)."""
        nc = self.nc
        return float(-self.f0 @ u - np.sum(self.structure.mu * N * (xi[:nc] + xi[nc:2 * nc])))

    def residuals(self, state: CollapseState) -> dict:
        return residuals(self, state.N, state.V, state.M, state.alpha, state.u, state.xi)


# ============================================================================ HiGHS
class _LP:
    """min c^T x, A x = b, lo <= x <= hi, warm-started, interruptible, with exact duals.

    Every HiGHS ``run()`` happens in a worker thread (highspy releases the GIL) while the
    calling thread waits in slices of WAIT_SLICE s and checks the deadline (small LPs,
    at most INLINE_COLUMNS columns, run inline: milliseconds each): a stop takes
    effect within a slice even where HiGHS calls no interrupt callback (IPX's crossover,
    presolve). The abandoned solve goes on in its thread until HiGHS notices the
    interrupt; its object is marked ``abandoned`` and never touched again (every later
    call raises :class:`Stopped`), so an engine is unusable after a Stopped.
    """

    def __init__(self, A, b, cost, lo, hi, deadline: Deadline, name=""):
        self.A = sp.csc_matrix(A)
        self.m, self.n = self.A.shape
        self.b = np.asarray(b, float)
        self.cost = np.asarray(cost, float).copy()
        self.lo, self.hi = np.asarray(lo, float).copy(), np.asarray(hi, float).copy()
        self.deadline = deadline
        self.name = name
        self._built = (self.cost.copy(), self.lo.copy(), self.hi.copy())
        self._fresh()
        self.n_solves = 0
        self.seconds = 0.0
        self.trace = None  # a print-like function to log every solve
        self.warm_iterations, self.warm_seconds = 0, 0.0  # of warm solves (see _backstop)
        self.abandoned = False

    def _fresh(self):
        """A new HiGHS object holding this LP (current costs and bounds), cold."""
        h = self.h = QuietHighs()
        h.setOptionValue("primal_feasibility_tolerance", LP_TOLERANCE)
        h.setOptionValue("dual_feasibility_tolerance", LP_TOLERANCE)
        lp = highspy.HighsLp()
        lp.num_col_, lp.num_row_ = self.n, self.m
        lp.col_cost_, lp.col_lower_, lp.col_upper_ = self.cost, self.lo, self.hi
        lp.row_lower_ = lp.row_upper_ = self.b
        lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
        lp.a_matrix_.start_ = self.A.indptr.astype(np.int32)
        lp.a_matrix_.index_ = self.A.indices.astype(np.int32)
        lp.a_matrix_.value_ = self.A.data.astype(float)
        h.passModel(lp)
        if self.n > INLINE_COLUMNS:
            # HiGHS calls these inside its iterations: the deadline and Ctrl-C reach into a
            # solve (inline solves take milliseconds: the deadline is checked between them)
            h.cbSimplexInterrupt.subscribe(self._interrupt)
            h.cbIpmInterrupt.subscribe(self._interrupt)
        self.cold = True

    def restart(self, basis):
        """Forget every solve so far: a new HiGHS object (options and solver state as
        built), warm from ``basis`` (:meth:`portable_basis`; None: cold)."""
        self._usable()
        self.cost, self.lo, self.hi = (v.copy() for v in self._built)
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
        if self.abandoned or self.deadline.expired():
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

    def set_bounds(self, lo, hi):
        self._usable()
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        changed = np.flatnonzero((lo != self.lo) | (hi != self.hi))
        if changed.size:
            self.h.changeColsBounds(changed.size, changed.astype(np.int32), lo[changed], hi[changed])
            self.lo, self.hi = lo.copy(), hi.copy()

    def solve(self, cap: int | None = None) -> str:
        """'optimal', 'infeasible', 'unbounded' or another HiGHS status word; raises Stopped.

        ``cap`` (simplex iterations) bounds this warm solve alone: past it the status is
        'iteration limit', the basis is the one it started from, and the search goes on (a
        certification LP that would take minutes is not worth it). Iterations, not
        seconds: the outcome does not depend on the machine or on its load.
        """
        self._usable()
        self.deadline.check()
        h = self.h
        start = h.getBasis() if cap is not None and not self.cold else None
        if start is None:
            cap = None
        # HiGHS counts simplex_iteration_limit per run (its iteration count restarts at 0)
        h.setOptionValue("simplex_iteration_limit", highspy.kHighsIInf if cap is None else max(int(cap), 1))
        left = self.deadline.remaining()
        backstop = self._backstop(cap)
        if backstop < left:
            left = backstop
        else:
            backstop = None
        # HiGHS compares time_limit with the run time accumulated over all runs of this object
        h.setOptionValue("time_limit", h.getRunTime() + float(max(left, 1e-3)) if left < INF else INF)
        t = time.perf_counter()
        if self.cold and self.n > IPM_COLUMNS:
            # Cold simplex on a large degenerate statics LP takes minutes; IPM + crossover
            # takes seconds and leaves a basis for the warm simplex re-solves. At HiGHS's
            # default tolerances: at 1e-9 IPX's crossover is "imprecise" on large models
            # (2040 blocks: dual infeasibility 6e-6) and HiGHS falls back to a dual simplex
            # clean-up of 44,000 iterations (150 s); the warm primal simplex below reaches
            # 1e-9 from the crossover basis in a few iterations.
            for option in ("primal_feasibility_tolerance", "dual_feasibility_tolerance"):
                h.setOptionValue(option, 1e-7)
            h.setOptionValue("solver", "ipm")
            h.setOptionValue("run_crossover", "on")
            self._run()
            for option in ("primal_feasibility_tolerance", "dual_feasibility_tolerance"):
                h.setOptionValue(option, LP_TOLERANCE)
            if h.getModelStatus() == highspy.HighsModelStatus.kOptimal and not self.deadline.expired():
                h.setOptionValue("solver", "simplex")
                h.setOptionValue("simplex_strategy", 4)
                self._run()
        else:
            h.setOptionValue("solver", "simplex")
            # Warm re-solves: primal simplex (the dual was 10-100x slower on these LPs).
            h.setOptionValue("simplex_strategy", 1 if self.cold else 4)
            self._run()
        was_cold, self.cold = self.cold, False
        self.n_solves += 1
        dt = time.perf_counter() - t
        self.seconds += dt
        st = h.getModelStatus()
        if self.trace is not None:
            info = h.getInfo()
            self.trace(f"    LP {self.name:9s} {dt:7.2f} s  {info.simplex_iteration_count:6d} it  "
                       f"{h.modelStatusToString(st)}")
        S = highspy.HighsModelStatus
        iterations = h.getInfo().simplex_iteration_count
        if not was_cold and iterations > 0 and st in (S.kOptimal, S.kInfeasible, S.kUnbounded, S.kIterationLimit):
            self.warm_iterations += iterations
            self.warm_seconds += dt
        if st in (S.kInterrupt, S.kTimeLimit) or self.deadline.expired():
            if st != S.kTimeLimit or backstop is None or self.deadline.expired():
                raise Stopped()
            st = S.kIterationLimit  # the backstop: capped as if by iterations
        if st == S.kIterationLimit and cap is not None:
            h.setBasis(start)  # back to the basis the capped solve started from
            return "iteration limit"
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
        iterations in every ordinary case."""
        if cap is None:
            return INF
        if self.warm_iterations < CAP_BACKSTOP_SAMPLE:
            return CAP_BACKSTOP_MIN * CAP_BACKSTOP
        return max(CAP_BACKSTOP_MIN, CAP_BACKSTOP * cap * self.warm_seconds / self.warm_iterations)

    def x(self) -> np.ndarray:
        return np.array(self.h.getSolution().col_value)

    def _basis(self):
        """(cols, rows): the basic columns and basic rows (ascending), or None if HiGHS's
        basis is not a square basis."""
        status, basic = self.h.getBasicVariables()
        if status != highspy.HighsStatus.kOk or basic.size != self.m:
            return None
        return np.sort(basic[basic >= 0]), np.sort(-basic[basic < 0] - 1)

    def _basis_solve(self, cols, rows, rhs, transpose=False):
        """Solve B v = rhs (B^T v = rhs) with B = [A_cols | unit columns of rows] by a sparse
        LU; None if B is singular. B is gathered from A's CSC arrays directly (scipy's
        slicing and stacking cost more than the factorisation on small models)."""
        A, m = self.A, self.m
        start, count = A.indptr[cols], np.diff(A.indptr)[cols]
        indptr = np.zeros(cols.size + rows.size + 1, np.int64)
        indptr[1:cols.size + 1] = np.cumsum(count)
        indptr[cols.size + 1:] = indptr[cols.size] + np.arange(1, rows.size + 1)
        # positions in A.indices of every entry of the chosen columns, column by column
        pos = np.repeat(start - indptr[:cols.size], count) + np.arange(indptr[cols.size])
        indices = np.concatenate([A.indices[pos], rows])
        data = np.concatenate([A.data[pos], np.ones(rows.size)])
        Bm = sp.csc_matrix((data, indices, indptr), shape=(m, m))
        try:
            return splu(Bm).solve(rhs, trans="T" if transpose else "N")
        except RuntimeError:
            return None

    def exact_x(self) -> np.ndarray:
        """The primal solution recomputed from the final basis: nonbasic columns at their
        bound, ``B x_B = b - A_N x_N`` by an LU solve.

        HiGHS's own solution satisfies the rows to its tolerance on its scaled model only:
        at 1020 blocks a warm statics solve left equilibrium residuals of 5e-7..5e-6
        (relative), which failed the certification of exact collapse states.
        """
        x = self.x()
        basis = self._basis()
        if basis is None:
            return x
        cols, rows = basis
        xn = np.clip(x, self.lo, self.hi)
        xn[cols] = 0.0
        xb = self._basis_solve(cols, rows, self.b - self.A @ xn)
        if xb is None:
            return x
        if rows.size and np.abs(xb[cols.size:]).max() > 1e-9 * max(1.0, np.abs(xb).max()):
            return x  # a basic equality row off its value: keep HiGHS's
        xn[cols] = xb[:cols.size]
        if np.any(xn[cols] < self.lo[cols] - 1e-9 * max(1.0, np.abs(xb).max())) or \
                np.any(xn[cols] > self.hi[cols] + 1e-9 * max(1.0, np.abs(xb).max())):
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


# ========================================================================== results
@dataclass
class SearchResult:
    """Outcome of :func:`search`. ``best`` is certified (or None); alphas are multipliers."""

    status: str                 # 'certified', 'unstable', 'no collapse', 'none certified'
    best: CollapseState | None
    associative: float          # associative multiplier (upper bound), inf if unbounded
    message: str = ""
    interrupted: bool = False   # stopped by the time limit or the stop predicate / Ctrl-C
    first_alpha: float = np.nan
    first_time: float = np.nan
    history: list = field(default_factory=list)   # (seconds, alpha, source) of each improvement
    phases: dict = field(default_factory=dict)     # seconds per phase
    n_lps: int = 0
    seconds: float = 0.0

    @property
    def alpha(self) -> float:
        return np.nan if self.best is None else self.best.alpha


# =========================================================================== engine
class GapSearch:
    """The LP engine on one structure; see the module doc and :func:`search`.

    ``deadline``: a :class:`Deadline` (time limit / stop predicate); ``on_certified(state)``
    is called with every new best certified state (user units); ``seed`` drives the
    random perturbations. Methods raise :class:`Stopped` when the deadline fires.
    """

    def __init__(self, structure: Structure, deadline: Deadline | None = None, on_certified=None,
                 seed: int = 0, verbose: bool = False):
        self.user = structure
        self.deadline = deadline or Deadline()
        self.on_certified = on_certified
        self.on_state = None
        self._certified = {}   # flow pattern -> certified state (or None)
        self._descended = {}   # flow pattern of a certified state -> its descent
        self.rng = np.random.default_rng(seed)
        self.verbose = verbose
        self.t0 = time.perf_counter()
        self.F, self.L = _scales(structure)
        s = self.s = _scaled(structure, self.F, self.L)
        self.nb, self.nc = nb, nc = s.n_blocks, s.n_contacts
        self.A = equilibrium_matrix(s)
        self.f0, self.fbar = load_vectors(s)
        self.Y = yield_matrix(s)
        self.G = flow_matrix(s)
        self.mu = s.mu
        self.check_scaled = Checker(s)
        self.check_user = Checker(structure)
        # --- statics in generator form: columns lambda (4 nc), alpha
        self.T = generator_matrix(s)
        self.Slam = (-(self.Y @ self.T)).tocsr()  # yield slacks = Slam @ lambda (>= 0)
        assert self.Slam.min() >= 0
        # held row r <-> the two lambdas of its slack fixed at 0, by construction of the
        # generators (columns 1+, 1-, 2+, 2- of a contact): slide+ {1-, 2-}, slide- {1+, 2+},
        # hinge+ {1+, 1-}, hinge- {2+, 2-}. From the pattern, not from Slam's nonzeros: with
        # mu = 0 a slide's slack coefficients vanish (and holding it constrains nothing more).
        k4 = 4 * np.arange(nc)
        self.held_lams = np.concatenate([np.column_stack([k4 + a, k4 + b])
                                         for a, b in ((1, 3), (0, 2), (0, 1), (2, 3))])
        self.Slam.sort_indices()
        on = (self.mu > 0)[np.arange(4 * nc) % nc] | (np.arange(4 * nc) >= 2 * nc)
        check = self.Slam[np.flatnonzero(on)]
        assert np.all(np.diff(check.indptr) == 2) and np.array_equal(check.indices.reshape(-1, 2),
                                                                     self.held_lams[on])
        rows = np.repeat(np.arange(4 * nc), 2)
        self.row_of_pair = sp.csr_matrix((np.ones(8 * nc), (rows, self.held_lams.ravel())), shape=self.Slam.shape)
        Ag = sp.hstack([self.A @ self.T, self.fbar.reshape(-1, 1)]).tocsc()
        self.nl = 4 * nc
        lo = np.zeros(self.nl + 1)
        hi = np.full(self.nl + 1, INF)
        self.stat = _LP(Ag, -self.f0, np.zeros(self.nl + 1), lo, hi, self.deadline, "statics")
        # --- fictitious cohesive LP: columns (n1, n2, V) per contact, alpha
        self.Tc = cohesive_matrix(s)
        Ac = sp.hstack([self.A @ self.Tc, self.fbar.reshape(-1, 1)]).tocsc()
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
        self.coh = _LP(Ac, -self.f0, cost, clo, chi, self.deadline, "cohesive")
        # Restricted mechanisms (flow allowed on some rows only) get their own copy: switching
        # one LP between the two kinds cost 10-17 s a re-solve at 2040 blocks.
        self.coh_r = _LP(Ac, -self.f0, cost, clo, chi, self.deadline, "cohesive-r")
        self.lps = {"stat": self.stat, "coh": self.coh, "coh_r": self.coh_r}  # (snapshots name them)
        if verbose > 1:
            for lp in self.lps.values():
                lp.trace = lambda m: print(f"{self.elapsed():8.2f} {m}", flush=True)
        self.phases = {}
        self.best: CollapseState | None = None      # scaled units
        self.best_user: CollapseState | None = None
        self.first = None
        self.history = []
        self.N_assoc = None
        self.lps_elsewhere = 0  # LPs solved for this search by evaluator engines (see merge)
        self._carried_bases = None  # the last merged evaluation's final bases (see snapshot)

    # ------------------------------------------------------------------ bookkeeping
    def _phase(self, name, t):
        self.phases[name] = self.phases.get(name, 0.0) + time.perf_counter() - t

    def elapsed(self):
        return time.perf_counter() - self.t0

    def n_lps(self):
        return sum(lp.n_solves for lp in self.lps.values()) + self.lps_elsewhere

    # ------------------------------------------------------------------- the pieces
    def forces(self, lam):
        return self.T @ lam[:self.nl]

    def N_of(self, lam):
        return (self.T @ lam[:self.nl])[:self.nc]

    def statics(self, cost_lam=None, held=None, maximize=False, cap=None, alpha_cost=1.0):
        """Optimise over S in generator form: min (max) alpha_cost alpha + cost_lam^T lambda
        with the yield rows ``held`` (bool, 4 nc) at equality. Returns (status, x)."""
        cost = np.zeros(self.nl + 1)
        cost[-1] = -alpha_cost if maximize else alpha_cost
        if cost_lam is not None:
            cost[:self.nl] = cost_lam
        hi = np.full(self.nl + 1, INF)
        if held is not None and held.any():
            hi[:self.nl][self.zeroed(held)] = 0.0
        self.stat.set_cost(cost)
        self.stat.set_bounds(np.zeros(self.nl + 1), hi)
        status = self.stat.solve(cap)
        if status != "optimal":
            return status, None
        x = np.maximum(self.stat.x(), 0.0)
        return status, x

    def zeroed(self, held):
        """The lambdas (bool, 4 nc) that holding the yield rows ``held`` sets to zero."""
        out = np.zeros(self.nl, bool)
        out[self.held_lams[held].ravel()] = True
        return out

    def mechanism(self, c, allowed=None):
        """The cohesive LP for cohesions c (>= 0), flow allowed on rows ``allowed`` only.

        Returns (status, alpha_as, x, u, xi): its statics x (n1, n2, V, alpha) and its
        mechanism (u, xi) of least alpha_K, exact from the final basis, fbar^T u = 1.
        """
        nc = self.nc
        c = np.maximum(np.asarray(c, float), 0.0)
        lo = np.zeros(3 * nc + 1)
        hi = np.full(3 * nc + 1, INF)
        lo[2::3][:nc], hi[2::3][:nc] = -c, c
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
        lp.set_bounds(lo, hi)
        status = lp.solve()
        if status != "optimal":
            return status, np.nan, None, None, None
        x = lp.x()
        y, z = lp.exact_duals()
        u = -y / self.obj_scale
        fu = self.fbar @ u
        if not fu > 0:
            return "degenerate", np.nan, None, None, None
        u = u / fu
        z = z / (self.obj_scale * fu)
        # compatibility in the cohesive columns: Gc^T xi = -(A Tc)^T u = -z on the (n, V) columns
        xi = np.maximum(-z[self.gc_col] / self.gc_val, 0.0)
        if allowed is not None:
            xi[~allowed] = 0.0
        top = xi.max() if xi.size else 0.0
        xi[xi <= FLOW_TOL * top] = 0.0
        return status, float(x[-1]), x, u, xi

    def alpha_K(self, u, xi, N):
        nc = self.nc
        return float(-self.f0 @ u - np.sum(self.mu * N * (xi[:nc] + xi[nc:2 * nc])))

    def gap_weights(self, xi):
        """w with w^T lambda = alpha_K(N(lambda)) - alpha = slack^T xi (virtual work)."""
        return self.Slam.T @ xi

    # ---------------------------------------------------------------- certification
    def certify(self, u, xi, source):
        """Statics with the rows xi flows on held, min alpha: an exact collapse state or None."""
        flow = xi > 0
        if not flow.any():
            return None
        # The answer depends on the flow pattern alone (hold its rows, min alpha; any
        # mechanism with that pattern is then compatible with the statics): searches meet
        # the same patterns again and again (wall55: 169 certifications, 33 patterns).
        key = flow.tobytes()
        if key in self._certified:
            return self._certified[key]
        state = self._certify(u, xi, flow, source)
        if state is not _CAPPED:
            self._certified[key] = state
            return state
        return None

    def _certify(self, u, xi, flow, source):
        # Holding the rows by bounds makes the warm basis infeasible, and the primal phase 1
        # took minutes at 2040 blocks. Instead: (1) min of the sum of the lambdas the held
        # rows set to zero, from the current (feasible) basis; zero means the rows can be
        # held; (2) then those lambdas are zero, so bounding them keeps the basis feasible,
        # and min alpha is a warm primal solve. Each is capped (iterations, GapSearch._cap):
        # a certification that hard is not worth it now. Unit weights, not the gap's
        # virtual-work weights w: a row flowing 1e-9 of the largest flow weighs its lambdas
        # so little that w^T lambda ~ 1e-10 left them at 0.1 (1020 blocks), and the held LP
        # then started infeasible (primal phase 1 gave up, HiGHS's dual simplex ran on
        # singular bases for minutes).
        cap = self._cap()
        zeroed = self.zeroed(flow)
        status, x = self.statics(cost_lam=zeroed.astype(float), alpha_cost=0.0, cap=cap)
        if status == "iteration limit":
            return _CAPPED
        if status != "optimal" or x[:self.nl][zeroed].max() > LP_TOLERANCE * max(1.0, np.abs(x).max()):
            return None
        status, x = self.statics(held=flow, cap=cap)
        if status == "iteration limit":
            return _CAPPED
        if status != "optimal":
            return None
        x = self.stat.exact_x()  # equilibrium to round-off, not to HiGHS's tolerance
        return self._accept(x, u, xi, flow, source)

    def _cap(self):
        """Iteration cap of a statics LP that may be hard (certification, hold step, the
        first gap step of a perturbation): CERTIFY_CAP_ROWS simplex iterations a row of
        the statics (3 nb rows). Warm solves mostly take a few iterations, the hardest of
        the 255- and 510-block running-bond walls up to 1.9 a row; one that needs more is
        not worth it now."""
        return int(CERTIFY_CAP_ROWS * self.stat.m)

    def _accept(self, x, u, xi, flow, source):
        s = self.forces(x)
        nc = self.nc
        state = CollapseState(alpha=float(x[-1]), N=s[:nc].copy(), V=s[nc:2 * nc].copy(), M=s[2 * nc:].copy(),
                              u=u.copy(), xi=np.where(flow, xi, 0.0), flow=flow.copy(), source=source)
        state.residual = self.check_scaled.residuals(state)
        if max(state.residual.values()) > RESIDUAL_TOLERANCE:
            if self.verbose > 1:
                bad = {k: f"{v:.1e}" for k, v in state.residual.items() if v > RESIDUAL_TOLERANCE}
                print(f"{self.elapsed():8.2f}   rejected alpha {state.alpha:.7f}: {bad}", flush=True)
            return None
        state.lam = x  # kept for warm descents (not part of the user state)
        if self.on_state is not None:  # every certified state (scaled units), e.g. an archive
            self.on_state(state)
        self._record(state)
        return state

    def _record(self, state):
        a = state.alpha
        if self.best is not None and a >= self.best.alpha - 1e-12 * max(1.0, abs(a)):
            return
        user = self.to_user(state)
        if max(user.residual.values()) > RESIDUAL_TOLERANCE:
            if self.verbose > 1:
                bad = {k: f"{v:.1e}" for k, v in user.residual.items() if v > RESIDUAL_TOLERANCE}
                print(f"{self.elapsed():8.2f}   rejected alpha {a:.7f} in the user's units: {bad} "
                      f"(scaled: {max(state.residual.values()):.1e})", flush=True)
            return
        self.best, self.best_user = state, user
        t = self.elapsed()
        if self.first is None:
            self.first = (a, t)
        self.history.append((t, a, state.source))
        if self.verbose:
            print(f"  {t:8.2f} s  alpha {a:.6f}  {state.source}", flush=True)
        if self.on_certified is not None:
            self.on_certified(user)

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
        out.residual = self.check_user.residuals(out)
        return out

    # ------------------------------------------------------------------- descents
    def active_rows(self, lam, tol):
        slack = self.Slam @ lam[:self.nl]
        return slack <= tol * max(1.0, np.abs(lam).max())

    def descend(self, state, max_steps=30):
        """From a certified state: mechanisms restricted to its active rows, then a pressure
        step (release held rows whose lambdas the certification LP would like positive)."""
        key = state.flow.tobytes()
        if key in self._descended:  # a descent depends on the certified state alone
            return self._descended[key]
        start = state
        t = time.perf_counter()
        try:
            for _ in range(max_steps):
                nxt = self._descend_step(state)
                if nxt is None or nxt.alpha >= state.alpha - 1e-10 * max(1.0, state.alpha):
                    nxt = self._pressure_step(state)
                if nxt is None or nxt.alpha >= state.alpha - 1e-10 * max(1.0, state.alpha):
                    break
                state = nxt
            self._descended[key] = self._descended[start.flow.tobytes()] = state
        finally:
            self._phase("descend", t)
        return state

    def _descend_step(self, state):
        return self._first_lower(state, (self.active_rows(state.lam, tol) for tol in ACTIVE_TOLS[:2]), "+descend")

    def _first_lower(self, state, allowed_sets, tag):
        """Mechanisms for the state's cohesions restricted to each allowed set in turn, each
        certified; stops at the first certified state below the state's alpha. The least
        certified (or None)."""
        best = None
        c = -self.mu * state.N
        for allowed in allowed_sets:
            status, _, _, u, xi = self.mechanism(c, allowed)
            if status != "optimal":
                continue
            cand = self.certify(u, xi, state.source + tag)
            if cand is not None and (best is None or cand.alpha < best.alpha):
                best = cand
            if best is not None and best.alpha < state.alpha - 1e-10:
                break
        return best

    def _pressure_step(self, state):
        """Reduced costs of the held lambdas (min alpha with the flow rows held) say which
        held rows push alpha up; let the most pushing ones go (not allowed to flow)."""
        status, x = self.statics(held=state.flow)
        if status != "optimal":
            return None
        _, z = self.stat.exact_duals()
        zl = z[:self.nl]
        push = np.where(self.zeroed(state.flow) & (zl < -1e-12), -zl, 0.0)
        if not push.any():
            return None
        row_push = self.row_of_pair @ push  # per yield row: how much its lambdas push
        row_push[~state.flow] = 0.0
        order = np.argsort(-row_push)
        order = order[row_push[order] > 0]
        allowed0 = self.active_rows(state.lam, ACTIVE_TOLS[1])
        # the most pushing rows one at a time, then the top ones together
        trials = [order[i:i + 1] for i in range(min(PRESSURE_SINGLE, order.size))]
        trials += [order[:n] for n in (2, 4, 8) if n <= order.size]

        def released(rel):
            allowed = allowed0.copy()
            allowed[rel] = False
            return allowed
        return self._first_lower(state, (released(rel) for rel in trials), "+pressure")

    # ------------------------------------------------------------------ alternation
    def alternate(self, x, rhos=RHO_MAIN, source="gap", max_steps=200, forbid_slack=False):
        """Mechanism step / gap step from the statics x until alpha + rho gap stops falling.

        Certifies whenever the gap is small; returns the best certified state of the run
        (or None) and the last statics.
        """
        t = time.perf_counter()
        best = None
        found = []  # certified states of the near certifications (see _near)
        last_cert_key = None
        try:
            for rho in rhos:
                obj_prev = INF
                for _ in range(max_steps):
                    alpha = float(x[-1])
                    N = self.N_of(x)
                    allowed = None
                    if forbid_slack:
                        allowed = self.active_rows(x, 1e-3)
                    status, a_as, _, u, xi = self.mechanism(-self.mu * N, allowed)
                    if status != "optimal":
                        break
                    gap = float(self.gap_weights(xi) @ x[:self.nl])
                    tight = self.active_rows(x, ACTIVE_TOLS[0])
                    slack_flow = (xi > 0) & ~tight
                    self._near(u, xi, tight, slack_flow, source, found)
                    if slack_flow.any() and gap <= GAP_HOLD * max(1.0, alpha) and not forbid_slack:
                        # Hold step. Near convergence the least-alpha_K mechanism flows, a
                        # little (1e-8..3e-7 of its largest flow at 1020 blocks), on a few rows
                        # this statics keeps slack, and no statics holds them all: the gap step
                        # stalls at a gap ~1e-8 (the rho-weights of those rows are negligible).
                        # Hold at equality the rows it flows on that are already tight and
                        # minimise alpha: x stays feasible (warm), alpha falls, and the next
                        # mechanism often flows only on tight rows (gap exactly 0: certified).
                        st_h, xh = self.statics(held=(xi > 0) & tight, cap=self._cap())
                        if self.verbose > 1:
                            print(f"{self.elapsed():8.2f}   hold: alpha {alpha:.7f} gap {gap:.2e} slack flows "
                                  f"{int(slack_flow.sum())} -> {st_h} {xh[-1] if xh is not None else ''}", flush=True)
                        if st_h == "optimal" and xh[-1] < alpha - 1e-12 * max(1.0, alpha):
                            x = xh  # (obj_prev kept: the rho ladder still ends on a stall)
                            continue
                    if slack_flow.any() and gap <= GAP_FORBID * max(1.0, alpha):
                        # Near convergence the least-alpha_K mechanism still flows, slightly,
                        # on rows this statics keeps slack (2040 blocks: flows ~3e-7 of the
                        # largest on heavily compressed rows hold the gap near 4e-8, and no
                        # statics can hold those rows). Forbid them for this step.
                        st2, _, _, u2, xi2 = self.mechanism(-self.mu * N, ~slack_flow)
                        if st2 == "optimal":
                            u, xi = u2, xi2
                            slack_flow = (xi > 0) & ~tight
                            self._near(u, xi, tight, slack_flow, source, found)
                    step_gap = float(self.gap_weights(xi) @ x[:self.nl])
                    if self.verbose > 1:
                        rel = xi[slack_flow].max() / xi.max() if slack_flow.any() else 0.0
                        print(f"{self.elapsed():8.2f}   rho {rho:g} alpha {alpha:.7f} gap {gap:.2e} step gap "
                              f"{step_gap:.2e} slack flows {int(slack_flow.sum())} (max rel {rel:.1e})", flush=True)
                    # With flows left on slack rows the certification's first LP (min gap of
                    # this mechanism, capped) decides whether a statics can hold them all.
                    if step_gap <= GAP_CERTIFY * max(1.0, alpha):
                        key = (xi > 0).tobytes()
                        if key != last_cert_key:
                            last_cert_key = key
                            st = self.certify(u, xi, source)
                            if st is not None:
                                st = self.descend(st)
                                if best is None or st.alpha < best.alpha:
                                    best = st
                    obj = alpha + rho * gap
                    if obj >= obj_prev - 1e-9 * max(1.0, abs(obj_prev)):
                        break
                    obj_prev = obj
                    status, xn = self.statics(cost_lam=rho * self.gap_weights(xi))
                    if status != "optimal":
                        break
                    x = xn
        finally:
            self._phase("alternate", t)
        for st in found:
            if best is None or st.alpha < best.alpha:
                best = st
        return best, x

    def _near(self, u, xi, tight, slack_flow, source, found):
        """A stall whose flows on slack rows are all below NEAR_FLOW of the largest (1020
        blocks: 4e-8..6e-8, gap 4e-9, and no statics holds them): the mechanism without
        them, certified as any other (held rows, min alpha, every residual within
        RESIDUAL_TOLERANCE) and descended; appended to ``found``."""
        if not slack_flow.any() or xi[slack_flow].max() > NEAR_FLOW * xi.max():
            return
        st = self.certify(u, np.where(tight, xi, 0.0), source + "-near")
        if st is not None:
            found.append(self.descend(st))

    # --------------------------------------------------------------- exploration
    def chain(self, c, steps=6, source="chain"):
        """The seed's fixed-point chain c <- -mu N(cohesive solution); certifies each mechanism."""
        best = None
        for _ in range(steps):
            status, _, xc, u, xi = self.mechanism(c)
            if status != "optimal":
                break
            st = self.certify(u, xi, source)
            if st is not None:
                st = self.descend(st)
                if best is None or st.alpha < best.alpha:
                    best = st
            N = (self.Tc @ xc[:3 * self.nc])[:self.nc]
            c_new = -self.mu * N
            if np.allclose(c_new, c, rtol=1e-9, atol=1e-12):
                break
            c = c_new
        return best

    def perturbed(self, c, source="perturb"):
        """Cohesions c: a mechanism, then the gap alternation from the best statics for it."""
        status, _, _, u, xi = self.mechanism(c)
        if status != "optimal":
            return None
        best = self.certify(u, xi, source)
        if best is not None:
            best = self.descend(best)
        # capped: from a far perturbation the first gap step can take 10 s at 1020 blocks
        # (12,000 iterations), the time of many cheaper perturbations
        status, x = self.statics(cost_lam=RHO_MAIN[0] * self.gap_weights(xi), cap=self._cap())
        if status == "optimal":
            st, x = self.alternate(x, source=source)
            if st is not None and (best is None or st.alpha < best.alpha):
                best = st
            if best is None or x[-1] < best.alpha - 1e-9 * max(1.0, best.alpha):
                # the alternation stalled below what it certified (flows left on slack
                # rows): mechanisms on the rows this statics nearly holds
                st = self.certify_near(x, source + "-near")
                if st is not None and (best is None or st.alpha < best.alpha):
                    best = st
        return best

    def reference_N(self):
        """Normal forces of the best certified state (else the associative ones)."""
        if self.best is not None:
            return self.best.N.copy()
        return None if self.N_assoc is None else self.N_assoc.copy()

    def evaluate(self, genome, reference_N=None, chain_steps=3):
        """Fitness and local search for a GA whose genome is the vector of per-contact
        log-perturbations z of the cohesions: c = -mu N_ref exp(z).

        ``reference_N`` (scaled units, see :meth:`reference_N`) defaults to the one frozen at
        the first call, so that a genome keeps its meaning during a GA run. From c: the
        mechanism, the gap alternation and the seed's fixed-point chain, each certified
        state descended. Returns the least certified alpha reached (inf if none); the
        search's best (and ``on_certified``) follow. Raises Stopped at the deadline.
        """
        if reference_N is None:
            if getattr(self, "_ref_N", None) is None:
                self._ref_N = self.reference_N()
            reference_N = self._ref_N
        if reference_N is None:
            return INF
        c = -self.mu * reference_N * np.exp(np.asarray(genome, float))
        best = self.perturbed(c, source="genome")
        st = self.chain(c, steps=chain_steps, source="genome-chain")
        if st is not None and (best is None or st.alpha < best.alpha):
            best = st
        return INF if best is None else best.alpha

    # ------------------------------------------------- evaluations in parallel
    def snapshot(self) -> dict:
        """What a pure evaluation starts from (:meth:`evaluate_pure`): the warm bases of
        the three LPs (those the last evaluation taken ended with, as a serial search
        goes on from the previous evaluation's; this engine's own before any), the
        reference normal forces and the caches (certifications and descents by flow
        pattern), frozen. Plain arrays and states: it pickles (Dask)."""
        return dict(bases=self._carried_bases or self._bases(),
                    reference_N=self.reference_N(),
                    certified=dict(self._certified), descended=dict(self._descended))

    def _bases(self):
        return {name: lp.portable_basis() for name, lp in self.lps.items()}

    def evaluator(self) -> "GapSearch":
        """An engine of its own (HiGHS objects, caches) on the same structure and deadline,
        for evaluations in another thread (HiGHS releases the GIL while it solves)."""
        return GapSearch(self.user, self.deadline, seed=0)

    def use_deadline(self, deadline: Deadline):
        """From now on this engine and its LPs stop at ``deadline``."""
        self.deadline = deadline
        for lp in self.lps.values():
            lp.deadline = deadline

    def evaluate_pure(self, snap: dict, genome, chain_steps=3):
        """:meth:`evaluate` as a pure function of (snapshot, genome): this engine's LPs
        restart from the snapshot's bases on new HiGHS objects, its caches are the
        snapshot's and its records emptied, so the outcome does not depend on what it
        evaluated before (nor on which thread, process or machine, or how many run: every
        cap is counted in iterations). Returns (alpha, certified states in the order found
        (scaled units), LP solves, what it learned: its additions to the caches and the
        bases it ended with)."""
        for name, lp in self.lps.items():
            lp.restart(snap["bases"][name])
        self._certified, self._descended = dict(snap["certified"]), dict(snap["descended"])
        self.best = self.best_user = self.first = None
        self.history = []
        found = []
        self.on_state = found.append
        lps = self.n_lps()
        alpha = self.evaluate(genome, reference_N=snap["reference_N"], chain_steps=chain_steps)
        learned = dict(certified={k: v for k, v in self._certified.items() if k not in snap["certified"]},
                       descended={k: v for k, v in self._descended.items() if k not in snap["descended"]},
                       bases=self._bases())
        return alpha, found, self.n_lps() - lps, learned

    def merge(self, states, lps, learned=None):
        """What an evaluator found, taken here as if found here (in the order given:
        callers merge evaluations in task order): its certified states, its LP count and
        what it learned (certifications and descents by flow pattern, and its final bases,
        for later snapshots)."""
        for st in states:
            if self.on_state is not None:
                self.on_state(st)
            self._record(st)
        self.lps_elsewhere += lps
        if learned is not None:
            for mine, theirs in ((self._certified, learned["certified"]), (self._descended, learned["descended"])):
                for key, value in theirs.items():
                    mine.setdefault(key, value)
            self._carried_bases = learned["bases"]

    # ---------------------------------------------------------------------- stalls
    def first_certificate(self, x_assoc):
        """The gap alternation from the associative statics and, if it certifies nothing,
        the rescue from where it stalled."""
        _, x = self.alternate(x_assoc, source="gap")
        if self.best is None:
            self.rescue(x_assoc, x)

    def continuations(self, x_assoc):
        """The continuation starts (one per ladder of RHO_CONTS, in turn); then the LPs get
        back the bases they had before them (a cold LP is made cold again), so that what
        follows (the GA, serial or pure evaluations from a snapshot) starts where it would
        without them: measured, a 28-block wall's parallel GA certified nothing from the
        bases the continuation left."""
        saved = {name: None if lp.cold else lp.h.getBasis() for name, lp in self.lps.items()}
        for rhos in RHO_CONTS:
            self.continuation(x_assoc, rhos)
        for name, lp in self.lps.items():
            if saved[name] is None:
                lp.restart(None)
            else:
                lp.h.setBasis(saved[name])

    def continuation(self, x_assoc, rhos=RHO_CONTS[0]):
        """A start from the associative statics on the penalty ladder ``rhos``: a
        low rho lets alpha fall far before the gap is squeezed out, into other collapse
        states than the main ladder's (the penalty method's continuation). Where it stalls
        below the best certified alpha, rho goes on up (RHO_HIGH) and the rows the statics
        nearly holds are certified. Returns the least certified state of the start (or None)."""
        t = time.perf_counter()
        try:
            best, x = self.alternate(x_assoc, rhos=rhos, source="continuation")
            if self.best is None or x[-1] < self.best.alpha - 1e-9 * max(1.0, self.best.alpha):
                st, x = self.alternate(x, rhos=RHO_HIGH, source="continuation")
                if st is not None and (best is None or st.alpha < best.alpha):
                    best = st
                if self.best is None or x[-1] < self.best.alpha - 1e-9 * max(1.0, self.best.alpha):
                    st = self.certify_near(x, "continuation-near")
                    if st is not None and (best is None or st.alpha < best.alpha):
                        best = st
            return best
        finally:
            self._phase("continuation", t)

    def rescue(self, x_assoc, x_stall=None):
        """When the main ladder certifies nothing: higher rho from where it stalled (the
        gap, and the flows on slack rows, shrink with rho: 2040 blocks), then from the
        associative state with flow on slack rows forbidden, and a low rho ladder; each
        followed by certification from near-active rows."""
        best = None
        starts = [(x_assoc, dict(rhos=RHO_MAIN, forbid_slack=True)), (x_assoc, dict(rhos=RHO_LOW))]
        if x_stall is not None:
            starts.insert(0, (x_stall, dict(rhos=RHO_HIGH)))
        for x0, kw in starts:
            st, x = self.alternate(x0, source="rescue", **kw)
            if st is not None and (best is None or st.alpha < best.alpha):
                best = st
            st = self.certify_near(x, "rescue-near")
            if st is not None and (best is None or st.alpha < best.alpha):
                best = st
            if best is not None:
                break
        return best

    def certify_near(self, x, source, first=False):
        """Certification from the rows a statics holds nearly active, at several tolerances
        (``first``: stop at the first tolerance that certifies)."""
        return self.certify_slack(self.Slam @ x[:self.nl], max(1.0, np.abs(x).max()), self.N_of(x), source,
                                  first=first)

    def certify_slack(self, slack, scale, N, source, tols=ACTIVE_TOLS, first=False):
        """For each tolerance: the rows with slack <= tol * scale may flow; the least-alpha_K
        mechanism on them for cohesions -mu N, certified and descended. The least alpha
        certified (``first``: at the first tolerance that certifies), or None."""
        best = None
        c = -self.mu * N
        tried = set()
        for tol in tols:
            allowed = slack <= tol * scale
            key = allowed.tobytes()
            if key in tried or not allowed.any():
                continue
            tried.add(key)
            status, _, _, u, xi = self.mechanism(c, allowed)
            if status != "optimal":
                continue
            st = self.certify(u, xi, source)
            if st is not None:
                st = self.descend(st)
                if best is None or st.alpha < best.alpha:
                    best = st
                if first:
                    break
        return best

    # ------------------------------------------------------------------------ run
    def start(self):
        """Stability and the associative bound. Returns (status, alpha_assoc, x_assoc)."""
        t = time.perf_counter()
        try:
            status, x = self.statics(maximize=True)
            if status == "infeasible":
                return "unstable", np.nan, None
            if status == "unbounded":
                _, x = self.statics()  # least alpha instead: start somewhere finite
                return "unbounded", INF, x
            if status != "optimal":
                return status, np.nan, None
            return "ok", float(x[-1]), x
        finally:
            self._phase("associative", t)

    def stable(self) -> bool:
        """Some statics carries the dead load alone (min alpha over S is 0).

        Solved warm from the last basis (a certification LP's, near the least alpha):
        cheap after a certificate, where a cold start costs as much as the associative LP.
        """
        t = time.perf_counter()
        before = None if self.stat.cold else self.stat.h.getBasis()
        try:
            status, x = self.statics()
            return status == "optimal" and x[-1] <= 1e-9
        finally:
            if before is not None and not self.stat.abandoned:
                # Back to the basis near the collapse states: from the alpha = 0 vertex
                # every later certification LP of a 1020-block wall hit its iteration cap
                # (6120 iterations, 4.4 s each) and the exploration certified nothing.
                self.stat.h.setBasis(before)
            self._phase("stability", t)

    def run(self, explore=True, patience=None) -> SearchResult:
        """The whole search; see :func:`search`."""
        res = SearchResult(status="none certified", best=None, associative=np.nan)
        self.checked_stable = None
        interrupted = False
        try:
            status, a_assoc, x0 = self.start()
            res.associative = a_assoc
            self.N_assoc = self.N_of(x0) if x0 is not None else None
            if status == "unstable":
                res.status = "unstable"
                res.message = ("no statically admissible state carries the dead load alone (alpha = 0): "
                               "the structure is not in equilibrium without live load")
                return self._finish(res, False)
            if status not in ("ok", "unbounded"):
                res.message = f"associative LP: {status}"
                return self._finish(res, False)
            self._t_assoc = self.elapsed()
            t = time.perf_counter()
            self.first_certificate(x0)
            self._phase("first", t)
            self.checked_stable = self.stable()
            if not self.checked_stable:
                res.status = "unstable"
                res.message = ("no statically admissible state carries the dead load alone (alpha = 0): "
                               "the structure is not in equilibrium without live load")
                self.best = self.best_user = None
                return self._finish(res, False)
            if explore:
                if x0 is not None and np.isfinite(a_assoc):
                    self.continuations(x0)
                self.explore(patience)
        except Stopped:
            interrupted = True
        return self._finish(res, interrupted)

    def explore(self, patience=None):
        """Perturbations exp(sigma z) of the best cohesions (sigma 0.1/0.3/1) alternating
        with the seed's fixed-point chain, until the deadline or ``patience`` seconds
        without improvement (default: scaled to the time of the first certificate)."""
        t = time.perf_counter()
        try:
            if patience is None:
                t_first = self.first[1] if self.first else self.elapsed()
                patience = max(0.25, 3.0 * t_first)
            last = time.perf_counter()
            best = self.best.alpha if self.best else INF
            sigmas = (0.1, 0.3, 1.0)
            k = 0
            while time.perf_counter() - last < patience:
                self.deadline.check()
                N = self.reference_N()
                if N is None:
                    break
                z = self.rng.standard_normal(self.nc)
                c = -self.mu * N * np.exp(sigmas[k % 3] * z)
                if k % 2 == 0:
                    self.perturbed(c)
                else:
                    self.chain(c)
                k += 1
                if self.best is not None and self.best.alpha < best - 1e-10 * max(1.0, best):
                    best = self.best.alpha
                    last = time.perf_counter()
        finally:
            self._phase("explore", t)

    def _finish(self, res, interrupted):
        res.interrupted = interrupted
        res.best = self.best_user
        res.history = list(self.history)
        res.phases = dict(self.phases)
        res.n_lps = self.n_lps()
        res.seconds = self.elapsed()
        if self.first is not None:
            res.first_alpha, res.first_time = self.first
        if res.status in ("unstable",):
            return res
        if self.best_user is not None:
            res.status = "certified"
            res.message = "least certified collapse multiplier found by the search"
            if self.checked_stable is None:
                res.message += " (stopped before checking stability under the dead load alone)"
        elif res.associative == INF:
            res.status = "no collapse"
            res.message = ("the associative LP is unbounded (the statics carries any multiple of the live "
                           "load) and the search found no mechanism of the frictional assembly: rigid blocks "
                           "with non-dilatant friction can lock (e.g. a block wedged between piers)")
        elif not res.message:
            res.status = "none certified"
            res.message = (f"no collapse state certified{' before the stop' if interrupted else ''}; "
                           f"the associative multiplier {res.associative:.6g} bounds alpha_c from above")
        return res


def search(structure: Structure, time_limit: float | None = None, stop=None, on_certified=None,
           seed: int = 0, explore: bool = True, patience: float | None = None, handle_sigint: bool = True,
           verbose: bool = False) -> SearchResult:
    """Least certified collapse multiplier of a frictional block assembly (seed eq. 5).

    ``time_limit`` (s) and ``stop`` (a callable, e.g. ``event.is_set``) end the search
    early, also inside an LP; with ``handle_sigint`` Ctrl-C does the same (in the main
    thread). ``on_certified(state)`` receives each new best certified state, in the
    user's units. Without a time limit the search stops when exploring has not improved
    for ``patience`` seconds (default: three times the time to the first certificate).
    """
    deadline = Deadline.after(time_limit, stop)
    old = catch_sigint(lambda: setattr(deadline, "flag", True)) if handle_sigint else None
    try:
        engine = GapSearch(structure, deadline, on_certified=on_certified, seed=seed, verbose=verbose)
        return engine.run(explore=explore, patience=patience)
    except Stopped:  # during construction
        return SearchResult(status="none certified", best=None, associative=np.nan, interrupted=True,
                            message="stopped before the first LP")
    finally:
        restore_sigint(old)
