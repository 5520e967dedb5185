"""The seed's fixed-point chain ``c <- -mu N(cohesive solution)``, every mechanism certified:
the GA's local search, and two lanes of the search (why the alternation stalls, when a
chain ends, and the ways measured and not used: docs/method/evidence.md, "The fixed-point
fallback").

* :class:`FromZero`: the chain from zero cohesion, once a search;
* :class:`FixedPoint`: the chains from where the gap alternation stalled and from the
  associative statics.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np

from ..tuning import (CHAIN_ATOL, CHAIN_RELAXATION, CHAIN_RTOL, DESCENT_STEP, FALLBACK_PATIENCE, FALLBACK_STEPS,
                      RHO_MAIN)
from .alternation import Alternation
from .certify import Certifier
from .descent import Descent
from .near import Near
from .program import GapProgram
from .record import least

log = logging.getLogger(__name__)


class Chains:
    """The seed's chains on a problem; each returns its least certified state (or None)."""

    def __init__(self, problem: GapProgram, certifier: Certifier, descent: Descent, alternation: Alternation,
                 near: Near):
        self.problem, self.certifier, self.descent, self.near = problem, certifier, descent, near
        self.alternate = alternation.alternate
        self.cycles = 0  # chains that met a cohesion again (see chain)

    def chain(self, c, steps, source="chain", patience=None, until=None):
        """The seed's fixed-point chain c <- -mu N(cohesive solution); certifies each mechanism.
        ``patience``: once it certified, stop after that many steps without improvement;
        ``until()``: True stops it. It also stops at a fixed point. Where the cohesions
        repeat those of an earlier step (a cycle, counted in ``cycles``), or the chain has
        certified nothing after FALLBACK_PATIENCE steps, it goes on relaxed,
        ``c <- (1 - w) c + w c_new`` (w = CHAIN_RELAXATION: averaging damps an oscillation);
        a cycle then ends it, and a chain that certified nothing ends with the gap
        alternation from its last cohesions (:meth:`perturbed`)."""
        p = self.problem
        best, since = None, 0
        seen = []  # the cohesions of the steps so far
        relax = 1.0
        for step in range(steps):
            if until is not None and until():
                break
            if relax == 1.0 and best is None and step >= FALLBACK_PATIENCE:
                relax, seen = CHAIN_RELAXATION, []  # not converging: averaged from here
            status, a_k, xc, u, xi = p.mechanism(c)
            log.debug("%8.2f   chain %s step %d: %s alpha_K %.7f relax %g", p.elapsed(), source, step, status, a_k,
                      relax)
            if status != "optimal":
                break
            st = self.certifier.certify(u, xi, source)
            if st is not None:
                st = self.descent.descend(st)
                if best is None or st.alpha < best.alpha - DESCENT_STEP * max(1.0, best.alpha):
                    since = 0
                best = least(best, st)
            since += best is not None
            if patience is not None and since > patience:
                break
            c_new = -p.mu * p.cohesive_N(xc)
            if np.allclose(c_new, c, rtol=CHAIN_RTOL, atol=CHAIN_ATOL):
                break
            nxt = c_new if relax == 1.0 else (1.0 - relax) * c + relax * c_new
            if any(np.allclose(nxt, old, rtol=CHAIN_RTOL, atol=CHAIN_ATOL) for old in seen):
                self.cycles += 1
                if relax < 1.0:
                    break
                relax, seen = CHAIN_RELAXATION, []
                nxt = (1.0 - relax) * c + relax * c_new
            seen.append(c)
            c = nxt
        if best is None and relax < 1.0 and (until is None or not until()):
            best = self.perturbed(c, source + "-relaxed")
        return best

    def perturbed(self, c, source="perturb"):
        """Cohesions c: a mechanism, then the gap alternation from the best statics for it."""
        p = self.problem
        status, _, _, u, xi = p.mechanism(c)
        if status != "optimal":
            return None
        best = self.certifier.certify(u, xi, source)
        if best is not None:
            best = self.descent.descend(best)
        # capped: from a far perturbation the first gap step can take 10 s at 1020 blocks
        # (12,000 iterations), the time of many cheaper perturbations
        status, x = p.statics(cost_lam=RHO_MAIN[0] * p.gap_weights(xi, u), cap=self.certifier.cap())
        if status == "optimal":
            st, x = self.alternate(x, source=source)
            best = least(best, st)
            if self.near.stalled_below(x, best):
                # the alternation stalled below what it certified (flows left on slack
                # rows): mechanisms on the rows this statics nearly holds
                best = least(best, self.near.certify(x, source + "-near"))
        return best

    def fixed_point(self, statics, from_zero=False, source="fixed-point", until=None):
        """The fixed-point chain from the cohesions ``-mu N`` of each statics given (scaled
        units; None is skipped) and, with ``from_zero``, from zero cohesion (the weakest
        fictitious system: the chain from below). Chains from different starts reach
        different fixed points (the 33-block panel at mu = 0.9: 0.685714 from its stall and
        from the associative statics, 0.617364 from zero cohesion). ``until()``: True stops
        the chains. Returns the least certified state (or None)."""
        p = self.problem
        cohesions = [-p.mu * p.N_of(x) for x in statics if x is not None]
        if from_zero:
            cohesions.append(np.zeros(p.nc))
        best = None
        for c in cohesions:
            best = least(best, self.chain(c, FALLBACK_STEPS, source=source, patience=FALLBACK_PATIENCE, until=until))
        return best


@dataclass(frozen=True)
class FromZero:
    """The seed's chain from zero cohesion, once a search: the weakest fictitious system, a
    start that depends on nothing found before (what it finds: docs/method/evidence.md).
    ``cold``: its cohesive LP starts cold (where the alternation stalled: the cohesive LP's
    statics is massively degenerate and the chain follows the optimum HiGHS returns; warm
    from the stalled alternations' bases it stays where they stalled). It stops at the
    work bounds."""

    cold: bool = False
    name = "chain from zero cohesion"
    once = "from zero"

    def run(self, engine, start):
        p = engine.problem
        if self.cold:
            p.load_bases({name: None for name in p.save_bases(("coh",))})
        ran = engine.lanes.ran
        if self.once not in ran:
            t = time.perf_counter()
            budget = engine.budget
            found = None  # where the work bounds end it: its states so far are in the record
            try:
                with budget.lane():
                    found = engine.chains.fixed_point((), from_zero=True, source="zero-cohesion", until=budget.spent)
                ran[self.once] = (found,)
            finally:
                engine.record.phase("zero cohesion", t)
        return ran[self.once][0]


@dataclass(frozen=True)
class FixedPoint:
    """The seed's fixed-point chains from where the gap alternation stalled and from the
    associative statics."""

    name = "fixed-point fallback"
    once = None

    def run(self, engine, start):
        return engine.chains.fixed_point((start.x_stall, start.x_assoc))
