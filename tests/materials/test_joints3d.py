"""Joints with strengths in space (the point-contact model): closed forms on a box on the
ground, the dry answers kept, inputs with one-line errors, contacts.csv's caps checked by
the oracle rebuilt from the CSV columns, tributary areas.

The box a x b x h (weight W, its base's four corners, each of tributary area a b / 4)
under a horizontal load alpha W at its centroid, mu large. Moments about the base's
centre: alpha W h / 2 = (P_f - P_b) a / 2 with P_f + P_b = W, P_f the two front (rocking
edge) points' compression, P_b the back two's. The most alpha has P_f as large as the caps
allow: P_f <= P_c = 2 f_c a b / 4 (crushing) and P_b >= -P_t = -2 f_t a b / 4 (tension), so

    alpha = (2 min(W + P_t, P_c) - W) a / (W h),

a / h dry (P_c infinite, P_t = 0); with W > P_c the front points crush and the block sinks
about the back edge (the dissipation P_c a against the dead load's W a / 2 and the load's
alpha W h / 2); with W > 2 P_c it cannot stand. Sliding with cohesion c0: every point
carries ``c0 a b / 4 + mu |N_i|``, so alpha = (mu W + c0 a b) / W. A point takes tension
only under its cone's apex: ``N <= c0 A / mu``, so the tension test gives it cohesion
``c0 >= mu f_t``.
"""
import json
from pathlib import Path
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from builders3d import box_on_ground, stack_of_boxes, transformed
from oracle3d import violations
from lamodel.cli import command
from lamodel.errors import InputError
from lamodel.geometry.tributary import point_areas
from lamodel.io.json3d import structure3d_from_spec
from lamodel.output.view3d import points_on_caps, write_view3d
from lamodel.search.search3d import solve3d

A, B, H, W = 2.0, 1.0, 4.0, 1.0


def solve(s):
    return solve3d(s, time_limit=120)


def strong(s, **k):
    """The structure with these strengths on every point (the rest the structure's)."""
    return replace(s, **{key: np.full(s.n_points, float(v)) for key, v in k.items()}, area=None).validate()


def rocking(fc=np.inf, ft=0.0):
    Pc, Pt = fc * A * B / 2, ft * A * B / 2
    return (2 * min(W + Pt, Pc) - W) * A / (W * H)


# ====================================================================== closed forms
@pytest.mark.parametrize("fc", [np.inf, 10.0, 0.8, 0.6])
def test_box_rocking_with_crushing(fc):
    s = box_on_ground(A, B, H, mu=5.0)
    r = solve(s if np.isinf(fc) else strong(s, fc=fc))
    assert r.state is not None
    assert r.alpha == pytest.approx(rocking(fc), abs=1e-7)
    modes = list(r.state.modes)
    if fc * A * B / 2 < W:   # the rocking edge's points sit on their caps
        front = s.point[:, 0] > 0
        assert all(m == "crushing" for m, f in zip(modes, front) if f) and r.alpha < A / H
        assert np.allclose(r.state.N[front], -fc * A * B / 4)


def test_box_that_crushes_under_its_own_weight_is_unstable():
    r = solve(strong(box_on_ground(A, B, H, mu=5.0), fc=0.45))   # W > 2 P_c = 0.9
    assert r.status == "unstable" and r.state is None
    assert "with dry joints it stands" in r.message and "crush" in r.message


@pytest.mark.parametrize("c0", [0.0, 0.1, 0.3])
def test_box_sliding_with_cohesion(c0):
    mu = 0.3
    r = solve(strong(box_on_ground(A, B, 0.2, mu=mu), cohesion=c0))
    assert r.state is not None and r.alpha == pytest.approx((mu * W + c0 * A * B) / W, abs=1e-7)
    assert set(r.state.modes) == {"sliding"}


@pytest.mark.parametrize("ft", [0.05, 0.1])
def test_tension_raises_alpha(ft):
    mu = 5.0
    r = solve(strong(box_on_ground(A, B, H, mu=mu), ft=ft, cohesion=mu * ft))
    assert r.state is not None and r.alpha == pytest.approx(rocking(ft=ft), abs=1e-7)
    assert r.alpha > A / H


