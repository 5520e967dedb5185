"""An independent check of a 3D result folder, from its CSV files alone.

Plain loops over the rows of summary.csv, blocks.csv and contacts.csv; nothing of lamodel
is imported. For the alpha of summary.csv it rebuilds each block's six equilibrium rows
(forces and moments about the centroid: the dead and live loads and their moments, and at
every contact point ``N n + T1 t1 + T2 t2`` on block_a, its opposite on block_b), checks
that they balance, that every point's force lies in the Coulomb cone, and — from the block
motions — the mechanism: ``live . u = 1``, openings only where N = 0, slips only on the
cone with T along the slip, and the seed's eq. 5, ``alpha = alpha_K = -dead . u +
sum(-mu N |slip|)``.

With the joints' strengths (columns ``fc``, ``ft``, ``cohesion``, ``area``) each point's
caps are rebuilt from them: ``-fc area <= N <= N_t``, ``hypot(T1, T2) <= cohesion area
- mu N``, where ``N_t = min(ft area, cohesion area / mu)`` (the cone's apex bounds the
tension too); it opens only at ``N = N_t``, closes only at ``N = -fc area``, and eq. 5
gains ``N_t qn`` (opening), ``-fc area |qn|`` (closing) and ``(cohesion area - mu N)
|slip|``.

A folder without a certified state must say so: alpha, every force and every motion empty
(NaN), every mode ``unknown`` (:func:`uncertified`). summary.csv's ``live_load`` must be
empty or three numbers (:func:`live_load`), and :func:`live_load_gap` measures how far the
blocks' live loads are from ``live_load x unit_weight x volume``.
"""
import csv
import math


