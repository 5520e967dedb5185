"""A proven lower bound on the least collapse multiplier, and proofs of the global minimum.

:func:`lower_bound` (``lower.py``) returns a :class:`LowerBound`: no collapse state of the
frictional assembly has alpha below ``alpha_lower`` under its load pattern. The LPs are in
``lps.py``, the rounds, alpha-intervals and branch-and-bound in ``branch.py``, the exact
checks of every certificate in ``exact.py``. Nothing loads HiGHS until it is used.
"""
from __future__ import annotations

__all__ = ["LowerBound", "lower_bound"]


def __getattr__(name):
    if name in __all__:
        from . import lower
        return getattr(lower, name)
    raise AttributeError(name)
