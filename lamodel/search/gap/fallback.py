"""Where the gap alternation stalls without a certificate: the seed's fixed-point chain
from there, every mechanism certified.

Why the alternation stalls. The gap step minimises ``alpha + rho w(xi)^T lambda`` over S
for the mechanism xi of least alpha_K at the current normal forces; the mechanism step
takes that mechanism again at the new forces. It is block-coordinate descent on the
bilinear gap ``slack(s)^T xi`` (eq. 5: alpha_K - alpha), and it stops at a partial
optimum wherever the least-alpha_K mechanism flows on a row that no admissible statics
can hold together with its other rows (``min_S w(xi)^T lambda > 0`` for that xi, at every
rho). Measured at mu = 0.9 (running bond, 4 x 1.75 blocks, live load = weight): the seed's
33-block panel stalls at gap 4.1e-3 with one hinge row flowing on slack, a 20 x 25 wall
(510 blocks) at gap 7.8e-4 with 30 rows; rho up to 1e7 leaves both gaps unchanged, and
the rows their statics hold admit no mechanism (the restricted cohesive LP is unbounded
at every tolerance of :meth:`~.starts.Starts.certify_near`). The alternation only ever
reads the cohesive LP's duals; its statics, where the other mechanisms are, is unused.

The fallback (:func:`fallback`). The chain ``c <- -mu N(cohesive statics for c)`` from
the stalled statics' cohesions, the associative statics' and zero cohesion
(:meth:`~.starts.Starts.chain`): each step's mechanism is
certified (its flow rows held, min alpha over S: feasible means an exact collapse state,
whatever the chain's forces) and descended. A step costs a mechanism LP and, for a flow
pattern not seen before, a certification. The chain is followed until it certified and
then did not improve for FALLBACK_PATIENCE steps, until its cohesions repeat (a fixed
point), or for FALLBACK_STEPS steps. At a fixed point ``c = -mu N`` the cohesive LP's own
statics is admissible (``|V| <= c = -mu N``) and holds every row its mechanism flows on,
so the certification cannot fail there: the chain ends without a certificate only if it
cycles for FALLBACK_STEPS steps.
"""
from __future__ import annotations

import numpy as np

from ..tuning import FALLBACK_PATIENCE, FALLBACK_STEPS


def fallback(starts, statics, from_zero=False, source="fixed-point", until=None):
    """The fixed-point chain from the cohesions ``-mu N`` of each statics given (scaled
    units; None is skipped) and, with ``from_zero``, from zero cohesion (the weakest
    fictitious system: the chain from below), on :class:`~.starts.Starts` ``starts``.
    Chains from different starts reach different fixed points (the 33-block panel at
    mu = 0.9: 0.685714 from its stall and from the associative statics, 0.617364 from
    zero cohesion). ``until()``: True stops the chains. Returns the least certified state
    (or None)."""
    p = starts.problem
    cohesions = [-p.mu * p.N_of(x) for x in statics if x is not None]
    if from_zero:
        cohesions.append(np.zeros(p.nc))
    best = None
    for c in cohesions:
        st = starts.chain(c, FALLBACK_STEPS, source=source, patience=FALLBACK_PATIENCE, until=until)
        if st is not None and (best is None or st.alpha < best.alpha):
            best = st
    return best
