"""One budget a search runs under: the user's time cap and the work counted in LP solves
and LP work (simplex iterations times rows).

The time cap (``--time-limit``, and a stop: Ctrl-C, a caller's predicate) is a
:class:`~.options.Deadline` made once, by :meth:`Budget.for_solve`. The work bounds are
counted, not timed, so a seed gives the same answer on any machine: without a time limit
the default rule (:class:`WorkRule`) sets them; under one none is set and the time cap is
the search's only bound. Every solve of an engine reads its budget's :attr:`Budget.deadline`
at the call (HiGHS's interrupt callback, Clarabel's time limit): it expires at the time
cap, a stop, or once the work bounds that apply are spent, between two solves. Lanes run
elsewhere are given child budgets (:meth:`Budget.share`, :meth:`Budget.side_lane`, the
the first certificate's two lanes bounding each other: :class:`FirstLanes`); the Ipopt
polish is given the time the search leaves it (:meth:`Budget.reserve`).
"""
from __future__ import annotations

import math
import threading
from contextlib import contextmanager
from dataclasses import dataclass

from .options import Deadline, Stopped
from .tuning import EVALUATION_SLICE, FIRST_WORK, MAIN_LANE_SHARE, POLISH_SHARE, SIDE_LANE_SHARE, TOTAL_WORK


@dataclass(frozen=True)
class WorkRule:
    """The default run's stopping rule without a time limit: the first certificate ends at
    ``first`` times the formulation's work bound (``work_bound()``: WORK_PER_BLOCK a block),
    the whole search at ``total`` times the first certificate's LP solves and at the work
    bound."""

    first: float
    total: float


class Charged(Deadline):
    """What every solve of an engine is given: its budget's time cap, a stop, and the work
    bounds that apply now (:meth:`Budget.stopping`), read at the call."""

    def __init__(self, budget):
        self.budget, self.stop, self.flag = budget, budget.stopping, False

    @property
    def at(self):
        return self.budget.cap.at

    def __getstate__(self):
        """It travels as the plain deadline it is now (seconds left)."""
        return Deadline(self.at, self.stop).__getstate__()

    def __reduce__(self):
        return Deadline, (), self.__getstate__()


