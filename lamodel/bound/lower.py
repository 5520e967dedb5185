"""``lower_bound``: no collapse state below alpha_lower, and when it meets alpha, a proof.

The theorem (the seed's first theorem, and monotonicity of an LP's value in its bounds):
every collapse state s* of the frictional assembly has ``alpha* = alpha_coh(-mu N*)``,
the collapse multiplier of the fictitious system with cohesions ``-mu N*``; alpha_coh
never decreases as a cohesion grows. Hence for any lower bounds ``Nmin_k <= -N*_k``,
``alpha* >= alpha_coh(mu Nmin)``. :mod:`.branch` computes such bounds on regions of the
statics, :mod:`.exact` checks every one in exact arithmetic on the user's data.
"""
from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass

from ..search.options import Deadline
from ..search.tuning import (ALPHA_SPLIT, BOUND_FLOOR_SECONDS, BOUND_FLOOR_SECONDS_3D, BOUND_SECONDS, BOUND_SHARE,
                             LPS_PER_CONTACT, LPS_PER_POINT, MAX_LPS_3D, PROVEN_TOL)
from ..structure import Structure
from ..structure3d import Structure3D
from .branch import BranchAndBound  # at load time: the bound runs in a thread beside the search

log = logging.getLogger(__name__)


@dataclass
class LowerBound:
    """What :func:`lower_bound` proved.

    ``alpha_lower``: no collapse state (under this load pattern) has alpha below it
    (NaN when nothing could be proved); ``proven_global``: it meets ``alpha_upper`` within
    ``PROVEN_TOL * max(1, alpha_upper)``; ``exact_check``: "passed" when every
    certificate behind the bound was checked exactly, "lowered" when some failed and
    their bounds were lowered or dropped (the bound stays proven), "none" when no
    certificate was needed (alpha_lower 0)."""

    alpha_lower: float
    alpha_upper: float
    proven_global: bool
    rounds: int
    intervals: int
    nodes: int
    excluded: int
    lps: int
    time: float
    exact_check: str
    root_bound: float = math.nan
    complete: bool = True     # False when the budget ended the search

    @property
    def gap(self) -> float:
        """alpha_upper - alpha_lower."""
        return self.alpha_upper - self.alpha_lower


def proves(alpha_lower: float, alpha: float) -> bool:
    """``alpha_lower`` proves ``alpha`` (a certified multiplier) the global minimum."""
    return bool(alpha - alpha_lower <= PROVEN_TOL * max(1.0, alpha))


def default_budget(search_seconds: float, structure) -> dict:
    """The keyword arguments of :func:`lower_bound` for the default bound on ``structure``
    after a search that took ``search_seconds`` (see LPS_PER_CONTACT, LPS_PER_POINT)."""
    return default_counts(structure) | {"budget": default_seconds(search_seconds, structure)}


def default_counts(structure) -> dict:
    """The counted limits of the default bound (the same bound on any machine)."""
    if getattr(structure, "dimension", 2) == 3:
        return {"max_lps": min(MAX_LPS_3D, LPS_PER_POINT * max(1, structure.n_points))}
    return {"max_nodes": 1, "max_lps": LPS_PER_CONTACT * max(1, structure.n_contacts)}


def default_seconds(search_seconds: float, structure) -> float:
    """The default bound's time guard: BOUND_SHARE of the search's seconds, at least the floor."""
    floor = BOUND_FLOOR_SECONDS_3D if getattr(structure, "dimension", 2) == 3 else BOUND_FLOOR_SECONDS
    return max(floor, BOUND_SHARE * float(search_seconds))


def lower_bound(structure: Structure | Structure3D, alpha_upper: float, budget: float = BOUND_SECONDS,
                alpha_split: int = ALPHA_SPLIT, max_nodes: int | None = None, pairs: str = "none",
                max_lps: int | None = None, eager_root: bool = False, deadline=None) -> LowerBound:
    """A proven lower bound on the least collapse multiplier of ``structure``.

    ``alpha_upper``: the best certified alpha (any number works as the top of the searched
    range; the claim is "no collapse state below alpha_lower", alpha_lower <= alpha_upper).
    ``budget``: seconds; the search is anytime and stops there with what it proved.
    ``alpha_split``: alpha-intervals are halved while wider than 1/alpha_split of the
    range left after the root's rounds, then the normal-force ranges are branched on.
    ``max_nodes``: stop after this many nodes (1: the root's rounds only), whatever the
    time left: a count gives the same bound on any machine; ``max_lps`` likewise stops
    after this many LP solves (checked before each). ``pairs``: where the polygon
    bound of two contacts (:mod:`.plane`) follows the rounds: "none", "root" or "all".
    ``eager_root``: the root's first round solves every contact's Nmin LP, not only
    those its cohesive mechanism slides on (same proofs on the seed's instances, 17 times
    the LPs on a running-bond wall). ``deadline``: a
    :class:`~lamodel.search.options.Deadline` to stop at instead of ``budget`` (one that
    can be set or stopped from another thread: :mod:`.beside`)."""
    t0 = time.perf_counter()
    structure.validate()
    if not math.isfinite(alpha_upper) or alpha_upper < 0:
        return LowerBound(math.nan, alpha_upper, False, 0, 0, 0, 0, 0, 0.0, "none")
    if deadline is None:
        deadline = Deadline.after(float(budget))
    bb = BranchAndBound(structure, alpha_upper, deadline, alpha_split=alpha_split, max_nodes=max_nodes,
                        pairs=pairs, max_lps=max_lps, eager_root=eager_root)
    L, open_nodes = bb.run(0.0)
    p = bb.progress
    proven = proves(L, alpha_upper)
    check = "none" if L <= 0 else ("lowered" if p.checks_failed else "passed")
    complete = proven or not open_nodes or not bb.out_of_budget
    log.info("lower bound %.6f%s (%d LPs, %d nodes, %.2f s)", L, ", the global minimum" if proven else "", p.lps,
             p.nodes, time.perf_counter() - t0)
    return LowerBound(alpha_lower=float(L), alpha_upper=float(alpha_upper), proven_global=bool(proven),
                      rounds=p.rounds, intervals=p.alpha_splits + 1, nodes=p.nodes, excluded=p.excluded,
                      lps=p.lps, time=time.perf_counter() - t0, exact_check=check,
                      root_bound=float(bb.root_bound) if bb.root_bound is not None else float(L),
                      complete=bool(complete))
