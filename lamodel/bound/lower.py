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

from ..structure import Structure

#: alpha - alpha_lower <= PROVEN_TOL * max(1, alpha): a proven global minimum
PROVEN_TOL = 1e-6
#: The default budget is counted in LP solves, so that the same structure gets the same
#: bound on any machine: this fraction of the search's own LP solves, at least LP_FLOOR
#: (the proofs of the seed's arch, portal and portal_columns take 99, 78 and 77 LPs;
#: wall33 and wall55 stay at 0 after 500 LPs and after 330,000). A seconds backstop of
#: the search's own time, at least FLOOR_SECONDS, guards against pathological LPs only.
BUDGET_FRACTION, LP_FLOOR, FLOOR_SECONDS = 0.25, 200, 2.0


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


def default_budget(search_seconds: float, search_lps: int) -> tuple[float, int]:
    """(seconds backstop, LP solves) for the bound after a search that took
    ``search_seconds`` and ``search_lps`` LP solves."""
    return max(FLOOR_SECONDS, float(search_seconds)), max(LP_FLOOR, int(BUDGET_FRACTION * search_lps))


def lower_bound(structure: Structure, alpha_upper: float, budget: float = 10.0,
                alpha_split: int = 8, max_nodes: int | None = None, pairs: str = "none",
                max_lps: int | None = None) -> LowerBound:
    """A proven lower bound on the least collapse multiplier of ``structure``.

    ``alpha_upper``: the best certified alpha (any number works as the top of the searched
    range; the claim is "no collapse state below alpha_lower", alpha_lower <= alpha_upper).
    ``budget``: seconds; the search is anytime and stops there with what it proved.
    ``alpha_split``: alpha-intervals are halved while wider than 1/alpha_split of the
    range left after the root's rounds, then the normal-force ranges are branched on.
    ``max_nodes``: stop after this many nodes (1: the root's rounds only), whatever the
    time left: a count gives the same bound on any machine; ``max_lps`` likewise stops
    after this many LP solves (checked before each). ``pairs``: where the polygon
    bound of two contacts (:mod:`.plane`) follows the rounds: "none", "root" or "all"."""
    from .branch import BranchAndBound
    t0 = time.perf_counter()
    structure.validate()
    if not math.isfinite(alpha_upper) or alpha_upper < 0:
        return LowerBound(math.nan, alpha_upper, False, 0, 0, 0, 0, 0, 0.0, "none")
    deadline = time.monotonic() + float(budget)
    bb = BranchAndBound(structure, alpha_upper, deadline, alpha_split=alpha_split, max_nodes=max_nodes,
                        pairs=pairs, max_lps=max_lps)
    L, open_nodes = bb.run(0.0)
    p = bb.progress
    proven = alpha_upper - L <= PROVEN_TOL * max(1.0, alpha_upper)
    check = "none" if L <= 0 else ("lowered" if p.checks_failed else "passed")
    complete = proven or not open_nodes or not bb.out_of_budget
    return LowerBound(alpha_lower=float(L), alpha_upper=float(alpha_upper), proven_global=bool(proven),
                      rounds=p.rounds, intervals=p.alpha_splits + 1, nodes=p.nodes, excluded=p.excluded,
                      lps=p.lps, time=time.perf_counter() - t0, exact_check=check,
                      root_bound=float(bb.root_bound) if bb.root_bound is not None else float(L),
                      complete=bool(complete))
