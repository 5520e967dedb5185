#!/usr/bin/env python3
"""The joints' strengths in space (the point-contact model): convergence and cost.

    python benchmarks/materials3d.py                      # both tables
    python benchmarks/materials3d.py --cases bond32-oop   # the second table on cases of solve3d.py

1. A 2 x 1 x 4 box on the ground (unit weight: W = 8), f_c = 16, mu = 5, its base's
   points the vertices or a ``grid:n``: alpha against the planar stress block's
   (B/2 - W / (2 f_c b)) / (H/2) = 0.375, and the points' count and time.
2. Structures in space (a running-bond wall panel, a barrel vault, a dome, the facade
   instance): dry, f_c = 10^9 (every cap far: the capped programs) and two finite f_c
   (multiples of the weight over the supports' interface area), and cohesion
   c0 = 0.1 sigma: alpha, time, the first certificate's time, cone programs and LPs with
   the defaults. ``--cases``: the cases of ``benchmarks/solve3d.py`` instead (``bond32-oop``:
   the 816-block running-bond wall loaded out of plane). A measurement, not a test: the
   tests assert the values (tests/materials/test_joints3d.py). ``--joints``: some of the
   variants (dry, fc1e9, fc20, fc5, c0); ``--time-limit``: seconds a solve; ``x first``: the
   time over the first variant's (the dry one's by default); ``path``: what certified the
   state reported (``dry``: the dry certificate).

    python benchmarks/materials3d.py --cases bond32-oop --joints dry --time-limit 90
"""
import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from lamodel.geometry.generators3d import barrel_vault, dome, wall_panel  # noqa: E402
from lamodel.io import read  # noqa: E402
from lamodel.io.json3d import structure3d_from_spec  # noqa: E402
from lamodel.search.search3d import solve3d  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
A, B, H, FC = 2.0, 1.0, 4.0, 16.0


def cuboid(x0, y0, z0, x1, y1, z1):
    return [[x, y, z] for z in (z0, z1) for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]


def grid_table():
    exact = (A / 2 - A * B * H / (2 * FC * B)) / (H / 2)
    rows = []
    for points in ("vertices", "grid:2", "grid:4", "grid:8", "grid:16"):
        spec = {"name": "box", "dimension": 3, "mu": 5.0, "fc": FC, "contact_points": points, "blocks": [
            {"id": "ground", "support": True, "vertices": cuboid(-2, -1, -0.5, 2, 1, 0)},
            {"id": "B", "vertices": cuboid(-A / 2, -B / 2, 0, A / 2, B / 2, H)}]}
        s = structure3d_from_spec(spec)
        t = time.perf_counter()
        r = solve3d(s)
        rows.append({"contact points": points, "points": s.n_points, "alpha": round(r.alpha, 6),
                     "stress block": exact, "error": f"{(r.alpha - exact) / exact:+.2e}",
                     "seconds": round(time.perf_counter() - t, 2)})
    return pd.DataFrame(rows)


def reference_stress(s):
    """The blocks' weight over the area of the interfaces on supports."""
    on_support = np.isin(np.asarray(s.iface_a)[s.point_interface], s.supports)
    return float(-s.dead[:, 2].sum() / s.areas()[on_support].sum())


def structures():
    yield structure3d_from_spec(wall_panel(length=2.4, courses=8))
    yield structure3d_from_spec(barrel_vault(n_voussoirs=9))
    yield structure3d_from_spec(dome(n_rings=4, n_per_ring=8))
    yield read(ROOT / "instances" / "facade.json")


#: The variants of a structure: key -> (label, fc and c0 as multiples of sigma; 1e9: f_c itself).
JOINTS = {"dry": ("dry", None, None), "fc1e9": ("fc 1e9", 1e9, None), "fc20": ("fc 20 sigma", 20, None),
          "fc5": ("fc 5 sigma", 5, None), "c0": ("c0 0.1 sigma", None, 0.1)}


def joints(s, sigma, keys=tuple(JOINTS)):
    """(label, fc, cohesion) of the variants ``keys`` of one structure, in that order."""
    for key in keys:
        label, fc, c0 = JOINTS[key]
        yield label, None if fc is None else (fc if fc == 1e9 else fc * sigma), None if c0 is None else c0 * sigma


def structure_table(structures, keys=tuple(JOINTS), time_limit=None):
    rows = []
    for s in structures:
        sigma = reference_stress(s)
        dry_time = None
        for label, fc, c0 in joints(s, sigma, keys):
            v = s
            if fc is not None:
                v = replace(v, fc=np.full(s.n_points, fc), area=s.areas())
            if c0 is not None:
                v = replace(v, cohesion=np.full(s.n_points, c0), area=s.areas())
            t = time.perf_counter()
            r = solve3d(v, time_limit=time_limit)
            sec = time.perf_counter() - t
            dry_time = dry_time or sec
            rows.append({"structure": s.name, "blocks": s.n_blocks, "points": s.n_points, "joints": label,
                         "fc": np.nan if fc is None else round(fc, 4), "c0": np.nan if c0 is None else round(c0, 4),
                         "alpha": r.alpha, "status": r.status, "first s": round(r.first_time, 2),
                         "seconds": round(sec, 2), "cones": r.n_cone, "LPs": r.n_lp,
                         "x first": round(sec / dry_time, 1), "path": r.path.split("+")[0]})
            print(pd.DataFrame(rows[-1:]).to_string(index=False, header=len(rows) == 1), flush=True)
    return pd.DataFrame(rows)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", help="cases of benchmarks/solve3d.py (comma-separated) instead of the defaults")
    ap.add_argument("--joints", default=",".join(JOINTS),
                    help=f"the variants, comma-separated, of {', '.join(JOINTS)} (default: all, in that order)")
    ap.add_argument("--time-limit", type=float, help="seconds a solve (default: none, the work bounds)")
    a = ap.parse_args(argv)
    keys = tuple(a.joints.split(","))
    bad = [k for k in keys if k not in JOINTS]
    if bad:
        ap.error(f"--joints: unknown variant {bad[0]!r}; expected some of {', '.join(JOINTS)}")
    if a.cases:
        sys.path.insert(0, str(ROOT / "benchmarks"))
        from solve3d import build
        table = structure_table((build(case)[0] for case in a.cases.split(",")), keys, a.time_limit)
    else:
        print(grid_table().to_string(index=False), flush=True)
        print()
        table = structure_table(structures(), keys, a.time_limit)
    print()
    print(table.to_string(index=False))


if __name__ == "__main__":
    main()
