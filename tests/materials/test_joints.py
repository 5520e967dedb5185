"""Joints with strengths in the plane: crushing, cohesion, tension (lamodel.formulation.joints).

Closed forms of one B x H block (thickness b) on the ground, its weight W at the centroid
and the horizontal live load alpha W there; every reported state re-checked by the oracle
against the stress block itself (not lamodel's polygon).
"""
import dataclasses

import numpy as np
import pytest

from conftest import INSTANCES, rect, stack_spec
from oracle import check_state, stress_block_moment
from lamodel.formulation.joints import facets, fractions, moment_capacity, relative_error_bound
from lamodel.formulation import matrices
from lamodel.formulation.matrices import Formulation, far_bounds, flow_matrix, strength_rows, yield_matrix
from lamodel.io.datfile import read_dat
from lamodel.io.jsonspec import structure_from_json
from lamodel.search.driver import SolveOptions, solve
from lamodel.search.gap import formulation_of
from lamodel.search.gap.problem import ScaledProblem
from lamodel.search.gap.strengths import StrengthProblem
from lamodel.search.tuning import CAP_FAR, CRUSHING_FAN_RATIO, CRUSHING_FACETS, CRUSHING_FLOOR

B, H = 2.0, 3.0
EPS = relative_error_bound(CRUSHING_FACETS)


def block(**strengths):
    """The 2 x 3 block (W = 6, unit weight, thickness 1) on the ground, with strengths."""
    s = structure_from_json({"name": "block", "mu": 5.0, "blocks": [
        {"id": "a", "vertices": rect(0, 0, B, H)},
        {"id": "ground", "support": True, "vertices": rect(-1, -1, 3, 0)}]})
    return dataclasses.replace(s, **{k: np.full(s.n_contacts, float(v)) for k, v in strengths.items()})


def solved(s):
    out = solve(s, SolveOptions(workers=1, starts=0))
    assert out.best is not None, out.message
    check_state(s, out.best)
    return out.best.alpha


# ============================================================================ the domain
@pytest.mark.parametrize("fc, ft", [(5.0, 0.0), (5.0, 0.4), (80.0, 1.0)])
def test_polygon_is_inscribed_within_its_bound(fc, ft):
    """Vertices on the stress block's parabola, the chords inside it, the loss at every N
    at most the stated bound (and at most the fraction x near the tension end)."""
    d, b = 0.7, 1.3
    a, beta = facets(d, b, fc, ft, CRUSHING_FACETS, CRUSHING_FLOOR, CRUSHING_FAN_RATIO)
    Nt, Nc = 2 * d * b * ft, -2 * d * b * fc
    x = np.concatenate([np.geomspace(1e-9, 1e-2, 4000), np.linspace(1e-2, 1, 20001)])[:-1]
    N = Nt + (Nc - Nt) * x
    polygon = np.min(beta[:, None] - a[:, None] * N[None, :], axis=0)
    exact = moment_capacity(N, d, b, fc, ft)
    assert np.allclose(exact, [stress_block_moment(n, d, b, fc, ft) for n in N], rtol=1e-12)
    loss = 1 - polygon / exact
    assert loss.min() >= -1e-9                                       # inscribed
    assert loss.max() <= EPS * (1 + 1e-9)                            # the stated bound
    bound = relative_error_bound(CRUSHING_FACETS, CRUSHING_FLOOR, x, CRUSHING_FAN_RATIO)
    assert np.all((loss - bound) * exact <= 1e-13)                        # moments: round-off only
    assert bound[0] <= CRUSHING_FAN_RATIO * CRUSHING_FLOOR                # f_c -> inf: eq. (4)
    assert EPS == pytest.approx(np.sin(np.pi / (2 * CRUSHING_FACETS)) ** 2)
    assert len(fractions(CRUSHING_FACETS, CRUSHING_FLOOR, CRUSHING_FAN_RATIO)) - 1 == len(a)


def test_infinite_strength_is_the_cone_of_eq4_shifted_by_the_tension():
    a, beta = facets(0.5, 2.0, np.inf, 0.3, CRUSHING_FACETS, CRUSHING_FLOOR, CRUSHING_FAN_RATIO)
    assert a.tolist() == [0.5] and beta[0] == pytest.approx(0.5 * 2 * 0.5 * 2.0 * 0.3)


