"""Sliding directions made exact (lamodel.search.certify3d.align): a dome whose gap
alternation closed its gap to 1e-10 is certified only once its conic slip directions are
turned to ones a statics holds."""
import numpy as np
import pytest

from lamodel.formulation.space import Formulation3D, scaled, scales
from lamodel.geometry.generators3d import dome
from lamodel.io.json3d import structure3d_from_spec
from lamodel.search.certify3d import (RESIDUAL_TOLERANCE, align, exact_state, project_mechanism, residuals,
                                      statics_lp)
from lamodel.search.cone import ConePrograms


def _pattern(form, u, tol=1e-6):
    n = form.np
    q = form.strains(u)
    U = np.abs(q).max()
    opening = q[:n] > tol * U
    sliding = (np.hypot(q[n:2 * n], q[2 * n:]) > tol * U) & ~opening
    return opening, sliding


@pytest.fixture(scope="module")
def near_collapse():
    """A dome of 3 rings of 6: the relaxed fixed-point chain from the associative statics,
    then gap steps until the gap is below 1e-9 (statics x in S, mechanism u)."""
    s = structure3d_from_spec(dome(3, 6))
    form = Formulation3D.of(scaled(s, *scales(s)))
    cone = ConePrograms(form)
    n, mu = form.np, form.mu
    x = cone.associative().x
    c = -mu * x[:n]
    for _ in range(60):
        res = cone.cohesive(c)
        c = 0.8 * c + 0.2 * (-mu * res.x[:n])
    for _ in range(12):
        q = form.strains(res.u)
        q[:n] = np.maximum(q[:n], 0.0)
        w = form.gap_weights(q)
        gap = float(w @ x[:3 * n])
        if gap < 1e-9:
            break
        x = cone.statics(w=1e5 * w).x
        res = cone.cohesive(-mu * x[:n])
    assert gap < 1e-9
    return form, cone, x, res.u


def test_conic_directions_leave_no_exact_statics_and_align_makes_one(near_collapse):
    form, cone, x, u = near_collapse
    n = form.np
    opening, sliding = _pattern(form, u)
    exact = project_mechanism(form, u, ~(opening | sliding), sliding)
    q = form.strains(exact)
    sdir = np.column_stack([q[n:2 * n], q[2 * n:]]) / np.maximum(np.hypot(q[n:2 * n], q[2 * n:]), 1e-300)[:, None]
    # the pair (x, u) is a collapse state but for the directions of the conic slips
    res = residuals(form, *form.split(x), x[-1], exact, q)
    assert res["slip_alignment"] > RESIDUAL_TOLERANCE
    assert max(v for k, v in res.items() if k != "slip_alignment") <= RESIDUAL_TOLERANCE
    assert cone.statics(opening=opening, sliding=sliding, slide_dir=sdir).status == "infeasible"
    got = align(form, opening, sliding, exact, x[:n])
    assert got is not None
    d, moved = got
    assert np.allclose(np.hypot(d[sliding, 0], d[sliding, 1]), 1.0)
    turn = np.abs(np.arctan2(sdir[:, 0] * d[:, 1] - sdir[:, 1] * d[:, 0], (sdir * d).sum(1)))[sliding]
    assert turn.max() < 1e-3            # a small turn, not another mechanism
    moved = project_mechanism(form, moved, ~(opening | sliding), sliding)
    cand = statics_lp(form, opening, sliding, d, np.column_stack([x[n:2 * n], x[2 * n:3 * n]]))
    st = exact_state(form, cand, moved)
    assert st is not None                       # every residual at most 1e-7
    assert st.alpha == pytest.approx(x[-1], abs=1e-5)   # the collapse state next to x


def test_align_refuses_a_pattern_without_sliding(near_collapse):
    form, _, x, u = near_collapse
    none = np.zeros(form.np, bool)
    assert align(form, none, none, u, x[:form.np]) is None


@pytest.mark.slow
def test_default_search_certifies_a_dome_only_the_alignment_certifies():
    """A dome of 4 rings of 6: without the alignment the default run certifies nothing
    (its conic slips are off by the solver's tolerance); with it the certified state
    passes every residual, in the scaled frame and in the user's units."""
    from lamodel.search.search3d import solve3d
    s = structure3d_from_spec(dome(4, 6))
    r = solve3d(s)
    assert r.status == "certified"
    assert any("+align-" in source for _, _, source in r.history)
    assert max(r.state.residual.values()) <= RESIDUAL_TOLERANCE
    form = Formulation3D.of(s)
    st = r.state
    res = residuals(form, st.N, st.T1, st.T2, st.alpha, st.u, form.strains(st.u))
    assert max(res.values()) <= RESIDUAL_TOLERANCE
    assert st.alpha <= r.associative + 1e-9


def test_align_is_bounded_counted_and_stopped_by_its_deadline(near_collapse):
    from lamodel.search.options import Deadline, Stopped
    form, _, x, u = near_collapse
    opening, sliding = _pattern(form, u)
    exact = project_mechanism(form, u, ~(opening | sliding), sliding)
    work = []
    assert align(form, opening, sliding, exact, x[:form.np], tally=work.append) is not None
    assert len(work) >= 2 and all(w >= 0 for w in work) and sum(work) > 0   # warm steps after the first
    capped = []
    assert align(form, opening, sliding, exact, x[:form.np], ipm_cap=1, tally=capped.append) is None
    assert len(capped) == 1                     # the first LP stopped at its cap: no step taken
    with pytest.raises(Stopped):
        align(form, opening, sliding, exact, x[:form.np], deadline=Deadline.after(-1.0))
