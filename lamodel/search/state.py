"""A collapse state of the frictional assembly: what the search finds and reports."""
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