def test_dry_joints_keep_the_lps_of_eq4():
    """f_c = inf, c0 = f_t = 0: the structure has no materials, the planar program is the
    generator form's and its matrices are eq. (4)'s, entry for entry."""
    s = read_dat(INSTANCES / "arch.dat")
    assert not s.has_materials and formulation_of(s) is ScaledProblem
    form = Formulation.of(s)
    assert form.b is None and (form.Y != yield_matrix(s)).nnz == 0 and (form.G != flow_matrix(s)).nnz == 0
    # the strength rows of a joint with no strength are those rows, with b = 0
    Y, G, b = strength_rows(s)
    assert (Y != yield_matrix(s)).nnz == 0 and (G != flow_matrix(s)).nnz == 0 and not b.any()
    assert formulation_of(block(fc=10)) is StrengthProblem


# ======================================================================= closed forms
@pytest.mark.parametrize("fc", [100.0, 10.0, 4.0])
def test_block_crushing(fc):
    """alpha = (B/2 - W / (2 f_c b)) / (H/2) for the parabola; the polygon's at most
    EPS below it (the moment capacity at N = -W)."""
    W = 6.0
    exact = (B / 2 - W / (2 * fc)) / (H / 2)
    alpha = solved(block(fc=fc))
    assert exact * (1 - EPS) - 1e-9 <= alpha <= exact + 1e-9


def test_block_with_a_huge_strength_tends_to_b_over_h():
    """N / N_c = 3e-9: on the polygon's first chord, which loses at most its end fraction."""
    loss = relative_error_bound(CRUSHING_FACETS, CRUSHING_FLOOR, 3e-9, CRUSHING_FAN_RATIO)
    assert loss < CRUSHING_FAN_RATIO * CRUSHING_FLOOR
    assert B / H * (1 - loss) - 1e-9 <= solved(block(fc=1e9)) <= B / H + 1e-9


@pytest.mark.parametrize("fc", [1e18, 1e20, 1e300])
def test_block_with_an_absurd_strength_is_the_dry_block(fc):
    """A crushing force far beyond the loads (CRUSHING_FAR) takes eq. 4's rows: the dry
    block's B / H (its polygon's facets, of the size of f_c, made the associative LP
    'Empty' from f_c = 1e18)."""
    assert solved(block(fc=fc)) == pytest.approx(B / H, rel=1e-9)


def test_block_that_crushes_under_its_own_weight():
    out = solve(block(fc=2.9), SolveOptions(workers=1, starts=0))   # W = 6 > B b f_c = 5.8
    assert out.status == "unstable" and out.best is None
    assert "crush" in out.message and "fc" in out.message


def test_glued_block_slides_at_mu_plus_cohesion():
    """A glued block slides at alpha = mu + c0 B b / W (overturning needs B/H = 0.667)."""
    s = dataclasses.replace(block(cohesion=0.1), mu=np.full(1, 0.3))
    assert solved(s) == pytest.approx(0.3 + 0.1 * B / 6.0, rel=1e-9)


@pytest.mark.parametrize("fc, ft", [(np.inf, 0.5), (20.0, 0.5), (20.0, 2.0)])
def test_block_overturning_with_tensile_strength(fc, ft):
    """Stress blocks at the base (thickness b = 1): compression f_c over a depth y at the
    toe, tension f_t over the rest, N = -W: f_c y - f_t (B - y) = W, so
    y = (W + f_t B) / (f_c + f_t), and the moment about the base's centre is
    (f_c + f_t) y (B - y) / 2 (f_c = inf: (W + f_t B) B / 2, all the compression at the toe).
    Overturning: alpha W H / 2 = that moment. Cohesion keeps it from sliding."""
    W = 6.0
    if np.isinf(fc):
        moment = (W + ft * B) * B / 2
    else:
        y = (W + ft * B) / (fc + ft)
        moment = (fc + ft) * y * (B - y) / 2
    exact = moment / (W * H / 2)
    alpha = solved(block(fc=fc, ft=ft, cohesion=5.0))
    assert exact * (1 - EPS) - 1e-9 <= alpha <= exact + 1e-9
    if np.isinf(fc):
        assert alpha == pytest.approx(exact, rel=1e-9)


