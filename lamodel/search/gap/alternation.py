"""The gap alternation: from a statics, mechanism step and statics step in turn.

* **Mechanism step**: the least-alpha_K mechanism (u, xi) for cohesions ``-mu N`` of the
  current statics (:meth:`ScaledProblem.mechanism`).
* **Gap step**: ``alpha_K(N) - alpha = w^T lambda >= 0`` with ``w = -(Y T)^T xi``; min
  ``alpha + rho w^T lambda`` over S pulls the statics towards a collapse state; rho climbs a
  ladder (:mod:`..tuning`) each time ``alpha + rho gap`` stops falling.
* **Hold step** (the gap stalled near 1e-8 with a few rows flowing while slack): min alpha
  with the rows the mechanism flows on that the statics already holds kept at equality;
  the next mechanism often flows on tight rows only.
* **Near-flow step**: a mechanism whose flows on slack rows are all tiny is certified
  without them.

Whenever the gap is small the mechanism is certified and the certified state descended.
Where the programs start cold (in space) the alternation ends at a certified mechanism:
the gap it has left is round-off, and a step that lowers only that is a cone program of
seconds (:attr:`Alternation.converged` then tells that it converged, not stalled).
With a dilatancy t > 0 (:class:`~.dilatancy.Dilatancy`) the mechanism step is that of
the fictitious system whose sliding dilates by t mu, cohesions ``-(1 - t) mu N``; the gap
is the same ``slack^T xi`` (:func:`~lamodel.formulation.matrices.dilatant_flows`), and
nothing is certified or held: that system's collapse states are not the real one's.
"""
from __future__ import annotations

import logging
import time

import numpy as np

from ..highs import INF
from ..tuning import (ACTIVE_TOLERANCES, ALTERNATION_MAX_STEPS, FORBID_ACTIVE, GAP_CERTIFY, GAP_FORBID, GAP_HOLD,
                      IMPROVEMENT, NEAR_FLOW, RHO_MAIN, STALL)
from .certify import Certifier
from .descent import Descent
from .program import GapProgram
from .record import Record

log = logging.getLogger(__name__)


