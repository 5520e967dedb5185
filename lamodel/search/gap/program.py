"""What the search asks of a formulation: the statics, the fictitious cohesive system and
its mechanism, the certificate, and the way back to the user's units (eq. 1-5).

The search (:mod:`lamodel.search.gap`, run by :func:`lamodel.search.driver.solve`) is
written once against :class:`GapProgram`; each formulation implements it:

* in the plane, :class:`~.problem.ScaledProblem`: LPs with HiGHS, statics in friction-cone
  generator form, yield rows (4 a contact: slide +/-, hinge at both ends), warm bases;
* in the plane with joints that crush, take tension or have cohesion,
  :class:`~.strengths.StrengthProblem`: the same LPs with explicit slack columns for the
  bounded domain of each joint (:mod:`lamodel.formulation.joints`);
* in space, :class:`~.problem3d.ConeProblem`: second-order cone programs with Clarabel on
  the Coulomb cone (point contacts), exact certification on fixed cones with HiGHS
  (:mod:`lamodel.search.certify3d`); rows are 2 a point (opening where ``N = 0``, sliding
  on the cone), no warm bases.

Words used below:

* a **statics** ``x`` is a vector of the program's own columns whose last entry is alpha;
* the **rows** are the conditions of eq. (4) a mechanism may flow on; ``slack(x)`` is one
  non-negative number a row, zero exactly when the statics holds the row at equality;
* a **mechanism** is ``(u, xi)``: the block motions u (``fbar^T u = 1``) and the flows xi
  (one non-negative number a row); ``xi > 0`` is its flow pattern;
* the **gap** of a statics for a mechanism is ``alpha_K(N) - alpha = w(u, xi)^T x`` (eq. 5,
  virtual work), linear in the statics;
* **cohesions** ``c = -mu N`` (one a contact or contact point, ``nc`` of them) define the
  fictitious cohesive system of the seed (a joint's own cohesion ``c0 A`` is the
  formulation's to add).
"""
from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

#: What :meth:`GapProgram.certificates` yields when a certification LP hit its iteration
#: cap: not an answer to remember.
CAPPED = "capped"


@runtime_checkable
class GapProgram(Protocol):
    """The formulation interface of the search (see the module doc).

    Every program solve is given :attr:`deadline`, read at the call (its engine's budget:
    the time cap, a stop, the work bounds that apply then; :mod:`lamodel.search.budget`),
    and raises :class:`~lamodel.search.options.Stopped` when it fires.
    """

    #: friction coefficients, one a contact (plane) or contact point (space)
    mu: np.ndarray
    #: number of cohesions (contacts, or contact points): the GA's genome length
    nc: int
    deadline: object
    #: the warm-started LPs by name (empty where programs start cold)
    lps: dict
    #: program solves made for this search elsewhere (pure GA evaluations merged in)
    lps_elsewhere: int
    work_elsewhere: int
    #: least alpha over S at or below this counts as zero (the dead load stands alone)
    stable_alpha: float
    #: whether the driver polishes the search's states with Ipopt on eq. (5)
    polish: bool

    # ------------------------------------------------------------- bookkeeping
    def elapsed(self) -> float:
        """Seconds since the program was built."""

    def n_lps(self) -> int:
        """Program solves so far (LPs, cone programs), merged evaluations included: the
        stopping rule's unit."""

    def work(self) -> float:
        """Solver work so far, counted (iterations weighted by the program's size): about
        proportional to the time, the same on any machine."""

    def work_bound(self) -> float:
        """Without a time limit the search stops at this much :meth:`work`, its first
        certificate at FIRST_WORK times it."""

    def bases(self) -> dict:
        """The warm bases by name, portable (they pickle)."""

    def restart(self, bases: dict):
        """Start afresh from ``bases`` (:meth:`bases`), nothing else remembered: a pure GA
        evaluation depends on its snapshot alone."""

    def save_bases(self, names=None) -> dict:
        """The current bases of the LPs ``names`` (all: None), to :meth:`load_bases` later."""

    def load_bases(self, saved: dict, restart_cold: bool = True):
        """Back to bases :meth:`save_bases` gave (a cold one restarts cold if ``restart_cold``)."""

    # ----------------------------------------------------------------- statics
    def statics(self, cost_lam=None, held=None, maximize=False, cap=None, alpha_cost=1.0, u=None):
        """Optimise over S (eq. 1-4): min (max) ``alpha_cost alpha + cost_lam^T x`` with the
        rows ``held`` (bool, a row) at equality (``u``: the mechanism that flows on them,
        which fixes a sliding point's direction in space); ``cap``: an iteration cap.
        Returns (status, x)."""

    def N_of(self, x) -> np.ndarray:
        """Normal forces (one a cohesion) of a statics."""

    def cohesive_N(self, xc) -> np.ndarray:
        """Normal forces of the cohesive program's statics."""

    def slack(self, x) -> np.ndarray:
        """Slack of every row (>= 0) in a statics."""

    def active_rows(self, x, tol) -> np.ndarray:
        """Rows whose slack is at most ``tol`` times the statics' largest entry (or 1)."""

    def gap_weights(self, xi, u=None) -> np.ndarray:
        """w with ``w^T x = alpha_K(N(x)) - alpha`` for the mechanism (u, xi) (eq. 5)."""

    def gap(self, x, xi, u=None) -> float:
        """The gap ``alpha_K - alpha`` of statics x for the mechanism (u, xi)."""

    # --------------------------------------------------------------- mechanism
    def mechanism(self, c, allowed=None, dilatancy=0.0):
        """The fictitious cohesive system for cohesions c, flow allowed on rows ``allowed``
        only: (status, alpha_as, its statics xc, u, xi), the mechanism of least alpha_K.
        ``dilatancy`` t > 0: the system whose sliding dilates by t mu (friction t mu besides
        the cohesions; t = 1, c = 0 is the associative system), every row allowed; its xi
        are such that ``gap(x, xi, u) = alpha_K - alpha`` still (the dilatancy
        continuation, :class:`~.dilatancy.Dilatancy`)."""

    # ----------------------------------------------------------- certification
    def iteration_cap(self) -> int | None:
        """Iteration cap of a statics solve that may be hard (None: none)."""

    def pattern(self, u, flow) -> bytes:
        """The key of a certificate: what its answer depends on (the flow pattern, and in
        space the sliding directions)."""

    def certificates(self, u, xi, flow, cap):
        """Candidates ``(x, u, xi, flow, tag)`` for the collapse state of mechanism (u, xi)
        flowing on ``flow``: statics with those rows held, least alpha (the seed's second
        theorem); :data:`CAPPED` when a solve hit ``cap``. Each is checked by
        :meth:`state` and the residual test; the first that passes is the certificate."""

    def pushing_rows(self, state):
        """Per row, how much holding it pushes the certified ``state``'s alpha up (the
        descent's pressure step), or None where the formulation has no such measure."""

    def state(self, x, u, xi, flow, source):
        """The collapse state of statics x and mechanism (u, xi), with its residuals
        (scaled units); it has ``alpha``, ``N``, ``u``, ``flow``, ``source``, ``residual``."""

    def to_user(self, state):
        """A scaled state in the user's units, re-checked there."""
