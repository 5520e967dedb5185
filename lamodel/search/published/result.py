"""What a published method returns (:class:`MethodResult`): its raw answer (its own forces,
multiplier and mechanism), reported as it is with the largest residual of the conditions of
a collapse state (:func:`lamodel.search.certify.residuals`), and that answer certified
(:func:`lamodel.search.certify.certify`: the raw answer's active rows, no further search).
A raw answer that yields no collapse state is reported as not certified, never replaced."""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ...structure import Structure
from ..options import SolveOptions
from ..outcome import Outcome
from ..state import CERTIFIED, FAILED, NO_COLLAPSE, NOT_CERTIFIED, UNSTABLE, CollapseState, unstable_message
from ..tuning import STABLE_ALPHA


@dataclass
class MethodResult:
    """One method on one structure: its raw answer, and that answer certified."""

    method: str
    structure: Structure
    alpha_raw: float = np.nan
    raw_residual: float = np.nan          # largest residual of the raw answer (0: exact)
    state: CollapseState | None = None    # the certified state, or None
    alpha_associative: float = np.nan
    seconds: float = 0.0
    iterations: int = 0                   # LPs (associative, successive-lp) or Ipopt iterations
    notes: str = ""
    status: str = NOT_CERTIFIED           # one of lamodel.search.state.STATUSES (all but interrupted)
    runs: list = field(default_factory=list)
    seed: int = 0

    @property
    def alpha_certified(self) -> float:
        return self.state.alpha if self.state is not None else np.nan

    @property
    def certified(self) -> bool:
        return self.state is not None

    def outcome(self):
        """The method's answer as a driver :class:`~lamodel.search.outcome.Outcome` (for the
        result folder: summary, blocks, contacts, runs)."""
        return Outcome(self.structure, self.state, self.alpha_associative, self.runs, self.status, self.notes,
                       self.seconds, self.seed)

    def failed(self, notes, t0, status=FAILED):
        """No raw answer: why, and the time spent."""
        self.notes, self.status = notes, status
        self.seconds = time.perf_counter() - t0
        return self


def associative_lp(lps):
    """(status, message, LP result): the associative LP, or why no method can start."""
    at_rest = lps.statics(None, minimize=True)
    if at_rest.status == "infeasible" or (at_rest.ok and at_rest.alpha > STABLE_ALPHA):
        return UNSTABLE, unstable_message(at_rest.alpha if at_rest.ok else None) + crushing_message(lps), None
    assoc = lps.associative()
    if assoc.ok:
        return "ok", "", assoc
    if assoc.status.startswith("unbounded"):
        return NO_COLLAPSE, ("the associative LP is unbounded: no dilatant collapse for this live load "
                               "(use --method lamodel for a frictional one)"), None
    return FAILED, f"the associative LP failed ({assoc.status})", None


def crushing_message(lps) -> str:
    """Why a structure with the joints' strengths cannot stand, when they are the reason
    (the search's words, :meth:`lamodel.search.gap.strengths.StrengthProblem.crushing_message`); '' otherwise."""
    if not getattr(lps.structure, "has_materials", False):
        return ""
    from ..gap.strengths import StrengthProblem
    return StrengthProblem(lps.structure, lps.deadline).crushing_message()


def start_state(lps, assoc, source="associative"):
    """A complete start point of eq. (5): the associative statics and the mechanism of the
    fictitious system with cohesion -mu N of those statics (the cohesive LP's duals); None
    where that LP ends without an optimum (e.g. at the time limit)."""
    N, V, M, alpha = lps.split(assoc.x)
    res, u, xi = lps.cohesive(-lps.structure.mu * N)
    if not res.ok:
        return None
    return CollapseState(alpha=alpha, N=N, V=V, M=M, u=u, xi=xi, flow=xi > 0, source=source)


def ipopt_model(structure, options: SolveOptions):
    """The Pyomo model of eq. (5) compiled once for Ipopt (None: Pyomo's ipopt executable)."""
    from ...formulation.model import create_model
    from ...solvers.bridge import QuadraticNLP
    m = create_model(structure, xi_factor=options.xi_factor)
    return m, (QuadraticNLP(m) if options.solver == "lamodel_ipopt" else None)


def finish(result: MethodResult, lps, raw, t0, extra="", run=0):
    """Put the raw answer (N, V, M, alpha, u, xi) through the certification; fill notes
    and the certified alpha of the run (``result.runs[run]``) that gave the raw answer.
    The certification's LPs (a few) run past the method's time limit: a raw answer found
    in time is certified, not reported uncertified for want of a second."""
    from ..certify import RESIDUAL_TOLERANCE, certify, residuals
    from ..options import Deadline
    lps.deadline = Deadline()
    N, V, M, alpha, u, xi = raw
    result.alpha_raw = float(alpha)
    r = residuals(lps, N, V, M, alpha, u, np.asarray(xi, dtype=float))
    worst = max(r, key=r.get)
    result.raw_residual = r[worst]
    state = certify(lps, N, V, M, alpha, u, xi, source=result.method)
    result.state = state
    result.status = CERTIFIED if state is not None else NOT_CERTIFIED
    if state is not None and result.runs:
        result.runs[run].alpha_certified = state.alpha
    if r[worst] <= RESIDUAL_TOLERANCE:
        what = f"raw answer is a collapse state (largest residual {r[worst]:.1e})"
    else:
        what = f"raw answer is not a collapse state ({worst} residual {r[worst]:.1e})"
    if state is None:
        what += "; no collapse state from its active rows: not certified"
    elif abs(state.alpha - alpha) > 1e-8 * max(1.0, abs(alpha)):
        what += f"; certified (least alpha on its active rows): {state.alpha:.6f}"
    result.notes = "; ".join(x for x in (extra, what) if x)
    result.seconds = time.perf_counter() - t0
    return result
