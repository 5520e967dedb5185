#!/usr/bin/env python3
"""lamodel inside a user's Pyomo study: the cheapest tie that keeps a wall's collapse load up.

    python examples/tie_force.py                   # wall33, tie at b33, target alpha >= 0.645
    python examples/tie_force.py --target 0.70     # a target this tie cannot reach (exit 1)

The user's model: the limit-analysis model of wall33 (``lamodel.LimitAnalysisBlock``,
eq. 1-5 of the seed) inside the user's ``ConcreteModel``, plus the user's decision, a
horizontal tie force 0 <= T <= t_max pulling the right end block of the top course (b33)
against the live load, at a price per unit force; the collapse multiplier must reach a
target; minimise the cost. Ipopt (``SolverFactory('lamodel_ipopt')``) solves it.

The tie enters through the block's public ``extra_x`` expression (``m.wall.extra_x['b33'] =
-m.T``): a user's constant force at the centroid, part of f0, so the model puts it in both
places it belongs — the x equilibrium of b33 and the bilinear condition alpha = alpha_K,
where the constant forces do work on the mechanism (T * ux[b33]). A force put in the
equilibrium alone would leave points that are not collapse states of the tied wall: flow on
rows that are not at yield would make up the missing work.

What Ipopt returns is *a* collapse state of the tied wall with alpha >= target (a point
of eq. 5 with T fixed), which is not necessarily the least collapse multiplier of that wall:
eq. 5 has many local solutions, and minimising T pushes towards the largest of them.
So the answer is checked independently: the tie force found becomes a constant dead force
on b33 in a copy of the Structure, and ``lamodel.search.driver.solve`` (LPs only, ``starts=0``;
its default GA and ``--checks`` wider GA searches) looks for the least certified collapse
multiplier of the tied wall. Only that number says whether the target is met, and
it is itself the least multiplier lamodel found (an upper bound on the true minimum).

Measured with the LP engine as the core of the search: Ipopt designs T = 0.049028 for a
target of 0.645, and the tied wall's least certified multiplier is 0.650334 (Ipopt's own
point, 0.651634, is a collapse state but not the least): target met. At T = 1.0-1.5 the
search certifies a half block sliding out alone at alpha = mu = 0.65, so no tie at b33
reaches 0.66. Earlier, weaker searches reported: the least certified multiplier of the
tied wall rises with T (0.66 at T = 0.3)
(the whole wall sliding on the ground: alpha = 0.65 + T / 30) up to about 0.667 near
T = 0.5; from T of about 0.55 on, the statics can hold b33 off the half block b28 below
it, and a half block at the right end (b28, or b17 lower down: the same multiplier) slides
out alone, unloaded, at alpha = mu = 0.65. A target above about 0.667 (e.g. 0.70) is out
of reach with this single tie, whatever T: Ipopt finds T = 1.5 with alpha = 0.70, and the
check finds a collapse state at 0.65.

Exit status: 0 target met (certified), 1 not met, 2 bad arguments.
"""
import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run from a checkout without installing

TOLERANCE = 1e-6  # certified alpha >= target - TOLERANCE counts as met (Ipopt's T is exact to ~1e-8)


