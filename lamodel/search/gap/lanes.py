"""Lanes: strategies run in turn on one engine, and lanes side by side.

A lane (:class:`Lane`) is a tuple of strategies, each an object with one method
``run(engine, start) -> least certified state (or None)`` (:mod:`.rescue`, :mod:`.chains`,
:mod:`.continuation`, :mod:`.dilatancy`); ``start`` (:class:`Start`) holds the statics it
starts from. Lanes side by side run as **pure evaluations** on engines of their own
(:func:`run_pure`): a function of a snapshot of the search (:meth:`Lanes.snapshot`), the
lane and its budget alone (a share of the work bounds left: :mod:`lamodel.search.budget`), so their outcomes, merged in the order given
(:meth:`Lanes.merge`), are the same with any number of threads. HiGHS releases the GIL
while it solves: two lanes take about the time of the longer one on two cores.
"""
from __future__ import annotations

import logging
import queue
import time
from dataclasses import dataclass

import numpy as np

from ..options import Stopped
from ..workers import threads

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Start:
    """Where the strategies of a lane start: the associative statics, and the statics where
    the gap alternation stalled (None: it did not stall)."""

    x_assoc: np.ndarray
    x_stall: np.ndarray | None = None


@dataclass(frozen=True)
class Lane:
    """Strategies run in turn on one engine (``until_certified``: only until the search
    has a certified state)."""

    strategies: tuple
    until_certified: bool = False

    @property
    def names(self) -> list:
        return [s.name for s in self.strategies]

    def without(self, ran) -> "Lane":
        """The lane without the once-a-search strategies that ran already."""
        return Lane(tuple(s for s in self.strategies if s.once is None or s.once not in ran), self.until_certified)

    def run(self, engine, start):
        for i, strategy in enumerate(self.strategies):
            if self.until_certified and i and engine.record.best is not None:
                break
            strategy.run(engine, start)