@pytest.mark.parametrize("c0", [0.0, 0.01])
def test_tension_needs_cohesion(c0):
    """Two unit cubes stacked (mu 0.6), f_t = 0.1: a point takes tension only under its
    cone's apex, min(f_t, c0 / mu) A. Without cohesion none (the dry alpha, 1/2); with
    c0 = 0.01 the base's back points open at the apex: alpha = 1/2 + (c0 / mu) A."""
    mu, area = 0.6, 0.25
    r = solve(strong(stack_of_boxes(2, 1.0, 1.0, 1.0, mu=mu), ft=0.1, cohesion=c0))
    assert r.state is not None and r.alpha == pytest.approx(0.5 + min(0.1, c0 / mu) * area, abs=1e-7)


@pytest.mark.parametrize("mu", [1e8, 1e9])
@pytest.mark.parametrize("fc", [np.inf, 10.0])
def test_a_huge_mu_keeps_the_associative_bound_above_alpha(mu, fc):
    """Three unit cubes stacked, mu 1e8 or 1e9 (no sliding): the stack turns about a base
    edge at alpha = 1/3 and the associative bound, max alpha over S, is not below it (the
    cones' rows scaled to the solver's tolerances: at mu 1e8 the bound was 7e-6 under alpha,
    at 1e9 the stack was found unstable)."""
    s = stack_of_boxes(3, 1.0, 1.0, 1.0, mu=mu)
    r = solve(s if np.isinf(fc) else strong(s, fc=fc))
    assert r.state is not None and r.alpha == pytest.approx(1 / 3, abs=1e-7)
    assert r.associative >= r.alpha - 1e-8


def test_units_scale_the_stresses():
    """Lengths times 3, forces times 7: stresses times 7 / 9, the same alpha."""
    s = box_on_ground(A, B, H, mu=5.0)
    base = solve(strong(s, fc=0.8)).alpha
    t = transformed(s, length=3.0, force=7.0)
    assert solve(strong(t, fc=0.8 * 7 / 9)).alpha == pytest.approx(base, rel=1e-7)


# ================================================================ the dry answers kept
def test_huge_strengths_give_the_dry_alpha():
    """fc = 1e9 (every cap far) solved by the capped programs: the dry alpha."""
    for s in (box_on_ground(A, B, H, mu=5.0), box_on_ground(A, B, 0.2, mu=0.3), stack_of_boxes(3, 1.0, 1.0, 0.8)):
        dry, capped = solve(s), solve(strong(s, fc=1e9))
        assert capped.state is not None
        assert capped.alpha == pytest.approx(dry.alpha, rel=1e-7, abs=1e-9)


def box_spec(**top):
    return {"name": "box", "dimension": 3, "mu": 5.0, **top, "blocks": [
        {"id": "ground", "support": True, "vertices": cuboid(-2, -1, -0.5, 2, 1, 0)},
        {"id": "B", "vertices": cuboid(-A / 2, -B / 2, 0, A / 2, B / 2, H)}]}


def cuboid(x0, y0, z0, x1, y1, z1):
    return [[x, y, z] for z in (z0, z1) for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]


@pytest.mark.parametrize("fc", [np.inf, 1e20])
def test_glued_joints_do_not_collapse(fc, monkeypatch):
    """Two unit cubes stacked (mu 0.6), f_t = c0 = 1e20 (and f_c): every tensile and cohesion
    force is far beyond the loads (CAP_FAR), so no point opens or slides and no mechanism
    exists: no collapse, said in one line (once not certified: the programs' rows of 1e20),
    also where the least-alpha statics the search starts from has no optimum (once a TypeError)."""
    from lamodel.search.gap.capped3d import CappedConeProblem
    s = strong(stack_of_boxes(2, 1.0, 1.0, 1.0, mu=0.6), ft=1e20, cohesion=1e20, fc=fc)
    r = solve(s)
    assert r.status == "no_collapse" and r.state is None and "glue" in r.message and "\n" not in r.message
    statics = CappedConeProblem.statics
    monkeypatch.setattr(CappedConeProblem, "statics", lambda self, *a, maximize=False, **k: (
        statics(self, *a, maximize=True, **k) if maximize else ("InsufficientProgress", None)))
    r = solve(s)
    assert r.status == "no_collapse" and r.state is None


