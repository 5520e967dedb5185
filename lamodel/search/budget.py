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
latter bounded by the main lane's work once it certifies: :class:`MainLane`); the Ipopt
polish is given the time the search leaves it (:meth:`Budget.reserve`).
"""
from __future__ import annotations

import math
import threading
from contextlib import contextmanager
from dataclasses import dataclass

from .options import Deadline, Stopped
from .tuning import EVALUATION_SLICE, FIRST_WORK, POLISH_SHARE, SIDE_LANE_SHARE, TOTAL_WORK


@dataclass(frozen=True)
class WorkRule:
    """The default run's stopping rule without a time limit: the first certificate ends at
    ``first`` times the formulation's work bound (``work_bound()``: WORK_PER_BLOCK a block),
    the whole search at ``total`` times the first certificate's LP solves and at the work
    bound."""

    first: float
    total: float
    #: the work bound times this (a study's variant solved again: RETRY_WORK)
    scale: float = 1.0


class Charged(Deadline):
    """What every solve of an engine is given: its budget's time cap, a stop, and the work
    bounds that apply now (:meth:`Budget.stopping`), read at the call."""

    def __init__(self, budget):
        self.budget, self.stop, self.flag = budget, budget.stopping, False

    @property
    def at(self):
        return self.budget.cap.at

    def work_left(self) -> float:
        """LP work left before the bounds that apply now (the whole search's, the first
        certificate's while it runs): a solve is cut there, not after it (a slow lane's LP
        of 45 s ran on past its share)."""
        b = self.budget
        bounds = ([b.work_bound] if b._charged else []) + ([b.first_bound] if b._first else [])
        return min((x - b.work() for x in bounds if x is not None), default=math.inf)

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
        #: a side lane's bound by the main lane beside it (:class:`MainLane`; None: none), and
        #: this engine's work when the side lane began
        self.main_lane, self._side_from = None, 0.0
        #: (LP solves, LP work) of a step set aside (the dry certificate that certified
        #: nothing: :mod:`.gap.dry`): counted, the bounds of the rest moved by as much
        self.aside = (0, 0.0)
        self.deadline = Charged(self)

    @classmethod
    def for_solve(cls, time_limit=None, stop=None, work_scale=1.0) -> "Budget":
        """The budget of a solve: the time cap from ``time_limit`` seconds (None: none) and
        ``stop``; without a time limit, the default rule's work bounds (times ``work_scale``)."""
        rule = WorkRule(FIRST_WORK, TOTAL_WORK * work_scale, work_scale) if time_limit is None else None
        return cls(Deadline.after(time_limit, stop), rule, time_limit)

    def count(self, problem) -> "Budget":
        """The engine's formulation ``problem`` counts its work here."""
        self.problem = problem
        self.first_bound = None if self.rule is None else self.rule.first * self.whole_bound()
        return self

    def whole_bound(self) -> float:
        """The whole search's LP work bound: the formulation's (WORK_PER_BLOCK a block) times
        the rule's scale."""
        return self.problem.work_bound() * (self.rule.scale if self.rule is not None else 1.0)

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
            lps, work = self.aside
            self.bound(self.rule.total * (lps_first - lps) + lps, self.whole_bound() + work)

    def bound(self, work_limit=None, work_bound=None):
        """Bounds of this engine's search from here (None: no bound)."""
        self.work_limit, self.work_bound = work_limit, work_bound

    def work(self) -> int:
        """The LP work of the search so far (:attr:`lamodel.search.highs.HighsLP.work`)."""
        return self.problem.work()

    def spent(self) -> bool:
        """The work bounds (LP solves, LP work) are reached, or a side lane's bound by the
        main lane beside it (:meth:`MainLane.reached`: it may wait for the main lane)."""
        return ((self.work_limit is not None and self.problem.n_lps() >= self.work_limit)
                or (self.work_bound is not None and self.work() >= self.work_bound)
                or (self.main_lane is not None and self.main_lane.reached(self.work() - self._side_from)))

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

    def side_lane(self) -> "Budget":
        """The budget of a lane beside the first certificate: the whole first-certificate
        work left (no bound without one), under the time cap alone; without a time limit
        also bounded by the main lane on this engine once it certifies (its
        :attr:`main_lane`, told by :meth:`MainLane.ended`)."""
        self._lane_from = self.work()
        left = None if self.first_bound is None else max(0.0, self.first_bound - self._lane_from)
        child = Budget(self.cap, allowance=(None, left))
        if self.rule is not None:
            start = self._lane_from
            child.main_lane = MainLane(lambda: self.work() - start)
        return child

    def run_under(self, child: "Budget"):
        """This engine's next run is under ``child``: its time cap, its allowance counted
        from this engine's work now, and its bound by a main lane (if any)."""
        lps, work = child.allowance
        self.cap, self._charged = child.cap, True
        self.main_lane, self._side_from = child.main_lane, self.work()
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


class MainLane:
    """What bounds a lane beside the first certificate's main lane: once the main lane
    certified, the side lane may spend SIDE_LANE_SHARE times the LP work the main lane
    took (``main_work()``: its work so far), else what its budget allows. Counted work, so
    the side lane's run is the same with any number of threads: with one it runs after
    the main lane, the bound known; beside it, it waits before a solve that the bound might
    forbid until the main lane has done more work or ended."""

    def __init__(self, main_work):
        self.main_work = main_work
        self.limit = None  # the side lane's work allowed, once the main lane ended (inf: no bound)
        self.done = threading.Event()

    def ended(self, certified: bool):
        """The main lane ended (``certified``: the search has a certified state)."""
        self.limit = SIDE_LANE_SHARE * self.main_work() if certified else math.inf
        self.done.set()

    def reached(self, work) -> bool:
        """The side lane, having spent ``work``, may not go on. Never true inside a solve
        that began allowed: the main lane's work only grows."""
        while not self.done.is_set():
            if work < SIDE_LANE_SHARE * self.main_work():
                return False  # allowed whatever the main lane does next
            self.done.wait(EVALUATION_SLICE)
        return work >= self.limit
