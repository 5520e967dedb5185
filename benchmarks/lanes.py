#!/usr/bin/env python3
"""The published methods' lane of the default search, on and off, across the families.

    python benchmarks/lanes.py                                   # the small families' cases
    python benchmarks/lanes.py --families stones,direction --max-blocks 120

Per case (the cases of ``benchmarks/families.py --quick``, up to ``--max-blocks``): the
default run's certified alpha without the lane (``before``) and with it (``after``), the
path that certified the best (runs.csv's ``path``), the least alpha the lane certified
itself, and its share of the run: LP solves (of the search's, Ipopt polish excluded) and
seconds. Each run is the default run (no options), in this process, one after the other.
A benchmark, not a test: nothing is asserted. Times depend on the machine's load; LP
counts do not.
"""
from __future__ import annotations

import argparse
import logging
import re
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

LANE = re.compile(r"lane \[successive LP, successive cone\]: (?:least certified alpha ([0-9.]+)|no new certified "
                  r"state), (\d+) LP solves")


class Lines(logging.Handler):
    """The search's log lines at INFO, kept."""

    def __init__(self):
        super().__init__(logging.INFO)
        self.lines = []

    def emit(self, record):
        self.lines.append(record.getMessage())


def solve_once(structure, lane_on, lines):
    from lamodel.search import plan
    from lamodel.search.driver import SolveOptions, path_of, solve
    from lamodel.search.gap.lanes import Lane
    kept = plan.PUBLISHED
    plan.PUBLISHED = kept if lane_on else Lane(())
    lines.lines.clear()
    t = time.perf_counter()
    try:
        o = solve(structure, SolveOptions())
    finally:
        plan.PUBLISHED = kept
    seconds = time.perf_counter() - t
    lane = [m for m in map(LANE.search, lines.lines) if m]
    return dict(alpha=o.best.alpha if o.best is not None else np.nan, path=path_of(o.best), seconds=seconds, work=o.work,
                lps=o.runs[0].iterations if o.runs else 0, lane_seconds=o.phases.get("published methods", 0.0),
                lane_alpha=float(lane[0].group(1)) if lane and lane[0].group(1) else np.nan,
                lane_lps=int(lane[0].group(2)) if lane else 0)


def extra_cases():
    """Stone walls of 50 stones at mu 0.6 (seeds 0-2): where the lane was measured to give
    the best (seed 0)."""
    from families import _stones
    return [("stones", f"stones50_s{seed}_mu0.6", lambda seed=seed: _stones(50, seed, 0.6, f"stones50_s{seed}_mu0.6"))
            for seed in range(3)]


def main(argv=None):
    import pandas as pd
    from families import cases
    from lamodel.io.jsonspec import structure_from_json
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--families", default="stones,direction,friction,buttress,bond,arch,point",
                    help="comma-separated families of benchmarks/families.py --quick")
    ap.add_argument("--max-blocks", type=int, default=110, help="cases up to this many blocks")
    ap.add_argument("--csv", default=str(ROOT / "results" / "lanes.csv"))
    args = ap.parse_args(argv)
    wanted = set(filter(None, args.families.split(",")))
    lines = Lines()
    log = logging.getLogger("lamodel")
    log.addHandler(lines)
    log.setLevel(logging.INFO)
    rows = []
    for fam, name, build in cases(quick=True) + extra_cases():
        if fam not in wanted:
            continue
        s = structure_from_json(build())
        if s.n_blocks > args.max_blocks:
            continue
        off, on = solve_once(s, False, lines), solve_once(s, True, lines)
        row = dict(family=fam, case=name, blocks=s.n_blocks, before=off["alpha"], after=on["alpha"],
                   best_by=on["path"], lane_alpha=on["lane_alpha"], lane_lp_share=on["lane_lps"] / max(on["lps"], 1),
                   # the search before the lane is the same with it or without: the rest is the lane's
                   lane_work_share=(on["work"] - off["work"]) / max(on["work"], 1),
                   lane_time_share=on["lane_seconds"] / on["seconds"], lps_before=off["lps"], lps_after=on["lps"],
                   s_before=off["seconds"], s_after=on["seconds"])
        rows.append(row)
        print(f"{fam:9s} {name:28s} {s.n_blocks:4d}  before {row['before']:.6f}  after {row['after']:.6f}  "
              f"{row['best_by']:24s} lane {row['lane_alpha']:.6f}  LP share {row['lane_lp_share']:.2f}  work share {row['lane_work_share']:.2f}  "
              f"time share {row['lane_time_share']:.2f}", flush=True)
    df = pd.DataFrame(rows)
    Path(args.csv).parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(args.csv, index=False)
    cols = ["case", "blocks", "before", "after", "best_by", "lane_alpha", "lane_lp_share", "lane_work_share",
            "lane_time_share"]
    with pd.option_context("display.width", 200, "display.max_columns", 20):
        print(df[cols].to_string(index=False, float_format=lambda v: f"{v:.6g}"))
    print(f"lower with the lane: {(df.after < df.before - 1e-9).sum()}, higher: {(df.after > df.before + 1e-9).sum()}, "
          f"of {len(df)}; median shares of the lane: LP solves {df.lane_lp_share.median():.3f}, LP work "
          f"{df.lane_work_share.median():.3f}, time {df.lane_time_share.median():.3f}; cases: {args.csv}")


if __name__ == "__main__":
    main()
