#!/usr/bin/env python3
"""The proven lower bound alpha_lower against the certified alpha on the shipped instances.

    python benchmarks/lower_bound.py                          # instances/*.dat and *.json
    python benchmarks/lower_bound.py --prove 600 wall33.dat   # a longer budget on one file

For each instance: the search (``lamodel.search.driver.solve``, default options), then
``lamodel.bound.lower_bound`` with the certified alpha as the top of the range and the
budget of ``lamodel solve`` (a quarter of the search's time, at least 2 s) or ``--prove``.
Prints one Markdown table row per instance: alpha, alpha_lower, their ratio, proven,
the search's and the bound's seconds, rounds, nodes, LPs. A benchmark: nothing is asserted.
"""
import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("names", nargs="*", help="file names in instances/ (default: every .dat and .json)")
    p.add_argument("--prove", type=float, default=None, help="seconds for the bound (default: solve's default)")
    args = p.parse_args(argv)
    from lamodel.bound.lower import default_budget, lower_bound
    from lamodel.io import read
    from lamodel.search.driver import SolveOptions, solve
    names = args.names or sorted(f.name for f in (ROOT / "instances").iterdir() if f.suffix in (".dat", ".json"))
    print("| instance | blocks | contacts | alpha | alpha_lower | alpha_lower / alpha | proven | search s | bound s "
          "| rounds | nodes | LPs |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name in names:
        s = read(ROOT / "instances" / name)
        t = time.perf_counter()
        o = solve(s, SolveOptions(progress=False))
        search = time.perf_counter() - t
        if not o.certified:
            print(f"| {name} | {s.n_blocks} | {s.n_contacts} | (not certified) | | | | {search:.1f} | | | | |")
            continue
        budget = args.prove if args.prove is not None else default_budget(o.wall_time_s)
        lb = lower_bound(s, o.best.alpha, budget=budget)
        print(f"| {name} | {s.n_blocks} | {s.n_contacts} | {o.best.alpha:.6f} | {lb.alpha_lower:.6f} | "
              f"{lb.alpha_lower / o.best.alpha:.6f} | {'yes' if lb.proven_global else 'no'} | {search:.1f} | "
              f"{lb.time:.1f} | {lb.rounds} | {lb.nodes} | {lb.lps} |", flush=True)


if __name__ == "__main__":
    main()
