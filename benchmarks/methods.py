#!/usr/bin/env python3
"""Methods side by side on wall33, wall55, a wall with openings and the arch.

    python benchmarks/methods.py                      # all four instances, default budgets
    python benchmarks/methods.py --instances wall33 --csv results/methods_bench.csv
    python benchmarks/methods.py --fc 20 --cohesion 0.01    # every joint with these strengths

With ``--fc``, ``--ft``, ``--cohesion`` every joint has those strengths (the methods
take them as lamodel does: lamodel.search.lp). Every method of ``lamodel.search.methods`` (associative LP, successive LP of Gilbert et al.
2006, the MPEC relaxation of Ferris & Tin-Loi 2001, the seed's GA + Ipopt, lamodel's
certified search) runs in this process on the same structure, with its default options
(seed 0). For each: its raw alpha, the certified alpha of that raw answer,
raw - certified (how far the method's own number is from the collapse state it points
to), certified - best (how far from the least certified alpha of the instance), seconds
and iterations. A benchmark, not a test: nothing is asserted.
"""
import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

# A 6-block-long running-bond wall, 8 courses (bottom first), with a door (1 block wide,
# 3 courses high, under a lintel course) and two windows (1 block wide, 2 courses high):
# negative entries are openings (lamodel.geometry.running_bond_wall). Small enough for the
# Ipopt methods (the 129-block default of lamodel.geometry.wall_with_openings takes them
# minutes a solve), and its collapse runs through the openings.
OPENINGS = [[0.5, 1, 1, -1, 1, 1, 0.5],
            [1, 1, 0.5, -1, 0.5, 1, 1],
            [0.5, 1, 1, -1, 1, 1, 0.5],
            [1, 1, 1, 1, 1, 1],
            [0.5, -1, 1, 1, 1, -1, 0.5],
            [0.5, -1, 0.5, 1, 1, 0.5, -1, 0.5],
            [1, 1, 1, 1, 1, 1],
            [0.5, 1, 1, 1, 1, 1, 0.5]]


def instances(names):
    from lamodel.geometry import running_bond_wall
    from lamodel.io import read
    from lamodel.io.jsonspec import structure_from_json
    make = {"wall33": lambda: read(ROOT / "instances" / "wall33.dat"),
            "wall55": lambda: read(ROOT / "instances" / "wall55.dat"),
            "openings": lambda: structure_from_json(running_bond_wall(OPENINGS, name="openings")),
            "arch": lambda: read(ROOT / "instances" / "arch.json")}
    for name in names:
        yield name, make[name]()


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--instances", default="wall33,wall55,openings,arch",
                   help="comma-separated: wall33, wall55, openings, arch (default: all four)")
    p.add_argument("--csv", help="also write the table to this CSV file")
    for name in ("fc", "ft", "cohesion"):
        p.add_argument(f"--{name}", type=float, help=f"every joint's {name} (lamodel.variants.with_strengths)")
    args = p.parse_args(argv)
    names = [n.strip() for n in args.instances.split(",") if n.strip()]
    bad = [n for n in names if n not in ("wall33", "wall55", "openings", "arch")]
    if bad:
        p.error(f"unknown instance '{bad[0]}'; expected wall33, wall55, openings or arch")

    import pandas as pd

    from lamodel.output.methods import methods_frame
    from lamodel.search.methods import run_methods
    from lamodel.search.options import SolveOptions
    from lamodel.variants import with_strengths

    tables = []
    strengths = {k: getattr(args, k) for k in ("fc", "ft", "cohesion") if getattr(args, k) is not None}
    for name, s in instances(names):
        s = with_strengths(s, **strengths) if strengths else s
        print(f"{name}: {s.n_blocks} blocks, {s.n_contacts} contacts", flush=True)
        found = run_methods("all", s, SolveOptions(), progress=lambda r: print(
            f"  {r.method:14s} raw {r.alpha_raw:.6f}  certified {r.alpha_certified:.6f}  {r.seconds:6.1f} s",
            flush=True))
        t = methods_frame(found)
        t.insert(0, "instance", name)
        t.insert(4, "raw_minus_certified", t.alpha_raw - t.alpha_certified)
        tables.append(t)
    table = pd.concat(tables, ignore_index=True)
    fmt = {c: (lambda v: "" if pd.isna(v) else f"{v:.6f}") for c in ("alpha_raw", "alpha_certified")}
    fmt.update({c: (lambda v: "" if pd.isna(v) else f"{v:+.1e}") for c in ("raw_minus_certified", "gap_to_best")})
    fmt["seconds"] = lambda v: f"{v:.1f}"
    print()
    print(table.drop(columns="notes").to_string(index=False, formatters=fmt))
    print()
    for r in table.itertuples(index=False):
        print(f"{r.instance} {r.method}: {r.notes}")
    if args.csv:
        Path(args.csv).parent.mkdir(parents=True, exist_ok=True)
        table.to_csv(args.csv, index=False, float_format="%.17g")
        print(f"written to {args.csv}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
