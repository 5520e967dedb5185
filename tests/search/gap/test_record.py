"""The record keeps the least certified state, checked again in the user's units."""
import dataclasses

from lamodel.search.gap import GapSearch

from .helpers import wall
from lamodel.search.gap.phases import associative
from lamodel.search.plan import first_certificate


def test_only_improvements_are_recorded_and_announced():
    heard = []
    e = GapSearch(wall(6), on_certified=heard.append)
    _, _, x0 = associative(e)
    first_certificate(e, x0)
    r = e.record
    best, n = r.best, len(r.history)
    assert best is not None and n == len(heard) >= 1
    assert r.first[0] == r.history[0][1] and r.alpha() == best.alpha
    r.take(dataclasses.replace(best, alpha=best.alpha + 0.1))  # worse: ignored
    assert r.best is best and len(r.history) == n
    r.forget()
    assert r.best is None and r.history == [] and r.alpha() == float("inf")
