#!/usr/bin/env python3
"""Wall-clock time of scripts/solve.py on the seed's walls and on large running-bond walls.

    python benchmarks/walls.py                          # wall33, wall55, 20x10 and 40x20 walls
    python benchmarks/walls.py --sizes 12x6 --csv results/bench.csv

Each case runs ``scripts/solve.py`` in a subprocess, as a user would (results in a
temporary folder, mechanism picture included), and is timed from the outside. The seed's
walls run with the default options and with ``--starts 0`` (LPs only); the generated walls
(``lamodel.geometry.running_bond_wall``: COURSES x BLOCKS, courses alternating BLOCKS full
blocks and BLOCKS - 1 full blocks between two half blocks, written to a temporary .json)
run with ``--starts 0`` and ``--time-limit`` (default 900 s). alpha is read from the
result folder's summary.csv. A benchmark, not a test: nothing is asserted.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def parse_sizes(text):
    sizes = []
    for part in filter(None, (p.strip() for p in text.split(","))):
        try:
            courses, blocks = (int(x) for x in part.lower().split("x"))
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected sizes like 20x10,40x20, got '{part}'") from None
        if courses < 1 or blocks < 2:
            raise argparse.ArgumentTypeError(f"expected at least 1 course of at least 2 blocks, got '{part}'")
        sizes.append((courses, blocks))
    return sizes


def bond_wall(courses: int, blocks: int, folder: Path) -> Path:
    from lamodel.geometry import running_bond_wall
    rows = [[0.5] + [1] * (blocks - 1) + [0.5] if r % 2 == 0 else [1] * blocks for r in range(courses)]
    name = f"bond{courses}x{blocks}"
    path = folder / f"{name}.json"
    path.write_text(json.dumps(running_bond_wall(rows, name=name)))
    return path


def run_case(instance: Path, options: list, folder: Path, timeout: float) -> dict:
    from lamodel.io import read as load_structure
    from lamodel.output.results import Results
    structure = load_structure(str(instance))  # sizes even when the solve writes nothing
    out = folder / f"{instance.stem}_{len(list(folder.iterdir()))}"
    cmd = [sys.executable, str(ROOT / "scripts" / "solve.py"), str(instance), "--out", str(out), "--quiet", *options]
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    t = time.perf_counter()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
        rc = proc.returncode
    except subprocess.TimeoutExpired:
        rc = "timeout"
    else:
        if rc < 0:  # killed by a signal
            rc = f"signal {-rc}"
    seconds = time.perf_counter() - t
    row = {"instance": instance.stem, "n_blocks": structure.n_blocks, "n_contacts": structure.n_contacts,
           "options": " ".join(options) or "(default)",
           "alpha": float("nan"), "certified": False, "seconds": seconds, "exit": rc}
    if (out / "summary.csv").exists():
        summary = Results.read(out).summary.iloc[0]
        row.update(alpha=float(summary["alpha"]), certified=bool(summary["certified"]))
    return row


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--sizes", type=parse_sizes, default=[(20, 10), (40, 20)],
                   help="generated walls, COURSESxBLOCKS comma-separated (default 20x10,40x20; '' for none)")
    p.add_argument("--time-limit", type=float, default=900.0, help="--time-limit of the generated walls (s)")
    p.add_argument("--no-seed-walls", action="store_true", help="skip wall33 and wall55")
    p.add_argument("--csv", help="also write the table here")
    args = p.parse_args(argv)

    import pandas as pd

    from lamodel.io.files import write_csv

    cases = []
    if not args.no_seed_walls:
        for wall in ("wall33", "wall55"):
            for options in ([], ["--starts", "0"]):
                cases.append((ROOT / "instances" / f"{wall}.dat", options, 3600.0))
    rows = []
    with tempfile.TemporaryDirectory(prefix="lamodel_bench_") as tmp:
        tmp = Path(tmp)
        (tmp / "out").mkdir()
        for courses, blocks in args.sizes:
            cases.append((bond_wall(courses, blocks, tmp), ["--starts", "0", "--time-limit", f"{args.time_limit:g}"],
                          args.time_limit + 600.0))
        for instance, options, timeout in cases:
            row = run_case(instance, options, tmp / "out", timeout)
            rows.append(row)
            print(f"  {row['instance']} {row['options']}: alpha {row['alpha']:.6f}, "
                  f"{'certified' if row['certified'] else 'not certified'}, {row['seconds']:.1f} s "
                  f"(exit {row['exit']})", flush=True)
    df = pd.DataFrame(rows, columns=["instance", "n_blocks", "n_contacts", "options", "alpha", "certified", "seconds",
                                     "exit"])
    print(f"python {sys.version.split()[0]}, {os.cpu_count()} cores")
    print(df.to_string(index=False, formatters={"alpha": lambda v: f"{v:.6f}", "seconds": lambda v: f"{v:.1f}"}))
    if args.csv:
        write_csv(df, args.csv)
    return 0


if __name__ == "__main__":
    sys.exit(main())
