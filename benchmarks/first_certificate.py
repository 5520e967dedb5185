#!/usr/bin/env python3
"""The first certificate where the gap alternation stalls: running bond at several
frictions and sizes, stack bond and a stone wall, under the strategies of the lane that
runs at a stall (:data:`lamodel.search.plan.IF_STALLED`) in the plan's order or another.

    python benchmarks/first_certificate.py                          # the plan's order
    python benchmarks/first_certificate.py --stalled single,rescue,zero,fixed
    python benchmarks/first_certificate.py --sizes 15x10 --mus 0.9,1.0 --no-others
    python benchmarks/first_certificate.py --alone single,rescue,zero,fixed,dilatancy --sizes 25x20

Each case runs the default search (:func:`lamodel.search.driver.solve`, default options)
in this process. Per case: whether the alternation stalled (which lane gave the first
certificate), LP solves and seconds to the first certificate, its alpha, the final alpha
and the whole run's seconds. With ``--alone``: where the alternation stalls, each strategy
named run alone from the stall (on an engine of its own): its LP solves, seconds and least
certified alpha. LP solves do not depend on the machine's load; seconds do.
A benchmark, not a test: nothing is asserted.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

MUS = (0.5, 0.75, 0.8, 0.9, 1.0)
SIZES = ((15, 10), (20, 15))


def strategies():
    """The strategies a stalled lane may hold, by the name ``--stalled`` gives them."""
    from lamodel.search.gap.chains import FixedPoint, FromZero
    from lamodel.search.gap.rescue import Rescue
    from lamodel.search.gap.single import SingleBlocks
    from lamodel.search.gap.dilatancy import Dilatancy
    return dict(single=SingleBlocks(), rescue=Rescue(), zero=FromZero(cold=True), fixed=FixedPoint(),
                dilatancy=Dilatancy())


def cases(sizes, mus, others):
    """(case name, JSON-spec builder)."""
    from families import _stones, _wall
    out = []
    for c, b in sizes:
        for mu in mus:
            out.append((f"bond{c}x{b}_mu{mu:g}", lambda c=c, b=b, mu=mu: _wall(c, b, mu)))
    if others:
        for mu in (0.75, 0.9):
            out.append((f"stack15x10_mu{mu:g}", lambda mu=mu: _wall(15, 10, mu, stack=True)))
        for mu in (0.65, 0.8):
            out.append((f"stones160_s2_mu{mu:g}", lambda mu=mu: _stones(160, 2, mu, "stones")))
    return out


def run(spec):
    from lamodel.io.jsonspec import structure_from_json
    from lamodel.search.driver import SolveOptions, solve
    s = structure_from_json(spec)
    t = time.perf_counter()
    o = solve(s, SolveOptions())
    total = time.perf_counter() - t
    h = o.history
    first = h[0] if h else (np.nan, np.nan, "", np.nan)
    return dict(blocks=s.n_blocks, first_by=str(first[2]).split("+")[0], lps_first=first[3], t_first=first[0],
                alpha_first=first[1], alpha=o.best.alpha if o.best else np.nan, total=total)


def alone(spec, names):
    """Each strategy of ``names`` alone from where the gap alternation stalls: (name, LP
    solves, seconds, least certified alpha) rows; none where the alternation certifies."""
    from lamodel.io.jsonspec import structure_from_json
    from lamodel.search.gap import GapSearch
    from lamodel.search.gap.lanes import Start
    from lamodel.search.gap.phases import associative
    s = structure_from_json(spec)
    known, out = strategies(), []
    for name in names:
        engine = GapSearch(s)
        _, _, x0 = associative(engine)
        _, x = engine.alternation.alternate(x0, source="gap")
        if engine.record.best is not None:
            return out
        lps, t = engine.n_lps(), time.perf_counter()
        known[name].run(engine, Start(x0, x))
        best = engine.record.best
        out.append((name, engine.n_lps() - lps, time.perf_counter() - t, best.alpha if best else np.nan))
    return out


def main(argv=None):
    import pandas as pd
    from lamodel.search import plan
    from lamodel.search.gap.lanes import Lane
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--stalled", default="", help="the stalled lane's strategies in order, comma-separated, of "
                    "single, rescue, zero, fixed (default: the plan's)")
    ap.add_argument("--sizes", default=",".join(f"{c}x{b}" for c, b in SIZES), help="running-bond sizes, CxB")
    ap.add_argument("--mus", default=",".join(f"{m:g}" for m in MUS), help="frictions of the running-bond walls")
    ap.add_argument("--no-others", action="store_true", help="running bond only (no stack bond, no stone wall)")
    ap.add_argument("--alone", default="", help="instead: these strategies (of single, rescue, zero, fixed, "
                    "dilatancy), each alone from the stall")
    ap.add_argument("--csv", default=None, help="also write the table here")
    args = ap.parse_args(argv)
    if args.stalled:
        known = strategies()
        plan.IF_STALLED = Lane(tuple(known[k] for k in args.stalled.split(",")), until_certified=True)
    sizes = [tuple(int(v) for v in s.split("x")) for s in args.sizes.split(",") if s]
    mus = [float(m) for m in args.mus.split(",") if m]
    if args.alone:
        for name, build in cases(sizes, mus, not args.no_others):
            found = alone(build(), args.alone.split(","))
            print(f"{name:22s} " + ("not stalled" if not found else "  ".join(
                f"{k} {n} LPs {t:.1f} s alpha {a:.6f}" for k, n, t, a in found)), flush=True)
        return
    print("stalled lane:", ", ".join(plan.IF_STALLED.names), flush=True)
    rows = []
    for name, build in cases(sizes, mus, not args.no_others):
        row = dict(case=name, **run(build()))
        rows.append(row)
        print(f"{name:22s} {row['blocks']:5d} blocks  first by {row['first_by']:16s} LPs {row['lps_first']:6.0f} "
              f"{row['t_first']:7.2f} s  alpha {row['alpha_first']:.6f}  final {row['alpha']:.6f} "
              f"({row['total']:.1f} s)", flush=True)
    if args.csv:
        pd.DataFrame(rows).to_csv(args.csv, index=False)


if __name__ == "__main__":
    main()
