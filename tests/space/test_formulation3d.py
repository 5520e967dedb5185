"""Eq. 1-2 in space and the residual test of certification."""
import numpy as np

from builders3d import box_on_ground
from conftest import INSTANCES
from lamodel.formulation.extrude import extrude
from lamodel.formulation.matrices import equilibrium_matrix as planar_matrix
from lamodel.formulation.space import Formulation3D, equilibrium_matrix
from lamodel.io import read
from lamodel.search.certify3d import passes, residuals
from lamodel.search.search3d import solve3d


def test_strains_are_the_relative_motion_of_b_at_the_point():
    s = box_on_ground(2.0, 1.0, 1.0)
    f = Formulation3D.of(s)
    n = s.n_points
    up = np.array([0, 0, 1.0, 0, 0, 0])       # the block (body b) lifts: every point opens by 1
    q = f.strains(up)
    assert np.allclose(q[:n], 1.0) and np.allclose(q[n:], 0.0)
    turn = np.array([0, 0, 0, 0, 0, 1.0])     # a turn about the vertical axis through the centroid
    q = f.strains(turn)
    slip = np.column_stack([q[n:2 * n], q[2 * n:]])
    assert np.allclose(q[:n], 0.0)
    assert np.allclose(np.linalg.norm(slip, axis=1), np.hypot(1.0, 0.5))  # |omega x r| at the corners
    # the slip is the motion omega x r expressed in (t1, t2)
    r = s.point - s.centroid[0]
    v = np.cross([0, 0, 1.0], r)
    assert np.allclose(slip[:, 0], (v * s.tangent1).sum(1)) and np.allclose(slip[:, 1], (v * s.tangent2).sum(1))


def test_extruded_points_carry_the_planar_contact_forces():
    # a planar (N, V, M) spread over the contact's four points gives the planar block resultants
    s2 = read(INSTANCES / "wall33.dat")
    s3 = extrude(s2, depth=1.0)
    rng = np.random.default_rng(1)
    nc = s2.n_contacts
    N = -rng.uniform(1, 2, nc)
    V = rng.uniform(-0.5, 0.5, nc)
    M = rng.uniform(-0.5, 0.5, nc) * -N * s2.d
    ends = [(N - M / s2.d) / 2, (N + M / s2.d) / 2]   # end 1 at centre + d t, end 2 at centre - d t
    Np = np.column_stack([ends[0] / 2, ends[0] / 2, ends[1] / 2, ends[1] / 2]).ravel()
    t3 = np.repeat(np.column_stack([-s2.normal[:, 1], np.zeros(nc), s2.normal[:, 0]]), 4, axis=0)
    Tp = np.repeat(V / 4, 4)[:, None] * t3
    s_f = np.concatenate([Np, (Tp * s3.tangent1).sum(1), (Tp * s3.tangent2).sum(1)])
    r3 = (equilibrium_matrix(s3) @ s_f).reshape(-1, 6)
    r2 = (planar_matrix(s2) @ np.concatenate([N, V, M])).reshape(-1, 3)
    assert np.allclose(r3[:, [0, 2]], r2[:, :2]) and np.allclose(r3[:, 4], -r2[:, 2])
    assert np.allclose(r3[:, [1, 3, 5]], 0.0)


def test_residual_test_rejects_a_twisted_or_non_collapse_state():
    s = box_on_ground(2.0, 2.0, 0.2, 0.6, (1.0, 0.0, 0.0))
    r = solve3d(s)
    st = r.state
    f = Formulation3D.of(s)
    assert passes(residuals(f, st.N, st.T1, st.T2, st.alpha, st.u, st.q))
    # the friction force of one sliding point (the one carrying most: the statics' vertex may
    # leave some points without force) turned away from its slip (still on the cone)
    c, si = np.cos(0.01), np.sin(0.01)
    T1, T2 = st.T1.copy(), st.T2.copy()
    k = int(np.argmax(np.hypot(st.T1, st.T2)))
    T1[k], T2[k] = c * st.T1[k] - si * st.T2[k], si * st.T1[k] + c * st.T2[k]
    res = residuals(f, st.N, T1, T2, st.alpha, st.u, st.q)
    assert res["slip_alignment"] > 1e-5 and not passes(res)
    # a lower alpha with the same forces: equilibrium and alpha = alpha_K fail
    res = residuals(f, st.N, st.T1, st.T2, st.alpha * 0.9, st.u, st.q)
    assert res["equilibrium"] > 1e-3 and res["virtual_work"] > 1e-3
    # a block that lifts everywhere while its points are compressed: opening where N < 0
    up = np.array([0, 0, 1.0, 0, 0, 0]) / 1.0
    res = residuals(f, st.N, st.T1, st.T2, st.alpha, up, f.strains(up))
    assert res["opening_complementarity"] > 1e-3



def _pyramid_associative(s, facets, circumscribed):
    """max alpha over S with every cone replaced by a pyramid of ``facets`` facets
    (generator form, HiGHS through scipy)."""
    import scipy.sparse as sp
    from scipy.optimize import linprog
    f = Formulation3D.of(s)
    n = s.n_points
    radius = 1.0 / np.cos(np.pi / facets) if circumscribed else 1.0
    th = 2 * np.pi * np.arange(facets) / facets
    p = np.repeat(np.arange(n), facets)
    g = np.tile(th, n)
    m = p.size
    cols = np.arange(m)
    Tg = sp.csr_matrix((np.concatenate([-np.ones(m), s.mu[p] * radius * np.cos(g), s.mu[p] * radius * np.sin(g)]),
                        (np.concatenate([p, n + p, 2 * n + p]), np.concatenate([cols, cols, cols]))), shape=(3 * n, m))
    E = sp.hstack([f.A @ Tg, sp.csr_matrix(f.fbar.reshape(-1, 1))]).tocsc()
    cost = np.zeros(m + 1)
    cost[-1] = -1.0
    res = linprog(cost, A_eq=E, b_eq=-f.f0, bounds=(0, None), method="highs")
    return res.x[-1]


def test_pyramids_of_16_facets_bracket_the_cone():
    # the associative bound of a block on 4 corners twisted and pushed at once
    s = box_on_ground(1.0, 0.7, 1.5, 0.6, (0.3, 0.2, 0.0), live_m=(0.0, 0.0, 0.4))
    cone = solve3d(s, method="gap", explore=False).associative
    inner = _pyramid_associative(s, 16, circumscribed=False)
    outer = _pyramid_associative(s, 16, circumscribed=True)
    assert inner <= cone + 1e-7 <= outer + 2e-7
    assert outer / inner - 1 < 0.02 + 1e-9