@pytest.mark.parametrize("extra", [[], ["--fc", "1e20"]])
def test_glued_joints_on_the_command_line(tmp_path, capsys, extra):
    """The same stack from a 3D JSON file, --ft 1e20 --cohesion 1e20: exit status 3 and
    no_collapse, no internal error (once a TypeError from the associative program's
    least-alpha fallback)."""
    d = {"name": "stack", "dimension": 3, "mu": 0.6, "live_load": [1.0, 0.0, 0.0], "blocks": [
        {"id": "ground", "support": True, "vertices": cuboid(-2, -2, -1, 2, 2, 0)},
        {"id": "b1", "vertices": cuboid(-0.5, -0.5, 0, 0.5, 0.5, 1)},
        {"id": "b2", "vertices": cuboid(-0.5, -0.5, 1, 0.5, 0.5, 2)}]}
    f = tmp_path / "stack.json"
    f.write_text(json.dumps(d))
    args = [str(f), "--out", str(tmp_path / "o"), "--no-plot", "--quiet", "--ft", "1e20", "--cohesion", "1e20"]
    assert command("solve", args + extra) == 3
    assert "error" not in capsys.readouterr().err
    assert pd.read_csv(tmp_path / "o" / "summary.csv")["status"][0] == "no_collapse"


def test_a_huge_cohesion_alone_blocks_sliding_only():
    """c0 = 1e20 alone (f_t = 0): no point slides, none takes tension, so the stack of two
    unit cubes still turns about a base edge at the dry alpha 1/2 (once 'associative LP
    failed' from the cones' radii of 1e20); with mu 0.3 it slides dry at 0.3, glued at 1/2.
    Cohesion glueing only the base: the top cube slides on it (mu 0.6)."""
    for mu in (0.6, 0.3):
        r = solve(strong(stack_of_boxes(2, 1.0, 1.0, 1.0, mu=mu), cohesion=1e20))
        assert r.status == "certified" and r.alpha == pytest.approx(0.5, abs=1e-7)
        assert "sliding" not in set(r.state.modes)
    s = stack_of_boxes(2, 1.0, 1.0, 1.0, mu=0.6)
    base = s.point_interface == 0
    s = replace(s, ft=np.where(base, 1e20, 0.0), cohesion=np.where(base, 1e20, 0.0), fc=np.full(s.n_points, np.inf),
                area=None).validate()
    r = solve(s)
    assert r.status == "certified" and r.alpha == pytest.approx(0.6, abs=1e-7)
    assert set(np.asarray(r.state.modes)[base]) == {"stuck"} and set(np.asarray(r.state.modes)[~base]) == {"sliding"}


def test_zero_strengths_write_today_s_files(tmp_path):
    """A file with "ft": 0 and "cohesion": 0 (and no fc) is the dry structure: the same
    result files, byte for byte (but the command line in the summary)."""
    out = []
    for k, extra in enumerate(({}, {"ft": 0, "cohesion": 0})):
        f = tmp_path / f"box{k}.json"
        f.write_text(json.dumps(box_spec(**extra)))
        assert command("solve", [str(f), "--out", str(tmp_path / f"o{k}"), "--no-plot", "--quiet"]) == 0
        out.append(tmp_path / f"o{k}")
    for name in ("contacts.csv", "blocks.csv"):
        assert (out[0] / name).read_bytes() == (out[1] / name).read_bytes()
    a, b = (pd.read_csv(o / "summary.csv") for o in out)
    assert a["alpha"][0] == b["alpha"][0] and a["alpha"][0] == pytest.approx(A / H)


# ============================================================= inputs, outputs, oracle
def test_json_strengths_top_body_joint_and_areas():
    d = box_spec(fc=50.0, cohesion=0.2)
    d["blocks"].append({"id": "C", "vertices": cuboid(-A / 2, -B / 2, H, A / 2, B / 2, 2 * H), "fc": 30.0})
    d["joints"] = [{"between": ["B", "C"], "ft": 0.1}]
    s = structure3d_from_spec(d)
    top = s.point_interface == s.iface_b.index("C")
    assert np.all(s.fc[~top] == 50) and np.all(s.fc[top] == 30) and np.all(s.cohesion == 0.2)
    assert np.all(s.ft[top] == 0.1) and np.all(s.ft[~top] == 0)
    assert np.allclose(s.areas(), A * B / 4)


