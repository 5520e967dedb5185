"""The search's work bounds, counted in LP solves and LP work (simplex iterations times
rows), not timed: a seed gives the same answer on any machine. Under a time limit none is
set: the deadline (:class:`.options.Deadline`, on every solve) is the search's only bound."""
from __future__ import annotations

from dataclasses import dataclass

from .options import Deadline, Stopped


@dataclass(frozen=True)
class WorkRule:
    """The default run's stopping rule without a time limit: the first certificate ends at
    ``first`` times the formulation's work bound (``work_bound()``: WORK_PER_BLOCK a block),
    the whole search at ``total`` times the first certificate's LP solves and at the work
    bound."""

    first: float
    total: float


class Budget:
    """The work bounds of one search on a formulation ``problem`` (``rule``: a
    :class:`WorkRule`, None: no bound). Lanes run elsewhere get a share of what is left
    (:meth:`shares`, :meth:`side_lane`) and bound their own engine's budget with it
    (:meth:`bound`)."""

    def __init__(self, problem, rule: WorkRule | None = None):
        self.problem, self.rule = problem, rule
        #: LP solves, and LP work (:meth:`work`), at which what follows the first
        #: certificate stops (None: no bound)
        self.work_limit = self.work_bound = None
        #: LP work at which the first certificate ends (None: no bound), and whether it did
        self.first_bound = None if rule is None else rule.first * problem.work_bound()
        self.first_spent = False
        self._lane_from = 0.0  # the search's work when the first certificate's side lanes began

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
        """The work bounds (LP solves, LP work) are reached."""
        return ((self.work_limit is not None and self.problem.n_lps() >= self.work_limit)
                or (self.work_bound is not None and self.work() >= self.work_bound))

    def first(self, run, certified):
        """``run()``, the first certificate, ending between two solves once the search's
        work reaches ``first_bound`` (``first_spent`` then tells so; ``certified()``: the
        search has a certified state). The time limit and a stop are the caller's."""
        if self.first_bound is None:
            return run()
        try:
            with self.problem.until(self.bounded(self.first_done)):
                run()
        except Stopped:
            if self.problem.deadline.expired():
                raise
            self.first_spent = True
        if not certified() and self.first_done():
            self.first_spent = True  # the side lanes spent it

    def first_done(self) -> bool:
        """The first certificate's work bound is reached (False: none)."""
        return self.first_bound is not None and self.work() >= self.first_bound

    def bounded(self, spent=None) -> Deadline:
        """The search's deadline, which also expires once the work bounds are spent
        (``spent()``: other bounds; default :meth:`spent`). The work grows only when a
        solve ends, so it expires between two solves: no LP is cut inside HiGHS (the LPs
        stay usable), the next one raises Stopped before it starts."""
        real = self.problem.deadline
        spent = spent or self.spent
        return Deadline(real.at, lambda: real.expired() or spent())

    def shares(self, k) -> tuple:
        """Each of ``k`` lanes' equal share of the bounds left: (LP solves, LP work), None
        where no bound is set."""
        lps = None if self.work_limit is None else max(0, self.work_limit - self.problem.n_lps()) // k
        work = None if self.work_bound is None else max(0.0, self.work_bound - self.work()) / k
        return lps, work

    def side_lane(self):
        """A lane beside the first certificate's begins: the whole first-certificate work
        left is its (None: no bound)."""
        self._lane_from = self.work()
        return None if self.first_bound is None else max(0.0, self.first_bound - self._lane_from)

    def share(self, running) -> float | None:
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
