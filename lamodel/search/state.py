"""What the search finds and reports: a collapse state, a row of runs.csv, and the one
vocabulary of statuses and messages that a solve and every method end with."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class CollapseState:
    """An exact collapse state: forces, multiplier, mechanism and the rows that flow."""

    alpha: float
    N: np.ndarray
    V: np.ndarray
    M: np.ndarray
    u: np.ndarray          # (3 nb): ux, uy, theta block after block
    xi: np.ndarray         # (4 nc): stacked by yield row (slide+, slide-, hinge+, hinge-)
    flow: np.ndarray       # (4 nc) bool: rows that flow
    source: str = ""
    residual: dict = field(default_factory=dict)

    @property
    def forces(self) -> np.ndarray:
        return np.concatenate([self.N, self.V, self.M, [self.alpha]])


@dataclass
class Run:
    """One start of the search (a row of runs.csv)."""

    start: int
    source: str
    alpha_ipopt: float = np.nan
    status: str = ""
    alpha_certified: float = np.nan
    iterations: int = 0
    seconds: float = 0.0
    path: str = ""         # which path of the search certified its state (driver.path_of)


#: How a solve (:class:`lamodel.search.driver.Outcome`) or a method
#: (:class:`lamodel.search.methods.MethodResult`) ends: a certified collapse state; none
#: certified (the associative bound, if any, still holds); unstable under the dead load
#: alone; no collapse for this live load; stopped by Ctrl-C or a stop predicate (the best
#: certified state so far is reported); a method that could not run.
CERTIFIED, NOT_CERTIFIED, UNSTABLE, NO_COLLAPSE, INTERRUPTED, FAILED = (
    "certified", "not_certified", "unstable", "no_collapse", "interrupted", "failed")
STATUSES = (CERTIFIED, NOT_CERTIFIED, UNSTABLE, NO_COLLAPSE, INTERRUPTED, FAILED)


def unstable_message(alpha_needed: float | None = None) -> str:
    """The message of an UNSTABLE status: no statically admissible state carries the dead
    load alone; ``alpha_needed``: the least alpha at which one exists (if any)."""
    base = "unstable under dead load: no statically admissible state at alpha = 0"
    if alpha_needed is not None and alpha_needed > 0:
        return base + f" (it needs alpha >= {alpha_needed:.6g} to stand)"
    return base
