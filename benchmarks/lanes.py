#!/usr/bin/env python3
"""A lane of the default search, on and off, across the families (by default the
published methods' lane).

    python benchmarks/lanes.py                                   # the small families' cases
    python benchmarks/lanes.py --families stones,direction --max-blocks 120
    python benchmarks/lanes.py --lane "slow continuation" --all --families stones

Per case (the cases of ``benchmarks/families.py --quick``, up to ``--max-blocks``): the
default run's certified alpha without the lane's strategies (``before``) and with them
(``after``), the path that certified the best (runs.csv's ``path``), the least alpha the
lane certified itself, and its share of the run: LP solves (of the search's, Ipopt polish
excluded) and seconds; with ``--all``, also the least certified alpha of every published
method (``--method all``) and the gap of the default run to it before and after. Each run
is the default run (no options), in this process, one after the other. A benchmark, not a
test: nothing is asserted. Times depend on the machine's load; LP counts do not.
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

PUBLISHED = "successive LP,successive cone"


def lane_line(names):
    """The log line of the lane of these strategies (:func:`lamodel.search.gap.lanes._log_lanes`)."""
    return re.compile(r"lane \[" + re.escape(", ".join(names)) + r"\]: (?:least certified alpha ([0-9.]+)|no new "
                      r"certified state), (\d+) LP solves")


class Lines(logging.Handler):
    """The search's log lines at INFO, kept."""

    def __init__(self):
        super().__init__(logging.INFO)
        self.lines = []

    def emit(self, record):
        self.lines.append(record.getMessage())


def solve_once(structure, names, lane_on, lines):
    """The default run with the strategies ``names`` (their runs.csv paths) or without them."""
    from families import _without
    from lamodel.search import plan
    from lamodel.search.driver import SolveOptions, path_of, solve
    kept = plan.IF_STALLED, plan.BESIDE_STALLED, plan.CONTINUATIONS, plan.PUBLISHED, plan.SLOW, plan.MPEC_LANE
    if not lane_on:
        _without(set(names))
    lines.lines.clear()
    t = time.perf_counter()
    try:
        o = solve(structure, SolveOptions())
    finally:
        plan.IF_STALLED, plan.BESIDE_STALLED, plan.CONTINUATIONS, plan.PUBLISHED, plan.SLOW, plan.MPEC_LANE = kept
    seconds = time.perf_counter() - t
    lane = [m for m in map(lane_line(names).search, lines.lines) if m]
    # the lane's seconds: the published methods' phase is its own; a lane beside others is
    # timed by the phase that waits for them (not counted here)
    return dict(alpha=o.best.alpha if o.best is not None else np.nan, path=path_of(o.best), seconds=seconds, work=o.work,
                lps=o.runs[0].iterations if o.runs else 0, lane_seconds=o.phases.get(
                    "published methods" if ",".join(names) == PUBLISHED else names[0], 0.0),
                lane_alpha=float(lane[0].group(1)) if lane and lane[0].group(1) else np.nan,
                lane_lps=int(lane[0].group(2)) if lane else 0)


def extra_cases():
    """Stone walls of 50 stones at mu 0.6 (seeds 0-2): where the lane was measured to give
    the best (seed 0)."""
    from families import _stones
    return [("stones", f"stones50_s{seed}_mu0.6", lambda seed=seed: _stones(50, seed, 0.6, f"stones50_s{seed}_mu0.6"))
            for seed in range(3)]


def least_published(structure):
    """The least certified alpha of the published methods (``--method all`` without lamodel's
    own) and its method."""
    from lamodel.search.methods import METHODS, run_method
    from lamodel.search.options import SolveOptions
    found = [(run_method(m, structure, SolveOptions()).alpha_certified, m) for m in METHODS[:-1]]
    return min(((a, m) for a, m in found if np.isfinite(a)), default=(np.nan, ""))