# ============================================================== the seed's structures
@pytest.mark.parametrize("name", ["arch", "portal"])
def test_huge_strength_gives_eq4_back(name):
    """f_c = 1e9 on every joint: the polygon's LPs give the dry joints' alpha within the
    moment the polygon loses there (its first chord: below CRUSHING_FAN_RATIO times
    CRUSHING_FLOOR)."""
    s = read_dat(INSTANCES / f"{name}.dat")
    dry = solved(s)
    huge = solved(dataclasses.replace(s, fc=np.full(s.n_contacts, 1e9)))
    assert huge == pytest.approx(dry, rel=CRUSHING_FAN_RATIO * CRUSHING_FLOOR)


def test_arch_alpha_falls_with_the_compressive_strength():
    s = read_dat(INSTANCES / "arch.dat")
    alphas = [solved(s)] + [solved(dataclasses.replace(s, fc=np.full(s.n_contacts, fc))) for fc in (40.0, 25.0, 15.0)]
    assert all(b < a for a, b in zip(alphas, alphas[1:])), alphas
    out = solve(dataclasses.replace(s, fc=np.full(s.n_contacts, 10.0)), SolveOptions(workers=1, starts=0))
    assert out.status == "unstable" and "crush" in out.message


@pytest.mark.parametrize("name, alpha", [("wall33", 0.638982), ("wall55", 0.557416)])
def test_strength_lps_give_table1_back(name, alpha):
    """Table 1's walls: dry, on eq. (4)'s LPs, and with a negligible cohesion, on the
    strength LPs (explicit slacks, the fictitious LP's rows as rows): the same alpha."""
    s = read_dat(INSTANCES / f"{name}.dat")
    assert solved(s) == pytest.approx(alpha, abs=1e-6)
    glued = dataclasses.replace(s, cohesion=np.full(s.n_contacts, 1e-14))
    assert formulation_of(glued) is StrengthProblem
    assert solved(glued) == pytest.approx(alpha, abs=1e-6)


def test_arch_hinges_move_inward_as_fc_falls():
    """With a finite f_c no hinge sits at an edge: each crushes over the depth of its
    stress block, which grows as f_c falls."""
    from lamodel.output.modes import modes_from_flow
    s = read_dat(INSTANCES / "arch.dat")
    depths = []
    for fc in (40.0, 20.0):
        sf = dataclasses.replace(s, fc=np.full(s.n_contacts, fc))
        best = solve(sf, SolveOptions(workers=1, starts=0)).best
        modes = modes_from_flow(sf, best.xi)
        assert "hinging" not in modes and "crushing" in modes
        crushed = [k for k, m in enumerate(modes) if m.startswith("crushing")]
        depths.append(max(-best.N[k] / (sf.thickness[k] * fc) for k in crushed))
    assert depths[1] > depths[0]


def test_units_scale_the_stresses():
    """Lengths x 10 and a unit weight of 3: forces x 300, stresses x 3; alpha the same
    (metamorphic: the strengths convert like every other number)."""
    def scaled_block(L, unit_weight, fc, ft, c0):
        s = structure_from_json({"name": "block", "mu": 0.4, "unit_weight": unit_weight, "blocks": [
            {"id": "a", "vertices": rect(0, 0, B * L, H * L)},
            {"id": "ground", "support": True, "vertices": rect(-L, -L, 3 * L, 0)}]})
        return dataclasses.replace(s, fc=np.full(1, fc), ft=np.full(1, ft), cohesion=np.full(1, c0),
                                   thickness=np.full(1, L))
    one = solved(scaled_block(1.0, 1.0, 12.0, 0.5, 0.3))
    assert solved(scaled_block(10.0, 3.0, 36.0, 1.5, 0.9)) == pytest.approx(one, rel=1e-9)


def test_mirror_gives_the_same_alpha():
    s = block(fc=10.0, ft=0.5, cohesion=1.0)
    mirror = structure_from_json({"name": "mirror", "mu": 5.0, "blocks": [
        {"id": "a", "vertices": rect(-B, 0, 0, H)},
        {"id": "ground", "support": True, "vertices": rect(-3, -1, 1, 0)}], "live_load": [-1.0, 0.0]})
    mirror = dataclasses.replace(mirror, fc=np.full(1, 10.0), ft=np.full(1, 0.5), cohesion=np.full(1, 1.0))
    assert solved(mirror) == pytest.approx(solved(s), rel=1e-9)


