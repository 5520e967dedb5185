#!/usr/bin/env python3
"""The joints' strengths (lamodel.formulation.joints): time and alpha beside the dry joints.

    python benchmarks/materials.py [case ...]
    python benchmarks/materials.py bond5x10 stack5x10 stones40    # the family's cases

For the seed's arch and portals, Table 1's walls and a running-bond wall of 205 blocks
(bond10x20: 10 courses of 20 blocks, lamodel.geometry.running_bond_wall): the dry joints
(eq. 4's LPs), a negligible cohesion (the strength LPs with the hinge rows only), a huge
compressive strength (the inscribed polygon: 2 + 2 x 20 rows a contact, those in force in
the LPs) and finite ones, each solved with the defaults and LPs only (--starts 0, one
worker); ``case``: only those (default: all). The family's cases (running-bond walls
bond5x10, bond10x10, stack-bond stack5x10 and a panel of 40 stones, stones40, built as in
benchmarks/families.py) try f_c = 1e9, 10 and 3 and a mortar (cohesion and tensile
strength 0.05). Beside the seconds the LP solves and the LP
work (iterations times rows), which do not depend on the machine's load, and the path that
certified the state reported (``dry certificate``: :mod:`lamodel.search.gap.dry`) and
``first s``, the seconds to the first certified state. A measurement,
not a test: the tests assert the values (tests/materials/).
"""
import argparse
import dataclasses
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from families import _bond_rows, _stones  # noqa: E402
from lamodel.geometry import running_bond_wall  # noqa: E402
from lamodel.io.datfile import read_dat  # noqa: E402
from lamodel.io.jsonspec import structure_from_json  # noqa: E402
from lamodel.search.driver import SolveOptions, path_of, solve  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
#: (instance, finite compressive strengths tried): a few times the joints' mean stress
CASES = [("arch", (40.0, 20.0)), ("portal", (50.0, 20.0)), ("portal_columns", (50.0, 20.0)),
         ("wall33", (3.0, 2.0)), ("wall55", (8.0, 4.0)), ("bond10x20", (10.0,))]
#: the family's cases (not run by default): f_c 10 and 3 against base stresses of 1.25 to 2.5
FAMILY = [("bond5x10", (10.0, 3.0)), ("bond10x10", (10.0, 3.0)), ("stack5x10", (10.0, 3.0)),
          ("stones40", (10.0, 3.0))]
MORTAR = 0.05  # the family's cohesion and tensile strength


def structure(name):
    """An instance of the seed, or bondCxB: a running-bond wall of C courses of B blocks
    (a full block weighs 1: at f_c = 10 the base joints work at a quarter of it)."""
    if name.startswith("stones"):
        return structure_from_json(_stones(int(name[6:]), 0, 0.65, name), name=name)
    if not name.startswith(("bond", "stack")):
        return read_dat(ROOT / "instances" / f"{name}.dat")
    stack = name.startswith("stack")
    courses, blocks = map(int, name[5 if stack else 4:].split("x"))
    return structure_from_json(running_bond_wall(_bond_rows(courses, blocks, stack), name=name), name=name)


def variants(s, strengths, family=False):
    yield "dry", s
    if not family:
        yield "cohesion 1e-14", dataclasses.replace(s, cohesion=np.full(s.n_contacts, 1e-14))
    for fc in (1e9, *strengths):
        yield f"fc {fc:g}", dataclasses.replace(s, fc=np.full(s.n_contacts, fc))
    if family:
        mortar = np.full(s.n_contacts, MORTAR)
        yield f"c0 = ft = {MORTAR:g}", dataclasses.replace(s, cohesion=mortar, ft=mortar)


def main(argv=None):
    names = [name for name, _ in CASES + FAMILY]
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case", nargs="*", help=f"only these, of {', '.join(names)} (default: all but the family's)")
    only = set(ap.parse_args(argv).case)
    if only - set(names):  # (argparse's choices refuse an empty list)
        ap.error(f"unknown case {', '.join(sorted(only - set(names)))}; expected some of {', '.join(names)}")
    family = {name for name, _ in FAMILY}
    cases = [(structure(name), fcs, name in family) for name, fcs in CASES + FAMILY
             if (not only and name not in family) or name in only]
    rows = []
    for s, fcs, in_family in cases:
        dry_time = dry_lps = None
        for label, v in variants(s, fcs, in_family):
            t = time.perf_counter()
            out = solve(v, SolveOptions(workers=1, starts=0))
            sec = time.perf_counter() - t
            lps = sum(r.iterations for r in out.runs)
            dry_time, dry_lps = dry_time or sec, dry_lps or lps
            rows.append({"structure": s.name, "blocks": s.n_blocks, "joints": label,
                         "alpha": out.best.alpha if out.best is not None else np.nan, "status": out.status,
                         "first s": round(out.first[1], 2), "seconds": round(sec, 2), "x dry": round(sec / dry_time, 1),
                         "LPs": lps, "LPs x dry": round(lps / dry_lps, 1), "work": f"{out.work:.2e}",
                         "path": path_of(out.best)})
            print(pd.DataFrame(rows[-1:]).to_string(index=False, header=len(rows) == 1), flush=True)
    print()
    print(pd.DataFrame(rows).to_string(index=False))


if __name__ == "__main__":
    main()
