"""``lower_bound``: no collapse state below alpha_lower, and when it meets alpha, a proof.

The theorem (the seed's first theorem, and monotonicity of an LP's value in its bounds):
every collapse state s* of the frictional assembly has ``alpha* = alpha_coh(-mu N*)``,
the collapse multiplier of the fictitious system with cohesions ``-mu N*``; alpha_coh
never decreases as a cohesion grows. Hence for any lower bounds ``Nmin_k <= -N*_k``,
``alpha* >= alpha_coh(mu Nmin)``. :mod:`.branch` computes such bounds on regions of the
statics, :mod:`.exact` checks every one in exact arithmetic on the user's data.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

from ..search.options import Deadline
from ..structure import Structure
from ..structure3d import Structure3D
from .branch import BranchAndBound  # at load time: the bound runs in a thread beside the search

#: alpha - alpha_lower <= PROVEN_TOL * max(1, alpha): a proven global minimum
PROVEN_TOL = 1e-6
#: The default bound is the root's rounds to their fixed point: they end when a round
#: raises nothing (each round: one cohesive LP, then one Nmin LP per contact its mechanism
#: slides on; the screen of branch.py first). That proves the seed's arch, portal and
#: portal_columns (119, 98, 95 LPs, 0.2-0.5 s of CPU) and costs 4 LPs on wall33 and 3 on
#: wall55 (0.01-0.02 s, idle), where the branching proves nothing
#: in 500 LPs nor in 48,000 (benchmarks/lower_bound.py; measured under load). The
#: branching converges linearly (about 10^5 nodes for 1e-6 on a trilithon): it is what
#: ``--prove`` buys. Guards: at most LPS_PER_CONTACT LPs per contact (counted, the same
#: on any machine; the arches and portals take at most 8) and SHARE of the search's own
#: seconds, at least FLOOR_SECONDS: on a 1,020-block running-bond wall the root's 50 Nmin
#: LPs (0.5 s each) proved 0 in 28 s after a 75 s search (the screen now decides it in 3
#: LPs, 2.8 s); the guard keeps the bound's cost a quarter of the search's at most, in
#: the plane and in space.
LPS_PER_CONTACT, FLOOR_SECONDS, SHARE = 16, 2.0, 0.25
#: In space a block on three or more contact points can rest on any three of them, so at
#: alpha = 0 every point's Nmin is 0 and the root proves nothing: the default branches, at
#: most LPS_PER_POINT LPs per contact point and MAX_LPS_3D in all (counted: the same bound
#: on any machine), with SHARE of the search's seconds, at least FLOOR_SECONDS_3D, as a
#: guard. A block 1 x 0.5 x 2 on four points is proven at its 0.5 in 117 LPs (0.09 s); a
#: 10-block panel (88 points) is left at 0 after 128 (0.3 s, the search 0.4 s).
LPS_PER_POINT, MAX_LPS_3D, FLOOR_SECONDS_3D = 32, 128, 1.0


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
    """The default bound's time guard: SHARE of the search's seconds, at least the floor."""
    floor = FLOOR_SECONDS_3D if getattr(structure, "dimension", 2) == 3 else FLOOR_SECONDS
    return max(floor, SHARE * float(search_seconds))


def lower_bound(structure: Structure | Structure3D, alpha_upper: float, budget: float = 10.0,
                alpha_split: int = 8, max_nodes: int | None = None, pairs: str = "none",
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
    return LowerBound(alpha_lower=float(L), alpha_upper=float(alpha_upper), proven_global=bool(proven),
                      rounds=p.rounds, intervals=p.alpha_splits + 1, nodes=p.nodes, excluded=p.excluded,
                      lps=p.lps, time=time.perf_counter() - t0, exact_check=check,
                      root_bound=float(bb.root_bound) if bb.root_bound is not None else float(L),
                      complete=bool(complete))
