"""The LPs of joints with strengths hold only the facets in force (lamodel.search.gap.strengths):
their optima are those over the whole inscribed polygon, and bases carry across copies."""
import dataclasses

import numpy as np
import pytest

from conftest import INSTANCES
from lamodel.io.datfile import read_dat
from lamodel.search.gap.strengths import StrengthProblem


def problems(fc):
    """wall33 with compressive strength fc: the search's problem (facets come into force as
    they are violated) and the same with every facet in its LPs from the start."""
    s = read_dat(INSTANCES / "wall33.dat")
    s = dataclasses.replace(s, fc=np.full(s.n_contacts, fc))
    lazy, full = StrengthProblem(s), StrengthProblem(s)
    full._bring_into_force(np.ones(full.nr, bool))
    return lazy, full


def cohesions(p):
    """The fictitious cohesions -mu N of the least-alpha statics and of the greatest."""
    out = []
    for maximize in (False, True):
        status, x = p.statics(maximize=maximize)
        assert status == "optimal"
        out.append(-p.mu * p.N_of(x))
    return out


@pytest.mark.parametrize("fc", [3.0, 1e9])
def test_the_lps_optima_are_those_of_the_whole_polygon(fc):
    lazy, full = problems(fc)
    for maximize in (False, True):
        a, b = lazy.statics(maximize=maximize)[1], full.statics(maximize=maximize)[1]
        assert a[-1] == pytest.approx(b[-1], rel=1e-9, abs=1e-12)
        # every facet holds on the statics found with some of them left out
        s_f = a[lazy.nl:lazy.nl + 3 * lazy.nc]
        assert np.all(lazy.Y @ s_f <= lazy.b + 1e-8 * np.maximum(1.0, np.abs(lazy.b)))
    for c in cohesions(full):
        got, want = lazy.mechanism(c), full.mechanism(c)
        assert got[0] == want[0] == "optimal"
        assert got[1] == pytest.approx(want[1], rel=1e-9)
        xi = got[4]
        assert xi.shape == (lazy.nr,) and not xi[~lazy.in_force].any()
        hi = lazy.b.copy()
        hi[:2 * lazy.nc] = np.tile(np.maximum(c, 0.0) + lazy.cohesion_area, 2)
        s_f = got[2][:3 * lazy.nc]
        assert np.all(lazy.G @ s_f <= hi + 1e-8 * np.maximum(1.0, np.abs(hi)))
    if fc == 3.0:
        assert lazy.facet_rounds > 0  # facets beyond eq. 4's came into force
    assert lazy.in_force.sum() < lazy.nr / 2
    # the statics' rows: equilibrium and the facets in force only
    assert lazy.stat.m == 3 * lazy.nb + lazy.in_force.sum() < full.stat.m


def test_bases_carry_the_facets_in_force_to_another_copy():
    lazy, _ = problems(3.0)
    c = cohesions(lazy)[0]
    alpha = lazy.mechanism(c)[1]
    other, _ = problems(3.0)
    other.restart(lazy.bases())
    assert np.array_equal(other.in_force, lazy.in_force)
    assert np.array_equal(np.sort(other.fict_rows), np.sort(lazy.fict_rows))  # in another order
    got = other.mechanism(c)
    assert got[0] == "optimal" and got[1] == pytest.approx(alpha, rel=1e-9)
    # warm: the carried basis, its rows mapped to this copy's order, is already optimal
    assert other.coh.n_solves == 1 and other.coh.h.getInfo().simplex_iteration_count == 0


def test_a_dry_joint_among_crushing_ones_keeps_eq4s_rows():
    """Joints of infinite f_c beside crushing ones: their copies of the hinge rows are not in
    the LPs (4 sigma columns a dry joint), yet the statics' optima are those of the LP over
    every row of the layout (rebuilt here with SciPy's HiGHS), and the slacks of the copies
    are those of the rows they copy."""
    from scipy.optimize import linprog
    s = read_dat(INSTANCES / "wall33.dat")
    fc = np.where(np.arange(s.n_contacts) % 2 == 0, 3.0, np.inf)
    p = StrengthProblem(dataclasses.replace(s, fc=fc))
    crushing = int(np.isfinite(fc).sum())
    assert p.nl == 4 * (p.nc - crushing) + (p.nr // p.nc) * crushing < p.nr
    n = 3 * p.nc + 1
    A_eq = np.hstack([p.A.toarray(), p.fbar.reshape(-1, 1)])
    A_ub = np.hstack([p.Y.toarray(), np.zeros((p.nr, 1))])
    bounds = [(None, None)] * (3 * p.nc) + [(0, None)]
    for maximize in (False, True):
        status, x = p.statics(maximize=maximize)
        assert status == "optimal"
        cost = np.zeros(n)
        cost[-1] = -1.0 if maximize else 1.0
        ref = linprog(cost, A_ub=A_ub, b_ub=p.b, A_eq=A_eq, b_eq=-p.f0, bounds=bounds, method="highs")
        assert ref.status == 0
        assert x[-1] == pytest.approx(ref.x[-1], rel=1e-7, abs=1e-9)
        slack = p.slack(x)
        s_f = x[p.nl:p.nl + 3 * p.nc]
        assert slack.shape == (p.nr,)
        assert slack == pytest.approx(p.b - p.Y @ s_f, abs=1e-7 * max(1.0, np.abs(p.b).max()))


def test_a_flow_is_small_against_the_blocks_motion_not_only_the_largest_flow():
    """Two facets closing a short joint without turning it flow ~1/d times the closure (a
    bridge's fill restraint: 224 where the blocks moved 1): a flow of 1e-7 elsewhere is
    part of the mechanism (dropping it cost a virtual-work residual of 1.7e-6), one of
    1e-12 of the motion is round-off."""
    s = read_dat(INSTANCES / "wall33.dat")
    s = dataclasses.replace(s, fc=np.full(s.n_contacts, 3.0))
    p = StrengthProblem(s)
    u = np.zeros(3 * p.nb)
    u[0::3] = 1.0                                  # every block moves by 1 (non-dimensional)
    xi = np.zeros(p.nr)
    closing = 2 * p.nc + 5                         # a facet of contact 5
    xi[closing] = 224.0 / p.form.structure.size()  # a rotation, 224 as the residual test measures it
    xi[0], xi[1] = 1e-7, 1e-12                     # slides of contacts 0 and 1
    kept = p._significant(xi.copy(), u)
    assert kept[closing] > 0 and kept[0] == 1e-7 and kept[1] == 0.0
    # measured against the largest flow alone (the generator form's rule) it is dropped
    assert p._significant(xi.copy())[0] == 0.0
