"""What a solve found (:class:`Outcome`): the search's (:func:`lamodel.search.driver.solve`)
or a published method's (:class:`lamodel.search.published.result.MethodResult`);
:mod:`lamodel.output.report` turns it into tables."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..structure import Structure
from ..structure3d import Structure3D
from .state import CollapseState


@dataclass
class Outcome:
    """What the driver found; :mod:`lamodel.output.report` turns it into tables."""

    structure: Structure | Structure3D
    best: CollapseState | None                      # (a CollapseState3D in space)
    alpha_associative: float
    runs: list
    status: str                # one of lamodel.search.state.STATUSES (all but failed)
    message: str
    wall_time_s: float
    seed: int
    first: tuple = (np.nan, np.nan)                 # (alpha, seconds) of the first certificate
    phases: dict = field(default_factory=dict)      # seconds per phase of the search
    history: list = field(default_factory=list)     # (seconds, alpha, source, LP solves) of each improvement
    lps_first: int = 0                              # LP solves of the first phase (the stopping rule's unit)
    work: int = 0                                   # LP work of the search (HighsLP.work: iterations x rows)
    certification_lps: int = 0                      # in space: the certification LPs among the solves
    #: nothing certified: (alpha, alpha_K, relative gap, rows holding it) of the search's
    #: step nearest a collapse state (Record.stall); None otherwise
    stalled: tuple | None = None

    @property
    def certified(self) -> bool:
        return self.best is not None
