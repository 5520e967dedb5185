#!/usr/bin/env python3
"""The search in space (lamodel.search.search3d.solve3d: the planar search on the cone
formulation) on extruded walls: a benchmark table.

    python benchmarks/solve3d.py                        # every case
    python benchmarks/solve3d.py --cases bond32-oop     # one case
    python benchmarks/solve3d.py --method gap --time-limit 120
    python benchmarks/solve3d.py --cases box1000,armadillo --compas DIR   # DIR holds armadillo.json
    python benchmarks/solve3d.py --cases vault,dome3x6,dome3x8,facade

Cases: ``bondC-oop`` — a running-bond wall of C courses (from the bottom 1/2 + 24 + 1/2 and
25 full blocks of 4 x 1.75, mu 0.65, as the planar benchmark's ``bondC``; bond32: 816
blocks) extruded to a depth of 1 and loaded out of plane (live load along the depth, equal
to each block's weight): it overturns as a whole, alpha = depth / height. ``wall33`` and
``wall55`` (the seed's walls) extruded, loaded in plane (the planar alpha of the first
certificate), out of plane (``-oop``) and at 45 degrees between (``-diag``). ``box1000``: the
one-room box building of :func:`lamodel.geometry.box_building` (7.6 x 5.6, 16 courses of
0.4 x 0.2 x 0.2 blocks: 1,005 blocks, a door and three windows with lintels), mu 0.6, live
load along +x equal to each block's weight. ``armadillo``: compas_cra's Armadillo vault
(399 blocks, ``armadillo.json`` from the folder given with ``--compas``; supports: the 33
blocks below z = 0.5, those compas_cra's ``armadillo_cra.json`` flags; tolerance 1e-4) under self-weight
(unit weight 1) plus a horizontal load along +x equal to each block's weight, mu 0.6.
``vault``: :func:`lamodel.geometry.barrel_vault` with its defaults; ``domeRxS``: a dome of R
rings of S voussoirs (:func:`lamodel.geometry.dome`, other defaults); ``tower``: the
circular tower of :func:`lamodel.geometry.tower` (16 staggered courses of 12 voussoirs, 192
blocks, 2,976 contact points, mu 0.7, live load along +x); ``towerCxV`` the same with C
courses of V voussoirs, options after dashes: ``-stack`` (no stagger), ``-dDEG`` (the load
turned by DEG degrees in plan), ``-muM`` (e.g. ``tower8x8-stack-d22.5-mu0.5``); ``facade``:
``instances/facade.json``.
Columns: blocks, contact points, the
associative bound and the time of its cone program, the first certified alpha and its time,
the best certified alpha and its time, the whole time and its CPU seconds (this process),
program solves (cone programs and LPs; ``--method gap``/``successive``: the LPs of
those apart), and the closed form where one applies (the first certificate's: the search
may certify lower states, e.g. blocks left behind in an out-of-plane wall).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

COURSE = 1.75
DEFAULT = ("wall33", "wall33-oop", "wall33-diag", "wall55", "wall55-oop", "wall55-diag", "bond32-oop")


def build(case: str, compas=None):
    """(Structure3D, closed-form alpha or nan) of a case name; ``compas``: the folder of
    the COMPAS samples (armadillo.json)."""
    from lamodel.formulation.extrude import extrude
    from lamodel.geometry import box_building, running_bond_wall, seed_wall
    from lamodel.io.jsonspec import structure_from_json
    name, _, load = case.partition("-")
    if name in ("vault", "facade") or name.startswith(("dome", "tower")):
        from lamodel.geometry import generators3d as G
        from lamodel.io.json3d import structure3d_from_spec
        if name == "vault":
            spec = G.barrel_vault()
        elif name.startswith("tower"):
            spec = _tower(name, load)
        elif name == "facade":
            from lamodel.io import read
            return read(ROOT / "instances" / "facade.json"), np.nan
        else:
            rings, _, per_ring = name[4:].partition("x")
            spec = G.dome(int(rings), int(per_ring))
        return structure3d_from_spec(spec), np.nan
    if name == "box1000":
        from lamodel.io.json3d import structure3d_from_spec
        return structure3d_from_spec(box_building(length=7.6, width=5.6, courses=16)), np.nan
    if name == "armadillo":
        if compas is None:
            raise SystemExit("case armadillo: give the folder holding armadillo.json with --compas DIR")
        from lamodel.io.assemblies import read_compas
        # the 33 blocks below z = 0.5 are the supports (those compas_cra's armadillo_cra.json
        # flags); of the 1,014 joints compas_cra finds, 1,010 are found at 1e-4, 886 at the default 1e-6
        return read_compas(Path(compas) / "armadillo.json", supports_below=0.5, tolerance=1e-4), np.nan
    if name in ("wall33", "wall55"):
        courses = 6 if name == "wall33" else 10
        s2 = structure_from_json(seed_wall(courses))
    elif name.startswith("bond"):
        courses = int(name[4:])
        rows = [[0.5] + [1] * 24 + [0.5] if r % 2 == 0 else [1] * 25 for r in range(courses)]
        s2 = structure_from_json(running_bond_wall(rows, name=name))
    else:
        raise SystemExit(f"unknown case '{case}'")
    s = extrude(s2, depth=1.0)
    closed = np.nan
    if load == "oop":  # live load along the depth, equal to the weight of each block
        s.live = np.column_stack([np.zeros(s.n_blocks), -s.dead[:, 2], np.zeros(s.n_blocks)])
        closed = 1.0 / (courses * COURSE)
    elif load == "diag":  # half in plane, half out of plane (45 degrees)
        w = -s.dead[:, 2] / np.sqrt(2)
        s.live = np.column_stack([w, w, np.zeros(s.n_blocks)])
    return s.validate(), closed


def _tower(name: str, options: str) -> dict:
    """The spec of a tower case: ``tower`` or ``towerCxV`` (C courses of V voussoirs), then
    options joined by ``-``: ``stack`` (joints not staggered), ``dDEG`` (the live load
    turned by DEG degrees in plan from +x), ``muM`` (friction M)."""
    import math
    from lamodel.geometry import generators3d as G
    kw = {}
    if name != "tower":
        courses, _, per = name[5:].partition("x")
        kw.update(courses=int(courses), per_course=int(per))
    for opt in filter(None, options.split("-")):
        if opt == "stack":
            kw["stagger"] = False
        elif opt.startswith("mu"):
            kw["mu"] = float(opt[2:])
        elif opt.startswith("d"):
            turn = math.radians(float(opt[1:]))
            kw["live_load"] = (math.cos(turn), math.sin(turn), 0.0)
        else:
            raise SystemExit(f"unknown tower option '{opt}' in '{name}-{options}'")
    return G.tower(**kw)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default=",".join(DEFAULT))
    ap.add_argument("--method", default="all", choices=("all", "gap", "successive"),
                    help="all: the search; gap, successive: that method alone")
    ap.add_argument("--time-limit", type=float, default=None)
    ap.add_argument("--compas", metavar="DIR", help="folder of the COMPAS samples (armadillo.json)")
    a = ap.parse_args(argv)
    from lamodel.search.search3d import solve3d
    head = (f"{'case':12s} {'blocks':>6s} {'points':>6s} {'assoc':>9s} {'t_as s':>7s} {'first':>9s} "
            f"{'t_1st s':>7s} {'best':>9s} {'t_best s':>8s} {'total s':>7s} {'cpu s':>7s} {'solves':>6s} "
            f"{'LPs':>4s} {'closed':>9s}")
    print(head)
    print("-" * len(head))
    for case in a.cases.split(","):
        t = time.perf_counter()
        s, closed = build(case, a.compas)
        t_build = time.perf_counter() - t
        cpu = time.process_time()
        r = solve3d(s, method=a.method, explore=a.method == "all", time_limit=a.time_limit)
        cpu = time.process_time() - cpu
        t_best = r.history[-1][0] if r.history else np.nan
        print(f"{case:12s} {s.n_blocks:6d} {s.n_points:6d} {r.associative:9.6f} {r.associative_time:7.2f} "
              f"{r.first_alpha:9.6f} {r.first_time:7.2f} {r.alpha:9.6f} {t_best:8.2f} {r.seconds:7.2f} {cpu:7.2f} "
              f"{r.n_cone:6d} {r.n_lp:4d} {closed:9.6f}   (build {t_build:.1f} s; {r.status}; {r.path})", flush=True)


if __name__ == "__main__":
    main()
