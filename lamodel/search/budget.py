"""The search's work bounds, counted in LP solves and LP work (not timed: a seed gives the
same answer on any machine), and the progress display's share of them."""
from __future__ import annotations

from .options import Deadline


class Budget:
    """The work bounds of one search on a formulation ``problem`` (None: no bound).

    ``work_limit``: LP solves, and ``work_bound``: LP work (:meth:`work`), at which the
    continuations, the chain from zero cohesion and the GA stop (the driver's, without a
    time limit); ``first_bound``: LP work at which the first certificate ends, and
    ``first_spent`` whether it did.
    """

    def __init__(self, problem, work_limit=None, work_bound=None, first_bound=None):
        self.problem = problem
        self.work_limit, self.work_bound, self.first_bound = work_limit, work_bound, first_bound
        self.first_spent = False
        self.lane_from = 0.0  # the search's work when the first certificate's side lane began

    def bound(self, work_limit=None, work_bound=None):
        """The bounds of what follows the first certificate (None: no bound)."""
        self.work_limit, self.work_bound = work_limit, work_bound

    def work(self) -> int:
        """The LP work of the search so far (:attr:`lamodel.search.highs.HighsLP.work`)."""
        return self.problem.work()

    def spent(self) -> bool:
        """The work bounds (LP solves, LP work) are reached."""
        return ((self.work_limit is not None and self.problem.n_lps() >= self.work_limit)
                or (self.work_bound is not None and self.work() >= self.work_bound))

    def bounded(self, spent=None) -> Deadline:
        """The search's deadline, which also expires once the work bounds are spent
        (``spent()``: other bounds; default :meth:`spent`). The work grows only when a
        solve ends, so it expires between two solves: no LP is cut inside HiGHS (the LPs
        stay usable), the next one raises Stopped before it starts."""
        real = self.problem.deadline
        spent = spent or self.spent
        return Deadline(real.at, lambda: real.expired() or spent())

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
            there = 0.0 if lane is None else self.lane_from + lane
            return max(self.work(), there) / self.first_bound
        return None
