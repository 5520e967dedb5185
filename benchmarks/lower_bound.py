#!/usr/bin/env python3
"""The proven lower bound alpha_lower against the certified alpha, in the plane and in space.

    python benchmarks/lower_bound.py                          # shipped and generated instances
    python benchmarks/lower_bound.py wall33.dat arch9         # some of them
    python benchmarks/lower_bound.py --prove 600 wall33.dat   # the branch-and-bound for 600 s

For each instance: the search (``lamodel.search.driver.solve``, or ``solve3d`` in space,
default options), then ``lamodel.bound.lower_bound`` with the certified alpha as the top of
the range, in the default budget of ``lamodel solve``
(:func:`lamodel.bound.lower.default_budget`) or ``--prove`` seconds. Prints one Markdown
row per instance: alpha, alpha_lower, their ratio, proven, the search's wall seconds, the
bound's CPU seconds and their ratio, rounds, nodes, LPs. A benchmark: nothing is asserted.
Under load, compare the LP counts; the seconds are inflated.
"""
import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def generated():
    """Generated instances: name -> spec (JSON dict)."""
    from lamodel.geometry.generators import arch, portal, seed_wall
    from lamodel.geometry.generators3d import wall_panel
    def box(x0, y0, z0, x1, y1, z1):
        return [[x, y, z] for z in (z0, z1) for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]
    block3d = {"name": "block3d", "dimension": 3, "mu": 0.6, "unit_weight": 1.0, "live_load": [1.0, 0.0, 0.0],
               "blocks": [{"id": "ground", "support": True, "vertices": box(-2, -2, -0.5, 2, 2, 0)},
                          {"id": "B", "vertices": box(-0.5, -0.25, 0, 0.5, 0.25, 2)}]}
    return {"arch9": arch(9), "arch21": arch(21), "portal7": portal(7), "wall4courses": seed_wall(4),
            "wall8courses": seed_wall(8), "block3d": block3d, "panel3d": wall_panel(length=1.2, courses=3)}


def load(name, specs):
    from lamodel.io import read
    from lamodel.io.jsonspec import structure_from_json
    if name in specs:
        spec = specs[name]
        if spec.get("dimension") == 3:
            from lamodel.io.json3d import structure3d_from_spec
            return structure3d_from_spec(spec)
        return structure_from_json(spec)
    return read(ROOT / "instances" / name)


def search(s):
    """(certified alpha or None, wall seconds) of the default search."""
    from lamodel.structure3d import Structure3D
    t = time.perf_counter()
    if isinstance(s, Structure3D):
        from lamodel.search.search3d import solve3d
        r = solve3d(s)
        return (r.alpha if r.state is not None else None), time.perf_counter() - t
    else:
        from lamodel.search.driver import SolveOptions, solve
        o = solve(s, SolveOptions(progress=False))
    return (o.best.alpha if o.certified else None), time.perf_counter() - t


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("names", nargs="*", help="file names in instances/ or generated names (default: all)")
    p.add_argument("--prove", type=float, default=None, help="seconds for the bound (default: solve's default)")
    args = p.parse_args(argv)
    from lamodel.bound.lower import default_budget, lower_bound
    specs = generated()
    names = args.names or (sorted(f.name for f in (ROOT / "instances").iterdir() if f.suffix == ".dat")
                           + ["facade.json"] + list(specs))
    print("| instance | blocks | contacts | alpha | alpha_lower | alpha_lower / alpha | proven | search s "
          "| bound CPU s | bound / search | rounds | nodes | LPs |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name in names:
        s = load(name, specs)
        contacts = getattr(s, "n_points", None) or s.n_contacts
        alpha, seconds = search(s)
        if alpha is None:
            print(f"| {name} | {s.n_blocks} | {contacts} | (not certified) | | | | {seconds:.2f} | | | | | |")
            continue
        limits = {"budget": args.prove} if args.prove is not None else default_budget(seconds, s)
        cpu = time.process_time()
        lb = lower_bound(s, alpha, **limits)
        cpu = time.process_time() - cpu
        print(f"| {name} | {s.n_blocks} | {contacts} | {alpha:.6f} | {lb.alpha_lower:.6f} | "
              f"{lb.alpha_lower / alpha:.6f} | {'yes' if lb.proven_global else 'no'} | {seconds:.2f} | "
              f"{cpu:.2f} | {cpu / seconds:.2f} | {lb.rounds} | {lb.nodes} | {lb.lps} |", flush=True)


if __name__ == "__main__":
    main()
