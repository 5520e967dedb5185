"""The certified search on the complementarity gap of eq. (5): LPs only, warm-started.

Its pieces, in the order the algorithm runs them (each an object handed the ones before):

1. the formulation (:mod:`.program`: the interface the steps below are written against):
   :mod:`.problem` in the plane — the scaled LPs: statics in friction-cone generator
   form, the fictitious cohesive LP whose duals are a mechanism, the way back to the
   user's units (:mod:`.strengths` where joints crush, take tension or have cohesion);
   :mod:`.problem3d` in space — Clarabel's cone programs on the Coulomb cone
   and exact certification LPs on fixed cones (:mod:`.capped3d` where joints have strengths);
2. :mod:`.record` — the best certified state so far, its history, the phase times;
3. :mod:`.certify` — the certificate of a mechanism (the formulation's held statics,
   then the residual test), and its cache;
4. :mod:`.descent` — from a certified state to lower ones;
5. :mod:`.alternation` — the gap alternation (gap, hold and near-flow steps);
6. :mod:`.near` — certification from the rows a stalled statics nearly holds;
7. :mod:`.chains` — the seed's fixed-point chain (the GA's local search, and the lanes
   from zero cohesion and from a stall);
8. the lanes (:mod:`.lanes`: strategies run in turn, lanes side by side as pure
   evaluations, snapshots and merges): :mod:`.rescue`, :mod:`.chains`,
   :mod:`.continuation`, :mod:`.dilatancy`; the phases around them (:mod:`.phases`);
9. :mod:`.fitness` — the GA's evaluation of a genome, and its snapshots.

:class:`GapSearch` builds them for one structure; :func:`lamodel.search.driver.solve` runs
them. Every constant they use is in :mod:`lamodel.search.tuning`.
"""
from __future__ import annotations

from ...structure import Structure
from ...structure3d import Structure3D
from ..budget import Budget
from ..options import Deadline
from .alternation import Alternation
from .certify import Certifier
from .chains import Chains
from .descent import Descent
from .fitness import Fitness
from .lanes import Lanes
from .near import Near
from .problem import ScaledProblem
from .capped3d import CappedConeProblem
from .problem3d import ConeProblem
from .program import GapProgram
from .record import Record
from .strengths import StrengthProblem

__all__ = ["GapSearch", "formulation_of"]

#: The formulation of each kind of structure (each a :class:`~lamodel.search.gap.program.GapProgram`).
FORMULATIONS = {Structure: ScaledProblem, Structure3D: ConeProblem}


def formulation_of(structure):
    """The :class:`~lamodel.search.gap.program.GapProgram` class that formulates ``structure`` (planar or in space;
    a planar one whose joints have strengths: :class:`~.strengths.StrengthProblem`, one in
    space: :class:`~.capped3d.CappedConeProblem`)."""
    if isinstance(structure, Structure) and structure.has_materials:
        return StrengthProblem
    if isinstance(structure, Structure3D) and structure.has_materials:
        return CappedConeProblem
    for kind, program in FORMULATIONS.items():
        if isinstance(structure, kind):
            return program
    raise TypeError(f"no formulation of a {type(structure).__name__}; expected a Structure or a Structure3D")


class GapSearch:
    """The pieces of the search on one structure, built in the order the algorithm runs them.

    ``budget``: the :class:`~lamodel.search.budget.Budget` it runs under (time cap, stop,
    work bounds; None: none); every solve reads its deadline at the call.
    ``on_certified(state)`` is called with every new best certified state (user units),
    ``on_state(state)`` with every certified state (scaled units). Every method raises
    :class:`~lamodel.search.options.Stopped` when the budget's deadline fires; after a stop
    by the time cap the search is unusable (its LPs are abandoned).
    """

    def __init__(self, structure: Structure | Structure3D, budget: Budget | None = None, on_certified=None,
                 on_state=None):
        self.budget = budget or Budget()
        self.problem = formulation_of(structure)(structure, self.budget.deadline)
        self.budget.count(self.problem)
        self.record = Record(self.problem, on_certified, on_state)
        self.certifier = Certifier(self.problem, self.record)
        self.descent = Descent(self.problem, self.certifier, self.record)
        self.alternation = Alternation(self.problem, self.certifier, self.descent, self.record)
        self.near = Near(self.problem, self.certifier, self.descent, self.alternation)
        self.chains = Chains(self.problem, self.certifier, self.descent, self.alternation, self.near)
        self.lanes = Lanes(self, new_engine=lambda: GapSearch(structure))
        self.fitness = Fitness(self.problem, self.chains, self.record, self.lanes)

    @property
    def deadline(self) -> Deadline:
        """The time cap and stop of its budget (what a pure evaluation elsewhere is given)."""
        return self.budget.cap

    def share(self):
        """The share of the work bounds spent so far (:meth:`~lamodel.search.budget.Budget.progress`)."""
        return self.budget.progress(self.lanes.running)

    def n_lps(self) -> int:
        return self.problem.n_lps()
