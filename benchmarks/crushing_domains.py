#!/usr/bin/env python3
"""The planar joint's N-M domain solved exactly (a rotated second-order cone, Clarabel)
and as the inscribed polygon lamodel reports (an LP, HiGHS): alpha and time side by side.

    python benchmarks/crushing_domains.py

The program compared is the associative one, max alpha over the statically admissible
set (equilibrium, |V| <= c0 A - mu N, the joint's N-M domain): its alpha bounds the
collapse multiplier from above for both domains, and the polygon's is at most the
parabola's and at least (1 - eps) of it (lamodel.formulation.joints). The parabola
``N^2 <= 2 f_c b (-d N -/+ M)`` (f_t = 0) is the rotated cone
``||(2 N, 2 f_c b - w)|| <= 2 f_c b + w``, ``w = -d N -/+ M``, one a side of a joint.
Each program is built once (its matrices; the polygon's facets) and solved cold REPEATS
times, the least solve time kept. A measurement, not a test.
"""
import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import clarabel  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import scipy.sparse as sp  # noqa: E402

from lamodel.formulation.matrices import Formulation, joint_area  # noqa: E402
from lamodel.io.datfile import read_dat  # noqa: E402
from lamodel.search.highs import INF, HighsLP  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CASES = [("arch", (40.0, 20.0)), ("portal", (50.0, 20.0)), ("wall33", (3.0, 2.0)), ("wall55", (8.0, 4.0))]
REPEATS = 3


def polygon_program(s):
    """max alpha with the inscribed polygon's rows ``Y s_f <= b`` (HiGHS): (its solve, rows)."""
    f = Formulation.of(s)
    nc = s.n_contacts
    E = sp.vstack([sp.hstack([f.A, f.fbar.reshape(-1, 1)]), sp.hstack([f.Y, sp.csr_matrix((f.Y.shape[0], 1))])])
    cost = np.zeros(3 * nc + 1)
    cost[-1] = -1.0
    args = (E.tocsc(), np.r_[-f.f0, np.full(f.Y.shape[0], -INF)], cost, np.full(3 * nc + 1, -INF),
            np.full(3 * nc + 1, INF), "polygon")

    def solve():
        lp = HighsLP(*args, b_hi=np.r_[-f.f0, f.b])   # cold, as the cone program
        return lp.x()[-1] if lp.solve() == "optimal" else np.nan
    return solve, E.shape[0]


def parabola_program(s):
    """max alpha with the exact parabola (Clarabel), f_t = 0: (its solve, rows)."""
    f = Formulation.of(replace(s, fc=np.full(s.n_contacts, np.inf)))   # equilibrium only
    nc, nx = s.n_contacts, 3 * s.n_contacts + 1
    k = np.arange(nc)
    cA = s.cohesion * joint_area(s)
    # the slides |V| <= c0 A - mu N: rows s = b - G x >= 0
    G_lin = sp.vstack([sp.csr_matrix((np.r_[s.mu, np.ones(nc)], (np.r_[k, k], np.r_[k, nc + k])), shape=(nc, nx)),
                       sp.csr_matrix((np.r_[s.mu, -np.ones(nc)], (np.r_[k, k], np.r_[k, nc + k])), shape=(nc, nx))])
    b_lin = np.r_[cA, cA]
    socs, b_soc = [], []
    two_cb = 2 * s.fc * s.thickness
    for sign in (1.0, -1.0):   # w = -d N - sign M; s = (2cb + w, 2N, 2cb - w)
        r = 3 * k
        rows = np.r_[r, r, r + 1, r + 2, r + 2]
        cols = np.r_[k, 2 * nc + k, k, k, 2 * nc + k]
        # s = b - G x: G holds minus each component's x-coefficients
        vals = np.r_[s.d, sign * np.ones(nc), -2 * np.ones(nc), -s.d, -sign * np.ones(nc)]
        socs.append(sp.csr_matrix((vals, (rows, cols)), shape=(3 * nc, nx)))
        b = np.zeros(3 * nc)
        b[0::3], b[2::3] = two_cb, two_cb
        b_soc.append(b)
    G = sp.vstack([sp.hstack([f.A, f.fbar.reshape(-1, 1)]), G_lin, *socs]).tocsc()
    b = np.r_[-f.f0, b_lin, *b_soc]
    cones = [clarabel.ZeroConeT(f.A.shape[0]), clarabel.NonnegativeConeT(2 * nc)] + [clarabel.SecondOrderConeT(3)] * (2 * nc)
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    cost = np.zeros(nx)
    cost[-1] = -1.0

    def solve():
        sol = clarabel.DefaultSolver(sp.csc_matrix((nx, nx)), cost, G, b, cones, settings).solve()
        return sol.x[-1] if str(sol.status).endswith("Solved") else np.nan
    return solve, G.shape[0]


def timed(program, s):
    """(alpha, rows, seconds to build the matrices, least seconds of REPEATS solves)."""
    t = time.perf_counter()
    solve, m = program(s)
    build, best, out = time.perf_counter() - t, np.inf, None
    for _ in range(REPEATS):
        t = time.perf_counter()
        out = solve()
        best = min(best, time.perf_counter() - t)
    return out, m, build, best


def main():
    rows = []
    for name, fcs in CASES:
        s = read_dat(ROOT / "instances" / f"{name}.dat")
        for fc in fcs:
            v = replace(s, fc=np.full(s.n_contacts, fc))
            a_poly, m_poly, b_poly, t_poly = timed(polygon_program, v)
            a_par, m_par, b_par, t_par = timed(parabola_program, v)
            rows.append({"structure": name, "contacts": s.n_contacts, "fc": fc, "alpha polygon": round(a_poly, 6),
                         "alpha parabola": round(a_par, 6), "rel. diff": f"{(a_poly - a_par) / a_par:+.2e}",
                         "rows LP": m_poly, "rows cone": m_par, "build LP": round(b_poly, 4),
                         "build cone": round(b_par, 4), "solve HiGHS": round(t_poly, 4),
                         "solve Clarabel": round(t_par, 4)})
            print(pd.DataFrame(rows[-1:]).to_string(index=False, header=len(rows) == 1), flush=True)
    print()
    print(pd.DataFrame(rows).to_string(index=False))


if __name__ == "__main__":
    # no options: --help, and an unknown option refused
    argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    main()
