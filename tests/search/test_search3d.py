"""The one search in space: :func:`lamodel.search.driver.solve` on a Structure3D, and
:func:`lamodel.search.search3d.solve3d`'s methods on the search's pieces."""
import numpy as np
import pytest

from builders3d import box_on_ground
from lamodel.formulation.extrude import extrude
from lamodel.io import read
from lamodel.search.driver import solve
from lamodel.search.options import SolveOptions
from lamodel.search.search3d import solve3d

from conftest import INSTANCES


def _tall_block():
    return box_on_ground(1.0, 0.5, 2.0, 0.6, (0.5, np.sqrt(3) / 2, 0.0))


def test_the_driver_solves_a_structure_in_space():
    o = solve(_tall_block(), SolveOptions(seed=0))
    assert o.status == "certified" and o.best.alpha == pytest.approx(0.288675, abs=1e-6)
    assert max(o.best.residual.values()) <= 1e-7
    assert [r.source for r in o.runs] == ["ga+lp"]       # no Ipopt polish in space
    assert o.runs[0].path == "gap alternation" and o.runs[0].iterations > 0
    assert o.lps_first > 0 and o.first[0] == pytest.approx(0.288675, abs=1e-6)


def test_without_a_time_limit_the_cone_work_is_bounded(monkeypatch):
    """In space the default run stops at the cone programs' work bound too (counted, the
    first certificate at FIRST_WORK times it): with no work allowed past the first
    certificate, nothing runs past the first phase; the bound grows with the blocks and
    has a floor."""
    from lamodel.search import budget
    from lamodel.search.gap import problem3d
    s = _tall_block()
    full = solve(s, SolveOptions(seed=0))
    monkeypatch.setattr(problem3d, "WORK_FLOOR_CONE", 1e-9)
    monkeypatch.setattr(problem3d, "WORK_PER_BLOCK_CONE", 0.0)
    monkeypatch.setattr(budget, "FIRST_WORK", 1e30)  # the first certificate's bound out of the way
    o = solve(s, SolveOptions(seed=0))
    assert o.certified and o.runs[0].iterations == o.lps_first < full.runs[0].iterations
    monkeypatch.setattr(problem3d, "WORK_FLOOR_CONE", 0.0)
    p = problem3d.ConeProblem(extrude(read(INSTANCES / "wall33.dat"), 1.0))
    assert p.work() == 0 and p.work_bound() == problem3d.WORK_PER_BLOCK_CONE * p.nb
    p.cone.associative()
    assert p.work() > 0


@pytest.mark.parametrize("method, path", [("gap", "gap"), ("successive", "successive"),
                                          ("associative", "associative")])
def test_each_method_alone(method, path):
    # the block slides at mu = 0.6 < its overturning 0.5/... : a squat block, dilatant
    # associative flow aside, every method certifies the closed form
    r = solve3d(box_on_ground(2.0, 2.0, 0.2, 0.6, (1.0, 0.0, 0.0)), method=method, explore=False)
    if method == "associative":   # its mechanism slides with dilatancy: not a collapse state
        assert r.status == "not_certified" and np.isfinite(r.associative)
        return
    assert r.status == "certified" and r.alpha == pytest.approx(0.6, abs=1e-6)
    assert r.path.startswith(path) and set(r.methods) == {method}
    assert r.n_cone >= r.n_lp > 0


@pytest.mark.slow
def test_the_ga_in_space_gives_the_same_answer_for_any_number_of_workers():
    s = extrude(read(INSTANCES / "wall33.dat"), depth=0.8)
    s.live = np.column_stack([np.zeros(s.n_blocks), -s.dead[:, 2], np.zeros(s.n_blocks)])
    outs = [solve(s, SolveOptions(seed=0, ga_workers=w, pop_size=4, generations=2)) for w in (1, 2)]
    a, b = outs
    assert a.status == b.status == "certified"
    assert a.best.alpha == b.best.alpha <= 0.8 / 10.5 + 1e-9
    assert [(x, src) for _, x, src, _ in a.history] == [(x, src) for _, x, src, _ in b.history]
    assert a.runs[0].iterations == b.runs[0].iterations


def _alternation_in_space(cold=True):
    """The gap alternation from the associative statics of the seed's wall (33 blocks)
    pushed out of its plane; the statics steps it made after its first certificate."""
    from lamodel.search.gap import GapSearch
    from lamodel.search.gap.phases import associative
    s = extrude(read(INSTANCES / "wall33.dat"), 1.0)
    s.live = np.column_stack([np.zeros(s.n_blocks), -s.dead[:, 2], np.zeros(s.n_blocks)])
    e = GapSearch(s.validate())
    p = e.problem
    if not cold:  # as if its programs were warm LPs: the alternation goes on past a certificate
        p.lps = {"warm": None}
    statics, after = p.statics, []

    def counted(*args, **kw):
        if e.record.best is not None:
            after.append(kw.get("cost_lam") is not None)
        return statics(*args, **kw)

    p.statics = counted
    _, alpha_assoc, x0 = associative(e)
    best, x = e.alternation.alternate(x0)
    return best, alpha_assoc, e, sum(after)


def test_in_space_the_alternation_ends_at_a_certified_mechanism():
    """Past a certified mechanism a gap step lowers only the round-off gap left (a cone
    program of seconds on large walls): in space the alternation takes one step to see
    that alpha does not fall and ends there, converged; the same certified state."""
    best, alpha_assoc, e, steps = _alternation_in_space()
    assert best is not None and best.alpha <= alpha_assoc + 1e-7
    assert max(best.residual.values()) <= 1e-7
    assert e.alternation.converged and not e.near.stalled_below(np.array([best.alpha - 1.0]), best)
    assert steps <= 1
    warm_best, _, warm, warm_steps = _alternation_in_space(cold=False)
    assert warm_steps > steps and not warm.alternation.converged
    assert warm_best.alpha == pytest.approx(best.alpha, abs=1e-7)
