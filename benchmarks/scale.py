#!/usr/bin/env python3
"""How the search (lamodel.search.driver.solve, what ``lamodel solve`` runs) scales.

    python benchmarks/scale.py                               # everything, 60 s budget a case
    python benchmarks/scale.py --cases bond10,bond40 --budget 60
    python benchmarks/scale.py --cases wall33,wall55,door1 --budget 0   # default stopping rule

Cases: ``wall33``/``wall55`` (the seed's Table 1), ``bondC`` (running bond of C courses of
25 blocks: courses alternate, from the bottom, 1/2 + 24 + 1/2 and 25 full blocks, as the
seed's panels), and ``doorK`` (walls with a door and windows,
:func:`lamodel.geometry.wall_with_openings`). Each
case runs in its own process (peak memory is that process's ru_maxrss), timed from the
search's start. ``--budget S`` is the time limit; 0 means no limit (the search's own
stopping rule). Prints one row per case and the growth exponent of the time to the
first certificate against the number of blocks (least squares in log-log).

``--cli`` times the whole command instead, as a user runs it: ``lamodel solve`` (no
options: the default run, the proven lower bound after the search, the result folder and
its picture) in a subprocess per case, its wall-clock and CPU seconds (its children's
included), the search's and the bound's seconds and LP solves from the result folder, and
the load average beside (times on a loaded machine are upper bounds; compare CPU)::

    python benchmarks/scale.py --cli --cases wall33,wall55,bond40,bond80
"""
from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import resource
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


# ------------------------------------------------------------------ instances
OPENINGS = {
    # ~50 blocks: one door
    "door1": dict(courses=6, width=8, openings=((3, 5, 0, 4),)),
    # ~146 blocks: a door and a window
    "door2": dict(courses=12, width=12, openings=((2, 4, 0, 7), (7, 9, 3, 8))),
    # ~290 blocks: a door and two windows, two storeys of windows
    "door3": dict(courses=16, width=20, openings=((3, 5, 0, 7), (9, 11, 3, 7), (15, 17, 3, 7),
                                                  (9, 11, 10, 14), (15, 17, 10, 14))),
}


def build(case: str):
    from lamodel.geometry import seed_wall
    from lamodel.io.jsonspec import structure_from_json
    if case in ("wall33", "wall55"):
        return structure_from_json(seed_wall(6 if case == "wall33" else 10))
    if case.startswith("bond") or case in OPENINGS:
        return structure_from_json(build_spec(case))
    raise SystemExit(f"unknown case '{case}'")


# ------------------------------------------------------------------------ runs
def run_case(case, budget, seed, queue, sigint_at=None):
    """The product's search (lamodel.search.driver.solve: the LP search, the GA with its
    stopping rule, Ipopt when affordable), with ``budget`` as --time-limit; ``sigint_at``:
    send SIGINT (Ctrl-C) to this process that many seconds after the start."""
    import os
    import signal
    import threading
    from lamodel.search.driver import SolveOptions, solve
    s = build(case)
    sent = []
    if sigint_at is not None:
        def send():
            sent.append(time.perf_counter())
            os.kill(os.getpid(), signal.SIGINT)
        timer = threading.Timer(sigint_at, send)
        timer.daemon = True
        timer.start()
    o = solve(s, SolveOptions(seed=seed, time_limit=budget if budget > 0 else None, progress=False))
    latency = time.perf_counter() - sent[0] if sent else np.nan
    row = dict(case=case, blocks=s.n_blocks, contacts=s.n_contacts, status=o.status,
               assoc=o.alpha_associative, t_assoc=o.phases.get("associative", np.nan),
               first=o.first[0], t_first=o.first[1], best=o.best.alpha if o.best else np.nan,
               t_best=o.history[-1][0] if o.history else np.nan, total=o.wall_time_s,
               lps=o.runs[0].iterations if o.runs else 0,
               phases={k: round(v, 2) for k, v in o.phases.items()},
               rss_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
               residual=max(o.best.residual.values()) if o.best else np.nan,
               interrupted=o.status == "interrupted" or "time limit" in o.message, latency=latency)
    queue.put(row)


