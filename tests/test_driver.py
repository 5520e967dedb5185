"""Certification, the GA, the driver and solve.py's output contract."""
import numpy as np
import pandas as pd
import pytest

from lamodel.output.modes import modes_from_flow
from lamodel.search.certify import certify, certify_flow, descend, residuals
from lamodel.search.driver import SolveOptions, solve
from lamodel.search.ga import genetic_search
from lamodel.geometry import running_bond_wall
from lamodel.io.jsonspec import structure_from_json
from lamodel.search.lp import LimitLPs

from conftest import INSTANCES, run_script, stack_spec


def small_wall():
    """A 3-course running-bond wall (8 blocks): quick, yet with sliding and hinging."""
    return structure_from_json(running_bond_wall([[0.5, 1, 1, 0.5], [1, 1, 1], [0.5, 1, 1, 0.5]], name="wall8"))


def check_collapse_state_from_csv(folder, tol=1e-7):
    """An external checker's view: rebuild the statics and the mechanism from the CSVs only."""
    summary = pd.read_csv(folder / "summary.csv")
    blocks = pd.read_csv(folder / "blocks.csv").set_index("block")
    contacts = pd.read_csv(folder / "contacts.csv")
    alpha = float(summary.alpha[0])
    # equilibrium, block by block, moments about the origin
    res = {b: np.array([r.dead_x + alpha * r.live_x, r.dead_y + alpha * r.live_y,
                        r.x * (r.dead_y + alpha * r.live_y) - r.y * (r.dead_x + alpha * r.live_x)])
           for b, r in blocks.iterrows()}
    scale = max(np.abs(blocks[["dead_x", "dead_y", "live_x", "live_y"]].values).max(), 1.0)
    for c in contacts.itertuples():
        n, t = np.array([c.nx, c.ny]), np.array([-c.ny, c.nx])
        F = c.N * n + c.V * t
        w = np.array([F[0], F[1], c.cx * F[1] - c.cy * F[0] + c.M])
        if c.block_a in res:
            res[c.block_a] += w
        if c.block_b in res:
            res[c.block_b] -= w
        # yield: compression, Coulomb, eccentricity
        assert c.N <= tol * scale
        assert abs(c.V) <= -c.mu * c.N + tol * scale
        assert abs(c.M) <= -c.d * c.N + tol * scale
    assert max(np.abs(r).max() for r in res.values()) <= tol * scale
    # the mechanism: normalised, no interpenetration, flow only where the yield row is active
    assert (blocks.live_x * blocks.ux + blocks.live_y * blocks.uy).sum() == pytest.approx(1.0, abs=1e-9)
    U = max(np.abs(blocks[["ux", "uy", "theta"]].values).max(), 1e-12)
    work = 0.0
    for c in contacts.itertuples():
        def disp(b):
            if b not in blocks.index:
                return np.zeros(2), 0.0
            r = blocks.loc[b]
            return np.array([r.ux - r.theta * (c.cy - r.y), r.uy + r.theta * (c.cx - r.x)]), r.theta
        (da, ta), (db, tb) = disp(c.block_a), disp(c.block_b)
        n, t = np.array([c.nx, c.ny]), np.array([-c.ny, c.nx])
        opening, slip, turn = (db - da) @ n, (db - da) @ t, tb - ta
        assert opening >= c.d * abs(turn) - tol * U  # no interpenetration at either edge
        if abs(slip) > tol * U:  # sliding: the shear is at the friction limit, against the slip
            assert abs(c.V) == pytest.approx(-c.mu * c.N, abs=tol * scale)
            assert np.sign(c.V) == np.sign(slip) or abs(c.V) < tol * scale
        if abs(turn) > tol * U:  # hinging: the normal force at the pivot edge
            assert abs(c.M) == pytest.approx(-c.d * c.N, abs=tol * scale)
        work += c.N * opening + c.V * slip + c.M * turn
    # virtual work: alpha fbar.u + f0.u = s.q
    dead_work = (blocks.dead_x * blocks.ux + blocks.dead_y * blocks.uy).sum()
    assert alpha + dead_work == pytest.approx(work, abs=1e-7)
    return alpha


def test_certified_lp_state_passes_an_independent_residual_check():
    s = small_wall()
    lps = LimitLPs(s)
    assoc = lps.associative()
    res, u, xi = lps.cohesive(-s.mu * lps.split(assoc.x)[0])
    state = certify_flow(lps, u, xi)
    assert state is not None
    assert max(state.residual.values()) < 1e-8
    assert state.alpha <= assoc.alpha + 1e-9


def test_perturbed_point_is_rejected(wall33):
    lps = LimitLPs(wall33)
    o = solve(wall33, SolveOptions(starts=0, pop_size=6, generations=2))
    best = o.best
    # a mechanism broken by a slip on one closed contact is no mechanism at all
    xi = best.xi.copy()
    closed = [k for k, m in enumerate(modes_from_flow(wall33, best.xi)) if m == "closed"]
    xi[closed[0]] += 0.05
    assert certify_flow(lps, best.u, xi) is None
    # forces pushed off their yield rows and a mechanism pushed off the flow rule: rejected
    rng = np.random.default_rng(0)
    assert certify(lps, best.N * (1 + 0.3 * rng.random(best.N.size)), best.V * 0.5, best.M * 0.5,
                   best.alpha, best.u + 0.1 * rng.normal(size=best.u.size), xi,
                   tolerances=(1e-9,)) is None


