"""Where the gap alternation starts from, in the order the search uses them.

1. :meth:`Starts.associative`: max alpha over S, the associative bound and first statics.
2. :meth:`Starts.first_certificate`: the alternation on RHO_MAIN from there and, if it
   certifies nothing, two lanes side by side (:meth:`Starts.fallbacks`): the rescue
   (:meth:`Starts.rescue`), the seed's chain from zero cohesion (cold) and the fixed-point
   chain from the stall (:meth:`Starts.chains`, :mod:`.fallback`); and the dilatancy
   continuation.
3. :meth:`Starts.stable`: some statics carries the dead load alone.
4. :meth:`Starts.continuations`: the penalty raised from a low rho (RHO_CONTS), the
   seed's chain from zero cohesion (:meth:`Starts.from_zero`) and the dilatancy
   continuation (:meth:`Starts.dilatancy`), each once a search, in two lanes side by side
   (:meth:`Starts.side_by_side`: pure evaluations on engines of their own), where the
   first certificate's lanes did not run them.
5. The GA's evaluations (:mod:`.fitness`): :meth:`Starts.perturbed` cohesions and the
   seed's fixed-point :meth:`Starts.chain`.

Where an alternation stalls without a certificate, :meth:`Starts.certify_near` certifies
from the rows its statics nearly holds, and the first certificate then falls back to the
seed's chain from the stall (:mod:`.fallback`).
"""
from __future__ import annotations

import logging
import time

import numpy as np

from ..highs import INF
from ..options import Deadline, Stopped
from ..tuning import (BELOW_BEST, CHAIN_ATOL, CHAIN_RELAXATION, CHAIN_RTOL, DESCENT_STEP, DILATANCY_STEPS,
                      DILATANCY_TRACK, FALLBACK_PATIENCE, RHO_CONTS, RHO_HIGH, RHO_LOW, RHO_MAIN, SEARCH_ACTIVE)
from .alternation import Alternation
from .certify import Certifier
from .descent import Descent
from .fallback import fallback
from .program import GapProgram
from .record import Record
from .side_by_side import alongside, side_by_side

log = logging.getLogger(__name__)


def _log_lanes(lanes, outcomes):
    """Each lane's least certified alpha and its LP solves (None: not counted here)."""
    for names, (_, states, lps, _) in zip(lanes, outcomes):
        least = min((st.alpha for st in states if st is not None), default=None)
        found = "no new certified state" if least is None else f"least certified alpha {least:.6f}"
        log.info("lane [%s]: %s%s", ", ".join(names), found, "" if lps is None else f", {lps} LP solves")


def _least(best, st):
    """The lesser of two certified states (either may be None)."""
    return st if st is not None and (best is None or st.alpha < best.alpha) else best