@pytest.mark.parametrize("strengths", [dict(fc=10.0), dict(fc=20.0, ft=0.5, cohesion=5.0), dict(cohesion=0.1)])
def test_pyomo_model_holds_the_certified_state(strengths):
    """create_model with the joints' strengths: the certified state satisfies every
    constraint (eq. 1-5 with Y s_f <= b and alpha_K's xi b), and alpha_K = alpha."""
    from pyomo.environ import Constraint, value
    from lamodel.formulation.model import create_model, get_state, kinematic_multiplier, set_state
    s = block(**strengths)
    if "cohesion" in strengths and len(strengths) == 1:
        s = dataclasses.replace(s, mu=np.full(1, 0.3))
    best = solve(s, SolveOptions(workers=1, starts=0)).best
    m = create_model(s)
    assert len(m.ROWS) == len(best.xi) // s.n_contacts
    set_state(m, s, best.N, best.V, best.M, best.alpha, best.u, best.xi)
    worst = 0.0
    for c in m.component_data_objects(Constraint, active=True):
        body = value(c.body)
        lo = -np.inf if c.lower is None else value(c.lower)
        hi = np.inf if c.upper is None else value(c.upper)
        worst = max(worst, lo - body, body - hi)
    assert worst <= 1e-8
    assert value(kinematic_multiplier(m)) == pytest.approx(best.alpha, abs=1e-9)
    assert np.allclose(get_state(m, s)[5], best.xi)


def test_ipopt_solves_the_model_with_crushing():
    from pyomo.environ import SolverFactory, value
    from lamodel.formulation.model import create_model
    s = block(fc=10.0)
    m = create_model(s)
    assert str(SolverFactory("lamodel_ipopt").solve(m).solver.termination_condition) == "optimal"
    assert value(m.alpha) == pytest.approx(solved(s), abs=1e-4)


@pytest.mark.parametrize("case", ["rotated 0.7 rad", "all at once"])
def test_arch_with_strengths_is_frame_free(case):
    """The metamorphic cases of the dry search (other units, turned, moved, mirrored,
    renumbered) with crushing and mortar: stresses convert as force / length^2, the
    thickness as a length; alpha the same."""
    from search.test_metamorphic import CASES as FRAMES, transform_spec
    from lamodel.geometry import arch
    spec = arch(9, 5.0, 1.5, impost_height=2.0, impost_width=2.5, name="arch9")
    strengths = dict(fc=20.0, ft=0.02, cohesion=0.05, thickness=1.0)
    base = solved(structure_from_json(dict(spec, **strengths)))
    assert base < solved(structure_from_json(spec))                       # the strengths matter
    kw = dict(FRAMES[case])
    if kw.get("perm") == "random":
        kw["perm"] = np.random.default_rng(5).permutation(len(spec["blocks"]))
    F, L = kw.get("force", 1.0), kw.get("length", 1.0)
    moved = transform_spec(spec, **kw)
    moved.update(fc=20.0 * F / L**2, ft=0.02 * F / L**2, cohesion=0.05 * F / L**2, thickness=L)
    assert solved(structure_from_json(moved)) == pytest.approx(base, rel=1e-6)


def least_thickness(fc=None, n=40):
    """The least t / R at which a semicircular arch of n voussoirs (centre-line radius R =
    1, unit weight, thickness b = 1, mu = 10) stands under its own weight on skewbacks:
    bisection on the statics LP (some statics at alpha = 0)."""
    from lamodel.geometry import arch

    def stands(t):
        s = structure_from_json(arch(n, 1.0 - t / 2, t, impost_height=0, mu=10.0))
        if fc is not None:
            s = dataclasses.replace(s, fc=np.full(s.n_contacts, fc))
        p = formulation_of(s)(s)
        status, x = p.statics()
        return status == "optimal" and x[-1] <= p.stable_alpha
    lo, hi = 0.05, 0.3
    for _ in range(16):
        lo, hi = (lo, (lo + hi) / 2) if stands((lo + hi) / 2) else ((lo + hi) / 2, hi)
    return hi


