#!/usr/bin/env python3
"""Where the gap alternation stops in space, and whether the stop is real: a diagnosis.

    python benchmarks/stall3d.py --cases armadillo --compas DIR
    python benchmarks/stall3d.py --cases vault,dome3x6
    python benchmarks/stall3d.py --cases tower,tower6x12-d30

For each case (the names of ``benchmarks/solve3d.py``) it runs the associative cone
program and the gap alternation from its statics (the search's first start), then, at the
statics x where the alternation ends:

1. the gap ``g(x) = alpha_K(-mu N(x)) - alpha(x)`` (eq. 5) of the least-alpha_K mechanism,
   split into its opening part (``-N open`` at points the mechanism opens and x
   compresses) and its sliding part, and how many points hold half, three quarters and
   nine tenths of it;
2. whether the stop is an artefact of the solver's accuracy: the mechanism step and a gap
   step (rho = 1e3) again at Clarabel tolerances 1e-8 and 1e-11 — a real partial optimum
   of the bilinear gap keeps the same gap and the same least gap over S;
3. whether x is a collapse state after all: a mechanism compatible with x
   (:func:`lamodel.search.certify3d.mechanism_lp`, opening only where N = 0, slip only on
   the cone along T) at contact tolerances 1e-9 .. 1e-5;
4. the seed's chain ``c <- -mu N(cohesive statics)`` from x, plain and averaged (weight
   0.2), a few steps: its alpha_as, flow counts, blocks moving and certificates.

Columns and lines are printed as they come; program counts and CPU seconds at the end.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from solve3d import build  # noqa: E402  (the benchmark cases)

CHAIN_STEPS = 8
AVERAGED = 0.2


def gap_parts(p, x, u, xi):
    """(gap, opening part, sliding part, points holding 50/75/90 % of the gap)."""
    n = p.np
    contrib = p.gap_weights(xi, u)[:3 * n] * x[:3 * n]
    per_point = contrib[:n] + contrib[n:2 * n] + contrib[2 * n:]
    q = p.form.strains(u)
    opening = -p.N_of(x) * np.maximum(q[:n], 0.0) * (xi[:n] > 0)
    total = per_point.sum()
    cum = np.cumsum(np.sort(per_point)[::-1]) / total if total > 0 else np.ones(1)
    held = [int(np.searchsorted(cum, f)) + 1 for f in (0.5, 0.75, 0.9)]
    return total, opening.sum(), total - opening.sum(), held


def accuracy(p, x):
    """The mechanism and gap steps again at two Clarabel tolerances: (tol, gap, least gap)."""
    from lamodel.search import cone
    kept = cone.CONE_TOLERANCE
    rows = []
    try:
        for tol in (1e-8, 1e-11):
            cone.CONE_TOLERANCE = tol
            r = p.cone.cohesive(-p.mu * p.N_of(x))
            if not r.ok or r.u is None:
                rows.append((tol, np.nan, np.nan))
                continue
            xi = p.flows(r.u)
            w = p.gap_weights(xi, r.u)
            step = p.cone.statics(1e3 * w)
            rows.append((tol, p.gap(x, xi, r.u), float(w @ step.x[:3 * p.np]) if step.ok else np.nan))
    finally:
        cone.CONE_TOLERANCE = kept
    return rows


def chain(engine, x, weight):
    """The seed's chain from x (``weight`` 1: plain; < 1: averaged), CHAIN_STEPS steps."""
    p = engine.problem
    n = p.np
    c = -p.mu * p.N_of(x)
    for step in range(CHAIN_STEPS):
        status, a, xc, u, xi = p.mechanism(c)
        if status != "optimal":
            print(f"    step {step}: cohesive program {status}")
            return
        st = engine.certifier.certify(u, xi, "chain")
        moving = np.linalg.norm(u.reshape(-1, 6), axis=1)
        c_new = (1.0 - weight) * c + weight * (-p.mu * p.cohesive_N(xc))
        change = np.abs(c_new - c).max() / max(np.abs(c).max(), 1e-300)
        print(f"    step {step}: alpha_as {a:.6f}, opening {int((xi[:n] > 0).sum())}, sliding "
              f"{int((xi[n:] > 0).sum())}, blocks moving {int((moving > 1e-3 * moving.max()).sum())}, "
              f"certified {'-' if st is None else f'{st.alpha:.6f}'}, cohesions change {change:.1e}", flush=True)
        if change <= 1e-6:
            print("    a fixed point")
            return
        c = c_new


def diagnose(case, compas):
    from lamodel.search.certify3d import mechanism_lp
    from lamodel.search.gap import GapSearch
    s, _ = build(case, compas)
    cpu = time.process_time()
    engine = GapSearch(s)
    p = engine.problem
    from lamodel.search.gap.phases import associative
    status, a_assoc, x_assoc = associative(engine)
    print(f"{case}: {s.n_blocks} blocks, {s.n_points} points; associative {status} {a_assoc:.6f}", flush=True)
    if status != "ok":
        return
    best, x = engine.alternation.alternate(x_assoc, source="gap")
    status, a_k, _, u, xi = p.mechanism(-p.mu * p.N_of(x))
    print(f"  alternation: alpha {x[-1]:.6f}, certified {'-' if best is None else f'{best.alpha:.6f}'}, "
          f"{p.n_lps()} programs", flush=True)
    if status != "optimal":
        print(f"  mechanism step at the end: {status}")
        return
    gap, opening, sliding, held = gap_parts(p, x, u, xi)
    n = p.np
    compressed = (xi[:n] > 0) & (p.N_of(x) < -1e-6 * np.abs(p.N_of(x)).max())
    print(f"  1. gap {gap:.3e} (alpha_K {a_k:.6f}): opening part {opening:.3e}, sliding part {sliding:.3e}; "
          f"points holding 50/75/90 %: {held[0]}/{held[1]}/{held[2]}; the mechanism opens "
          f"{int((xi[:n] > 0).sum())} points, {int(compressed.sum())} of them compressed by x", flush=True)
    for tol, g, least in accuracy(p, x):
        print(f"  2. Clarabel tolerance {tol:.0e}: gap {g:.6e}, least gap over S for its mechanism {least:.6e}",
              flush=True)
    N, T1, T2 = p.form.split(x)
    found = [tol for tol in (1e-9, 1e-7, 1e-5) if mechanism_lp(p.form, N, T1, T2, tol=tol) is not None]
    print(f"  3. a mechanism compatible with x at contact tolerances {found or 'none of 1e-9, 1e-7, 1e-5'}",
          flush=True)
    for weight in (1.0, AVERAGED):
        print(f"  4. chain from x, weight {weight}:")
        chain(engine, x, weight)
    print(f"  {p.n_lps()} programs, {time.process_time() - cpu:.1f} s CPU")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default="armadillo")
    ap.add_argument("--compas", metavar="DIR", help="folder of the COMPAS samples (armadillo.json)")
    a = ap.parse_args(argv)
    for case in a.cases.split(","):
        diagnose(case, a.compas)


if __name__ == "__main__":
    main()
