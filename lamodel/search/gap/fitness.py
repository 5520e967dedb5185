"""The GA's evaluation of a genome, and the snapshots that make it a pure function.

A genome is the vector z of per-contact log-perturbations of the cohesions around the
best certified state: ``c = -mu N_ref exp(z)``. Its evaluation is the local search of
:mod:`.starts` from c (the perturbed start and the seed's fixed-point chain, every
certified state descended); its fitness the least certified alpha reached.

For the GA's generations in parallel (:mod:`lamodel.search.generations`) an evaluation is
made a pure function of a **snapshot** (the warm bases, the reference normal forces, the
caches of certifications and descents) and the genome: :meth:`Fitness.evaluate_pure` on
an engine of its own, whose findings the search then :meth:`Fitness.merge`\\ s in task order.
"""
from __future__ import annotations

import numpy as np

from ..highs import INF
from ..options import Stopped
from .certify import Certifier
from .descent import Descent
from .program import GapProgram
from .record import Record
from .starts import Starts, _least


class Fitness:
    """Evaluates genomes on a problem (warm, or pure from a snapshot)."""

    def __init__(self, problem: GapProgram, certifier: Certifier, descent: Descent, starts: Starts,
                 record: Record):
        self.problem, self.certifier, self.descent, self.starts, self.record = (problem, certifier, descent, starts,
                                                                               record)
        self.N_assoc = None         # normal forces of the associative statics (set by the driver)
        self._ref_N = None
        self._carried_bases = None  # the last merged evaluation's final bases (see snapshot)
        self.stopped = False        # a pure evaluation was stopped: this engine is unusable

    def reference_N(self):
        """Normal forces of the best certified state (else the associative ones)."""
        if self.record.best is not None:
            return self.record.best.N.copy()
        return None if self.N_assoc is None else self.N_assoc.copy()

    def evaluate(self, genome, chain_steps, reference_N=None):
        """Fitness and local search of a genome: c = -mu N_ref exp(z).

        ``reference_N`` (scaled units, see :meth:`reference_N`) defaults to the one frozen at
        the first call, so that a genome keeps its meaning during a GA run. From c: the
        mechanism, the gap alternation and the seed's fixed-point chain of ``chain_steps``
        steps, each certified state descended. Returns the least certified alpha reached
        (inf if none); the record follows. Raises Stopped at the deadline.
        """
        if reference_N is None:
            if self._ref_N is None:
                self._ref_N = self.reference_N()
            reference_N = self._ref_N
        if reference_N is None:
            return INF
        c = -self.problem.mu * reference_N * np.exp(np.asarray(genome, float))
        best = self.starts.perturbed(c, source="genome")
        best = _least(best, self.starts.chain(c, steps=chain_steps, source="genome-chain"))
        return INF if best is None else best.alpha

    # ------------------------------------------------- evaluations in parallel
    def snapshot(self) -> dict:
        """What a pure evaluation starts from (:meth:`evaluate_pure`): the warm bases of
        the three LPs (those the last evaluation taken ended with, as a serial search
        goes on from the previous evaluation's; this engine's own before any), the
        reference normal forces and the caches (certifications and descents by flow
        pattern), frozen. Plain arrays and states: it pickles (Dask)."""
        return dict(bases=self._carried_bases or self.problem.bases(),
                    reference_N=self.reference_N(),
                    certified=dict(self.certifier.cache), descended=dict(self.descent.cache))

    def evaluate_pure(self, snap: dict, genome, chain_steps, deadline):
        """:meth:`evaluate` as a pure function of (snapshot, genome): the LPs restart from
        the snapshot's bases on new HiGHS objects, the caches are the snapshot's and the
        record emptied, so the outcome does not depend on what this engine evaluated
        before (nor on which thread, process or machine, or how many run: every cap is
        counted in iterations); its LPs stop at ``deadline``. Returns (alpha, certified states in the order found
        (scaled units), LP solves, what it learned: its additions to the caches and the
        bases it ended with)."""
        with _PureRun(self, snap, deadline) as run:
            alpha = self.evaluate(genome, chain_steps, reference_N=snap["reference_N"])
        return (alpha,) + run.outcome()

    def starts_pure(self, snap: dict, starts, lps, work, deadline):
        """Starts of :class:`.starts.Starts` run in turn (``starts``: ``(method, args)`` each,
        e.g. ``("continuation", (x_assoc, rhos))``) as a pure function of the snapshot (its
        bases, caches and ``best`` state, below which a stalled start goes on), ending between
        two solves after ``lps`` LP solves or ``work`` LP work of their own in all (None: no
        bound). Returns (stopped: the deadline ended them, certified states in the order
        found, LP solves, learned), what they certified before a stop included."""
        with _PureRun(self, snap, deadline, keep_stopped=True) as run:
            self.record.best = snap.get("best")
            s = self.starts
            s.work_limit = None if lps is None else self.problem.n_lps() + lps
            s.work_bound = None if work is None else s.work() + work
            try:
                for name, args in starts:
                    getattr(s, name)(*args)
            finally:
                s.work_limit = s.work_bound = None
        return (run.stopped,) + run.outcome()

    def merge(self, states, lps, learned=None):
        """What an evaluator found, taken here as if found here (:meth:`.starts.Starts.merge`;
        callers merge evaluations in task order), and the bases it ended with, for later
        snapshots."""
        self.starts.merge(states, lps, learned)
        if learned is not None and learned.get("bases") is not None:
            self._carried_bases = learned["bases"]


class _PureRun:
    """The context of a pure evaluation: the LPs restarted from the snapshot's bases, its
    caches, an empty record, every certified state collected, ``deadline`` on every solve.
    With ``keep_stopped`` a Stopped ends the block quietly (``stopped`` tells)."""

    def __init__(self, fitness, snap, deadline, keep_stopped=False):
        self.fitness, self.snap, self.deadline, self.keep_stopped = fitness, snap, deadline, keep_stopped
        self.found, self.stopped = [], False

    def __enter__(self):
        f = self.fitness
        p = f.problem
        p.restart(self.snap["bases"])
        f.certifier.cache, f.descent.cache = dict(self.snap["certified"]), dict(self.snap["descended"])
        f.record.forget()
        f.starts.forget()
        f.record.on_state = self.found.append
        self.lps, self.work = p.n_lps(), p.work()
        self._until = p.until(self.deadline)
        self._until.__enter__()
        return self

    def __exit__(self, kind, exc, tb):
        self._until.__exit__(kind, exc, tb)
        if kind is not None and issubclass(kind, Stopped):
            self.fitness.stopped = True
            if self.keep_stopped:
                self.stopped = True
                return True
        return False

    def outcome(self):
        """(certified states in the order found, LP solves, learned): what the search merges."""
        f, p = self.fitness, self.fitness.problem
        learned = dict(certified={k: v for k, v in f.certifier.cache.items() if k not in self.snap["certified"]},
                       descended={k: v for k, v in f.descent.cache.items() if k not in self.snap["descended"]},
                       bases=None if self.stopped else p.bases(), work=p.work() - self.work,
                       ran=f.starts.ran())
        return self.found, p.n_lps() - self.lps, learned
