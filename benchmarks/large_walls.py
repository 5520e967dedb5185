#!/usr/bin/env python3
"""Large running-bond walls, each solved by the command line in a process of its own: LP
solves and seconds to the first certificate and to the best, the whole process's seconds
(imports, the search, the lower bound beside it, the tables and the picture), the final alpha.

    python benchmarks/large_walls.py                                  # 40 x 25 at five frictions
    python benchmarks/large_walls.py --sizes 80x25 --mus 0.3,0.65,0.75,0.9
    python benchmarks/large_walls.py --sizes 40x25 --mus 0.9 --orders written,shuffled,ground-first
    python benchmarks/large_walls.py --sizes 20x15 --mus 0.9 --side-share inf    # no side-lane bound
    python benchmarks/large_walls.py --sizes 80x25 --mus 0.65 --tuning FIRST_WORK=16

The walls are those of ``benchmarks/families.py`` (``--orders``: the same wall written
another way, its ``_reordered``). A case past ``--timeout`` seconds is stopped and
reported so. LP solves do not depend on the machine's load; seconds do. ``--side-share``
replaces SIDE_LANE_SHARE (lamodel/search/tuning.py) in the solving process ("inf": the
lane beside the first certificate bounded by the first certificate's work alone);
``--tuning NAME=VALUE`` any constant of lamodel/search/tuning.py.
A benchmark, not a test: nothing is asserted.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

MUS = (0.3, 0.65, 0.75, 0.9, 1.0)


def spec(courses, blocks, mu, order):
    from families import _reordered, _wall
    name = f"bond{courses}x{blocks}_mu{mu:g}"
    return _wall(courses, blocks, mu, name=name) if order == "written" else _reordered(courses, blocks, mu, order, name)


def child(path, out, workers, tuned):
    """In the solving process: the command line's solve (``tuned``: NAME=VALUE,... set
    first), the search's outcome kept; prints one JSON line of what the table needs."""
    from families import _assignments, _tune
    from lamodel import cli
    from lamodel.search import driver
    _tune(_assignments(filter(None, tuned.split(","))))
    found = {}
    solve = driver.solve

    def keep(*args, **kwargs):
        found["outcome"] = o = solve(*args, **kwargs)
        return o

    driver.solve = keep
    argv = ["solve", path, "--out", out, "--quiet"] + ([] if workers is None else ["--workers", str(workers)])
    status = cli.main(argv)
    o = found.get("outcome")
    h = o.history if o is not None else []
    first, best = (h[0], h[-1]) if h else ((None,) * 4, (None,) * 4)
    plain = [None if v is None else int(v) if k.startswith("lps") else float(v) for k, v in
             (("lps", first[3]), ("t", first[0]), ("lps", best[3]), ("t", best[0]))]
    print(json.dumps(dict(status=status, lps_first=plain[0], t_first=plain[1], lps_best=plain[2], t_best=plain[3],
                          by=str(best[2]), alpha=float(o.best.alpha) if o is not None and o.best else None)))


def run(spec_, workers, tuned, timeout):
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"{spec_['name']}.json"
        path.write_text(json.dumps(spec_))
        cmd = [sys.executable, __file__, "--child", str(path), str(Path(tmp) / "out"),
               "" if workers is None else str(workers), tuned]
        t = time.perf_counter()
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, cwd=ROOT)
        except subprocess.TimeoutExpired:
            return dict(status="stopped", total=time.perf_counter() - t)
        total = time.perf_counter() - t
    if p.returncode not in (0, 3) or not p.stdout.strip():
        return dict(status=f"failed: {p.stderr.strip().splitlines()[-1:] }", total=total)
    row = json.loads(p.stdout.strip().splitlines()[-1])
    row["total"] = total
    return row


def _num(v, fmt):
    return "-" if v is None else format(v, fmt)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", default="40x25", help="running-bond sizes, COURSESxBLOCKS, comma-separated")
    ap.add_argument("--mus", default=",".join(f"{m:g}" for m in MUS), help="frictions, comma-separated")
    ap.add_argument("--orders", default="written", help="of written, shuffled, ground-first, renamed")
    ap.add_argument("--workers", type=int, default=None, help="the command line's --workers (default: its own)")
    ap.add_argument("--side-share", default=None, help="SIDE_LANE_SHARE in the solving process (inf: no bound)")
    ap.add_argument("--tuning", action="append", default=[], metavar="NAME=VALUE",
                    help="a constant of lamodel.search.tuning set in the solving process (repeatable)")
    ap.add_argument("--timeout", type=float, default=180.0, help="seconds before a case is stopped")
    ap.add_argument("--child", nargs=4, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        path, out, workers, tuned = args.child
        return child(path, out, int(workers) if workers else None, tuned)
    from families import _assignments
    tuned = list(args.tuning) + ([] if args.side_share is None else [f"SIDE_LANE_SHARE={args.side_share}"])
    _assignments(tuned)  # checked here, before any case runs
    tuned = ",".join(tuned)
    print(f"{'case':22s} {'order':13s} {'LPs first':>9s} {'s first':>8s} {'LPs best':>8s} {'s best':>8s} "
          f"{'process s':>9s} {'alpha':>9s}  best by", flush=True)
    for size in args.sizes.split(","):
        courses, blocks = (int(v) for v in size.split("x"))
        for mu in (float(m) for m in args.mus.split(",")):
            for order in args.orders.split(","):
                r = run(spec(courses, blocks, mu, order), args.workers, tuned, args.timeout)
                name = f"bond{courses}x{blocks}_mu{mu:g}"
                if "alpha" not in r:
                    print(f"{name:22s} {order:13s} {r['status']} after {r['total']:.1f} s", flush=True)
                    continue
                print(f"{name:22s} {order:13s} {_num(r['lps_first'], '9d')} {_num(r['t_first'], '8.1f')} "
                      f"{_num(r['lps_best'], '8d')} {_num(r['t_best'], '8.1f')} {r['total']:9.1f} "
                      f"{_num(r['alpha'], '9.6f')}  {r['by']}", flush=True)


if __name__ == "__main__":
    main()
