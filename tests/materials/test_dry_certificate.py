"""The dry certificate (lamodel.search.gap.dry): where joints only crush, a dry collapse
state within the caps is one of the structure with crushing.

The theorem it rests on, checked on the fictitious programs: with crushing only the
capped fictitious optimum is at most the dry one for the same cohesions (with tensile
strength it can be above it: the step does not run there). Then the closed forms of a
block and a box whose caps are far (the step certifies: its path) and near (the dry state
is beyond them: the search goes on as without it), every state re-checked by the oracles.
"""
import dataclasses

import numpy as np
import pytest

from builders3d import box_on_ground
from conftest import INSTANCES
from oracle import check_state
from test_joints import B, H, block
from lamodel.formulation.joints import relative_error_bound
from lamodel.formulation.space import Formulation3D
from lamodel.io.datfile import read_dat
from lamodel.search.certify3d import passes, residuals
from lamodel.search.driver import SolveOptions, path_of, solve
from lamodel.search.gap.dry import DryCertificate, crushing_only, within_caps
from lamodel.search.gap.problem import ScaledProblem
from lamodel.search.gap.strengths import StrengthProblem
from lamodel.search.search3d import solve3d
from lamodel.search.tuning import CRUSHING_FACETS, CRUSHING_FAN_RATIO, CRUSHING_FLOOR

W = 6.0                     # the planar block's weight (test_joints.block: 2 x 3, unit weight)
A3, B3, H3 = 2.0, 1.0, 4.0  # the box in space: weight 1
EPS = relative_error_bound(CRUSHING_FACETS)


def box(**strengths):
    s = box_on_ground(A3, B3, H3, mu=5.0)
    return dataclasses.replace(s, **{k: np.full(s.n_points, float(v)) for k, v in strengths.items()},
                               area=None).validate()


def solved(s):
    out = solve(s, SolveOptions(workers=1, starts=0))
    assert out.best is not None, out.message
    check_state(s, out.best)
    return out


# ============================================================================ the theorem
@pytest.mark.parametrize("fc", [40.0, 20.0])
def test_capped_fictitious_optimum_is_at_most_the_dry_one(fc):
    """On the arch, for cohesions of many sizes: alpha_K^cap(c) <= alpha_K^dry(c), and
    below it somewhere (the caps bind); with tensile strength above it somewhere."""
    s = read_dat(INSTANCES / "arch.dat")
    dry = ScaledProblem(s)
    capped = StrengthProblem(dataclasses.replace(s, fc=np.full(s.n_contacts, fc)))
    tension = StrengthProblem(dataclasses.replace(s, fc=np.full(s.n_contacts, fc), ft=np.full(s.n_contacts, 2.0),
                                                  cohesion=np.full(s.n_contacts, 2.0)))
    _, x = dry.statics(maximize=True)
    c_assoc = -dry.mu * dry.N_of(x)   # cohesions of the associative statics, scaled below
    rng = np.random.default_rng(0)
    below = above = solved_ = 0
    for scale in (1.0, 2.0, 4.0):
        for _ in range(5):
            c = scale * c_assoc * rng.uniform(0.5, 1.5, s.n_contacts)
            st_dry, a_dry = dry.mechanism(c)[:2]
            st_cap, a_cap = capped.mechanism(c)[:2]
            assert st_dry == "optimal" or st_cap != "optimal"   # the capped domain is the smaller
            if st_dry != "optimal" or st_cap != "optimal":
                continue
            solved_ += 1
            assert a_cap <= a_dry * (1 + 1e-9) + 1e-12
            below += a_cap < a_dry * (1 - 1e-6)
            above += tension.mechanism(c)[1] > a_dry * (1 + 1e-6)
    assert solved_ >= 10 and below > 0 and above > 0


