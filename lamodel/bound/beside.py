"""The default lower bound computed beside the search, on the core the search leaves idle.

The search's LPs are serial (HiGHS's simplex runs on one core) and the default bound
(:func:`~.lower.lower_bound` with :func:`~.lower.default_counts`) needs only the structure
and a top of the range of alpha it searches. Every collapse state's statics lies in S, so
the associative multiplier, the search's first LP, tops every collapse multiplier: the
bound starts from it while the search goes on, in a thread (HiGHS releases the GIL in its
solves). Its claim is the same (no collapse state below ``alpha_lower``); whether it proves
the certified alpha the global minimum is decided once that alpha is known
(:func:`~.lower.proves`). Measured (the seed's arch, portal, portal_columns, wall33 and
wall55 and the 41 cases of ``benchmarks/families.py --quick``): the bound from the
associative multiplier equals the bound from the certified alpha on every one, the
proofs included; on the 2,040-block running-bond wall at mu = 0.65 its 16.5 s (3 cold
LPs) now pass while the search runs.

Its time guard is the sequential bound's (:func:`~.lower.default_seconds` of the search's
seconds), counted from its own start and set when the search ends; a search that ends
without a state to bound (unstable, stopped) stops it.
"""
from __future__ import annotations

import math
import threading
import time

from ..search.options import Deadline
from ..search.tuning import LATE_SECONDS
from .lower import LowerBound, default_counts, default_seconds, lower_bound


class BoundBeside:
    """The default lower bound of ``structure`` in a thread, from a top given by the search.

    ``enabled=False`` (e.g. ``--prove``, which runs after the search): :meth:`start` starts
    nothing. Used as a context manager around the search, an exception stops the bound::

        with beside:
            outcome = solve(structure, options, on_associative=beside.start)
    """

    def __init__(self, structure, enabled: bool = True):
        self.structure = structure
        # the bound knows dry joints only (lamodel.output.report.bound_columns reports none)
        self.enabled = enabled and not getattr(structure, "has_materials", False)
        self._stop = threading.Event()
        #: no time of its own while the search runs (:meth:`finish` sets it); a stop ends it
        self.deadline = Deadline(None, self._stop.is_set)
        self._thread = None
        self._started = self._top = None
        self._result: LowerBound | None = None
        self._error: BaseException | None = None

    def start(self, alpha_upper: float):
        """Start the bound with ``alpha_upper`` (the associative multiplier) as the top of
        the range; a top that is not a finite multiplier starts nothing."""
        if not self.enabled or self._thread is not None or not (math.isfinite(alpha_upper) and alpha_upper >= 0):
            return
        self._started, self._top = time.monotonic(), float(alpha_upper)
        self._thread = threading.Thread(target=self._run, args=(float(alpha_upper),), name="lamodel-bound",
                                        daemon=True)
        self._thread.start()

    def _run(self, alpha_upper):
        try:
            self._result = lower_bound(self.structure, alpha_upper, deadline=self.deadline,
                                       **default_counts(self.structure))
        except BaseException as e:  # re-raised in the caller's thread by finish()
            self._error = e

    @property
    def started(self) -> bool:
        return self._thread is not None

    def finish(self, search_seconds: float) -> LowerBound | None:
        """The bound once the search took ``search_seconds``: it may go on until the
        default time guard from its own start, then ends with what it proved. None if it
        never started."""
        if self._thread is None:
            return None
        self.deadline.at = self._started + default_seconds(search_seconds, self.structure)
        # its LPs check the deadline inside HiGHS, so it ends within a solve's check of it;
        # a thread that would not is left behind (a daemon) rather than waited on for ever
        give_up = max(self.deadline.at, time.monotonic()) + LATE_SECONDS
        try:
            while self._thread.is_alive() and time.monotonic() < give_up:
                self._thread.join(0.1)
        except BaseException:  # Ctrl-C while waiting: the bound stops too
            self.stop()
            raise
        if self._thread.is_alive():  # nothing it proved can be read: no bound, the search's result stands
            self._stop.set()
            return LowerBound(math.nan, self._top, False, 0, 0, 0, 0, 0, time.monotonic() - self._started, "none",
                              complete=False)
        if self._error is not None:
            raise self._error
        return self._result

    def __enter__(self):
        return self

    def __exit__(self, kind, error, trace):
        if kind is not None:  # the search failed or was interrupted: the bound ends with it
            self.stop()
        return False

    def stop(self):
        """End the bound (its LPs stop at HiGHS's next interrupt check); nothing is kept."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join(5.0)
