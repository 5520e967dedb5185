#!/usr/bin/env python3
"""Eq. 5 handed whole to a global solver: SCIP on the linear program with complementarity
constraints, against lamodel's certified search.

    pip install pyscipopt                                    # SCIP (Apache-2.0), not a lamodel dependency
    python benchmarks/global_solver.py                       # portal, arch, portal_columns, wall33
    python benchmarks/global_solver.py --seconds 600 wall33.dat

Eq. 5 is a linear program with complementarity constraints: the statics of eq. 1-4 and
the mechanism of the fictitious cohesive system (``-A^T u = G^T xi``, ``fbar^T u = 1``,
``0 <= xi <= xi_bounds``) are linear, and ``alpha_K = alpha`` is ``xi_r * slack_r = 0`` on
every yield row r (the gap ``alpha_K - alpha = xi^T slack`` of the seed's theorem). Here
each pair (xi_r, slack_r) is one SOS1 constraint and SCIP minimises alpha >= 0 by
branch-and-bound on them, on the non-dimensional structure the search solves
(:func:`lamodel.formulation.scaling.scaled`). Its optimum, when it has one, is the global
minimum; its dual bound is a lower bound (in floating point, not checked as
``alpha_lower`` is). Prints one Markdown row per instance: blocks, contacts,
complementarity pairs, SCIP's status, its best alpha and dual bound, nodes, seconds, and
lamodel's certified alpha and seconds (default options). A benchmark: nothing is asserted.
"""
import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def lpcc(structure, seconds: float):
    """SCIP's model of eq. 5 as an LPCC, its time limit set; returns (model, number of contacts)."""
    from pyscipopt import Model, quicksum

    from lamodel.formulation.matrices import Formulation, xi_bounds
    from lamodel.formulation.scaling import scaled, scales
    s = scaled(structure, *scales(structure))
    f = Formulation.of(s)
    nb, nc = f.nb, f.nc
    m = Model()
    m.hideOutput()
    m.setParam("limits/time", seconds)
    forces = [m.addVar(lb=None) for _ in range(3 * nc)]
    alpha = m.addVar(lb=0.0)   # no collapse state has alpha < 0 when the dead load stands
    slack = [m.addVar(lb=0.0) for _ in range(4 * nc)]
    u = [m.addVar(lb=None) for _ in range(3 * nb)]
    xi = [m.addVar(lb=0.0, ub=b) for b in xi_bounds(s)]

    def rows(matrix, variables):
        matrix = matrix.tocsr()
        for i in range(matrix.shape[0]):
            a, b = matrix.indptr[i], matrix.indptr[i + 1]
            yield quicksum(matrix.data[k] * variables[matrix.indices[k]] for k in range(a, b))

    for i, row in enumerate(rows(f.A, forces)):                       # eq. 1-2
        m.addCons(row + f.fbar[i] * alpha == -f.f0[i])
    for r, row in enumerate(rows(f.Y, forces)):                       # eq. 4, slack = -Y s_f
        m.addCons(slack[r] + row == 0)
    for ra, rg in zip(rows(f.A.T, u), rows(f.G.T, xi)):               # the cohesive mechanism
        m.addCons(ra + rg == 0)
    m.addCons(quicksum(f.fbar[i] * u[i] for i in range(3 * nb) if f.fbar[i]) == 1)
    for r in range(4 * nc):                                           # alpha_K = alpha (eq. 5)
        m.addConsSOS1([xi[r], slack[r]])
    m.setObjective(alpha, "minimize")
    return m, nc


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("instances", nargs="*", default=["portal.dat", "arch.dat", "portal_columns.dat", "wall33.dat"],
                   help="files under instances/ (default: the seed's portal, arch, portal_columns and wall33)")
    p.add_argument("--seconds", type=float, default=120.0, help="SCIP's time limit per instance (default 120)")
    args = p.parse_args(argv)
    try:
        import pyscipopt  # noqa: F401
    except ImportError:
        sys.exit("global_solver.py: needs SCIP's Python interface: pip install pyscipopt")
    from lamodel.io import read
    from lamodel.search.driver import SolveOptions, solve
    print("| instance | blocks | contacts | pairs | SCIP status | SCIP alpha | SCIP dual bound | nodes | SCIP s "
          "| lamodel alpha | lamodel s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name in args.instances:
        s = read(ROOT / "instances" / name)
        t = time.perf_counter()
        m, nc = lpcc(s, args.seconds)
        m.optimize()
        scip_s = time.perf_counter() - t
        best = f"{m.getObjVal():.6f}" if m.getNSols() else "none"
        t = time.perf_counter()
        o = solve(s, SolveOptions(progress=False))
        ours = f"{o.best.alpha:.6f}" if o.certified else "none"
        print(f"| {name} | {s.n_blocks} | {nc} | {4 * nc} | {m.getStatus()} | {best} | {m.getDualbound():.6f} "
              f"| {m.getNNodes()} | {scip_s:.1f} | {ours} | {time.perf_counter() - t:.1f} |", flush=True)


if __name__ == "__main__":
    main()