class Budget:
    """The budget of one search (see the module doc). ``cap``: the time cap (a
    :class:`~.options.Deadline`; None: none); ``rule``: a :class:`WorkRule` (None: no work
    bound); ``seconds``: the time limit the cap was made from (None: none); ``allowance``:
    (LP solves, LP work) a child budget may spend (None: no bound). An engine counts its
    work into its budget (:meth:`count`)."""

    def __init__(self, cap: Deadline | None = None, rule: WorkRule | None = None, seconds=None, allowance=(None, None)):
        self.cap, self.rule, self.seconds, self.allowance = cap or Deadline(), rule, seconds, allowance
        self.problem = None
        self.parent = None  # the budget a reserve was taken from (its cap is the polish's)
        #: LP solves, and LP work (:meth:`work`), at which the search stops (None: no bound)
        self.work_limit = self.work_bound = None
        #: LP work at which the first certificate ends (None: no bound), and whether it did
        self.first_bound, self.first_spent = None, False
        self._first = False       # the first certificate runs: its bound applies
        self._charged = True      # the work bounds stop solves (not after the search)
        self._lane_from = 0.0     # the search's work when the first certificate's side lanes began
        #: the first certificate's lanes bounding each other (:class:`FirstLanes`; None: none),
        #: whether this engine runs the side lane, and its work when that lane began
        self.first_lanes, self.side, self._side_from = None, False, 0.0
        self.deadline = Charged(self)

    @classmethod
    def for_solve(cls, time_limit=None, stop=None) -> "Budget":
        """The budget of a solve: the time cap from ``time_limit`` seconds (None: none) and
        ``stop``; without a time limit, the default rule's work bounds."""
        rule = WorkRule(FIRST_WORK, TOTAL_WORK) if time_limit is None else None
        return cls(Deadline.after(time_limit, stop), rule, time_limit)

    def count(self, problem) -> "Budget":
        """The engine's formulation ``problem`` counts its work here."""
        self.problem = problem
        self.first_bound = None if self.rule is None else self.rule.first * problem.work_bound()
        return self

    # ------------------------------------------------------------------ the time cap
    def left(self) -> float:
        """Seconds left of the time cap (inf without a limit, 0 once stopped)."""
        return self.cap.left()

    def expired(self) -> bool:
        """The time cap passed, or a stop was asked for."""
        return self.cap.expired()

    def asked(self) -> bool:
        """A stop was asked for (Ctrl-C, the caller's predicate), not the time cap."""
        return self.cap.flag or (self.cap.stop is not None and bool(self.cap.stop()))

    def polish_seconds(self) -> float | None:
        """The most an Ipopt start may take: POLISH_SHARE of the time limit (None: none)."""
        return None if self.seconds is None else POLISH_SHARE * self.seconds

    def reserve(self, seconds: float) -> "Budget":
        """The search's budget, its time cap ``seconds`` earlier (at most POLISH_SHARE of the
        limit; none without one), the rest kept for the polish (:meth:`release`)."""
        keep = 0.0 if self.seconds is None else min(seconds, self.polish_seconds())
        child = Budget(self.cap.extended(-keep) if keep else self.cap, self.rule, self.seconds)
        child.parent = self
        return child

    def release(self):
        """The search ended: the time it left the polish is its (the Ipopt points are
        certified within the whole limit), the work bounds stop no solve."""
        self.end()
        if self.parent is not None:
            self.cap = self.parent.cap

    def end(self):
        """The search ended: its work bounds stop no later solve (a verdict's, a polish's)."""
        self._charged = False

    # ------------------------------------------------------------------ the work
    def stopping(self) -> bool:
        """What stops a solve now: the time cap, a stop, the first certificate's bound
        while it runs, or the work bounds (between two solves: the work grows only when
        a solve ends, so no LP is cut inside HiGHS)."""
        return self.over() or (self._charged and self.spent())

    def over(self) -> bool:
        """The time cap passed, a stop was asked for, or the first certificate's bound is
        reached while it runs: what a lane does not catch (:meth:`lane`)."""
        return self.cap.expired() or (self._first and self.first_done())

    @contextmanager
    def lane(self):
        """A lane's run (or a GA evaluation's): it ends quietly, between two solves, once
        the work bounds are spent; the time cap, a stop and the first certificate's bound
        go up as :class:`~.options.Stopped`."""
        try:
            yield
        except Stopped:
            if self.over():
                raise

    def after_first(self, lps_first):
        """The first certificate took ``lps_first`` LP solves: the rule's bounds of the rest
        of the search set."""
        if self.rule is not None:
            self.bound(self.rule.total * lps_first, self.problem.work_bound())

    def bound(self, work_limit=None, work_bound=None):
        """Bounds of this engine's search from here (None: no bound)."""
        self.work_limit, self.work_bound = work_limit, work_bound

    def work(self) -> int:
        """The LP work of the search so far (:attr:`lamodel.search.highs.HighsLP.work`)."""
        return self.problem.work()

    def spent(self) -> bool:
        """The work bounds (LP solves, LP work) are reached, or the bound of a first
        certificate's lane by the other (:class:`FirstLanes`: it may wait for the other)."""
        return ((self.work_limit is not None and self.problem.n_lps() >= self.work_limit)
                or (self.work_bound is not None and self.work() >= self.work_bound)
                or self._lane_bound())

    def _lane_bound(self) -> bool:
        lanes = self.first_lanes
        if lanes is None:
            return False
        if self.side:
            return lanes.reached(self.work() - self._side_from)
        return lanes.main_cut(self.work() - self._lane_from)

    def first(self, run, certified):
        """``run()``, the first certificate, ending between two solves once the search's
        work reaches ``first_bound`` (``first_spent`` then tells so; ``certified()``: the
        search has a certified state). The time limit and a stop are the caller's."""
        if self.first_bound is None:
            return run()
        self._first = True
        try:
            run()
        except Stopped:
            if self.cap.expired():
                raise
            self.first_spent = True
        finally:
            self._first = False
        if not certified() and self.first_done():
            self.first_spent = True  # the side lanes spent it

    def first_done(self) -> bool:
        """The first certificate's work bound is reached (False: none)."""
        return self.first_bound is not None and self.work() >= self.first_bound

    # ------------------------------------------------------------------ child budgets
    def share(self, k) -> list:
        """``k`` child budgets, each an equal share of the work bounds left (LP solves, LP
        work; None where no bound is set), under the same time cap."""
        lps = None if self.work_limit is None else max(0, self.work_limit - self.problem.n_lps()) // k
        work = None if self.work_bound is None else max(0.0, self.work_bound - self.work()) / k
        return [Budget(self.cap, allowance=(lps, work)) for _ in range(k)]

    def side_lane(self, workers=1) -> "Budget":
        """The budget of a lane beside the first certificate: the whole first-certificate
        work left (no bound without one), under the time cap alone; without a time limit
        the lane on this engine (the main lane) and it also bound each other
        (:class:`FirstLanes`, this budget's and the child's :attr:`first_lanes` until
        :meth:`lanes_ended`; ``workers``: 1, one of them runs at a time)."""
        self._lane_from = self.work()
        left = None if self.first_bound is None else max(0.0, self.first_bound - self._lane_from)
        child = Budget(self.cap, allowance=(None, left))
        if self.rule is not None:
            start = self._lane_from
            self.first_lanes = child.first_lanes = FirstLanes(lambda: self.work() - start, int(workers) <= 1)
            child.side = True
        return child

    def lanes_ended(self):
        """The first certificate's lanes ended: their bounds on each other no longer apply."""
        self.first_lanes = None

    def run_under(self, child: "Budget"):
        """This engine's next run is under ``child``: its time cap, its allowance counted
        from this engine's work now, and its bound by a main lane (if any)."""
        lps, work = child.allowance
        self.cap, self._charged = child.cap, True
        self.first_lanes, self.side, self._side_from = child.first_lanes, child.side, self.work()
        self.bound(None if lps is None else self.problem.n_lps() + lps, None if work is None else self.work() + work)

    def progress(self, running) -> float | None:
        """The share of the work bounds spent so far (a progress display's; ``running``:
        ``{id: (engine, work when it began)}`` of the lanes under way, counted): of the
        one closest to ending the search (LP solves or LP work), during the first
        certificate of its own bound (the side lane furthest on); None where no bound is
        set (a time limit)."""
        if self.work_bound is not None:
            lanes = sum(engine.problem.work() - begun for engine, begun in list(running.values()))
            shares = [(self.work() + lanes) / self.work_bound]
            if self.work_limit:
                shares.append(self.problem.n_lps() / self.work_limit)
            return max(shares)
        if self.first_bound is not None:  # the side lane may spend what was left at its start
            lane = max((engine.problem.work() - begun for engine, begun in list(running.values())), default=None)
            there = 0.0 if lane is None else self._lane_from + lane
            return max(self.work(), there) / self.first_bound
        return None


