#!/usr/bin/env python3
"""The TRL full-scale bridge tests against lamodel's predicted collapse load.

    python benchmarks/bridges_trl.py

Each bridge is a description in instances/ (its sources in its "description"); one set of
assumptions for all (the fill, the friction, the load patch: in the files, the same in
each), not tuned per bridge. The load is the test's line load across the full width at the
position of the test; the predicted collapse load is the certified alpha times the file's
axle force, with and without the passive restraint. LPs only (--starts 0).
"""
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import pandas as pd  # noqa: E402

from lamodel.bridges import read_bridge  # noqa: E402
from lamodel.bridges.adequacy import adequacy_study  # noqa: E402
from lamodel.search.options import SolveOptions  # noqa: E402

#: bridge file -> (measured collapse load [kN], failure reported, source)
TESTS = {
    "bridge_prestwood.json": (228.0, "four-hinge mechanism", "Page 1987, TRRL RR110"),
}


def main():
    rows = []
    for name, (measured, mode, source) in TESTS.items():
        bridge = read_bridge(ROOT / "instances" / name)
        t0 = time.perf_counter()
        passive = adequacy_study(bridge, SolveOptions(starts=0), passive=True)
        without = adequacy_study(bridge, SolveOptions(starts=0), passive=False)
        rows.append({"bridge": bridge.name, "measured_kN": measured, "reported": mode,
                     "predicted_kN": passive["collapse_load"].min(),
                     "no_passive_kN": without["collapse_load"].min(),
                     "ratio": passive["collapse_load"].min() / measured,
                     "certified": bool(passive["certified"].all() and without["certified"].all()),
                     "seconds": time.perf_counter() - t0, "source": source})
    print(pd.DataFrame(rows).to_string(index=False, float_format=lambda v: f"{v:.4g}"))


if __name__ == "__main__":
    main()