class Lanes:
    """The lanes of one engine's search: the once-a-search strategies that ran (``ran``:
    name -> (least certified state,)), its snapshots and merges, and the engines running
    its lanes (``running``, for a progress display). ``new_engine()``: a new engine of the
    same structure (:class:`~lamodel.search.gap.GapSearch`), for the pure evaluations."""

    def __init__(self, engine, new_engine=None):
        self.engine, self.new_engine = engine, new_engine
        self.running = {}
        self.ran = {}
        self.stopped = False  # a pure evaluation was stopped: this engine is unusable

    def forget(self):
        """No once-a-search strategy has run (a pure evaluation starts so)."""
        self.ran.clear()

    def snapshot(self) -> dict:
        """What a pure evaluation of a lane begins from (:func:`run_pure`): the LPs' bases,
        the caches of certifications and descents, the best state."""
        e = self.engine
        return dict(bases=e.problem.bases(), certified=dict(e.certifier.cache), descended=dict(e.descent.cache),
                    best=e.record.best)

    def merge(self, states, lps, learned=None):
        """What a pure evaluation found, taken here as if found here (callers merge in task
        order): its certified states, its LP solves and work, and its additions to the caches
        of certifications and descents by flow pattern."""
        e = self.engine
        for st in states:
            if e.record.on_state is not None:
                e.record.on_state(st)
            e.record.take(st)
        e.problem.lps_elsewhere += lps
        if learned is not None:
            e.problem.work_elsewhere += learned.get("work", 0)
            for name, ran in learned.get("ran", {}).items():
                self.ran.setdefault(name, ran)  # once a search: it ran there
            for mine, theirs in ((e.certifier.cache, learned["certified"]), (e.descent.cache, learned["descended"])):
                for key, value in theirs.items():
                    mine.setdefault(key, value)

    def beside(self, lanes, start, workers=1, phase="continuation"):
        """Independent ``lanes`` from this search's state, side by side in up to ``workers``
        threads, each a pure evaluation of a snapshot under its budget (an equal share of the
        work bounds left: :meth:`~lamodel.search.budget.Budget.share`), merged in the order
        given. Returns the least certified state of each lane (None: none); raises Stopped,
        after merging, where the time cap or a stop ended them."""
        e, budget = self.engine, self.engine.budget
        if not lanes or budget.spent():
            return [None] * len(lanes)
        t = time.perf_counter()
        snap = self.snapshot()
        tasks = [(run_pure, (snap, lane, start, share)) for lane, share in zip(lanes, budget.share(len(lanes)))]
        log.info("%s: lanes %s", phase, " beside ".join(f"[{', '.join(lane.names)}]" for lane in lanes))
        try:
            outcomes = side_by_side(self.new_engine, tasks, workers, running=self.running)
        finally:
            e.record.phase(phase, t)
        _log_lanes(lanes, outcomes)
        for _, states, n, learned in outcomes:
            self.merge(states, n, learned)
        if any(stopped for stopped, *_ in outcomes) and budget.expired():
            raise Stopped()
        return [min(states, key=lambda st: st.alpha, default=None) for _, states, _, _ in outcomes]

    def alongside(self, here, there, start, workers=1, phase="first certificate"):
        """Lane ``here`` on this engine, in this thread, as if alone, while the ``there``
        lanes run as pure evaluations from a snapshot taken before (other threads with
        ``workers`` > 1, else after ``here``), each with the whole first-certificate work
        left (their bound their own, so the answer does not depend on the threads), merged
        after ``here``. The search goes on from the bases of a ``there`` lane that certified
        a lower alpha than ``here`` (why: docs/method/evidence.md). The ``there`` lanes stop
        at the search's time cap, not at the first certificate's bound, and once ``here``
        certified at SIDE_LANE_SHARE times its work
        (:meth:`~lamodel.search.budget.Budget.side_lane`)."""
        e, budget = self.engine, self.engine.budget
        p = e.problem
        side = budget.side_lane()
        t = time.perf_counter()
        raised = []

        def mine():
            try:
                here.run(e, start)
            except Stopped as stop:  # our bound or the deadline: after the other lanes are merged
                raised.append(stop)
            finally:
                if side.main_lane is not None:  # the side lanes' bound, from the work this lane took
                    side.main_lane.ended(e.record.best is not None)

        snap = self.snapshot()
        tasks = [(run_pure, (snap, lane, start, side)) for lane in there]
        log.info("nothing certified by the alternation: lanes %s",
                 " beside ".join(f"[{', '.join(lane.names)}]" for lane in (here, *there)))
        try:
            outcomes = _alongside(mine, self.new_engine, tasks, workers, running=self.running)
        finally:
            e.record.phase(phase, t)
        best = e.record.best
        _log_lanes([here], [(None, [best] if best is not None else [], None, None)])
        _log_lanes(there, outcomes)
        for _, states, n, learned in outcomes:
            self.merge(states, n, learned)
        for _, states, _, learned in outcomes:
            st = min(states, key=lambda st: st.alpha, default=None)
            if st is not None and (best is None or st.alpha < best.alpha) and learned["bases"] is not None:
                best = st
                p.restart(learned["bases"])  # go on from the lane that certified the least alpha
        if raised:
            raise raised[0]
        if any(stopped for stopped, *_ in outcomes) and budget.expired():
            raise Stopped()


def _log_lanes(lanes, outcomes):
    """Each lane's least certified alpha and its LP solves (None: not counted here)."""
    for lane, (_, states, lps, _) in zip(lanes, outcomes):
        least = min((st.alpha for st in states if st is not None), default=None)
        found = "no new certified state" if least is None else f"least certified alpha {least:.6f}"
        log.info("lane [%s]: %s%s", ", ".join(lane.names), found, "" if lps is None else f", {lps} LP solves")


# ------------------------------------------------------------------ pure evaluations
def run_pure(engine, snap: dict, lane: Lane, start: Start, budget):
    """``lane`` as a pure function of the snapshot (its bases, caches and ``best`` state,
    below which a stalled start goes on), under ``budget`` (a child
    :class:`~lamodel.search.budget.Budget`: its time cap, and the LP solves and LP work it
    allows, ending between two solves). Returns (stopped: the time cap or a stop ended it,
    certified states in the order found, LP solves, learned), what it certified before a
    stop included."""
    with PureRun(engine, snap, budget, keep_stopped=True) as run:
        lane.run(engine, start)
    return (run.stopped,) + run.outcome()