def test_the_step_runs_only_where_joints_only_crush():
    assert crushing_only(block(fc=10.0)) and crushing_only(box(fc=10.0))
    for s in (block(), block(fc=10.0, cohesion=0.1), block(fc=10.0, ft=0.1, cohesion=1.0), block(cohesion=0.1)):
        assert not crushing_only(s)
    assert not crushing_only(box(fc=10.0, cohesion=0.1))


# ======================================================================= in the plane
def test_far_cap_in_the_plane_is_certified_by_the_dry_certificate():
    """f_c = 1e9: alpha = B / H within the polygon's loss at N / N_c = 3e-9, by the step."""
    loss = relative_error_bound(CRUSHING_FACETS, CRUSHING_FLOOR, 3e-9, CRUSHING_FAN_RATIO)
    out = solved(block(fc=1e9))
    assert B / H * (1 - loss) - 1e-9 <= out.best.alpha <= B / H + 1e-9
    assert path_of(out.best) == "dry certificate"


@pytest.mark.parametrize("fc", [10.0, 4.0])
def test_binding_cap_in_the_plane_goes_on_as_without_the_step(fc):
    """The dry hinge at the toe is beyond the stress block: the closed form
    (B/2 - W / (2 f_c)) / (H/2), not by the step."""
    exact = (B / 2 - W / (2 * fc)) / (H / 2)
    out = solved(block(fc=fc))
    assert exact * (1 - EPS) - 1e-9 <= out.best.alpha <= exact + 1e-9
    assert path_of(out.best) != "dry certificate"


def test_within_caps_in_the_plane():
    """The dry state of the block: within a far cap, beyond a binding one."""
    far = StrengthProblem(block(fc=1e9))
    near = StrengthProblem(block(fc=10.0))
    dry = ScaledProblem(block())
    _, x = dry.statics(maximize=True)
    st = dry.state(x, np.zeros(3 * dry.nb), np.zeros(4 * dry.nc), np.zeros(4 * dry.nc, bool), "")
    assert within_caps(far, st) and not within_caps(near, st)


# ============================================================================ in space
@pytest.mark.parametrize("fc", [1e9, 10.0])
def test_far_cap_in_space_is_certified_by_the_dry_certificate(fc):
    """The front points carry W / 2 = 0.5 against caps f_c A = 5 and more: alpha = a / h,
    by the step, every residual with the caps within tolerance."""
    s = box(fc=fc)
    r = solve3d(s, time_limit=120)
    assert r.alpha == pytest.approx(A3 / H3, abs=1e-7)
    assert r.path.startswith("dry")
    st = r.state
    assert passes(residuals(Formulation3D.of(s), st.N, st.T1, st.T2, st.alpha, st.u, st.q))


@pytest.mark.parametrize("fc", [0.8, 0.6])
def test_binding_cap_in_space_goes_on_as_without_the_step(fc):
    """P_c = f_c a b / 2 < W: the front points crush, alpha = (2 P_c - W) a / (W h)."""
    r = solve3d(box(fc=fc), time_limit=120)
    assert r.alpha == pytest.approx((2 * fc * A3 * B3 / 2 - 1.0) * A3 / H3, abs=1e-7)
    assert not r.path.startswith("dry")
    assert np.allclose(r.state.N[box().point[:, 0] > 0], -fc * A3 * B3 / 4)


def test_a_binding_cap_searches_as_without_the_step(monkeypatch):
    """The arch at f_c = 20 (its dry hinges beyond the stress block): the step certifies
    nothing, and the search after it (bounds moved by its work) ends where it ends without it."""
    s = read_dat(INSTANCES / "arch.dat")
    s = dataclasses.replace(s, fc=np.full(s.n_contacts, 20.0))
    with_step = solved(s)
    monkeypatch.setattr(DryCertificate, "applies", lambda self, engine: False)
    without = solved(s)
    assert path_of(with_step.best) != "dry certificate"
    assert with_step.best.alpha == without.best.alpha and path_of(with_step.best) == path_of(without.best)
    assert with_step.lps_first > without.lps_first   # the step's LP solves are counted