def run_cli(case, seed):
    """``lamodel solve`` on the case, whole process: a dict of what it took."""
    import csv
    import os
    import subprocess
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        if case in ("wall33", "wall55"):
            instance = str(ROOT / "instances" / f"{case}.dat")
        else:
            spec = build_spec(case)
            instance = os.path.join(tmp, f"{case}.json")
            with open(instance, "w") as f:
                json.dump(spec, f)
        out = os.path.join(tmp, "out")
        load = os.getloadavg()[0]
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t = time.perf_counter()
        status = subprocess.run([sys.executable, "-m", "lamodel.cli", "solve", instance, "--out", out, "--quiet",
                                 "--seed", str(seed)], env=dict(os.environ, PYTHONPATH=str(ROOT)),
                                stdout=subprocess.DEVNULL).returncode
        wall = time.perf_counter() - t
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        with open(os.path.join(out, "summary.csv")) as f:
            summary = next(csv.DictReader(f))
        with open(os.path.join(out, "runs.csv")) as f:
            lps = int(float(next(csv.DictReader(f))["iterations"]))
    return dict(case=case, exit=status, alpha=float(summary["alpha"]), search=float(summary["wall_time_s"]),
                lps=lps, bound=float(summary["alpha_lower_seconds"] or "nan"), wall=wall, cpu=cpu,
                load=(load, os.getloadavg()[0]))


def build_spec(case):
    """The JSON spec of a ``bondC`` or ``doorK`` case."""
    from lamodel.geometry import running_bond_wall, wall_with_openings
    if case.startswith("bond"):
        c = int(case[4:])
        return running_bond_wall([[0.5] + [1] * 24 + [0.5] if r % 2 == 0 else [1] * 25 for r in range(c)], name=case)
    return wall_with_openings(name=case, **OPENINGS[case])


def main_cli(cases, seed):
    print(f"{'case':8} {'exit':>4} {'alpha':>9} {'search_s':>8} {'LPs':>5} {'bound_s':>7} {'whole_s':>7} "
          f"{'cpu_s':>7}  load average (before, after)", flush=True)
    for case in cases:
        r = run_cli(case, seed)
        print(f"{r['case']:8} {r['exit']:4d} {r['alpha']:9.6f} {r['search']:8.2f} {r['lps']:5d} {r['bound']:7.2f} "
              f"{r['wall']:7.2f} {r['cpu']:7.2f}  {r['load'][0]:.2f}, {r['load'][1]:.2f}", flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", default="wall33,wall55,door1,door2,door3,bond10,bond20,bond40,bond80")
    ap.add_argument("--budget", type=float, default=60.0, help="time limit per case (s); 0: none")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", help="append the rows to this JSON-lines file")
    ap.add_argument("--sigint-at", type=float, help="send SIGINT (Ctrl-C) this many seconds after the "
                    "search starts; the row ends with the latency (s) from the signal to the search's return")
    ap.add_argument("--cli", action="store_true", help="time the whole `lamodel solve` command instead (default run)")
    a = ap.parse_args(argv)
    if a.cli:
        return main_cli(a.cases.split(","), a.seed)
    ctx = mp.get_context("fork")
    rows = []
    head = (f"{'case':8} {'blocks':>6} {'cont':>5} {'assoc':>9} {'t_as':>6} {'first':>9} {'t_1st':>7} "
            f"{'best':>9} {'t_best':>7} {'total':>7} {'LPs':>5} {'MB':>6}  phases (s)")
    print(head, flush=True)
    for case in a.cases.split(","):
        q = ctx.Queue()
        p = ctx.Process(target=run_case, args=(case, a.budget, a.seed, q, a.sigint_at))
        p.start()
        row = q.get()
        p.join()
        rows.append(row)
        print(f"{row['case']:8} {row['blocks']:6d} {row['contacts']:5d} {row['assoc']:9.6f} {row['t_assoc']:6.2f} "
              f"{row['first']:9.6f} {row['t_first']:7.2f} {row['best']:9.6f} {row['t_best']:7.2f} "
              f"{row['total']:7.2f} {row['lps']:5d} {row['rss_mb']:6.0f}  {row['phases']}"
              f"  [{row['status']}{', stopped' if row['interrupted'] else ''}]"
              + (f"  Ctrl-C latency {row['latency']:.2f} s" if a.sigint_at is not None else ""), flush=True)
        if a.json:
            with open(a.json, "a") as f:
                f.write(json.dumps(row, default=float) + "\n")
    pts = [(r["blocks"], r["t_first"]) for r in rows if r["case"].startswith("bond") and np.isfinite(r["t_first"])]
    if len(pts) >= 2:
        x, y = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
        k = np.polyfit(x, y, 1)[0]
        print(f"growth: time to the first certificate ~ blocks^{k:.2f} (running-bond walls)")
    pts = [(r["blocks"], r["t_assoc"]) for r in rows if r["case"].startswith("bond")]
    if len(pts) >= 2:
        k = np.polyfit(np.log([p[0] for p in pts]), np.log([p[1] for p in pts]), 1)[0]
        print(f"growth: associative LP ~ blocks^{k:.2f}")


if __name__ == "__main__":
    main()