def test_descend_never_increases_alpha(wall33):
    lps = LimitLPs(wall33)
    assoc = lps.associative()
    res, u, xi = lps.cohesive(-wall33.mu * lps.split(assoc.x)[0])
    state = certify_flow(lps, u, xi)
    better = descend(lps, state)
    assert better.alpha <= state.alpha + 1e-12
    r = residuals(lps, better.N, better.V, better.M, better.alpha, better.u, better.xi)
    assert max(r.values()) < 1e-7


def test_ga_is_deterministic_and_minimises():
    target = np.linspace(0.2, 1.8, 7)

    def sphere(g):
        return float(((g - target) ** 2).sum())

    a = genetic_search(sphere, 7, pop_size=20, generations=30, seed=5)
    b = genetic_search(sphere, 7, pop_size=20, generations=30, seed=5)
    c = genetic_search(sphere, 7, pop_size=20, generations=30, seed=6)
    assert np.array_equal(a[0], b[0]) and a[1] == b[1]
    assert not np.array_equal(a[0], c[0])
    assert a[1] < 0.05  # far below a random genome (~1.5 on average)


def test_same_seed_same_alpha_and_tables():
    s = small_wall()
    a = solve(s, SolveOptions(starts=0, seed=3))
    b = solve(s, SolveOptions(starts=0, seed=3))
    assert a.best.alpha == b.best.alpha
    assert np.array_equal(a.best.u, b.best.u) and np.array_equal(a.best.N, b.best.N)


def test_wall33_reaches_ferris_and_tin_loi(wall33):
    o = solve(wall33, SolveOptions(starts=0))
    assert o.certified
    assert o.best.alpha <= 0.63900  # Ferris & Tin-Loi 0.63898; the seed 0.63911
    assert o.best.alpha <= o.alpha_associative


def test_ipopt_start_is_certified():
    s = structure_from_json(stack_spec(n=3, width=1.0, height=1.0))
    o = solve(s, SolveOptions(starts=1, workers=1))
    assert o.certified and o.best.alpha == pytest.approx(1 / 3, abs=1e-9)
    ipopt = [r for r in o.runs if r.source.startswith("ipopt")]
    assert len(ipopt) == 1 and ipopt[0].alpha_certified == pytest.approx(1 / 3, abs=1e-9)


def test_solve_script_output_contract(tmp_path):
    out = tmp_path / "res"
    p = run_script("solve.py", INSTANCES / "wall33.dat", "--out", out, "--starts", "1", "--quiet")
    assert p.returncode == 0, p.stderr
    summary = pd.read_csv(out / "summary.csv")
    assert list(summary.columns[:9]) == ["instance", "alpha", "certified", "alpha_associative", "n_blocks",
                                         "n_contacts", "n_starts", "n_certified", "wall_time_s"]
    assert bool(summary.certified[0]) and summary.n_blocks[0] == 33 and summary.n_contacts[0] == 83
    assert list(pd.read_csv(out / "blocks.csv").columns) == ["block", "x", "y", "dead_x", "dead_y", "live_x",
                                                             "live_y", "ux", "uy", "theta"]
    contacts = pd.read_csv(out / "contacts.csv")
    assert list(contacts.columns) == ["contact", "block_a", "block_b", "cx", "cy", "nx", "ny", "d", "mu", "N", "V",
                                      "M", "mode"]
    assert set(contacts["mode"]) <= {"closed", "sliding", "hinging", "sliding+hinging", "open"}
    runs = pd.read_csv(out / "runs.csv")
    assert list(runs.columns) == ["start", "source", "alpha_ipopt", "status", "alpha_certified", "iterations",
                                  "seconds"]
    assert len(runs) == summary.n_starts[0]
    alpha = check_collapse_state_from_csv(out)
    assert alpha == pytest.approx(summary.alpha[0]) and alpha <= 0.63900
    assert (out / "mechanism.png").stat().st_size > 0
    assert "alpha = 0.6389" in p.stdout


def test_exit_codes(tmp_path):
    assert run_script("solve.py", tmp_path / "missing.dat").returncode == 2
    bad = tmp_path / "bad.dat"
    bad.write_text("set BLOCKS := ;\n")
    p = run_script("solve.py", bad, "--out", tmp_path / "o")
    assert p.returncode == 2 and "Traceback" not in p.stderr and len(p.stderr.strip().splitlines()) == 1
    # a block on a narrow ledge that overhangs: it cannot stand under its own weight
    spec = {"name": "ledge", "mu": 0.6, "blocks": [
        {"id": "ground", "vertices": [[-1, -1], [0.2, -1], [0.2, 0], [-1, 0]], "support": True},
        {"id": "b1", "vertices": [[0, 0], [2, 0], [2, 1], [0, 1]]}]}
    import json
    path = tmp_path / "ledge.json"
    path.write_text(json.dumps(spec))
    p = run_script("solve.py", path, "--out", tmp_path / "o2", "--quiet")
    assert p.returncode == 3 and "unstable under dead load" in p.stdout


@pytest.mark.parametrize("name", ["wall33", "wall55", "arch", "portal", "portal_columns"])
def test_every_instance_certifies_from_dat_and_json_alike(name):
    from lamodel.io.datfile import read_dat
    a = solve(read_dat(INSTANCES / f"{name}.dat"), SolveOptions(starts=0))
    b = solve(structure_from_json(INSTANCES / f"{name}.json"), SolveOptions(starts=0))
    assert a.certified and b.certified
    assert a.best.alpha == pytest.approx(b.best.alpha, abs=1e-9)
    assert a.best.alpha <= a.alpha_associative + 1e-9
