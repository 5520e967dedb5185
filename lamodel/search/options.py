"""The options of a solve, validated once, and the one clock every part of it reads."""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

from ..errors import InputError

SOLVERS = ("lamodel_ipopt", "ipopt")


@dataclass
class SolveOptions:
    """What a user can choose about a solve (``lamodel solve --help`` lists the same)."""

    seed: int = 0
    starts: int | None = None      # Ipopt solves of eq. (5); None: up to 2 when cheap (driver)
    workers: int | None = None     # worker processes (default: all cores)
    ga_workers: int | None = None  # threads for the GA's generations (pure evaluations); None: serial, warm
    time_limit: float | None = None
    pop_size: int = 10
    generations: int = 5
    chain: int = 4                 # fixed-point LP steps per fitness evaluation
    xi_factor: float = 100.0
    ipopt_options: dict = field(default_factory=dict)
    solver: str = "lamodel_ipopt"  # or "ipopt": Pyomo's interface to an ipopt executable on PATH
    progress: bool = False
    scheduler: str | None = None   # tcp://HOST:PORT of a dask.distributed cluster: the GA's pure
    #                                evaluations and the Ipopt starts run there

    def __post_init__(self):
        self.validate()

    def validate(self) -> "SolveOptions":
        """Raise InputError (one line) on an option no solve can use."""
        def whole(name, minimum, allow_none=False):
            v = getattr(self, name)
            if v is None and allow_none:
                return
            if isinstance(v, bool) or not isinstance(v, int) or v < minimum:
                raise InputError(f"option {name} is {v!r}; expected a whole number >= {minimum}")
        whole("seed", 0)
        if self.seed >= 2**63:  # numpy's generators take seeds >= 0; summary.csv stores a 64-bit integer
            raise InputError(f"option seed is {self.seed!r}; expected a whole number >= 0 and < 2**63")
        whole("starts", 0, allow_none=True)
        whole("workers", 1, allow_none=True)
        whole("ga_workers", 1, allow_none=True)
        whole("pop_size", 2)
        whole("generations", 1)
        whole("chain", 1)
        if self.time_limit is not None and not (isinstance(self.time_limit, (int, float))
                                                and self.time_limit > 0 and math.isfinite(self.time_limit)):
            raise InputError(f"option time_limit is {self.time_limit!r}; expected a number of seconds > 0")
        if not (isinstance(self.xi_factor, (int, float)) and self.xi_factor > 0):
            raise InputError(f"option xi_factor is {self.xi_factor!r}; expected a number > 0")
        if self.scheduler is not None and not (isinstance(self.scheduler, str) and "://" in self.scheduler):
            raise InputError(f"option scheduler is {self.scheduler!r}; expected an address tcp://HOST:PORT")
        if self.solver not in SOLVERS:
            raise InputError(f"solver '{self.solver}' is unknown; expected 'lamodel_ipopt' or 'ipopt'")
        return self


class Stopped(Exception):
    """The deadline passed, or a stop was asked for (Ctrl-C, a caller's predicate)."""


class Deadline:
    """The end of a time budget on the monotonic clock, and a stop that can come earlier.

    ``Deadline.after(None)`` never expires by itself. ``stop`` is any callable returning
    True to stop (``threading.Event().is_set`` works); ``flag`` is set by a signal handler
    (Ctrl-C). A solve makes one, the time cap of its budget (:mod:`.budget`), which every
    part of it asks: the LPs (inside HiGHS, through its interrupt callback), the cone
    programs, the GA, the Ipopt workers.
    """

    def __init__(self, at: float | None = None, stop=None):
        self.at = at
        self.stop = stop
        self.flag = False

    @classmethod
    def after(cls, seconds: float | None, stop=None) -> "Deadline":
        return cls(None if seconds is None else time.monotonic() + float(seconds), stop)

    def left(self) -> float:
        """Seconds left (inf without a limit, <= 0 once expired)."""
        if self.flag or (self.stop is not None and self.stop()):
            return 0.0
        return math.inf if self.at is None else self.at - time.monotonic()

    remaining = left

    def share(self, k: int) -> float | None:
        """An equal share of the seconds left among ``k`` runs (None: no limit), each of
        ``--method all``'s methods in turn (what one leaves goes to those after it)."""
        return None if self.at is None else max(self.left(), 1e-3) / k

    def expired(self) -> bool:
        if self.flag or (self.stop is not None and self.stop()):
            return True
        return self.at is not None and time.monotonic() > self.at

    def check(self):
        """Raise :class:`Stopped` once expired."""
        if self.expired():
            raise Stopped()

    def work_left(self) -> float:
        """LP work (iterations times rows) a solve may still spend before a work bound
        stops it: none here (a budget's deadline has them, :class:`~.budget.Charged`)."""
        return math.inf

    def extended(self, seconds: float) -> "Deadline":
        """The same deadline moved later by ``seconds`` (e.g. to finish what was found);
        a stop asked for still stops it."""
        d = Deadline(None if self.at is None else self.at + seconds, self.stop)
        d.flag = self.flag
        return d

    def __getstate__(self):
        """What travels to a worker (a local process or a Dask worker on another machine):
        the seconds left, the one wire format of a deadline (clocks of other machines
        differ; a stop predicate may not pickle). An expired deadline arrives expired."""
        return {"left": None if self.at is None and not self.expired() else max(self.left(), 0.0)}

    def __setstate__(self, state):
        self.at = None if state["left"] is None else time.monotonic() + state["left"]
        self.stop, self.flag = None, False
