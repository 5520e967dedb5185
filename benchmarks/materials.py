#!/usr/bin/env python3
"""The joints' strengths (lamodel.formulation.joints): time and alpha beside the dry joints.

    python benchmarks/materials.py

For the seed's arch and portals and Table 1's walls: the dry joints (eq. 4's LPs), a
negligible cohesion (the strength LPs with the hinge rows only), a huge compressive
strength (the inscribed polygon: 2 + 2 x 25 rows a contact) and finite ones, each solved
with the defaults and LPs only (--starts 0, one worker). A measurement, not a test: the
tests assert the values (tests/materials/).
"""
import dataclasses
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from lamodel.io.datfile import read_dat  # noqa: E402
from lamodel.search.driver import SolveOptions, solve  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
#: (instance, finite compressive strengths tried): a few times the joints' mean stress
CASES = [("arch", (40.0, 20.0)), ("portal", (50.0, 20.0)), ("portal_columns", (50.0, 20.0)),
         ("wall33", (3.0, 2.0)), ("wall55", (8.0, 4.0))]


def variants(s, strengths):
    yield "dry", s
    yield "cohesion 1e-14", dataclasses.replace(s, cohesion=np.full(s.n_contacts, 1e-14))
    for fc in (1e9, *strengths):
        yield f"fc {fc:g}", dataclasses.replace(s, fc=np.full(s.n_contacts, fc))


def main():
    cases = [(read_dat(ROOT / "instances" / f"{name}.dat"), fcs) for name, fcs in CASES]
    rows = []
    for s, fcs in cases:
        dry_time = None
        for label, v in variants(s, fcs):
            t = time.perf_counter()
            out = solve(v, SolveOptions(workers=1, starts=0))
            sec = time.perf_counter() - t
            dry_time = dry_time or sec
            rows.append({"structure": s.name, "blocks": s.n_blocks, "joints": label,
                         "alpha": out.best.alpha if out.best is not None else np.nan, "status": out.status,
                         "seconds": round(sec, 2), "x dry": round(sec / dry_time, 1)})
            print(pd.DataFrame(rows[-1:]).to_string(index=False, header=len(rows) == 1), flush=True)
    print()
    print(pd.DataFrame(rows).to_string(index=False))


if __name__ == "__main__":
    main()
