"""Where the gap alternation stalls without a certificate: the seed's fixed-point chain
from there, every mechanism certified (why it stalls, when a chain ends, and the ways
measured and not used: docs/method/evidence.md, "The fixed-point fallback")."""
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
