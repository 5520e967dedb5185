#!/usr/bin/env python3
"""The TRL full-scale bridge tests against lamodel's predicted collapse load.

    python benchmarks/bridges_trl.py

Each bridge is a description in instances/ whose "source" names where each number comes
from (or says it is not sourced). One set of assumptions for all (SHARED below: the
masonry, its friction and crushing strength, the fill, the load patch, the discretisation),
checked to be the same in every file, not tuned per bridge. The load is the test's line
load across the full width at the test's position; the predicted collapse load is the
certified alpha times the file's axle force: with the passive restraint and crushing,
without the restraint, and without crushing; the mechanism is the first one's. LPs only (--starts 0).
"""
import argparse
import dataclasses
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import pandas as pd  # noqa: E402

from lamodel.bridges import read_bridge  # noqa: E402
from lamodel.bridges.adequacy import adequacy_study  # noqa: E402
from lamodel.search.options import SolveOptions  # noqa: E402

#: bridge file -> (measured collapse load [kN], failure reported, source of both)
TESTS = {
    "bridge_prestwood.json": (228.0, "four-hinge mechanism", "Page 1987, TRRL RR110"),
    "bridge_preston.json": (2110.0, "crushing beneath the load", "Page 1987, TRRL RR110"),
    "bridge_torksey.json": (1080.0, "snap-through of three hinges", "Page 1988, TRRL RR159"),
    "bridge_shinafoot.json": (2524.0, "four-hinge mechanism", "Page 1988, TRRL RR159"),
}
#: The assumptions every bridge shares (Bridge attribute -> value).
SHARED = {"masonry_weight": 20.0, "mu": 0.6, "fc": 5000.0, "voussoirs": 24, "fill_weight": 18.0, "phi": 37.5,
          "lateral": "at_rest", "passive": 0.33, "spread": 30.0, "patch": 0.3, "abutment_kind": "rigid"}
#: Tests of the series whose geometry (rise, ring, width, fill) was not found in the sources
#: reachable: not described, listed with what their reports' abstracts give.
NOT_DESCRIBED = {
    "Bridgemill": "neither report nor geometry found",
    "Bargower": "neither report nor geometry found",
    "Strathmashie": "RR201: rubble, span 9.42 m, 1325 kN at 1/4 span; rise, ring, width, fill not found",
    "Barlae": "RR201: ashlar, skew 29 deg, square span 8.53 m, 2900 kN at 1/4 span; rise, ring, width, fill not found",
}


def main():
    rows = []
    for name, (measured, mode, source) in TESTS.items():
        bridge = read_bridge(ROOT / "instances" / name)
        differs = {k: getattr(bridge, k) for k, v in SHARED.items() if getattr(bridge, k) != v}
        if differs:
            raise SystemExit(f"{name}: {differs} differ from the shared assumptions {SHARED}")
        t0 = time.perf_counter()
        passive = adequacy_study(bridge, SolveOptions(starts=0), passive=True)
        without = adequacy_study(bridge, SolveOptions(starts=0), passive=False)
        rigid = adequacy_study(dataclasses.replace(bridge, fc=None), SolveOptions(starts=0), passive=True)
        unsourced = sorted(k for k, v in bridge.source.items() if v.startswith("not sourced"))
        rows.append({"bridge": bridge.name.removeprefix("bridge_"), "measured_kN": measured,
                     "predicted_kN": passive["collapse_load"].min(), "no_passive_kN": without["collapse_load"].min(),
                     "no_crushing_kN": rigid["collapse_load"].min(),
                     "ratio": passive["collapse_load"].min() / measured, "reported": mode,
                     "predicted": passive["mechanism"].iloc[0],
                     "certified": bool(passive["certified"].all() and without["certified"].all() and rigid["certified"].all()),
                     "seconds": time.perf_counter() - t0, "source": source,
                     "not_sourced": " ".join(unsourced)})
    pd.set_option("display.width", 250)
    print(pd.DataFrame(rows).to_string(index=False, na_rep="-", float_format=lambda v: f"{v:.4g}"))
    print("\nTests of the series not described:")
    for name, note in NOT_DESCRIBED.items():
        print(f"  {name:<12} {note}")


if __name__ == "__main__":
    # no options: --help, and an unknown option refused
    argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    main()