def test_heyman_least_thickness_grows_as_fc_falls():
    """Dry, the least thickness of a semicircular arch tends to Heyman's t/R = 0.1075 (from
    below: 40 voussoirs give 0.10743); with f_c = 1e9 the same; as f_c falls it grows."""
    dry = least_thickness()
    assert 0.1070 < dry < 0.1076
    assert least_thickness(1e9) == pytest.approx(dry, abs=1e-4)
    needed = [least_thickness(fc) for fc in (100.0, 20.0, 5.0)]
    assert dry < needed[0] < needed[1] < needed[2]


# ============================================ far tensile strengths and cohesions (CAP_FAR)
def stack(**strengths):
    """The README's two unit blocks stacked on the ground (mu 0.6, loads' sum 4, joints
    2 d b = 1): overturning at alpha = 1/2, sliding at mu."""
    return structure_from_json({**stack_spec(), **strengths})


def test_far_strengths_are_infinite_rows_of_the_programs_only():
    """Beyond CAP_FAR times the loads a cohesion leaves out its joint's slides, a tension
    all its facets (+inf in the programs' b); the real b, which the residual test reads, is
    unchanged; below it nothing is infinite."""
    s = stack(ft=1e12, cohesion=3.0)
    form = Formulation.of(s)
    nc = s.n_contacts
    assert np.isfinite(form.b).all() and np.isinf(form.b_far[2 * nc:]).all()
    assert np.array_equal(form.b_far[:2 * nc], form.b[:2 * nc])
    s = stack(cohesion=1e20)
    assert np.isinf(Formulation.of(s).b_far[:2 * nc]).all() and not Formulation.of(s).b_far[2 * nc:].any()
    below = stack(ft=CAP_FAR, cohesion=CAP_FAR)   # 1e6 < 1e6 x 4
    assert np.array_equal(far_bounds(below, strength_rows(below)[2]), strength_rows(below)[2])


@pytest.mark.parametrize("strengths", [dict(ft=1e12, cohesion=1e12), dict(ft=1e20, cohesion=1e20),
                                       dict(ft=1e20, cohesion=1e20, fc=1e20), dict(ft=1e12, cohesion=1e12, fc=1e12)])
def test_stack_glued_by_far_tension_and_cohesion_never_collapses(strengths):
    """At 1e12 the stack was called unstable ('the joints crush under the dead load': HiGHS
    ended the least-alpha statics 'unbounded'), at 1e20 the associative LP failed ('Empty')."""
    out = solve(stack(**strengths), SolveOptions(workers=1, starts=0))
    assert out.status == "no_collapse" and out.best is None, out.message
    assert "glue" in out.message and "\n" not in out.message


@pytest.mark.parametrize("v", [1e12, 1e20])
def test_far_cohesion_alone_rocks_and_far_tension_alone_slides(v):
    """Cohesion alone (f_t = 0): no sliding, the dry rocking alpha 1/2; tension alone (no
    cohesion: no tension under Coulomb's law) keeps it from turning, and it slides at mu."""
    assert solved(stack(cohesion=v)) == pytest.approx(0.5, rel=1e-9)
    assert solved(stack(ft=v)) == pytest.approx(0.6, rel=1e-9)


def test_far_cohesion_with_a_finite_fc_still_crushes():
    """c0 = 1e20 and f_c = 5: the crushing facets stay; the same alpha as with a small
    cohesion (rocking with crushing governs, sliding neither way)."""
    assert solved(stack(cohesion=1e20, fc=5.0)) == pytest.approx(solved(stack(cohesion=0.1, fc=5.0)), rel=1e-9)


def test_strengths_below_cap_far_are_unchanged():
    """f_t = c0 = 1e6 (forces 1e6 < CAP_FAR times the loads' 4): the closed form, the stack
    overturning about its toe against its tension N_t = 1e6: 2 alpha = d (N_t + W), W = 2."""
    assert solved(stack(ft=1e6, cohesion=1e6)) == pytest.approx(0.5 * (1e6 + 2) / 2, rel=1e-12)


def test_a_failed_stability_lp_is_no_instability(monkeypatch):
    """Without CAP_FAR, f_t = c0 = 1e12's least-alpha statics ends 'unbounded' (min alpha >= 0
    cannot be): that is no verdict of instability."""
    monkeypatch.setattr(matrices, "CAP_FAR", 1e300, raising=False)
    out = solve(stack(ft=1e12, cohesion=1e12), SolveOptions(workers=1, starts=0))
    assert out.status != "unstable", out.message