@pytest.mark.parametrize("field, value, words", [
    ("fc", -1, "'fc'"), ("fc", 0, "'fc' is 0"), ("cohesion", "x", "'cohesion'"), ("ft", -0.5, "'ft'")])
def test_bad_values_name_the_field(field, value, words):
    with pytest.raises(InputError, match=words):
        structure3d_from_spec(box_spec(**{field: value}))


def test_bad_values_on_the_command_line(tmp_path, capsys):
    f = tmp_path / "box.json"
    f.write_text(json.dumps(box_spec(fc=1.0, ft=2.0)))
    assert command("solve", [str(f), "--out", str(tmp_path / "o"), "--no-plot"]) == 2
    err = capsys.readouterr().err.strip()
    assert "ft" in err and "fc" in err and len(err.splitlines()) == 1
    with pytest.warns(UserWarning, match="fcc"):
        structure3d_from_spec(box_spec(fcc=3.0))


def test_contacts_csv_caps_and_the_oracle(tmp_path):
    """--fc on a 3D file: contacts.csv gains fc, ft, cohesion, area and the crushing
    mode; the oracle, rebuilding the caps from those columns, finds the state exact."""
    f = tmp_path / "box.json"
    f.write_text(json.dumps(box_spec()))
    o = tmp_path / "o"
    assert command("solve", [str(f), "--out", str(o), "--no-plot", "--quiet", "--fc", "6"]) == 0
    c = pd.read_csv(o / "contacts.csv")
    assert {"fc", "ft", "cohesion", "area"} <= set(c.columns) and np.allclose(c["area"], A * B / 4)
    assert (c["mode"] == "crushing").sum() == 2
    weight = A * B * H   # unit weight 1: P_c = 6 < W = 8
    assert pd.read_csv(o / "summary.csv")["alpha"][0] == pytest.approx((2 * 6 - weight) * A / (weight * H), abs=1e-7)
    assert violations(o) == []
    c["fc"] = np.where(c["mode"] == "crushing", 0.9 * c["fc"], c["fc"])   # a cap the forces exceed: the oracle sees it
    c.to_csv(o / "contacts.csv", index=False)
    assert any(v.startswith("cone") for v in violations(o))


def test_the_3d_view_marks_the_points_on_their_caps(tmp_path):
    """The box with a grid:4 base, fc = 16 (W = 8): the two front rows of points carry the
    weight at their crushing caps and are marked, nothing else; the same box dry has no
    mark; held by tension, the back edge's two points sit on their tensile caps."""
    s = structure3d_from_spec(box_spec(fc=16.0, contact_points="grid:4"))
    r = solve(s)
    on = points_on_caps(s, r.state.N)
    front = s.point[:, 0] > A / 4     # the rows at x = 0.75 and x = 1 (the rocking edge)
    assert np.array_equal(on["crushing"], front) and not on["tension"].any()
    assert np.allclose(r.state.N[front], -16.0 * s.areas()[front]) and r.state.N[front].sum() == pytest.approx(-A * B * H)
    text = Path(write_view3d(s, tmp_path / "crush.html", motions=r.motions, normal=r.state.N)).read_text()
    assert f"at the crushing cap (N = -fc A): {front.sum()} points" in text and "tensile cap" not in text
    dry = structure3d_from_spec(box_spec(contact_points="grid:4"))
    r = solve(dry)
    assert not any(m.any() for m in points_on_caps(dry, r.state.N).values())
    text = Path(write_view3d(dry, tmp_path / "dry.html", motions=r.motions, normal=r.state.N)).read_text()
    assert "crushing cap" not in text and "tensile cap" not in text
    held = strong(box_on_ground(A, B, H, mu=5.0), ft=0.1, cohesion=0.5)
    r = solve(held)
    on = points_on_caps(held, r.state.N)
    assert np.array_equal(on["tension"], held.point[:, 0] < 0) and not on["crushing"].any()
    text = Path(write_view3d(held, tmp_path / "held.html", motions=r.motions, normal=r.state.N)).read_text()
    assert "at the tensile cap (N = ft A): 2 points" in text