def main(argv=None):
    import pandas as pd
    from families import cases
    from lamodel.io.jsonspec import structure_from_json
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--families", default="stones,direction,friction,buttress,bond,arch,point",
                    help="comma-separated families of benchmarks/families.py --quick")
    ap.add_argument("--max-blocks", type=int, default=110, help="cases up to this many blocks")
    ap.add_argument("--min-blocks", type=int, default=0, help="cases of at least this many blocks")
    ap.add_argument("--cases", default="", help="comma-separated case names (default: all of the families')")
    ap.add_argument("--lane", default=PUBLISHED,
                    help="comma-separated strategies (runs.csv paths) left out before, kept after (default: the "
                         "published methods' lane)")
    ap.add_argument("--all", action="store_true", help="also the least certified alpha of --method all")
    ap.add_argument("--csv", default=str(ROOT / "results" / "lanes.csv"))
    ap.add_argument("--table", nargs="+", metavar="CSV", help="print the table of these runs' --csv files, solve none "
                    "(a long measurement run case by case)")
    args = ap.parse_args(argv)
    if args.table:
        missing = [f for f in args.table if not Path(f).is_file()]
        if missing:
            raise SystemExit(f"--table: no such file: {', '.join(missing)}")
        df = pd.concat([pd.read_csv(f) for f in args.table], ignore_index=True)
        return table(df, "least" in df and df["least"].notna().any())
    wanted = set(filter(None, args.families.split(",")))
    names = args.lane.split(",")
    only = set(filter(None, args.cases.split(",")))
    lines = Lines()
    log = logging.getLogger("lamodel")
    log.addHandler(lines)
    log.setLevel(logging.INFO)
    rows = []
    # the libraries loaded and the Ipopt workers' first fork paid before the first case's
    # timed runs (else its run without the lane, the first, pays them)
    from families import _wall
    solve_once(structure_from_json(_wall(2, 3, 0.65)), names, True, lines)
    for fam, name, build in cases(quick=True) + extra_cases():
        if fam not in wanted or (only and name not in only):
            continue
        s = structure_from_json(build())
        if not args.min_blocks <= s.n_blocks <= args.max_blocks:
            continue
        off, on = solve_once(s, names, False, lines), solve_once(s, names, True, lines)
        least, by = least_published(s) if args.all else (np.nan, "")
        if not least <= min(off["alpha"], on["alpha"]):  # of any method: lamodel's own runs included
            least, by = min(off["alpha"], on["alpha"]), "default run"
        row = dict(family=fam, case=name, blocks=s.n_blocks, before=off["alpha"], after=on["alpha"],
                   least=least, least_by=by, gap_before=off["alpha"] / least - 1.0, gap_after=on["alpha"] / least - 1.0,
                   best_by=on["path"], lane_alpha=on["lane_alpha"], lane_lp_share=on["lane_lps"] / max(on["lps"], 1),
                   # the search before the lane is the same with it or without: the rest is the lane's
                   lane_work_share=(on["work"] - off["work"]) / max(on["work"], 1),
                   lane_time_share=on["lane_seconds"] / on["seconds"], lps_before=off["lps"], lps_after=on["lps"],
                   s_before=off["seconds"], s_after=on["seconds"])
        rows.append(row)
        print(f"{fam:9s} {name:28s} {s.n_blocks:4d}  before {row['before']:.6f}  after {row['after']:.6f}  "
              f"least {least:.6f} {by:13s} {row['s_before']:5.1f} s -> {row['s_after']:5.1f} s  "
              f"{row['best_by']:24s} lane {row['lane_alpha']:.6f}  LP share {row['lane_lp_share']:.2f}  work share {row['lane_work_share']:.2f}  "
              f"time share {row['lane_time_share']:.2f}", flush=True)
    df = pd.DataFrame(rows)
    Path(args.csv).parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(args.csv, index=False)
    table(df, args.all)
    print(f"cases: {args.csv}")


def table(df, all_methods):
    """The table of the cases (a run's, or the rows of several runs' CSV files: --table)."""
    import pandas as pd
    cols = ["case", "blocks", "before", "after", "best_by", "lane_alpha", "lane_lp_share", "lane_work_share",
            "lane_time_share", "s_before", "s_after"]
    if all_methods:  # the lane's shares left out: the gap to the least alpha of any method instead
        cols = ["case", "blocks", "before", "after", "best_by", "least", "least_by", "gap_before", "gap_after",
                "s_before", "s_after"]
    with pd.option_context("display.width", 200, "display.max_columns", 20):
        print(df[cols].to_string(index=False, float_format=lambda v: f"{v:.6g}"))
    print(f"lower with the lane: {(df.after < df.before - 1e-9).sum()}, higher: {(df.after > df.before + 1e-9).sum()}, "
          f"of {len(df)}; median shares of the lane: LP solves {df.lane_lp_share.median():.3f}, LP work "
          f"{df.lane_work_share.median():.3f}, time {df.lane_time_share.median():.3f}")


if __name__ == "__main__":
    main()
