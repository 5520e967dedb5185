#!/usr/bin/env python3
"""Where the gap alternation stops on a planar structure, and whether the stop is real: a
diagnosis (the planar counterpart of ``benchmarks/stall3d.py``).

    python benchmarks/stall2d.py WALL.json
    python benchmarks/stall2d.py WALL.json --dilatancy --chain-from-zero

``WALL.json`` is any planar structure file ``lamodel solve`` reads (the running-bond walls
of ``benchmarks/families.py``, e.g. ``bond80x25_mu1.json``, are written by its ``--write DIR``). It runs the associative
LP and the gap alternation from its statics (the search's first start) or, with
``--dilatancy``, the dilatancy continuation (the systems of DILATANCY_STEPS, then the
seed's), and at the statics x where it ends prints:

1. the gap ``alpha_K(-mu N(x)) - alpha(x)`` (eq. 5) of the least-alpha_K mechanism, how
   many yield rows hold half, three quarters and 99 % of it, and the rows holding most
   (kind: slide+, slide-, hinge at end 1 or 2 of the contact; the contact's centre, its
   normal, the mechanism's flow and the statics' slack there, non-dimensional);
2. the least gap over the admissible set S for that mechanism (zero: some statics holds
   it, and x is one step from a collapse state);
3. with ``--chain-from-zero``: the seed's chain from zero cohesion (cohesive LP cold) run
   from there, as the first certificate's fallback lane runs it, without a work bound;
   its certified alpha (or none) and its LP work in units of the default work bound.

Lines are printed as they come; LP solves and CPU seconds at the end.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

KINDS = ("slide+", "slide-", "hinge 1", "hinge 2")
SHOWN = 6


def diagnose(path, dilatancy=False, from_zero=False):
    from lamodel.errors import InputError
    from lamodel.io import read
    from lamodel.search.gap import GapSearch
    from lamodel.search.gap.chains import FromZero
    from lamodel.search.gap.phases import associative
    from lamodel.search.tuning import DILATANCY_STEPS, DILATANCY_TRACK
    s = read(path)
    if not hasattr(s, "n_contacts"):
        raise InputError(f"{path}: a structure in space; benchmarks/stall3d.py diagnoses those")
    cpu = time.process_time()
    engine = GapSearch(s)
    p, alternate = engine.problem, engine.alternation.alternate
    status, a_assoc, x = associative(engine)
    print(f"{Path(path).name}: {s.n_blocks} blocks, {s.n_contacts} contacts; associative {status} "
          f"{a_assoc:.6f}", flush=True)
    if status != "ok":
        return
    if dilatancy:
        for t in DILATANCY_STEPS:
            _, x = alternate(x, source="dilatancy", dilatancy=t, max_steps=DILATANCY_TRACK)
    best, x = alternate(x, source="dilatancy" if dilatancy else "gap")
    print(f"  {'dilatancy continuation' if dilatancy else 'alternation'}: ends at alpha {x[-1]:.6f}, "
          f"certified {'-' if best is None else f'{best.alpha:.6f}'}, {p.n_lps()} LPs", flush=True)
    status, a_k, _, u, xi = p.mechanism(-p.mu * p.N_of(x))
    if status != "optimal":
        print(f"  mechanism step at the end: {status}")
        return
    sl = p.slack(x)
    part = sl * p.row_scale * xi  # per yield row its part of the gap (slack times flow, virtual work)
    gap = part.sum()
    order = np.argsort(-part)
    cum = np.cumsum(part[order]) / gap if gap > 0 else np.ones(1)
    held = [int(np.searchsorted(cum, f)) + 1 for f in (0.5, 0.75, 0.99)]
    where = (f"rows holding 50/75/99 %: {held[0]}/{held[1]}/{held[2]}" if gap > 0
             else "the statics holds every row it flows on: a collapse state")
    print(f"  1. gap {gap:.3e} (alpha_K {a_k:.6f}); {where}; the mechanism flows on {int((xi > 0).sum())} rows",
          flush=True)
    nc = p.nc
    for i in order[:SHOWN][part[order[:SHOWN]] > 0]:
        k = i % nc
        print(f"     {KINDS[i // nc]:7s} contact {k:5d} at ({s.centre[k][0]:.3g}, {s.centre[k][1]:.3g}) normal "
              f"({s.normal[k][0]:.2g}, {s.normal[k][1]:.2g}): flow {xi[i]:.2e}, slack {sl[i]:.2e}, "
              f"{part[i] / gap:.1%} of the gap", flush=True)
    st, xg = p.statics(cost_lam=p.gap_weights(xi), alpha_cost=0.0)
    print(f"  2. least gap over S for that mechanism: "
          f"{p.gap(xg, xi):.3e}" if st == "optimal" else f"  2. least gap over S: {st}", flush=True)
    if from_zero:
        w0 = p.work()
        found = FromZero(cold=True).run(engine, None)
        print(f"  3. chain from zero cohesion: certified {'-' if found is None else f'{found.alpha:.6f}'}, "
              f"{(p.work() - w0) / p.work_bound():.2f} default work bounds", flush=True)
    print(f"  {p.n_lps()} LPs, {time.process_time() - cpu:.1f} s CPU")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", help="a planar structure file (.dat or .json)")
    ap.add_argument("--dilatancy", action="store_true", help="diagnose where the dilatancy continuation ends")
    ap.add_argument("--chain-from-zero", action="store_true", help="then run the chain from zero cohesion")
    a = ap.parse_args(argv)
    from lamodel.errors import InputError
    try:
        diagnose(a.file, a.dilatancy, a.chain_from_zero)
    except InputError as err:
        raise SystemExit(f"error: {err}")


if __name__ == "__main__":
    main()