def test_tributary_areas():
    rect = np.array([[-1, -0.5, 0], [1, -0.5, 0], [1, 0.5, 0], [-1, 0.5, 0.0]])
    assert np.allclose(point_areas([rect], [0] * 4, rect), 0.5)
    inner = np.array([[x, y, 0.0] for x in (-0.5, 0.5) for y in (-0.25, 0.25)])
    a = point_areas([rect], [0] * 8, np.vstack([rect, inner]))
    assert a.sum() == pytest.approx(2.0) and np.all(a[4:] > a[:4])
    hole = np.array([[-0.2, -0.1, 0], [0.2, -0.1, 0], [0.2, 0.1, 0], [-0.2, 0.1, 0.0]])
    assert point_areas([rect], [0] * 4, rect, [[hole]]).sum() == pytest.approx(2.0 - 0.08)


@pytest.mark.parametrize("shift", [(0, 0, 0), (1000, -500, 20), (0.37, 2.1, -3)])
@pytest.mark.parametrize("turn", [0.0, 33.0, 90.0])
def test_the_points_of_a_vertical_joint_share_its_area_wherever_it_stands(shift, turn):
    """The four corners of a 0.3 x 0.5 vertical joint (cocircular: a degenerate Voronoi
    diagram) take a quarter each, and a 3 x 3 grid's areas add up to the joint's, wherever
    the joint stands and however it is turned (one corner took three quarters, the sum
    was 0.225, by where the joint lay)."""
    c, s = np.cos(np.radians(turn)), np.sin(np.radians(turn))
    corners = np.array([[1, 0, 0], [1, 0.3, 0], [1, 0.3, 0.5], [1, 0, 0.5]], float)
    turned = corners @ np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]]) + np.array(shift, float)
    assert np.allclose(point_areas([turned], [0] * 4, turned), 0.0375, rtol=1e-9)
    u, v = turned[1] - turned[0], turned[3] - turned[0]
    grid = np.array([turned[0] + a * u + b * v for a in (0.0, 0.5, 1.0) for b in (0.0, 0.5, 1.0)])
    areas = point_areas([turned], [0] * 9, grid)
    assert areas.sum() == pytest.approx(0.15, rel=1e-9) and np.allclose(areas[4], 0.0375)


def test_grid_points_converge_to_the_stress_block():
    """The box with a grid:n base (fc = 16, W = 8): alpha tends to the planar stress
    block's (A / 2 - W / (2 fc B)) / (H / 2) = 0.375 as n grows (the docs' table)."""
    exact = (A / 2 - A * B * H / (2 * 16.0 * B)) / (H / 2)
    errors = []
    for n in (4, 8, 16):
        s = structure3d_from_spec(box_spec(fc=16.0, contact_points=f"grid:{n}"))
        r = solve(s)
        assert r.state is not None
        errors.append(abs(r.alpha - exact) / exact)
    assert errors[0] > errors[1] > errors[2] and errors[2] < 1e-3


def test_turned_mirrored_renumbered_give_the_same_alpha():
    """The crushing stack of three boxes turned, mirrored and its blocks and points
    renumbered: the same alpha (uniform strengths, so each point keeps its own)."""
    s = stack_of_boxes(3, 1.0, 1.0, 0.8, mu=5.0)
    base = solve(strong(s, fc=5.0)).alpha
    c, t = np.cos(0.7), np.sin(0.7)
    turn = np.array([[c, -t, 0], [t, c, 0], [0, 0, 1.0]])
    mirror = np.diag([-1.0, 1.0, 1.0])
    rng = np.random.default_rng(3)
    for R in (turn, mirror @ turn):
        moved = transformed(s, R, block_order=rng.permutation(s.n_blocks), point_order=rng.permutation(s.n_points))
        assert solve(strong(moved, fc=5.0)).alpha == pytest.approx(base, rel=1e-7)


