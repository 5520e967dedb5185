#!/usr/bin/env python3
"""Structures whose collapse multiplier is known in closed form, solved by lamodel.

    python benchmarks/closed_forms.py

Each case is a small JSON geometry on a rigid ground; the closed form is written beside it
(W: a block's weight, b x h its width and height). The search runs with its defaults and
LPs only (--starts 0). A check, not a test: the tests assert the same values
(tests/search/test_methods.py, tests/test_engineer.py); this prints them side by side.
"""
import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import pandas as pd  # noqa: E402

from lamodel.io.jsonspec import structure_from_json  # noqa: E402
from lamodel.search.driver import SolveOptions, solve  # noqa: E402


def rect(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


def column(n, b, h, mu, loads=None):
    """n equal b x h blocks stacked on the ground."""
    blocks = [{"id": "ground", "vertices": rect(-4 * b, -1, 4 * b, 0), "support": True}]
    blocks += [{"id": f"b{i + 1}", "vertices": rect(0, i * h, b, (i + 1) * h)} for i in range(n)]
    spec = {"name": f"column{n}", "mu": mu, "blocks": blocks}
    if loads is None:
        spec["live_load"] = [1.0, 0.0]
    else:
        spec["loads"] = loads
    return spec


# (case, JSON spec, closed form, its expression)
CASES = [
    ("block 1 x 2 overturns", column(1, 1.0, 2.0, 0.6), 0.5, "b / h"),
    ("block 1 x 2 slides", column(1, 1.0, 2.0, 0.3), 0.3, "mu"),
    ("two 1 x 1 blocks overturn together", column(2, 1.0, 1.0, 0.6), 0.5, "b / (2 h)"),
    ("two 1 x 1 blocks slide", column(2, 1.0, 1.0, 0.4), 0.4, "mu"),
    ("block 1 x 2, point load P = 3 on its top", column(1, 1.0, 2.0, 5.0, [
        {"block": "b1", "at": [0.3, 2.0], "force": [3.0, 0.0]}]), 2.0 * 1.0 / (2 * 2.0 * 3.0), "W b / (2 h P)"),
    ("block 2 x 1, point load P = 0.5 on its top", column(1, 2.0, 1.0, 5.0, [
        {"block": "b1", "at": [0.0, 1.0], "force": [0.5, 0.0]}]), 2.0 * 2.0 / (2 * 1.0 * 0.5), "W b / (2 h P)"),
]


def main():
    rows = []
    for name, spec, closed, expr in CASES:
        s = structure_from_json(spec)
        t = time.perf_counter()
        out = solve(s, SolveOptions(starts=0))
        alpha = out.best.alpha if out.certified else float("nan")
        rows.append({"case": name, "closed form": expr, "expected": closed, "lamodel": alpha,
                     "difference": alpha - closed, "certified": out.certified,
                     "seconds": round(time.perf_counter() - t, 2)})
    with pd.option_context("display.width", 160, "display.max_colwidth", 60):
        print(pd.DataFrame(rows).to_string(index=False, float_format=lambda v: f"{v:.6g}"))


if __name__ == "__main__":
    # no options: --help, and an unknown option refused
    argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    main()