class FirstLanes:
    """The two lanes of a stalled first certificate bounding each other, by counted LP work
    (each from its start): once the main lane (plan.IF_STALLED, on the search's engine)
    certifies, the side lane may spend SIDE_LANE_SHARE times the main lane's work; once the
    side lane certifies first, at work s, the main lane ends at MAIN_LANE_SHARE times s.

    Counted, so the answer is the same with any number of threads: each lane, before a
    solve the other's next step might forbid, waits for the other to work more or end (they
    cannot both wait: SIDE_LANE_SHARE * MAIN_LANE_SHARE >= 1). With one worker
    (``token``) only one of them runs at a time: a lane gives the token up while it waits.
    ``main_work()``: the main lane's work so far."""

    def __init__(self, main_work, one_worker=False):
        self.main_work = main_work
        self.token = threading.Lock() if one_worker else None
        self.holding = set()  # the lanes (main: True) that began with the token
        self.changed = threading.Condition()
        self.main_ended, self.main_certified = False, False
        self.side_work, self.side_ended, self.side_certified = 0.0, False, None  # its work at its first state
        self.cut = False  # the main lane was ended by this bound

    # ------------------------------------------------------------------ the side lane's side
    def reached(self, work) -> bool:
        """The side lane, having spent ``work``, may not go on (never true inside a solve
        that began allowed: the main lane's work only grows)."""
        with self.changed:
            self.side_work = work
            self.changed.notify_all()
        self._wait(lambda: self.main_ended or work < SIDE_LANE_SHARE * self.main_work())
        return self.main_ended and self.main_certified and work >= SIDE_LANE_SHARE * self.main_work()

    def side_found(self, work):
        """The side lane certified a state, having spent ``work``."""
        with self.changed:
            if self.side_certified is None:
                self.side_certified = work
            self.changed.notify_all()

    # ------------------------------------------------------------------ the main lane's side
    def main_cut(self, work) -> bool:
        """The main lane, having spent ``work``, ends: the side lane certified first, at
        1 / MAIN_LANE_SHARE of it or less."""
        if not math.isfinite(MAIN_LANE_SHARE):
            return False
        self._wait(lambda: (self.side_ended or self.side_certified is not None
                            or work <= MAIN_LANE_SHARE * self.side_work))
        self.cut = self.side_certified is not None and work > MAIN_LANE_SHARE * self.side_certified
        return self.cut

    # ------------------------------------------------------------------ both
    def begin(self, main: bool):
        """A lane begins (``main``: the main lane; with one worker: once it holds the token)."""
        if self.token is not None:
            self.token.acquire()
            self.holding.add(main)

    def ended(self, main: bool, certified: bool = False):
        """A lane ended (``main``: the main lane; ``certified``: the search has a certified
        state), giving up the token."""
        with self.changed:
            if main:
                self.main_ended, self.main_certified = True, certified
            else:
                self.side_ended = True
            self.changed.notify_all()
        if main in self.holding:
            self.holding.discard(main)
            self.token.release()

    def _wait(self, allowed):
        """Until ``allowed()`` (read under the lock), the token given up meanwhile."""
        with self.changed:
            if allowed():
                return
            if self.token is not None:
                self.token.release()
            while not allowed():
                self.changed.wait(EVALUATION_SLICE)
        if self.token is not None:
            self.token.acquire()