def _pyomo_alpha(s, r):
    """The Pyomo model in space at the search's state: its largest constraint breach and
    its gap alpha_K - alpha; then Ipopt from there with alpha perturbed: alpha and the
    statics' largest breach of the caps and of the cone."""
    from pyomo.environ import Constraint, SolverFactory, value
    from lamodel.formulation.model3d import create_model3d, get_state3d, set_state3d
    m = create_model3d(s)
    set_state3d(m, r.state)
    at_state = max(max(-c.lslack(), -c.uslack(), 0.0) for c in m.component_data_objects(Constraint, active=True))
    gap = value(m.complementarity.body)
    m.alpha.set_value(r.alpha * 1.1 + 0.01)     # start away from the answer
    res = SolverFactory("lamodel_ipopt").solve(m)
    assert str(res.solver.termination_condition) in ("optimal", "locallyOptimal")
    N, T1, T2, alpha, _ = get_state3d(m)
    crush, tension, k = s.caps()
    breach = max((crush - N).max(), (N - tension).max(), (np.hypot(T1, T2) - (k - s.mu * N)).max())
    return at_state, gap, value(m.alpha), breach


@pytest.mark.skipif(not __import__("lamodel.solvers.bridge", fromlist=["x"]).ipopt_available(),
                    reason="cyipopt not installed")
@pytest.mark.parametrize("case", ["crushing", "cohesion", "tension"])
def test_the_pyomo_model_in_space_takes_strengths(case):
    """The Pyomo model of eq. (5) with the caps and the cohesion gives the closed forms
    (polished by Ipopt from a perturbed start): the same model as the search's."""
    mu = 0.3
    if case == "crushing":
        s, exact = strong(box_on_ground(A, B, H, mu=1.0), fc=0.8), rocking(0.8)
    elif case == "cohesion":
        s, exact = strong(box_on_ground(A, B, 0.2, mu=mu), cohesion=0.1), (mu * W + 0.1 * A * B) / W
    else:
        s, exact = strong(box_on_ground(A, B, H, mu=1.0), ft=0.05, cohesion=0.05), rocking(ft=0.05)
    r = solve(s)
    assert r.alpha == pytest.approx(exact, abs=1e-7)
    at_state, gap, alpha, breach = _pyomo_alpha(s, r)
    assert at_state < 1e-9 and abs(gap) < 1e-9  # the search's state is a zero-gap point of the model
    # Ipopt on the squared cones: the slips are as accurate as the square root of its
    # tolerance (a slip of 1e-4 breaches s1^2 + s2^2 <= sigma^2 by 1e-8)
    assert alpha == pytest.approx(exact, abs=1e-4)
    assert breach < 1e-6


def test_a_tension_state_passes_the_oracle(tmp_path):
    """--ft with the cohesion mu ft on the box file (W = 8): the back points open at their
    tensile caps, alpha = (W + 2 P_t) a / (W h), and the oracle finds the state exact."""
    f = tmp_path / "box.json"
    f.write_text(json.dumps(box_spec()))
    o = tmp_path / "o"
    assert command("solve", [str(f), "--out", str(o), "--no-plot", "--quiet", "--ft", "0.1", "--cohesion", "0.5"]) == 0
    weight, Pt = A * B * H, 0.1 * A * B / 2
    assert pd.read_csv(o / "summary.csv")["alpha"][0] == pytest.approx((weight + 2 * Pt) * A / (weight * H), abs=1e-7)
    c = pd.read_csv(o / "contacts.csv")
    opening = c["mode"] == "opening"
    assert opening.sum() == 2 and np.allclose(c["N"][opening], 0.1 * A * B / 4)
    assert violations(o) == []


def test_tension_at_the_cone_s_apex_passes_the_oracle(tmp_path):
    """--ft 0.1 --cohesion 0.05 on the box file (mu 5): the apex c0 A / mu is below f_t A;
    the back points open there and the oracle, rebuilding the caps from the CSV columns,
    finds the state exact."""
    f = tmp_path / "box.json"
    f.write_text(json.dumps(box_spec()))
    o = tmp_path / "o"
    assert command("solve", [str(f), "--out", str(o), "--no-plot", "--quiet", "--ft", "0.1", "--cohesion", "0.05"]) == 0
    weight, Pt = A * B * H, 2 * 0.05 / 5.0 * A * B / 4
    assert pd.read_csv(o / "summary.csv")["alpha"][0] == pytest.approx((weight + 2 * Pt) * A / (weight * H), abs=1e-7)
    assert violations(o) == []

