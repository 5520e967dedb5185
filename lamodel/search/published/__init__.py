"""The published ways of computing a frictional collapse multiplier, each in its own room,
each a strategy object: run alone (``lamodel solve --method``, :mod:`..methods`) or, the
fixed-point ones, as lanes of the default search (:mod:`lamodel.search.plan`).

* :mod:`.associative` — the LP of max alpha over S with associative (dilatant) flow;
* :mod:`.successive_lp` — Gilbert, Casapulla & Ahmed (2006), in the plane;
* :mod:`.successive_cone` — successive cone programming (Portioli et al.), in space;
* :mod:`.mpec` — Ferris & Tin-Loi (2001): the relaxed MPEC through Ipopt;
* :mod:`.seed` — the seed paper's GA on eq. (5), each individual an Ipopt solve.

:mod:`.result` holds what each method returns, and its certification.
"""