def _rows(path):
    with open(path, newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def _vec(row, names):
    return [float(row[n]) for n in names]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def check_folder(folder):
    """Violations (0 is exact) of each condition, each measured with one dimension:
    forces by the largest block load, moments and rotations by the structure's size,
    motions by the largest point motion. Also ``alpha`` (summary.csv) and ``alpha_fit``
    (the alpha that balances the rows best, by least squares)."""
    folder = str(folder)
    summary = _rows(folder + "/summary.csv")[0]
    alpha = float(summary["alpha"])
    blocks = _rows(folder + "/blocks.csv")
    contacts = _rows(folder + "/contacts.csv")
    index = {b["block"]: k for k, b in enumerate(blocks)}
    centroid = [_vec(b, ("x", "y", "z")) for b in blocks]
    pts = [_vec(c, ("x", "y", "z")) for c in contacts] + centroid
    size = math.sqrt(sum((max(p[k] for p in pts) - min(p[k] for p in pts)) ** 2 for k in range(3))) or 1.0
    fixed = [[0.0] * 6 for _ in blocks]   # dead loads and contact forces
    live = [[0.0] * 6 for _ in blocks]
    force_scale = 0.0
    for k, b in enumerate(blocks):
        dead = _vec(b, ("dead_x", "dead_y", "dead_z")) + [m / size for m in _vec(b, ("dead_mx", "dead_my", "dead_mz"))]
        lv = _vec(b, ("live_x", "live_y", "live_z")) + [m / size for m in _vec(b, ("live_mx", "live_my", "live_mz"))]
        for r in range(6):
            fixed[k][r] += dead[r]
            live[k][r] += lv[r]
        force_scale = max(force_scale, max(abs(v) for v in dead + lv))
    motion = [_vec(b, ("ux", "uy", "uz", "rx", "ry", "rz")) for b in blocks]

    def velocity(body, p):
        if body not in index:
            return [0.0, 0.0, 0.0]
        j = index[body]
        u = motion[j]
        w = _cross(u[3:], [p[i] - centroid[j][i] for i in range(3)])
        return [u[i] + w[i] for i in range(3)]

    cone = 0.0
    strains = []
    for c in contacts:
        p = _vec(c, ("x", "y", "z"))
        n, t1, t2 = _vec(c, ("nx", "ny", "nz")), _vec(c, ("t1x", "t1y", "t1z")), _vec(c, ("t2x", "t2y", "t2z"))
        N, T1, T2, mu = float(c["N"]), float(c["T1"]), float(c["T2"]), float(c["mu"])
        area = float(c.get("area") or 0.0)   # dry: no caps, no cohesion
        low = -float(c["fc"]) * area if c.get("fc") not in (None, "", "inf") else -math.inf
        high, k = float(c.get("ft") or 0.0) * area, float(c.get("cohesion") or 0.0) * area
        if mu > 0:   # the cone ends at its apex N = k / mu: no more tension than that
            high = min(high, k / mu)
        f = [N * n[i] + T1 * t1[i] + T2 * t2[i] for i in range(3)]
        for body, sign in ((c["block_a"], 1.0), (c["block_b"], -1.0)):
            if body in index:
                j = index[body]
                m = _cross([p[i] - centroid[j][i] for i in range(3)], f)
                for r in range(3):
                    fixed[j][r] += sign * f[r]
                    fixed[j][3 + r] += sign * m[r] / size
        cone = max(cone, math.hypot(T1, T2) + mu * N - k, N - high, low - N)
        d = [vb - va for vb, va in zip(velocity(c["block_b"], p), velocity(c["block_a"], p))]
        strains.append((N, T1, T2, mu, _dot(d, n), _dot(d, t1), _dot(d, t2), low, high, k))
    force_scale = force_scale or 1.0
    equilibrium = max(abs(fixed[k][r] + alpha * live[k][r]) for k in range(len(blocks)) for r in range(6))
    num = sum(fixed[k][r] * live[k][r] for k in range(len(blocks)) for r in range(6))
    den = sum(live[k][r] ** 2 for k in range(len(blocks)) for r in range(6))
    # the mechanism: normalisation, flow rule, virtual work (eq. 5)
    normalisation = sum(_dot(_vec(b, ("live_x", "live_y", "live_z")), motion[k][:3])
                        + _dot(_vec(b, ("live_mx", "live_my", "live_mz")), motion[k][3:]) for k, b in enumerate(blocks))
    scale_u = max([max(abs(v) for v in s[4:]) for s in strains] + [1e-300])
    alpha_k = -sum(_dot(_vec(b, ("dead_x", "dead_y", "dead_z")), motion[k][:3])
                   + _dot(_vec(b, ("dead_mx", "dead_my", "dead_mz")), motion[k][3:]) for k, b in enumerate(blocks))
    opening = flow = 0.0
    for N, T1, T2, mu, qn, s1, s2, low, high, k in strains:
        slip = math.hypot(s1, s2)
        alpha_k += max(k - mu * N, 0.0) * slip + high * max(qn, 0.0)
        if qn < 0 and low > -math.inf:   # a crushing point: on its cap, dissipating there
            alpha_k += low * qn
            opening = max(opening, min(abs(N - low) / force_scale, 1.0) * -qn / scale_u)
        else:
            opening = max(opening, -qn / scale_u)
        # opening off the tensile cap: the smaller of the motion and its work there
        opening = max(opening, min(abs(N - high) / force_scale, 1.0) * max(qn, 0.0) / scale_u)
        flow = max(flow, abs((k - mu * N) * slip - (T1 * s1 + T2 * s2)) / (force_scale * scale_u))
    return {"alpha": alpha, "alpha_fit": -num / den, "equilibrium": equilibrium / force_scale,
            "cone": max(cone, 0.0) / force_scale, "normalisation": abs(normalisation - 1.0),
            "opening": opening, "flow_rule": flow, "virtual_work": abs(alpha_k - alpha) / max(1.0, abs(alpha))}


def _number(cell):
    """A cell as a float; an empty cell is NaN (as the writer leaves nothing certified)."""
    return math.nan if cell.strip() == "" else float(cell)


def certified(folder):
    """summary.csv's ``certified``."""
    return _rows(str(folder) + "/summary.csv")[0]["certified"].strip().lower() == "true"


def uncertified(folder):
    """What a folder without a certified state writes that is not empty (NaN), as text:
    alpha, the forces of contacts.csv, the motions of blocks.csv; a mode other than
    ``unknown``."""
    folder = str(folder)
    bad = []
    if not math.isnan(_number(_rows(folder + "/summary.csv")[0]["alpha"])):
        bad.append("alpha is written without a certified state")
    for table, names in (("contacts", ("N", "T1", "T2")), ("blocks", ("ux", "uy", "uz", "rx", "ry", "rz"))):
        rows = _rows(f"{folder}/{table}.csv")
        known = sum(1 for r in rows for n in names if not math.isnan(_number(r[n])))
        if known:
            bad.append(f"{table}.csv: {known} values of {', '.join(names)} written without a certified state")
    modes = {c["mode"] for c in _rows(folder + "/contacts.csv")} - {"unknown"}
    if modes:
        bad.append(f"contacts.csv: modes {sorted(modes)} without a certified state")
    return bad


def live_load(folder):
    """summary.csv's ``live_load``: three floats, or None when empty; ValueError otherwise."""
    cell = _rows(str(folder) + "/summary.csv")[0]["live_load"].strip()
    if cell == "":
        return None
    parts = [float(v) for v in cell.split()]
    if len(parts) != 3 or not all(math.isfinite(v) for v in parts):
        raise ValueError(f"live_load '{cell}' is not three numbers")
    return parts


def live_load_gap(folder):
    """The largest difference, over the blocks, between the live force of blocks.csv and
    ``live_load x unit_weight x volume`` of summary.csv, by the largest live force (NaN
    when ``live_load`` is empty). 0 when every block's live load is the weight's share."""
    load = live_load(folder)
    if load is None:
        return math.nan
    weight = float(_rows(str(folder) + "/summary.csv")[0]["unit_weight"])
    blocks = _rows(str(folder) + "/blocks.csv")
    live = [_vec(b, ("live_x", "live_y", "live_z")) for b in blocks]
    share = [[c * weight * float(b["volume"]) for c in load] for b in blocks]
    scale = max([abs(v) for f in live + share for v in f] + [1e-300])
    return max(abs(f[i] - s[i]) for f, s in zip(live, share) for i in range(3)) / scale


def violations(folder, tol=1e-6):
    """The conditions of :func:`check_folder` beyond ``tol`` (alpha_fit against alpha), as
    text; for a folder without a certified state, those of :func:`uncertified`; in both, a
    ``live_load`` that is neither empty nor three numbers."""
    try:
        live_load(folder)
        bad = []
    except ValueError as exc:
        bad = [str(exc)]
    if not certified(folder):
        return bad + uncertified(folder)
    r = check_folder(folder)
    bad += [f"{k} {v:.2e}" for k, v in r.items() if k not in ("alpha", "alpha_fit") and v > tol]
    if abs(r["alpha_fit"] - r["alpha"]) > tol * max(1.0, abs(r["alpha"])):
        bad.append(f"alpha_fit {r['alpha_fit']:.9f} != alpha {r['alpha']:.9f}")
    return bad