class PureRun:
    """The context of a pure evaluation on ``engine``: the LPs restarted from the
    snapshot's bases, its caches, a record holding only the snapshot's best state, every
    certified state collected, the engine under ``budget`` (a child
    :class:`~lamodel.search.budget.Budget`). With ``keep_stopped`` a Stopped ends the block
    quietly (``stopped`` tells)."""

    def __init__(self, engine, snap, budget, keep_stopped=False):
        self.engine, self.snap, self.budget, self.keep_stopped = engine, snap, budget, keep_stopped
        self.found, self.stopped = [], False

    def __enter__(self):
        e = self.engine
        p = e.problem
        p.restart(self.snap["bases"])
        e.certifier.cache, e.descent.cache = dict(self.snap["certified"]), dict(self.snap["descended"])
        e.record.forget(best=self.snap.get("best"), on_state=self.found.append)
        e.lanes.forget()
        self.lps, self.work = p.n_lps(), p.work()
        e.budget.run_under(self.budget)
        return self

    def __exit__(self, kind, exc, tb):
        if kind is not None and issubclass(kind, Stopped):
            self.engine.lanes.stopped = True
            if self.keep_stopped:
                self.stopped = True
                return True
        return False

    def outcome(self):
        """(certified states in the order found, LP solves, learned): what the search merges."""
        e = self.engine
        p = e.problem
        learned = dict(certified={k: v for k, v in e.certifier.cache.items() if k not in self.snap["certified"]},
                       descended={k: v for k, v in e.descent.cache.items() if k not in self.snap["descended"]},
                       bases=None if self.stopped else p.bases(), work=p.work() - self.work, ran=dict(e.lanes.ran))
        return self.found, p.n_lps() - self.lps, learned


# ------------------------------------------------------------------ threads
class Engines:
    """Engines of one structure for pure evaluations, made by ``new_engine()`` on first need
    and reused (a HiGHS model is built once; each evaluation only re-warms it from its
    snapshot): one per evaluation running at a time. ``running`` (a dict), if given, holds
    each engine at work and its LP work when it began (for a progress display)."""

    def __init__(self, new_engine, running=None):
        self.new_engine, self.running = new_engine, running
        self.idle = queue.SimpleQueue()

    def run(self, task, *args):
        """``task(engine, *args)`` on an idle engine; the engine is reused unless the
        evaluation was stopped (an engine is unusable after a stop)."""
        try:
            engine = self.idle.get_nowait()
        except queue.Empty:
            engine = self.new_engine()
        if self.running is not None:
            self.running[id(engine)] = (engine, engine.problem.work())
        try:
            outcome = task(engine, *args)
        finally:
            if self.running is not None:
                self.running.pop(id(engine), None)
        if not engine.lanes.stopped:
            self.idle.put(engine)
        return outcome


def side_by_side(new_engine, tasks, workers: int, running=None):
    """The outcomes of ``tasks`` (each ``(function, args)``, run as ``function(engine,
    *args)``), in task order, run in up to ``workers`` threads (1: one after the other in
    this thread) on :class:`Engines` made by ``new_engine()``. Each evaluation stops at the
    deadline among its arguments (a Ctrl-C reaches it there); this waits for them all."""
    engines = Engines(new_engine, running)
    workers = max(1, min(int(workers), len(tasks)))
    if workers == 1:
        return [engines.run(task, *args) for task, args in tasks]
    with threads(workers, "start") as pool:
        futures = [pool.submit(engines.run, task, *args) for task, args in tasks]
        return [future.result() for future in futures]


def _alongside(here, new_engine, tasks, workers: int, running=None):
    """``here()`` in this thread (on the search's own engine) while the pure ``tasks`` run
    in up to ``workers - 1`` other threads (one worker: after it); the tasks' outcomes in
    task order, once ``here()`` and they have all ended, whatever ``here()`` raised (it is
    raised after them)."""
    if int(workers) <= 1:
        try:
            here()
        finally:
            outcomes = side_by_side(new_engine, tasks, 1, running)
        return outcomes
    with threads(1, "lanes") as pool:
        future = pool.submit(side_by_side, new_engine, tasks, int(workers) - 1, running)
        try:
            here()
        finally:
            outcomes = future.result()
    return outcomes
