#!/usr/bin/env python3
"""A three-span bridge on masonry piers, rolled across: seconds, LP solves and the adequacy
factor at each load position, and the whole run.

    python benchmarks/bridges.py [--positions K] [--voussoirs N] [--rings R] [--no-passive] [--workers W]
    python benchmarks/bridges.py --where --voussoirs 20

``--where``: where the time goes at the first position: without the restraint, with a ring
``fc`` and no restraint, with the restraint (joints, yield rows, LP solves, ms per LP).

Three segmental spans of 8 m (rise 2.5 m) on two piers 1.5 m wide and 5 m high, blocks on
the ground (they slide and rock); rigid abutments; a ring 0.5 m thick of R rings (default 2)
of N voussoirs each (default 40); backing to 1 m; fill 0.5 m over the crowns with the
passive restraint (m = 0.33); one 100 kN axle on a 0.3 m patch at 20 positions evenly from
springing to springing (``--positions K``: the first K of them). LPs only (--starts 0), as
``lamodel bridge --adequacy`` solves them: W positions at once (``--workers W``, default all
cores; 1: one after another, each search using the cores for its lanes).
"""
import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from lamodel.bridges import read_bridge  # noqa: E402
from lamodel.formulation.matrices import row_origins  # noqa: E402
from lamodel.loads import case_structure  # noqa: E402
from lamodel.search.driver import solve  # noqa: E402
from lamodel.bridges.adequacy import mechanism, structure_of  # noqa: E402
from lamodel.studies import load_case_study  # noqa: E402
from lamodel.search.options import SolveOptions  # noqa: E402

POSITIONS = 20


def description(voussoirs: int, rings: int, positions) -> dict:
    return {"name": "three_spans", "units": {"length": "m", "force": "kN"},
            "spans": [{"span": 8.0, "rise": 2.5}] * 3,
            "piers": [{"height": 5.0, "width": 1.5, "kind": "block"}] * 2,
            "ring": {"thickness": 0.5, "rings": rings, "voussoirs": voussoirs, "unit_weight": 20.0, "mu": 0.6},
            "abutments": {"height": 1.5, "width": 1.5}, "backing": {"height": 1.0},
            "fill": {"depth": 0.5, "unit_weight": 18.0, "phi": 35.0, "passive": 0.33, "spread": 30.0},
            "load": {"force": 100.0, "patch": 0.3, "positions": list(positions)}}


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--positions", type=int, default=POSITIONS, help="solve the first K of the 20 positions")
    p.add_argument("--voussoirs", type=int, default=40)
    p.add_argument("--rings", type=int, default=2)
    p.add_argument("--no-passive", action="store_true")
    p.add_argument("--workers", type=int, default=None, help="positions solved at once (default: all cores)")
    p.add_argument("--where", action="store_true", help="where the time goes at the first position")
    args = p.parse_args()
    length = 3 * 8.0 + 2 * 1.5
    every = [float(f"{x:.6g}") for x in np.linspace(-length / 2, length / 2, POSITIONS + 2)[1:-1]]
    if args.where:
        return where_the_time_goes(args, every[0])
    t0 = time.perf_counter()
    bridge = read_bridge(description(args.voussoirs, args.rings, every[:args.positions]))
    structure = structure_of(bridge, passive=not args.no_passive)
    built = time.perf_counter() - t0
    df, outcomes = load_case_study(structure, SolveOptions(starts=0, workers=args.workers))
    rows = [{"position": float(case[2:]), "adequacy": row.alpha_c, "certified": row.certified,
             "lps": lp_solves(outcomes[case]),
             "seconds": row.seconds, "mechanism": mechanism(outcomes[case])}
            for case, row in zip(df["case"], df.itertuples())]
    table = pd.DataFrame(rows)
    print(f"{len(structure.blocks)} blocks, {structure.n_contacts} contacts ({structure.restraints} passive "
          f"restraints); built in {built:.2f} s")
    print(table.to_string(index=False))
    print(f"positions {len(table)}  seconds {time.perf_counter() - t0:.1f}  LPs {table['lps'].sum()}  "
          f"worst adequacy {table['adequacy'].min():.6f}  all certified {bool(table['certified'].all())}")


def lp_solves(outcome) -> int:
    return sum(r.iterations for r in outcome.runs if r.source == "ga+lp")


def lp_rows(s) -> int:
    """Yield rows in the statics LP: 4 a joint of eq. 4, one a distinct row with strengths."""
    if not s.has_materials:
        return 4 * s.n_contacts
    origin = row_origins(s)
    return int((origin == np.arange(origin.size)).sum())


def where_the_time_goes(args, x):
    import dataclasses
    bridge = read_bridge(description(args.voussoirs, args.rings, [x]))
    rows = []
    for label, b, passive in (("no passive restraint", bridge, False),
                              ("ring fc, no restraint", dataclasses.replace(bridge, fc=5000.0), False),
                              ("passive restraint", bridge, True)):
        s = case_structure(structure_of(b, passive), f"x={x:.6g}")
        t0 = time.perf_counter()
        o = solve(s, SolveOptions(starts=0))
        seconds, lps = time.perf_counter() - t0, lp_solves(o)
        rows.append({"case": label, "joints": s.n_contacts, "yield_rows": lp_rows(s),
                     "lps": lps, "first_certificate_lps": o.lps_first, "ms_per_lp": 1000 * seconds / max(lps, 1),
                     "seconds": seconds, "alpha": o.best.alpha if o.best is not None else np.nan})
    print(pd.DataFrame(rows).to_string(index=False))


if __name__ == "__main__":
    main()