def build_user_model(structure, block, target, price, t_max, epsilon=1e-7):
    """The user's ConcreteModel: lamodel's block, the tie force T, the target, the cost."""
    import pyomo.environ as pe

    import lamodel

    m = pe.ConcreteModel(name="tie_design")
    m.wall = lamodel.LimitAnalysisBlock(structure=structure, objective=False)
    w = m.wall
    m.T = pe.Var(bounds=(0.0, t_max), initialize=0.0, doc="tie force, pulling the block against the live load")
    m.price = pe.Param(initialize=price, mutable=True, doc="cost per unit tie force")
    m.target = pe.Param(initialize=target, mutable=True, doc="least acceptable collapse multiplier")
    # the tie force (-T, 0) at the centroid of the block: a constant force of the user's, part
    # of f0, so it enters both the block's x equilibrium and alpha_K (eq. 5)
    w.extra_x[block] = -m.T
    m.safe = pe.Constraint(expr=w.alpha >= m.target)
    m.cost = pe.Objective(expr=m.price * m.T)
    w.epsilon = epsilon
    return m


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--instance", default=str(ROOT / "instances" / "wall33.dat"))
    p.add_argument("--block", default=None, help="tied block (default: the right end block of the top course)")
    p.add_argument("--target", type=float, default=0.645, help="least acceptable collapse multiplier (default 0.645)")
    p.add_argument("--price", type=float, default=1.0, help="cost per unit tie force (default 1)")
    p.add_argument("--t-max", type=float, default=5.0, help="largest tie force (default 5)")
    p.add_argument("--checks", type=int, default=2,
                   help="wider GA searches (pop 40, 15 generations) in the check, besides the default one")
    p.add_argument("--csv", help="write the summary table here")
    args = p.parse_args(argv)
    t_start = time.perf_counter()

    import pandas as pd
    import pyomo.environ as pe

    from lamodel.formulation.model import get_state, set_state
    from lamodel.io import read
    from lamodel.search.certify import certify
    from lamodel.search.driver import SolveOptions, solve
    from lamodel.search.lp import LimitLPs
    from lamodel.io.files import write_csv
    from lamodel.output.rows import mode_counts
    from lamodel.variants import with_dead_force

    s = read(args.instance)
    if args.block is None:  # the block of the top course with the largest centroid x
        y_top = s.centroid[:, 1].max()
        top = [j for j in range(s.n_blocks) if abs(s.centroid[j, 1] - y_top) < 1e-9 * max(1.0, abs(y_top))]
        args.block = s.blocks[max(top, key=lambda j: s.centroid[j, 0])]
    if args.block not in s.blocks:
        p.error(f"no movable block '{args.block}' in {s.name}")
    rows = []

    # 1. the untied wall: its least certified multiplier, and a warm start for Ipopt
    untied = solve(s, SolveOptions(seed=0, starts=0))
    if untied.best is None:
        print(f"{s.name}: no certified collapse state of the untied wall ({untied.message})")
        return 1
    rows.append(dict(step="untied wall: lamodel.search.driver.solve", T=0.0, alpha=untied.best.alpha, certified=True,
                     seconds=untied.wall_time_s))
    print(f"{s.name}: untied, certified alpha_c = {untied.best.alpha:.6f} (associative bound "
          f"{untied.alpha_associative:.6f}); target {args.target:g}, tie at {args.block}")

    # 2. the user's study, solved by Ipopt from the untied collapse state
    m = build_user_model(s, args.block, args.target, args.price, args.t_max)
    b = untied.best
    set_state(m.wall, s, b.N, b.V, b.M, b.alpha, b.u, b.xi)
    t = time.perf_counter()
    res = pe.SolverFactory("lamodel_ipopt").solve(m, options={"bound_relax_factor": 0.0, "max_iter": 3000})
    seconds = time.perf_counter() - t
    status = str(res.solver.termination_condition)
    T = float(pe.value(m.T))
    alpha_ipopt = float(pe.value(m.wall.alpha))
    rows.append(dict(step=f"user's model: Ipopt ({status})", T=T, alpha=alpha_ipopt, certified=False,
                     seconds=seconds))
    print(f"Ipopt: {status}, T = {T:.6f}, alpha = {alpha_ipopt:.6f}, cost = {pe.value(m.cost):.6f} "
          f"({seconds:.1f} s)")
    if status not in ("optimal", "locallyOptimal"):
        print(f"Ipopt did not solve the user's model ({status}): T = {T:.6f} is not a design")

    # 3. the check: the tie as a constant force on a copy of the structure
    tied = with_dead_force(s, args.block, fx=-T, name=f"{s.name}_tied")
    lps = LimitLPs(tied)
    N, V, M, alpha, u, xi = get_state(m.wall, s)
    t = time.perf_counter()
    point = certify(lps, N, V, M, alpha, u, xi, source="ipopt")
    rows.append(dict(step="Ipopt's point, certified on the tied wall", T=T,
                     alpha=point.alpha if point is not None else float("nan"), certified=point is not None,
                     seconds=time.perf_counter() - t))
    searches = [("tied wall: driver, default GA, seed 0", SolveOptions(seed=0, starts=0))]
    searches += [(f"tied wall: driver, GA 40x15, seed {k}", SolveOptions(seed=k, starts=0, pop_size=40,
                                                                         generations=15))
                 for k in range(1, args.checks + 1)]
    best = point
    for label, opt in searches:
        out = solve(tied, opt)
        rows.append(dict(step=label, T=T, alpha=out.best.alpha if out.best else float("nan"),
                         certified=out.best is not None, seconds=out.wall_time_s))
        if out.best is not None and (best is None or out.best.alpha < best.alpha):
            best = out.best

    table = pd.DataFrame(rows, columns=["step", "T", "alpha", "certified", "seconds"])
    with pd.option_context("display.width", 160, "display.max_colwidth", 60):
        print(table.to_string(index=False, float_format=lambda v: f"{v:.6f}"))
    if args.csv:
        write_csv(table, args.csv)

    if best is None:
        print(f"no certified collapse state of the tied wall: T = {T:.6f} is not checked")
        return 1
    counts = mode_counts(tied, best.xi)
    moving = [blk for blk, uu in zip(tied.blocks, best.u.reshape(-1, 3)) if abs(uu).max() > 1e-9 * abs(best.u).max()]
    print(f"least certified collapse state of the tied wall: alpha = {best.alpha:.6f}, {len(moving)} moving block(s)"
          f"{' (' + ', '.join(moving) + ')' if len(moving) <= 4 else ''}, {counts['n_sliding']} slipping and "
          f"{counts['n_hinging']} rotating contact(s), {counts['n_open']} open")
    met = best.alpha >= args.target - TOLERANCE
    if point is None:
        print("Ipopt's point is not a collapse state of the tied wall (the certification LPs reject it)")
    elif best.alpha < point.alpha - TOLERANCE:
        print(f"Ipopt's point is a collapse state at alpha = {point.alpha:.6f}, but not the least one: "
              f"the tied wall also collapses at alpha = {best.alpha:.6f}")
    if not met and args.block not in moving:
        print(f"{args.block} does not move in that mechanism: the tie does no work on it, so no tie force at "
              f"{args.block} raises its multiplier (restrain the moving blocks, or lower the target)")
    verdict = "target met" if met else "target NOT met"
    print(f"result: tie force T = {T:.6f} at {args.block}, cost {args.price * T:.6f}; certified alpha of the tied "
          f"wall = {best.alpha:.6f}, target {args.target:g}: {verdict} ({time.perf_counter() - t_start:.1f} s)")
    return 0 if met else 1


if __name__ == "__main__":
    sys.exit(main())
