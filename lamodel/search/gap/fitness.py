"""The GA's evaluation of a genome, and the snapshots that make it a pure function.

A genome is the vector z of per-contact log-perturbations of the cohesions around the
best certified state: ``c = -mu N_ref exp(z)``. Its evaluation is the local search of
:mod:`.chains` from c (the perturbed start and the seed's fixed-point chain, every
certified state descended); its fitness the least certified alpha reached.

For the GA's generations in parallel (:mod:`lamodel.search.generations`) an evaluation is
made a pure function of a **snapshot** (the warm bases, the reference normal forces, the
caches of certifications and descents) and the genome: :func:`evaluate_pure` on an engine
of its own, whose findings the search then :meth:`Fitness.merge`\\ s in task order.
"""
from __future__ import annotations

import numpy as np

from ..budget import Budget
from ..highs import INF
from .chains import Chains
from .lanes import Lanes, PureRun
from .program import GapProgram
from .record import Record, least


class Fitness:
    """Evaluates genomes on a problem (warm, or pure from a snapshot)."""

    def __init__(self, problem: GapProgram, chains: Chains, record: Record, lanes: Lanes):
        self.problem, self.chains, self.record, self.lanes = problem, chains, record, lanes
        self.N_assoc = None         # normal forces of the associative statics (associative)
        self._ref_N = None
        self._carried_bases = None  # the last merged evaluation's final bases (see snapshot)

    def associative(self, x_assoc):
        """The associative statics (scaled units; None: none), whose normal forces are the
        reference before any state is certified."""
        self.N_assoc = self.problem.N_of(x_assoc) if x_assoc is not None else None

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
        best = self.chains.perturbed(c, source="genome")
        best = least(best, self.chains.chain(c, steps=chain_steps, source="genome-chain"))
        return INF if best is None else best.alpha

    # ------------------------------------------------- evaluations in parallel
    def snapshot(self) -> dict:
        """What a pure evaluation starts from (:func:`evaluate_pure`): the warm bases of
        the three LPs (those the last evaluation taken ended with, as a serial search
        goes on from the previous evaluation's; this engine's own before any), the
        reference normal forces and the caches (certifications and descents by flow
        pattern), frozen. Plain arrays and states: it pickles (Dask)."""
        return dict(bases=self._carried_bases or self.problem.bases(),
                    reference_N=self.reference_N(),
                    certified=dict(self.lanes.engine.certifier.cache), descended=dict(self.lanes.engine.descent.cache))

    def evaluate_pure(self, snap: dict, genome, chain_steps, deadline):
        """:meth:`evaluate` as a pure function of (snapshot, genome) (:func:`evaluate_pure`)."""
        return evaluate_pure(self.lanes.engine, snap, genome, chain_steps, deadline)

    def merge(self, states, lps, learned=None):
        """What an evaluator found, taken here as if found here (:meth:`.lanes.Lanes.merge`;
        callers merge evaluations in task order), and the bases it ended with, for later
        snapshots."""
        self.lanes.merge(states, lps, learned)
        if learned is not None and learned.get("bases") is not None:
            self._carried_bases = learned["bases"]


def evaluate_pure(engine, snap: dict, genome, chain_steps, deadline):
    """:meth:`Fitness.evaluate` on ``engine`` as a pure function of (snapshot, genome): the
    LPs restart from the snapshot's bases on new HiGHS objects, the caches are the
    snapshot's and the record emptied, so the outcome does not depend on what this engine
    evaluated before (nor on which thread, process or machine, or how many run: every cap
    is counted in iterations); its LPs stop at ``deadline``. Returns (alpha, certified
    states in the order found (scaled units), LP solves, what it learned: its additions to
    the caches and the bases it ended with)."""
    with PureRun(engine, snap, Budget(deadline)) as run:
        alpha = engine.fitness.evaluate(genome, chain_steps, reference_N=snap["reference_N"])
    return (alpha,) + run.outcome()