class Starts:
    """The starts of the search on a problem; each returns its least certified state (or None)."""

    def __init__(self, problem: GapProgram, certifier: Certifier, descent: Descent, alternation: Alternation,
                 record: Record, new_engine=None):
        self.problem, self.certifier, self.descent, self.record = problem, certifier, descent, record
        self.alternate = alternation.alternate
        #: a new engine of the same structure (:class:`~lamodel.search.gap.GapSearch`), for
        #: the starts run as pure evaluations (:meth:`side_by_side`)
        self.new_engine = new_engine
        self._running = {}  # engines running lanes (side_by_side), for budget_share
        self._lane_from = 0.0  # the search's work when the first certificate's dilatancy lane began
        self.forget()
        #: LP solves, and LP work (:meth:`work`), at which the continuations
        #: and the chain from zero cohesion stop (None: no bound): the driver's work bounds
        #: without a time limit
        self.work_limit = None
        self.work_bound = None
        self.cycles = 0  # chains that met a cohesion again (see chain)
        #: LP work at which the first certificate ends (None: no bound) and whether it did
        self.first_bound, self.first_spent = None, False

    def forget(self):
        """No chain from zero cohesion nor dilatancy continuation has run (a pure evaluation
        starts so)."""
        self._from_zero = None  # (state,) once the chain from zero cohesion ran
        self._dilatancy = None  # (state,) once the dilatancy continuation ran

    def ran(self) -> dict:
        """The once-a-search starts that ran, each with its least certified state:
        ``{"from_zero": (state,), ...}`` (what a pure evaluation tells :meth:`merge`)."""
        return {name: getattr(self, "_" + name) for name in ("from_zero", "dilatancy")
                if getattr(self, "_" + name) is not None}

    def _stalled_below_best(self, x, best):
        return best is None or x[-1] < best.alpha - BELOW_BEST * max(1.0, best.alpha)

    # ---------------------------------------------------------------- associative
    def associative(self):
        """Stability and the associative bound. Returns (status, alpha_assoc, x_assoc):
        status 'ok', 'unstable' (S is empty), 'unbounded' (x: a least-alpha statics) or
        HiGHS's word."""
        t = time.perf_counter()
        p = self.problem
        try:
            status, x = p.statics(maximize=True)
            if status == "infeasible":
                return "unstable", np.nan, None
            if status == "unbounded":
                _, x = p.statics()  # least alpha instead: start somewhere finite
                return "unbounded", INF, x
            if status != "optimal":
                return status, np.nan, None
            return "ok", float(x[-1]), x
        finally:
            self.record.phase("associative", t)

    def stable(self) -> bool:
        """Some statics carries the dead load alone (min alpha over S is 0).

        Solved warm from the last basis (a certification LP's, near the least alpha):
        cheap after a certificate, where a cold start costs as much as the associative LP.
        """
        t = time.perf_counter()
        p = self.problem
        before = p.save_bases(("stat",))
        try:
            status, x = p.statics()
            return status == "optimal" and x[-1] <= p.stable_alpha
        finally:
            # Back to the basis near the collapse states: from the alpha = 0 vertex
            # every later certification LP of a 1020-block wall hit its iteration cap
            # (6120 iterations, 4.4 s each) and the exploration certified nothing.
            p.load_bases(before, restart_cold=False)
            self.record.phase("stability", t)

    # ------------------------------------------------------------ first certificate
    def first_certificate(self, x_assoc, workers=1):
        """The first certificate (:meth:`_first_certificate`; ``workers``: threads for its
        fallback lanes); with ``first_bound`` set (the driver's, without a time limit) it
        ends between two solves once the search's work reaches it (``first_spent`` then
        tells so)."""
        real = self.problem.deadline  # the dilatancy lane stops there, not at the first bound
        if self.first_bound is None:
            return self._first_certificate(x_assoc, workers, real)
        try:
            with self.problem.until(self.bounded(lambda: self.work() >= self.first_bound)):
                self._first_certificate(x_assoc, workers, real)
        except Stopped:
            if self.problem.deadline.expired():  # the time limit or a stop: the search's to handle
                raise
            self.first_spent = True
        if self.record.best is None and self.work() >= self.first_bound:
            self.first_spent = True  # the fallback lanes spent it

    def _first_certificate(self, x_assoc, workers=1, real=None):
        """The gap alternation from the associative statics and, if it certifies nothing,
        the fallbacks (:meth:`fallbacks`): two lanes side by side, the rescue from where it
        stalled and the chains (from zero cohesion, cold, then the fixed-point chain from
        the stall and from the associative statics, :mod:`.fallback`), and the dilatancy
        continuation."""
        _, x = self.alternate(x_assoc, source="gap")
        if self.record.best is None:
            self.fallbacks(x_assoc, x, workers, real)

    def fallbacks(self, x_assoc, x_stall, workers=1, real=None):
        """Where the gap alternation certifies nothing: two lanes side by side, each with
        the whole first-certificate work left (they are different methods, either may be
        the one that certifies): :meth:`chains` (the rescue, then the seed's chains) on
        this engine, in this thread, as if alone; the dilatancy continuation
        (:meth:`dilatancy`) as a pure evaluation from a snapshot taken before (an engine of
        its own, another thread with ``workers`` > 1, else after the chains; its work
        bound its own, so the answer does not depend on the threads), merged after the
        chains; both then count as run (once a search). The search goes on from the bases
        of the dilatancy lane where it certified a lower alpha than the chains (why lanes,
        and why the chains on this engine: docs/method/evidence.md)."""
        self._lane_from = self.work()
        left = None if self.first_bound is None else max(0.0, self.first_bound - self._lane_from)
        t = time.perf_counter()
        p = self.problem
        raised = []

        def here():
            try:
                self.chains(x_assoc, x_stall)
            except Stopped as stop:  # our bound or the deadline: after the other lane is merged
                raised.append(stop)

        snap = self.snapshot()
        real = real or p.deadline  # the search's deadline (the dilatancy lane's work bound is its own)
        calls = [("starts_pure", (snap, [("dilatancy", (x_assoc,))], None, left, real))]
        log.info("nothing certified by the alternation: lanes [rescue, from zero, fixed point] beside [dilatancy]")
        try:
            outcomes = alongside(here, self.new_engine, calls, workers, running=self._running)
        finally:
            self.record.phase("first certificate", t)
        mine = self.record.best
        _log_lanes([["chains"]], [(None, [mine] if mine is not None else [], None, None)])
        _log_lanes([["dilatancy"]], outcomes)
        for _, states, n, learned in outcomes:
            self.merge(states, n, learned)
        there = min(outcomes[0][1], key=lambda st: st.alpha, default=None)
        if there is not None and (mine is None or there.alpha < mine.alpha) and outcomes[0][3]["bases"] is not None:
            p.restart(outcomes[0][3]["bases"])  # go on from the lane that certified the least alpha
        if raised:
            raise raised[0]
        if outcomes[0][0] and real.expired():
            raise Stopped()

    def chains(self, x_assoc, x_stall):
        """The rescue (:meth:`rescue`) and, if it certified nothing, the seed's chain from
        zero cohesion with its cohesive LP cold, then the fixed-point chain from the stall and
        from the associative statics (:mod:`.fallback`), on this engine; the first certificate's
        bound ends them.
        Returns the least certified state (or None).

        Cold: the cohesive LP's statics is massively degenerate and the chain follows the
        optimum HiGHS returns; warm from the stalled alternations' bases it stays where they
        stalled (measured: docs/method/evidence.md)."""
        best = self.rescue(x_assoc, x_stall)
        if self.record.best is not None:
            return best
        self.problem.load_bases({name: None for name in self.problem.save_bases(("coh",))})
        best = self.from_zero()
        if self.record.best is None:
            best = _least(best, fallback(self, (x_stall, x_assoc)))
        return best

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
            best = _least(best, st)
            best = _least(best, self.certify_near(x, "rescue-near"))
            if best is not None:
                break
        return best

    # -------------------------------------------------------------- continuations
    def continuations(self, x_assoc, workers=1):
        """The continuation starts (one per ladder of RHO_CONTS), the chain from zero cohesion
        (:meth:`from_zero`) and the dilatancy continuation (:meth:`dilatancy`) where the first
        certificate did not run them, in one lane per ladder: the ladder, then the chain (first
        lane) or the dilatancy continuation (second lane) on the same engine, warm from where
        the ladder ended. The lanes run :meth:`side_by_side`. The LPs keep the bases they had
        before them (the lanes run on engines of their own), so that what follows (the GA,
        serial or pure evaluations from a snapshot) starts where it would without them."""
        lanes = [[("continuation", (x_assoc, rhos))] for rhos in RHO_CONTS]
        after = [("from_zero", (), self._from_zero), ("dilatancy", (x_assoc,), self._dilatancy)]
        for lane, (name, args, ran) in zip(lanes, after):
            if ran is None:
                lane.append((name, args))
        self.side_by_side(lanes, workers)

    def side_by_side(self, lanes, workers=1, phase="continuation"):
        """Independent ``lanes`` of starts (each a list of ``(method, args)`` of this class,
        run in turn on one engine) from this search's state, side by side in up to
        ``workers`` threads (:func:`~lamodel.search.gap.side_by_side.side_by_side`): each lane
        a pure function of a snapshot (:meth:`snapshot`) with an equal share of the work
        bounds left, merged in the order given, so that the answer is the same with any
        number of threads. Returns the least certified state of each lane (None: none); raises Stopped, after merging, where the deadline
        ended them."""
        if not lanes or self._spent():
            return [None] * len(lanes)
        t = time.perf_counter()
        p = self.problem
        snap = self.snapshot()
        k = len(lanes)
        lps = None if self.work_limit is None else max(0, self.work_limit - p.n_lps()) // k
        work = None if self.work_bound is None else max(0.0, self.work_bound - self.work()) / k
        calls = [("starts_pure", (snap, lane, lps, work, p.deadline)) for lane in lanes]
        log.info("%s: lanes %s", phase, " beside ".join(f"[{', '.join(name for name, *_ in lane)}]" for lane in lanes))
        try:
            outcomes = side_by_side(self.new_engine, calls, workers, running=self._running)
        finally:
            self.record.phase(phase, t)
        _log_lanes([[name for name, *_ in lane] for lane in lanes], outcomes)
        for _, states, n, learned in outcomes:
            self.merge(states, n, learned)
        if any(stopped for stopped, *_ in outcomes) and p.deadline.expired():
            raise Stopped()
        return [min(states, key=lambda st: st.alpha, default=None) for _, states, _, _ in outcomes]

    def snapshot(self) -> dict:
        """What a pure evaluation of starts begins from (:meth:`.fitness.Fitness.starts_pure`):
        the LPs' bases, the caches of certifications and descents, the best state."""
        return dict(bases=self.problem.bases(), certified=dict(self.certifier.cache),
                    descended=dict(self.descent.cache), best=self.record.best)

    def merge(self, states, lps, learned=None):
        """What a pure evaluation found, taken here as if found here (callers merge in task
        order): its certified states, its LP solves and work, and its additions to the caches
        of certifications and descents by flow pattern."""
        for st in states:
            if self.record.on_state is not None:
                self.record.on_state(st)
            self.record.take(st)
        self.problem.lps_elsewhere += lps
        if learned is not None:
            self.problem.work_elsewhere += learned.get("work", 0)
            for name, ran in learned.get("ran", {}).items():
                if getattr(self, "_" + name) is None:  # once a search: it ran there
                    setattr(self, "_" + name, ran)
            for mine, theirs in ((self.certifier.cache, learned["certified"]),
                                 (self.descent.cache, learned["descended"])):
                for key, value in theirs.items():
                    mine.setdefault(key, value)

    def continuation(self, x_assoc, rhos=RHO_CONTS[0]):
        """A start from the associative statics on the penalty ladder ``rhos``: a
        low rho lets alpha fall far before the gap is squeezed out, into other collapse
        states than the main ladder's (the penalty method's continuation). Where it stalls
        below the best certified alpha, rho goes on up (RHO_HIGH) and the rows the statics
        nearly holds are certified. It ends early, between two LP solves, once the work
        bounds are spent. Returns the least certified state of the start (or None; what it
        certified before an early end is in the record)."""
        t = time.perf_counter()
        try:
            with self.problem.until(self.bounded()):
                best, x = self.alternate(x_assoc, rhos=rhos, source="continuation")
                if self._stalled_below_best(x, self.record.best):
                    st, x = self.alternate(x, rhos=RHO_HIGH, source="continuation")
                    best = _least(best, st)
                    if self._stalled_below_best(x, self.record.best):
                        best = _least(best, self.certify_near(x, "continuation-near"))
            return best
        except Stopped:
            if self.problem.deadline.expired():  # the time limit or a stop: the search's to handle
                raise
            return None
        finally:
            self.record.phase("continuation", t)

    def bounded(self, spent=None) -> Deadline:
        """The search's deadline, which also expires once the work bounds are spent
        (``spent()``: other bounds; default the driver's). The work
        grows only when a solve ends, so it expires between two solves: no LP is cut inside
        HiGHS (the LPs stay usable), the next one raises Stopped before it starts."""
        real = self.problem.deadline
        spent = spent or self._spent
        return Deadline(real.at, lambda: real.expired() or spent())

    def work(self) -> int:
        """The LP work of the search so far (:attr:`lamodel.search.highs.HighsLP.work`)."""
        return self.problem.work()

    def budget_share(self):
        """The share of the driver's work bounds spent so far (a progress display's: the
        lanes' work under way counted): of the one closest to ending the search (LP solves
        or LP work), during the first certificate of its own bound (the fallback lane
        furthest on); None where no bound is set (a time limit)."""
        if self.work_bound is not None:
            lanes = sum(engine.problem.work() - begun for engine, begun in list(self._running.values()))
            shares = [(self.work() + lanes) / self.work_bound]
            if self.work_limit:
                shares.append(self.problem.n_lps() / self.work_limit)
            return max(shares)
        if self.first_bound is not None:  # the dilatancy lane may spend what was left at its start
            lane = max((engine.problem.work() - begun for engine, begun in list(self._running.values())),
                       default=None)
            there = 0.0 if lane is None else self._lane_from + lane
            return max(self.work(), there) / self.first_bound
        return None

    def _spent(self):
        """The driver's work bounds (LP solves, LP work) are reached."""
        return ((self.work_limit is not None and self.problem.n_lps() >= self.work_limit)
                or (self.work_bound is not None and self.work() >= self.work_bound))

    def from_zero(self):
        """The seed's fixed-point chain from zero cohesion (:mod:`.fallback`), once: the
        weakest fictitious system, a start that depends on nothing found before (what it
        finds: docs/method/evidence.md). Without a time limit it stops at ``work_limit``.
        Returns its least certified state (or None)."""
        if self._from_zero is None:
            t = time.perf_counter()
            try:
                with self.problem.until(self.bounded()):
                    self._from_zero = (fallback(self, (), from_zero=True, source="zero-cohesion", until=self._spent),)
            except Stopped:
                if self.problem.deadline.expired():
                    raise
                self._from_zero = (None,)  # its states so far are in the record
            finally:
                self.record.phase("zero cohesion", t)
        return self._from_zero[0]

    def dilatancy(self, x_assoc):
        """The dilatancy continuation, once: from the associative statics (at t = 1 the
        fictitious system whose sliding dilates by t mu is the associative one, whose
        optimum is a collapse state) through the systems of DILATANCY_STEPS down to the
        seed's (t = 0), the gap alternation tracking the statics at each t; at t = 0 the
        alternation certifies, and where it stalls below the best, RHO_HIGH and the rows the
        statics nearly holds, then the seed's fixed-point chain from the stall
        (:mod:`.fallback`; at t = 0 the continuation can stall at a partial optimum as the
        other alternations do). A homotopy from an exact solution, not a fixed point: it
        reaches collapse states the other starts miss (the 510-block running-bond wall at
        mu = 1.0: 0.568109, where the others certify 0.816327). Without a time limit it
        ends at the work bounds. Returns its least certified state (or None)."""
        if self._dilatancy is None:
            t = time.perf_counter()
            best = None
            try:
                with self.problem.until(self.bounded()):
                    x = x_assoc
                    for dil in DILATANCY_STEPS:
                        _, x = self.alternate(x, source="dilatancy", dilatancy=dil, max_steps=DILATANCY_TRACK)
                    best, x = self.alternate(x, source="dilatancy")
                    if self._stalled_below_best(x, self.record.best):
                        st, x = self.alternate(x, rhos=RHO_HIGH, source="dilatancy")
                        best = _least(best, st)
                        if self._stalled_below_best(x, self.record.best):
                            best = _least(best, self.certify_near(x, "dilatancy-near"))
                    if self._stalled_below_best(x, self.record.best):
                        best = _least(best, fallback(self, (x,), source="dilatancy-fixed", until=self._spent))
            except Stopped:
                if self.problem.deadline.expired():
                    raise
            finally:
                self._dilatancy = (best,)
                self.record.phase("dilatancy", t)
        return self._dilatancy[0]

    # ---------------------------------------------------------- near-active rows
    def certify_near(self, x, source, first=False):
        """Certification from the rows a statics holds nearly active, at several tolerances
        (``first``: stop at the first tolerance that certifies)."""
        p = self.problem
        return self.certify_slack(p.slack(x), max(1.0, np.abs(x).max()), p.N_of(x), source, first=first)

    def certify_slack(self, slack, scale, N, source, tols=SEARCH_ACTIVE, first=False):
        """For each tolerance: the rows with slack <= tol * scale may flow; the least-alpha_K
        mechanism on them for cohesions -mu N, certified and descended. The least alpha
        certified (``first``: at the first tolerance that certifies), or None."""
        best = None
        c = -self.problem.mu * N
        tried = set()
        for tol in tols:
            allowed = slack <= tol * scale
            key = allowed.tobytes()
            if key in tried or not allowed.any():
                continue
            tried.add(key)
            status, _, _, u, xi = self.problem.mechanism(c, allowed)
            if status != "optimal":
                continue
            st = self.certifier.certify(u, xi, source)
            if st is not None:
                best = _least(best, self.descent.descend(st))
                if first:
                    break
        return best

    # -------------------------------------------------------- the GA's local search
    def chain(self, c, steps, source="chain", patience=None, until=None):
        """The seed's fixed-point chain c <- -mu N(cohesive solution); certifies each mechanism.
        ``patience``: once it certified, stop after that many steps without improvement;
        ``until()``: True stops it. It also stops at a fixed point. Where the cohesions
        repeat those of an earlier step (a cycle, counted in ``cycles``), or the chain has
        certified nothing after FALLBACK_PATIENCE steps, it goes on relaxed,
        ``c <- (1 - w) c + w c_new`` (w = CHAIN_RELAXATION: averaging damps an oscillation);
        a cycle then ends it, and a chain that certified nothing ends with the gap
        alternation from its last cohesions (:meth:`perturbed`)."""
        p = self.problem
        best, since = None, 0
        seen = []  # the cohesions of the steps so far
        relax = 1.0
        for step in range(steps):
            if until is not None and until():
                break
            if relax == 1.0 and best is None and step >= FALLBACK_PATIENCE:
                relax, seen = CHAIN_RELAXATION, []  # not converging: averaged from here
            status, a_k, xc, u, xi = p.mechanism(c)
            log.debug("%8.2f   chain %s step %d: %s alpha_K %.7f relax %g", p.elapsed(), source, step, status, a_k,
                      relax)
            if status != "optimal":
                break
            st = self.certifier.certify(u, xi, source)
            if st is not None:
                st = self.descent.descend(st)
                if best is None or st.alpha < best.alpha - DESCENT_STEP * max(1.0, best.alpha):
                    since = 0
                best = _least(best, st)
            since += best is not None
            if patience is not None and since > patience:
                break
            c_new = -p.mu * p.cohesive_N(xc)
            if np.allclose(c_new, c, rtol=CHAIN_RTOL, atol=CHAIN_ATOL):
                break
            nxt = c_new if relax == 1.0 else (1.0 - relax) * c + relax * c_new
            if any(np.allclose(nxt, old, rtol=CHAIN_RTOL, atol=CHAIN_ATOL) for old in seen):
                self.cycles += 1
                if relax < 1.0:
                    break
                relax, seen = CHAIN_RELAXATION, []
                nxt = (1.0 - relax) * c + relax * c_new
            seen.append(c)
            c = nxt
        if best is None and relax < 1.0 and (until is None or not until()):
            best = self.perturbed(c, source + "-relaxed")
        return best

    def perturbed(self, c, source="perturb"):
        """Cohesions c: a mechanism, then the gap alternation from the best statics for it."""
        p = self.problem
        status, _, _, u, xi = p.mechanism(c)
        if status != "optimal":
            return None
        best = self.certifier.certify(u, xi, source)
        if best is not None:
            best = self.descent.descend(best)
        # capped: from a far perturbation the first gap step can take 10 s at 1020 blocks
        # (12,000 iterations), the time of many cheaper perturbations
        status, x = p.statics(cost_lam=RHO_MAIN[0] * p.gap_weights(xi, u), cap=self.certifier.cap())
        if status == "optimal":
            st, x = self.alternate(x, source=source)
            best = _least(best, st)
            if self._stalled_below_best(x, best):
                # the alternation stalled below what it certified (flows left on slack
                # rows): mechanisms on the rows this statics nearly holds
                best = _least(best, self.certify_near(x, source + "-near"))
        return best
