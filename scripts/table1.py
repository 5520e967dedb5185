#!/usr/bin/env python3
"""The seed's Table 1 with lamodel's results: python scripts/table1.py [--out results/table1.csv]

Solves instances/wall33.dat and instances/wall55.dat with lamodel.driver.solve and prints
the published collapse multipliers (references/table1.csv: Ferris & Tin-Loi [2], Gilbert
et al. [4], Mihai [5], the seed) beside lamodel's certified alpha and the associative
bound; writes the table as CSV (atomic write). The core is lamodel.studies.table1.

Exit status: 0 every wall certified, 3 some wall not certified, 2 bad input.
"""
import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout without installing


def main(argv=None):
    p = argparse.ArgumentParser(prog="table1.py", description="The seed's Table 1 with lamodel's certified alpha.")
    p.add_argument("--out", default="results/table1.csv", help="CSV file (default results/table1.csv)")
    p.add_argument("--seed", type=int, default=0, help="random seed of the GA (default 0)")
    p.add_argument("--starts", type=int, default=2, help="Ipopt solves of eq. 5 per wall (default 2; 0: LPs only)")
    p.add_argument("--workers", type=int, default=None, help="worker processes (default: all cores)")
    args = p.parse_args(argv)
    if args.starts < 0:
        p.error(f"--starts: expected a whole number >= 0, got {args.starts}")

    import pandas as pd

    from lamodel.driver import SolveOptions
    from lamodel.errors import InputError
    from lamodel.studies import table1, write_csv

    options = SolveOptions(seed=args.seed, starts=args.starts, workers=args.workers)
    try:
        df = table1(options, progress=lambda r: print(f"  {r['wall']}: alpha = {r['lamodel']:.6f} "
                                                      f"({'certified' if r['certified'] else 'NOT certified'}, "
                                                      f"{r['seconds']:.1f} s)", flush=True))
    except InputError as exc:
        print(f"table1.py: error: {exc}", file=sys.stderr)
        return 2
    with pd.option_context("display.width", 160, "display.max_columns", 20):
        print(df.to_string(index=False, formatters={
            c: (lambda v: f"{v:.6f}") for c in ("lamodel", "alpha_associative")} | {
            c: (lambda v: f"{v:.5f}") for c in ("ferris_tin_loi_2", "gilbert_4", "mihai_5", "seed")} | {
            "seconds": lambda v: f"{v:.1f}"}))
    write_csv(df, args.out)
    print(f"written to {args.out} (seed {args.seed}, starts {args.starts})")
    return 0 if df["certified"].all() else 3


if __name__ == "__main__":
    sys.exit(main())
