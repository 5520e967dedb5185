"""The independent oracle: is this a collapse state? Rebuilt from plain numbers, no lamodel.

Every test that checks a state uses this one module. It reads the output contract's
tables (blocks: x, y, dead_x, dead_y, live_x, live_y, ux, uy, theta, and when present
dead_m, live_m — the moments of the loads about the centroid; contacts: block_a,
block_b, cx, cy, nx, ny, d, mu, N, V, M, mode) and checks with plain loops, in the README's
conventions (n from block_a to block_b, t = (-n_y, n_x); N n + V t at the contact centre
and the couple M act on block_a, their opposites on block_b; N <= 0 is compression;
u = (ux, uy, theta) at the block centroid):

* statics: equilibrium of every block (eq. 1), no tension, Coulomb, eccentricity (eq. 4);
* kinematics: sum(live . u) = 1, no interpenetration at either end of a joint;
* complementarity: a sliding joint has its shear at the friction limit, opposing the
  relative slip of block a; a hinging joint has N at its pivot edge; an open joint carries
  nothing; a 'closed' joint does not move;
* virtual work: alpha + dead . u = sum over the contacts of N opening + V slip + M turn
  (the seed's alpha = alpha_K, eq. 5).

Joints with strengths (contacts.csv columns fc, ft, cohesion, thickness b; absent: a dry
joint, infinitely strong) are checked against the rectangular stress block itself, not
against lamodel's polygon: -2 d b fc <= N <= 2 d b ft, |M| at most the moment of the
stress blocks at that N, |V| <= cohesion 2 d b - mu N; a crushing joint may overlap; a
moving joint's N opening + M turn is the stress block's dissipation
b * integral(ft delta+ + fc delta-) over the joint (delta: the local opening) for an
infinite fc, and for a finite one at least that of the stress block whose moments are
shrunk by ``eps`` (lamodel's inscribed polygon, within its stated bound) and at most that.

Tolerances are relative to the structure's own force, length and displacement scales, so
the check means the same in any units.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd


def stress_block_moment(N, d, b, fc, ft):
    """The largest |M| of stresses in [-fc, ft] on a joint of half-length d, thickness b,
    with resultant N (None outside [-2 d b fc, 2 d b ft]): compression fc over a depth
    y_c at one end, tension ft over the rest, N = b (ft (2d - y_c) - fc y_c)."""
    if N > 2 * d * b * ft * (1 + 1e-12) + 1e-300 or (math.isfinite(fc) and N < -2 * d * b * fc * (1 + 1e-12)):
        return None
    if not math.isfinite(fc):  # all the compression at the edge, tension over the joint
        return d * (2 * d * b * ft - N)
    y_c = min(max((2 * d * b * ft - N) / (b * (fc + ft)), 0.0), 2 * d)
    C, T = fc * b * y_c, ft * b * (2 * d - y_c)  # the two blocks, about the joint's centre
    return C * (d - y_c / 2) + T * (d - (2 * d - y_c) / 2)


def stress_block_work(opening, turn, d, b, fc, ft):
    """The stress block's dissipation b * integral over [-d, d] of (ft delta+ + fc delta-),
    delta = opening + turn x (inf where an infinitely strong joint overlaps)."""
    x = np.linspace(-d, d, 20001)
    delta = opening + turn * x
    if not math.isfinite(fc):
        return b * ft * 2 * d * opening if delta.min() >= -1e-12 * max(abs(opening), abs(turn) * d, 1e-300) \
            else math.inf
    return float(b * np.trapezoid(ft * np.maximum(delta, 0) + fc * np.maximum(-delta, 0), x))


def shrunk_work(opening, turn, d, b, fc, ft, eps):
    """A lower bound of max N opening + M turn over the stress block's domain with every
    moment shrunk by eps (the domain lamodel's polygon contains): the max over a grid of N."""
    Ns = np.linspace(-2 * d * b * fc, 2 * d * b * ft, 4001)
    Ms = np.array([stress_block_moment(N, d, b, fc, ft) or 0.0 for N in Ns])
    return float(np.max(Ns * opening + (1 - eps) * Ms * abs(turn)))


def _strengths(c):
    """(fc, ft, cohesion, b) of a contacts row; a dry joint without the columns."""
    get = lambda name, default: float(getattr(c, name, default))  # noqa: E731
    fc, ft, c0, b = get("fc", math.inf), get("ft", 0.0), get("cohesion", 0.0), get("thickness", 1.0)
    return (fc if not math.isnan(fc) else math.inf), ft, c0, b


def check_collapse_state(blocks: pd.DataFrame, contacts: pd.DataFrame, alpha: float, tol: float = 1e-7,
                         eps: float = 0.0097):
    """Assert every condition of a collapse state (AssertionError naming the contact or block).
    ``eps``: how much lamodel's inscribed polygon may shrink a crushing joint's moments
    (its stated bound, 0.96%)."""
    B = {r.block: r for r in blocks.itertuples(index=False)}
    pts = [(r.x, r.y) for r in B.values()] + [(c.cx, c.cy) for c in contacts.itertuples(index=False)]
    L = float(np.ptp(np.array(pts), axis=0).max()) or 1.0
    F = float(np.abs(blocks[["dead_x", "dead_y", "live_x", "live_y"]].to_numpy()).max()) or 1.0
    U = max(1e-300, float(max(np.abs(blocks[["ux", "uy"]].to_numpy()).max(), np.abs(blocks.theta).max() * L)))
    assert math.isfinite(alpha) and alpha >= -tol, ("alpha", alpha)

    # statics: equilibrium of every block (moments about its own centroid) and yield
    dm = {r.block: getattr(r, "dead_m", 0.0) for r in B.values()}   # load moments about the centroid
    lm = {r.block: getattr(r, "live_m", 0.0) for r in B.values()}
    res = {b: np.array([r.dead_x + alpha * r.live_x, r.dead_y + alpha * r.live_y, dm[b] + alpha * lm[b]])
           for b, r in B.items()}
    for c in contacts.itertuples(index=False):
        n, t = np.array([c.nx, c.ny]), np.array([-c.ny, c.nx])
        f = c.N * n + c.V * t
        for body, sign in ((c.block_a, 1.0), (c.block_b, -1.0)):
            if body in B:
                r = np.array([c.cx - B[body].x, c.cy - B[body].y])
                res[body] += sign * np.array([f[0], f[1], r[0] * f[1] - r[1] * f[0] + c.M])
        fc, ft, c0, b = _strengths(c)
        area = 2 * c.d * b
        assert c.N <= area * ft + tol * F, (c.contact, "tension", c.N)
        assert c.N >= -area * fc - tol * F, (c.contact, "crushing", c.N)
        assert abs(c.V) <= c0 * area - c.mu * c.N + tol * F, (c.contact, "Coulomb", c.V, c.N)
        cap = stress_block_moment(min(max(c.N, -area * fc), area * ft), c.d, b, fc, ft)
        assert abs(c.M) <= cap + tol * F * L, (c.contact, "eccentricity", c.M, c.N)
    for b, r in res.items():
        assert np.abs(r[:2]).max() <= tol * F and abs(r[2]) <= tol * F * L, (b, "equilibrium", r)

    # kinematics: normalisation, no interpenetration, flow only on active yield rows
    norm = sum(r.live_x * r.ux + r.live_y * r.uy + lm[b] * r.theta for b, r in B.items())
    assert abs(norm - 1.0) <= 1e-9 * max(1.0, F * U), ("normalisation", norm)

    def motion(body, x, y):
        if body not in B:  # a support
            return np.zeros(2), 0.0
        r = B[body]
        return np.array([r.ux - r.theta * (y - r.y), r.uy + r.theta * (x - r.x)]), r.theta

    internal = 0.0
    for c in contacts.itertuples(index=False):
        (ua, ta), (ub, tb) = motion(c.block_a, c.cx, c.cy), motion(c.block_b, c.cx, c.cy)
        n, t = np.array([c.nx, c.ny]), np.array([-c.ny, c.nx])
        opening, slip, turn = (ub - ua) @ n, (ub - ua) @ t, tb - ta
        fc, ft, c0, b = _strengths(c)
        area = 2 * c.d * b
        if not math.isfinite(fc):  # an infinitely strong joint never overlaps
            assert opening >= c.d * abs(turn) - tol * U, (c.contact, "interpenetration", opening, turn)
        if abs(slip) > tol * U:  # sliding: shear at the friction limit, dragging a along the slip
            assert abs(abs(c.V) + c.mu * c.N - c0 * area) <= tol * F, (c.contact, "slip off the limit", c.V, c.N)
            assert c.V * slip >= -tol * F * U, (c.contact, "friction with the slip")
        work = c.N * opening + c.M * turn
        if not math.isfinite(fc):
            if c.d * abs(turn) > tol * U:  # hinging: the normal force at the pivot edge
                cap = stress_block_moment(c.N, c.d, b, fc, ft) or 0.0
                assert abs(abs(c.M) - cap) <= tol * F * L, (c.contact, "hinge off the limit", c.M, c.N)
            if opening > c.d * abs(turn) + tol * U:  # separating: the joint's tension, nothing else
                assert abs(c.N - area * ft) <= tol * F and abs(c.M) <= tol * F * L, (c.contact, "open joint")
                if ft == 0 and c0 == 0:
                    assert abs(c.V) <= tol * F, (c.contact, "open joint")
            # opening and hinging dissipate the tension's work only (dry: nothing)
            assert abs(work - area * ft * opening) <= 10 * tol * F * U, (c.contact, "hinge work")
        elif max(abs(opening), c.d * abs(turn)) > tol * U:  # crushing or opening: the stress block's work
            most = stress_block_work(opening, turn, c.d, b, fc, ft)
            least = shrunk_work(opening, turn, c.d, b, fc, ft, eps)
            assert least - 10 * tol * F * U <= work <= most + 10 * tol * F * U, \
                (c.contact, "joint work", work, least, most)
        if "mode" in contacts.columns and c.mode == "closed":
            assert max(abs(opening), abs(slip), c.d * abs(turn)) <= 1e-6 * U, (c.contact, "moves")
        internal += c.N * opening + c.V * slip + c.M * turn

    # virtual work: alpha fbar.u + f0.u = sum over the contacts of N opening + V slip + M turn
    dead = sum(r.dead_x * r.ux + r.dead_y * r.uy + dm[b] * r.theta for b, r in B.items())
    assert abs(alpha + dead - internal) <= 1e-7 * max(1.0, abs(alpha), abs(dead)) * max(1, len(contacts)) ** 0.5, \
        ("virtual work", alpha + dead, internal)
    return alpha


def check_folder(folder) -> float:
    """An external checker's view: rebuild the statics and the mechanism from the CSVs only.
    Returns the certified alpha."""
    folder = Path(folder)
    summary = pd.read_csv(folder / "summary.csv")
    assert bool(summary.certified[0]), "summary.csv says not certified"
    return check_collapse_state(pd.read_csv(folder / "blocks.csv"), pd.read_csv(folder / "contacts.csv"),
                                float(summary.alpha[0]))


def check_state(structure, state, tol: float = 1e-7) -> float:
    """The same check for a state in memory (``lamodel``'s array layout) of a Structure."""
    s = structure
    u = np.asarray(state.u, dtype=float).reshape(-1, 3)
    blocks = pd.DataFrame({"block": s.blocks, "x": s.centroid[:, 0], "y": s.centroid[:, 1],
                           "dead_x": s.dead[:, 0], "dead_y": s.dead[:, 1], "live_x": s.live[:, 0],
                           "live_y": s.live[:, 1], "ux": u[:, 0], "uy": u[:, 1], "theta": u[:, 2],
                           "dead_m": s.dead_m, "live_m": s.live_m})
    contacts = pd.DataFrame({"contact": s.contacts, "block_a": s.block_a, "block_b": s.block_b,
                             "cx": s.centre[:, 0], "cy": s.centre[:, 1], "nx": s.normal[:, 0], "ny": s.normal[:, 1],
                             "d": s.d, "mu": s.mu, "N": state.N, "V": state.V, "M": state.M})
    for name in ("fc", "ft", "cohesion", "thickness"):  # the joints' strengths, where the structure has them
        if getattr(s, name, None) is not None:
            contacts[name] = getattr(s, name)
    return check_collapse_state(blocks, contacts, float(state.alpha), tol)


def equilibrium_residual(s, N, V, M, alpha) -> float:
    """Largest out-of-balance force or moment of the blocks of Structure s (plain loops,
    moments about the origin)."""
    res = {b: np.zeros(3) for b in s.blocks}
    for j, b in enumerate(s.blocks):
        g, f = s.centroid[j], s.dead[j] + alpha * s.live[j]
        res[b] += [f[0], f[1], g[0] * f[1] - g[1] * f[0] + s.dead_m[j] + alpha * s.live_m[j]]
    for k in range(s.n_contacts):
        n = s.normal[k]
        t = np.array([-n[1], n[0]])
        F = N[k] * n + V[k] * t
        c = s.centre[k]
        w = np.array([F[0], F[1], c[0] * F[1] - c[1] * F[0] + M[k]])
        if s.block_a[k] in res:
            res[s.block_a[k]] += w
        if s.block_b[k] in res:
            res[s.block_b[k]] -= w
    return max(np.abs(r).max() for r in res.values())