class Alternation:
    """Runs the gap alternation on a problem; states certified and descended."""

    def __init__(self, problem: GapProgram, certifier: Certifier, descent: Descent, record: Record):
        self.problem, self.certifier, self.descent, self.record = problem, certifier, descent, record
        #: the last :meth:`alternate` ended at a certified mechanism: its statics is a collapse
        #: state's but for a round-off gap (converged, not stalled)
        self.converged = False

    def alternate(self, x, rhos=RHO_MAIN, source="gap", max_steps=ALTERNATION_MAX_STEPS, forbid_slack=False,
                  dilatancy=0.0):
        """Mechanism step / gap step from the statics x until alpha + rho gap stops falling.

        Certifies whenever the gap is small (``dilatancy`` 0: the seed's system); returns
        the best certified state of the run (or None) and the last statics.
        """
        real = dilatancy == 0
        p = self.problem
        # Programs that start cold (in space: a cone program of seconds) end at a certified
        # mechanism; in the plane a step past it is a few warm pivots, and the bases it leaves
        # are where the lanes after it start (ending there moved alpha both ways: evidence.md)
        end_certified = real and not p.lps
        t = time.perf_counter()
        best = None
        found = []  # certified states of the near-flow steps (see _near)
        last_cert_key = None
        certified = set()  # flow patterns certified in this run
        at_certified = self.converged = False
        try:
            for rho in rhos:
                if at_certified:  # a certified state's gap is round-off: a higher rho squeezes only that
                    break
                obj_prev = INF
                for _ in range(max_steps):
                    alpha = float(x[-1])
                    N = p.N_of(x)
                    allowed = None
                    if forbid_slack:
                        allowed = p.active_rows(x, FORBID_ACTIVE)
                    status, a_as, _, u, xi = p.mechanism(-(1.0 - dilatancy) * p.mu * N, allowed, dilatancy=dilatancy)
                    if status != "optimal":
                        break
                    gap = p.gap(x, xi, u)
                    tight = p.active_rows(x, ACTIVE_TOLERANCES[0])
                    slack_flow = (xi > 0) & ~tight & real
                    if real:
                        self.record.note_gap(alpha, gap, np.flatnonzero(slack_flow))
                    self._near(u, xi, tight, slack_flow, source, found)
                    if slack_flow.any() and gap <= GAP_HOLD * max(1.0, alpha) and not forbid_slack:
                        # Hold step. Near convergence the least-alpha_K mechanism flows, a
                        # little (1e-8..3e-7 of its largest flow at 1020 blocks), on a few rows
                        # this statics keeps slack, and no statics holds them all: the gap step
                        # stalls at a gap ~1e-8 (the rho-weights of those rows are negligible).
                        # Hold at equality the rows it flows on that are already tight and
                        # minimise alpha: x stays feasible (warm), alpha falls, and the next
                        # mechanism often flows only on tight rows (gap exactly 0: certified).
                        st_h, xh = p.statics(held=(xi > 0) & tight, cap=self.certifier.cap(), u=u)
                        log.debug("%8.2f   hold: alpha %.7f gap %.2e slack flows %d -> %s %s", p.elapsed(), alpha,
                                  gap, int(slack_flow.sum()), st_h, xh[-1] if xh is not None else "")
                        if st_h == "optimal" and xh[-1] < alpha - IMPROVEMENT * max(1.0, alpha):
                            x, at_certified = xh, False  # (obj_prev kept: the rho ladder still ends on a stall)
                            continue
                    if slack_flow.any() and gap <= GAP_FORBID * max(1.0, alpha):
                        # Near convergence the least-alpha_K mechanism still flows, slightly,
                        # on rows this statics keeps slack (2040 blocks: flows ~3e-7 of the
                        # largest on heavily compressed rows hold the gap near 4e-8, and no
                        # statics can hold those rows). Forbid them for this step.
                        st2, _, _, u2, xi2 = p.mechanism(-p.mu * N, ~slack_flow)
                        if st2 == "optimal":
                            u, xi = u2, xi2
                            slack_flow = (xi > 0) & ~tight
                            self._near(u, xi, tight, slack_flow, source, found)
                    step_gap = p.gap(x, xi, u)
                    if log.isEnabledFor(logging.DEBUG):
                        rel = xi[slack_flow].max() / xi.max() if slack_flow.any() else 0.0
                        log.debug("%8.2f   t %g rho %g alpha %.7f gap %.2e step gap %.2e slack flows %d (max rel %.1e)",
                                  p.elapsed(), dilatancy, rho, alpha, gap, step_gap, int(slack_flow.sum()), rel)
                    # With flows left on slack rows the certification's first LP (min gap of
                    # this mechanism, capped) decides whether a statics can hold them all.
                    if real and step_gap <= GAP_CERTIFY * max(1.0, alpha):
                        key = (xi > 0).tobytes()
                        if key != last_cert_key:
                            last_cert_key = key
                            st = self.certifier.certify(u, xi, source)
                            if st is not None:
                                certified.add(key)
                                st = self.descent.descend(st)
                                if best is None or st.alpha < best.alpha:
                                    best = st
                        at_certified = end_certified and key in certified
                    # At a certified mechanism the gap left is round-off: only a lower alpha is
                    # progress (816-block wall in space: four more program pairs, the gap 2e-8 -> 3e-11)
                    obj = alpha if at_certified else alpha + rho * gap
                    if obj >= obj_prev - STALL * max(1.0, abs(obj_prev)):
                        break
                    obj_prev = obj
                    status, xn = p.statics(cost_lam=rho * p.gap_weights(xi, u))
                    if status != "optimal":
                        break
                    x, at_certified = xn, False
        finally:
            self.converged = at_certified
            self.record.phase("alternate", t, step=True)
        for st in found:
            if best is None or st.alpha < best.alpha:
                best = st
        return best, x

    def _near(self, u, xi, tight, slack_flow, source, found):
        """Near-flow step: a stall whose flows on slack rows are all below NEAR_FLOW of the
        largest (1020 blocks: 4e-8..6e-8, gap 4e-9, and no statics holds them): the
        mechanism without them, certified as any other (held rows, min alpha, every residual
        within RESIDUAL_TOLERANCE) and descended; appended to ``found``."""
        if not slack_flow.any() or xi[slack_flow].max() > NEAR_FLOW * xi.max():
            return
        st = self.certifier.certify(u, np.where(tight, xi, 0.0), source + "-near")
        if st is not None:
            found.append(self.descent.descend(st))
