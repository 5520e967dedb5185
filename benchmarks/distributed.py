#!/usr/bin/env python3
"""Wall-clock of lamodel's executor: a study's speed-up with 2 local workers against 1, and
the overhead of a Dask cluster (a LocalCluster on 127.0.0.1) against local processes.

    PYTHONPATH=$PWD python benchmarks/distributed.py                 # 40 variants of wall33
    PYTHONPATH=$PWD python benchmarks/distributed.py --variants 8    # quicker
    PYTHONPATH=$PWD python benchmarks/distributed.py --exploration bond10   # the GA phase of one solve

The study is wall33 (starts 0: LPs only) with mu from 0.3 to 0.9 in ``--variants`` steps;
each configuration solves the same variants with the same seeds, so the tables agree (the
script checks it) and only the clock differs. A machine shared with other work makes the
numbers noisy: compare them within one run.
"""
import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# this file's folder first on sys.path would make "distributed" this script, not Dask's package
sys.path[:] = [str(ROOT)] + [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]

SCIENCE = ["mu", "alpha", "certified", "alpha_associative", "n_sliding", "n_hinging", "n_open", "ga_seed"]


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--variants", type=int, default=40, help="variants of the study (default 40)")
    p.add_argument("--instance", default=str(ROOT / "instances" / "wall33.json"))
    p.add_argument("--exploration", metavar="CASE",
                   help="instead: the GA phase of one solve of a benchmarks/scale.py case (e.g. bond10) "
                        "with --workers 1 and 2 (threads), on a 2-worker Dask LocalCluster, and without "
                        "--workers (serial, warm)")
    p.add_argument("--generations", type=int, default=3,
                   help="GA generations for --exploration, all of them run: the stopping rule is off (default 3)")
    args = p.parse_args(argv)
    if args.exploration:
        return exploration(args.exploration, args.generations)

    import os

    import dask
    import numpy as np
    import pandas as pd
    from distributed import LocalCluster

    from lamodel.io import read
    from lamodel.parametric import run_study, study_from_dict
    from lamodel.search.executor import Executor

    structure = read(args.instance)
    mus = np.round(np.linspace(0.3, 0.9, args.variants), 6).tolist()
    study = study_from_dict({"options": {"starts": 0}, "seed": 0, "vary": {"mu": mus}}, structure)
    one = study_from_dict({"options": {"starts": 0}, "seed": 0}, structure)
    rows, tables = [], {}

    def timed(case, where, s, **kw):
        t = time.perf_counter()
        df = run_study(s, progress=False, **kw)
        rows.append({"case": case, "where": where, "variants": len(df), "seconds": time.perf_counter() - t,
                     "certified": int(df["certified"].sum())})
        tables.setdefault(case, []).append(df[[c for c in SCIENCE if c in df.columns]])
        print(f"  {case:<28} {where:<30} {rows[-1]['seconds']:7.1f} s", flush=True)

    load = os.getloadavg()[0]
    print(f"{structure.name}: {len(mus)} variants, {os.cpu_count()} cores, load average {load:.2f} before", flush=True)
    timed("wall33 once", "this process", one, workers=1)
    timed("study", "1 process (this one)", study, workers=1)
    timed("study", "2 local processes", study, workers=2)
    with dask.config.set({"distributed.scheduler.allowed-failures": 1}):
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, host="127.0.0.1", dashboard_address=None,
                               env={"PYTHONPATH": str(ROOT)})
    try:
        with Executor(scheduler=cluster.scheduler_address) as ex:
            ex.client.wait_for_workers(2)
            timed("wall33 once", "dask task (cold worker)", one, executor=ex)
            timed("wall33 once", "dask task (warm worker)", one, executor=ex)
            timed("study", "dask, 2 workers", study, executor=ex)
    finally:
        cluster.close()

    for case, dfs in tables.items():
        assert all(d.equals(dfs[0]) for d in dfs), f"{case}: the tables differ between configurations"
    df = pd.DataFrame(rows)
    base = df.groupby("case")["seconds"].transform("first")
    df["speed-up"] = base / df["seconds"]
    print()
    print(df.to_string(index=False, float_format=lambda v: f"{v:.2f}"))
    print("\nevery configuration gave the same table (alpha, modes, seeds) for each case")
    print(f"load average {load:.2f} before, {os.getloadavg()[0]:.2f} after: other work on these cores "
          "takes from the speed-up (2 workers cannot beat 1 on one free core)")


def exploration(case, generations):
    """The GA phase (``phases['ga']``) of one solve, its LP count and alpha: pure evaluations
    with 1 and 2 threads and on a 2-worker Dask LocalCluster (twice: the first solve also
    builds each worker's engine), and the serial warm GA (no --workers). The stopping rule
    is off, so that every run evaluates ``generations`` full generations (bond10 stops
    after one otherwise: its first certificate is already its best)."""
    import math
    import os

    import dask
    import pandas as pd
    from distributed import LocalCluster

    from benchmarks.scale import build
    from lamodel.search import driver
    from lamodel.search.driver import solve
    from lamodel.search.options import SolveOptions

    driver.STALL_WORK = math.inf  # never stalled: exactly `generations` generations
    structure = build(case)
    print(f"{case}: {structure.n_blocks} blocks, {generations} generations, {os.cpu_count()} cores, "
          f"load average {os.getloadavg()[0]:.2f} before", flush=True)
    rows = []

    def timed(where, **kw):
        t = time.perf_counter()
        o = solve(structure, SolveOptions(seed=0, starts=0, generations=generations, **kw))
        rows.append({"where": where, "ga seconds": o.phases.get("ga", float("nan")),
                     "solve seconds": time.perf_counter() - t, "LPs": o.runs[0].iterations,
                     "alpha": o.best.alpha if o.best is not None else float("nan")})
        print(f"  {where:<32} GA {rows[-1]['ga seconds']:7.2f} s", flush=True)

    timed("1 thread", ga_workers=1)
    timed("2 threads", ga_workers=2)
    with dask.config.set({"distributed.scheduler.allowed-failures": 1}):
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, host="127.0.0.1", dashboard_address=None,
                               env={"PYTHONPATH": str(ROOT)})
    try:
        from distributed import Client
        with Client(cluster) as client:
            client.wait_for_workers(2)
        timed("dask, 2 workers (cold)", scheduler=cluster.scheduler_address)
        timed("dask, 2 workers (warm)", scheduler=cluster.scheduler_address)
    finally:
        cluster.close()
    timed("none (serial, warm)")
    df = pd.DataFrame(rows)
    df["GA speed-up vs 1 thread"] = df["ga seconds"].iloc[0] / df["ga seconds"]
    print()
    print(df.to_string(index=False, float_format=lambda v: f"{v:.6g}"))
    pure = df.iloc[:-1]
    same = (pure["alpha"] == pure["alpha"].iloc[0]).all() and (pure["LPs"] == pure["LPs"].iloc[0]).all()
    print(f"\nthreads and Dask: {'the same' if same else 'DIFFERENT'} alpha and LP count; "
          f"load average {os.getloadavg()[0]:.2f} after")


if __name__ == "__main__":
    main()
