#!/usr/bin/env python3
"""The certified search on generated families of structures, not on one wall.

    python benchmarks/families.py --quick                  # small sizes (minutes)
    python benchmarks/families.py                          # 50 to 2,000 blocks
    python benchmarks/families.py --quick --families bond,arch --csv results/families.csv
    python benchmarks/families.py --families bond --write walls/   # the structure files only

Families (each varies what users vary; mu from 0.3 to 1.0):

* ``bond``: running-bond walls (4 x 1.75 blocks, horizontal live load equal to the weight),
  squat to 2,000 blocks;
* ``stack``: stack-bond walls (every course of full blocks: continuous head joints);
* ``slender`` and ``squat``: tall narrow and long low running-bond walls;
* ``openings``: running-bond walls with doors and windows under lintels
  (:func:`lamodel.geometry.wall_with_openings`);
* ``arch`` and ``portal``: the seed's kinds, ring thickness varied;
* ``point``: a vertical live point load on an arch's haunch, and a horizontal one on the top
  course of a wall (only those loads are multiplied);
* ``multileaf``: the cross-section of a multi-leaf wall (two or three leaves of stacked
  stones, a through-stone across the leaves every few courses, continuous collar joints
  between), loaded out of its plane by a horizontal load equal to the weight;
* ``stones``: panels of irregular convex stones (centroidal Voronoi cells,
  :func:`lamodel.geometry.stone_wall`), several seeds and sizes, mu 0.5 to 0.8;
* ``friction``: running-bond walls at the frictions between the others' (0.5, 0.75, 0.8);
* ``direction``: running-bond walls loaded toward -x, and along +x inclined 30 degrees
  up and down;
* ``buttress``: a running-bond wall with a buttress of stacked long blocks at one end,
  loaded toward it and away from it;
* ``order``: one wall written in other orders (blocks shuffled, the ground first, ids
  renamed): the same structure, whose certificate must not depend on how it is written;
* in space (``benchmarks/families3d.py``): ``dome``, ``vault``, ``tower``, ``building``
  (box buildings, a façade), ``pyramid`` (a top box that slides, pushed in three
  directions), ``extruded`` (the seed's wall out of plane and at 45 degrees), and with
  ``--compas DIR`` the COMPAS samples of DIR.

Each case runs the default search (``lamodel solve`` with no options: its own stopping
rule) in its own process; with ``--all-below B`` (default 40 blocks in --quick, 0
otherwise), also every published method (``--method all``). Per case: status, certified
alpha, the path that certified it (runs.csv's ``path``), the lane that reached the best
(``best_by``: the first state within 1e-9 of the final alpha; later states lower by
round-off do not count), time to the first certificate and to the best, LP solves at the
first certificate and at the best, and the gap of the
default run's alpha to the least certified alpha any method found. Per family: success
rate over the cases stable under dead load, median times, worst gap. A benchmark, not a
test: nothing is asserted. Times depend on the machine's load; LP counts do not.
"""
from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

MUS = (0.3, 0.65, 0.9, 1.0)


# ------------------------------------------------------------------ instances
def _bond_rows(courses, blocks, stack=False):
    if stack:
        return [[1] * blocks for _ in range(courses)]
    return [[0.5] + [1] * (blocks - 1) + [0.5] if r % 2 == 0 else [1] * blocks for r in range(courses)]


def _wall(courses, blocks, mu, stack=False, name="wall"):
    from lamodel.geometry import running_bond_wall
    return running_bond_wall(_bond_rows(courses, blocks, stack), mu=mu, name=name)


def _multileaf(leaves, courses, every, mu, name):
    from lamodel.geometry import running_bond_wall
    rows = [[leaves] if r % every == every - 1 else [1] * leaves for r in range(courses)]
    # leaves 0.25 thick, courses 0.2 high (the section's proportions; the load is the weight)
    return running_bond_wall(rows, full=0.25, height=0.2, mu=mu, name=name)


def _openings(courses, width, mu, name):
    from lamodel.geometry import wall_with_openings
    w = width
    if courses < 10:  # one door
        openings = ((w // 2 - 1, w // 2 + 1, 0, courses - 2),)
    else:  # a door and a window on each storey
        openings = ((2, 4, 0, 7), (w - 5, w - 3, 3, 8))
        if courses >= 16:
            openings += ((w - 5, w - 3, 10, 14),)
    return wall_with_openings(courses=courses, width=width, openings=openings, mu=mu, name=name)


def _arch(thickness, mu, name, point=False):
    from lamodel.geometry import arch
    spec = arch(n_voussoirs=13, inner_radius=5.0, thickness=thickness, mu=mu, name=name)
    if point:
        # a vertical live point load on the top face of the fourth voussoir (the haunch)
        v = next(b for b in spec["blocks"] if b["id"] == "v4")
        xs = np.array(v["vertices"], float)
        top = xs[np.argsort(-np.hypot(xs[:, 0], xs[:, 1] + 0.0))[:2]]  # the two extrados corners
        at = top.mean(axis=0)
        spec.pop("live_load", None)
        spec["loads"] = [{"block": "v4", "at": [float(at[0]), float(at[1])], "force": [0.0, -1.0]}]
    return spec


def _portal(thickness, mu, name):
    from lamodel.geometry import portal
    return portal(n_voussoirs=11, inner_radius=3.0, thickness=thickness, mu=mu, name=name)


def _wall_point(courses, blocks, mu, name):
    spec = _wall(courses, blocks, mu, name=name)
    top = max((b for b in spec["blocks"] if not b.get("support")), key=lambda b: max(v[1] for v in b["vertices"])
              + 1e-6 * max(v[0] for v in b["vertices"]))
    xs = np.array(top["vertices"], float)
    y = xs[:, 1].max()
    x = xs[:, 0].min()
    spec.pop("live_load", None)
    spec["loads"] = [{"block": top["id"], "at": [float(x), float(y)], "force": [1.0, 0.0]}]
    return spec


def _stones(n, seed, mu, name):
    from lamodel.geometry import stone_wall
    width = 2.0 * np.sqrt(n / 10.0)  # stones of about the same size whatever their number
    return stone_wall(n, width=width, height=width / 2, seed=seed, mu=mu, name=name)


def _directed(courses, blocks, mu, degrees, sign, name):
    spec = _wall(courses, blocks, mu, name=name)
    a = np.radians(degrees)
    spec["live_load"] = [float(sign * np.cos(a)), float(np.sin(a))]
    return spec


def _buttress(courses, blocks, mu, sign, name):
    """A running-bond wall whose right end is a buttress two blocks long, one per course."""
    from lamodel.geometry import running_bond_wall
    rows = [r + [2] if r[-1] == 1 else r[:-1] + [2.5] for r in _bond_rows(courses, blocks)]
    return running_bond_wall(rows, mu=mu, live_load=(float(sign), 0.0), name=name)


def _reordered(courses, blocks, mu, how, name):
    """The same wall written another way: ``shuffled`` blocks, the ``ground-first``, or
    ``renamed`` ids (the order kept)."""
    spec = _wall(courses, blocks, mu, name=name)
    rng = np.random.default_rng(courses * 1000 + blocks)
    bodies = spec["blocks"]
    if how == "shuffled":
        spec["blocks"] = [bodies[i] for i in rng.permutation(len(bodies))]
    elif how == "ground-first":
        spec["blocks"] = bodies[-1:] + bodies[:-1]
    elif how == "renamed":
        for k, b in zip(rng.permutation(len(bodies)), bodies):
            b["id"] = f"{'support' if b.get('support') else 'stone'}-{k:05d}"
    return spec


def cases(quick: bool):
    """(family, case name, JSON-spec builder) for every case."""
    out = []
    if quick:
        sizes = {"bond": [(5, 10), (10, 10)], "stack": [(5, 10)], "slender": [(12, 3)], "squat": [(3, 15)],
                 "openings": [(6, 8)], "multileaf": [(2, 12, 4)]}
        thick = {"arch": (0.6, 1.5), "portal": (1.5,)}
        mus = MUS
    else:
        sizes = {"bond": [(10, 10), (20, 25), (40, 25), (80, 25)], "stack": [(10, 10), (20, 25)],
                 "slender": [(30, 4), (60, 8)], "squat": [(4, 25), (6, 50)], "openings": [(12, 12), (16, 20)],
                 "multileaf": [(2, 24, 4), (3, 24, 4), (2, 60, 5), (3, 100, 5)]}
        thick = {"arch": (0.5, 1.0, 1.5), "portal": (1.0, 1.5)}
        mus = MUS
    for fam in ("bond", "stack", "slender", "squat"):
        for c, b in sizes[fam]:
            for mu in mus:
                name = f"{fam}{c}x{b}_mu{mu:g}"
                out.append((fam, name, (lambda c=c, b=b, mu=mu, name=name, fam=fam:
                                        _wall(c, b, mu, stack=fam == "stack", name=name))))
    for c, w in sizes["openings"]:
        for mu in mus:
            name = f"openings{c}x{w}_mu{mu:g}"
            out.append(("openings", name, lambda c=c, w=w, mu=mu, name=name: _openings(c, w, mu, name)))
    for leaves, c, every in sizes["multileaf"]:
        for mu in mus:
            name = f"multileaf{leaves}x{c}_mu{mu:g}"
            out.append(("multileaf", name, lambda leaves=leaves, c=c, every=every, mu=mu, name=name:
                        _multileaf(leaves, c, every, mu, name)))
    for fam, build in (("arch", _arch), ("portal", _portal)):
        for t in thick[fam]:
            for mu in (0.3, 0.5, 0.9):
                name = f"{fam}_t{t:g}_mu{mu:g}"
                out.append((fam, name, lambda t=t, mu=mu, name=name, build=build: build(t, mu, name)))
    stones = [(40, 0), (40, 1), (80, 2)] if quick else [(40, 0), (80, 1), (160, 2), (160, 3), (320, 4)]
    for n, seed in stones:
        for mu in (0.5, 0.65, 0.8):
            name = f"stones{n}_s{seed}_mu{mu:g}"
            out.append(("stones", name, lambda n=n, seed=seed, mu=mu, name=name: _stones(n, seed, mu, name)))
    for c, b in sizes["bond"][:2 if quick else 3]:
        for mu in (0.5, 0.75, 0.8):
            name = f"friction{c}x{b}_mu{mu:g}"
            out.append(("friction", name, lambda c=c, b=b, mu=mu, name=name: _wall(c, b, mu, name=name)))
        for degrees, sign, word in ((0, -1, "minus_x"), (30, 1, "up30"), (-30, 1, "down30")):
            for mu in (0.65, 0.9):
                name = f"direction{c}x{b}_{word}_mu{mu:g}"
                out.append(("direction", name, lambda c=c, b=b, mu=mu, d=degrees, sg=sign, name=name:
                            _directed(c, b, mu, d, sg, name)))
        for sign, word in ((1, "toward"), (-1, "away")):
            name = f"buttress{c}x{b}_{word}_mu0.65"
            out.append(("buttress", name, lambda c=c, b=b, sg=sign, name=name: _buttress(c, b, 0.65, sg, name)))
    for c, b in ([(10, 10)] if quick else [(10, 10), (40, 25), (80, 25)]):
        for mu in (0.65, 0.9):
            for how in ("as-written", "shuffled", "ground-first", "renamed"):
                name = f"order{c}x{b}_{how}_mu{mu:g}"
                out.append(("order", name, lambda c=c, b=b, mu=mu, how=how, name=name: _reordered(c, b, mu, how, name)))
    for mu in (0.5, 0.9):
        name = f"point_arch_mu{mu:g}"
        out.append(("point", name, lambda mu=mu, name=name: _arch(1.0, mu, name, point=True)))
        c, b = sizes["bond"][0]
        name = f"point_wall{c}x{b}_mu{mu:g}"
        out.append(("point", name, lambda c=c, b=b, mu=mu, name=name: _wall_point(c, b, mu, name)))
    return out


# ------------------------------------------------------------------------ runs
def _without(names):
    """The plan without the strategies named (runs.csv's path words, e.g. "continuation"):
    a lane earns its place by what the families lose without it."""
    from lamodel.search import plan
    from lamodel.search.gap.lanes import Lane

    def cut(lane):
        return Lane(tuple(s for s in lane.strategies if s.name not in names), lane.until_certified)
    plan.IF_STALLED = cut(plan.IF_STALLED)
    plan.BESIDE_STALLED = tuple(cut(lane) for lane in plan.BESIDE_STALLED)
    # a lane cut to nothing is left out (the lanes beside each other share the work bounds)
    plan.CONTINUATIONS = tuple(lane for lane in map(cut, plan.CONTINUATIONS) if lane.strategies)
    plan.PUBLISHED = cut(plan.PUBLISHED)
    plan.SLOW = cut(plan.SLOW)
    plan.MPEC_LANE = cut(plan.MPEC_LANE)


def _assignments(items):
    """--tuning NAME=VALUE items as (name, value), checked here, before any case runs."""
    import lamodel.search.tuning as tuning
    out = []
    for item in items:
        name, _, value = item.partition("=")
        try:
            number = float(value)
        except ValueError:
            raise SystemExit(f"--tuning {item}: expected NAME=NUMBER") from None
        if not hasattr(tuning, name):
            raise SystemExit(f"--tuning {item}: no constant {name} in lamodel.search.tuning")
        out.append((name, number))
    return tuple(out)


def _tune(assignments):
    """(name, value) pairs: a constant of lamodel.search.tuning set for this run, in every
    module that holds it (to show its effect across the families)."""
    import sys
    for name, value in assignments:
        for module in list(sys.modules.values()):
            if getattr(module, "__name__", "").startswith("lamodel") and hasattr(module, name):
                setattr(module, name, value)


def _run(spec, all_methods, total_work, queue, without=(), tuning=()):
    from lamodel.io.jsonspec import structure_from_json
    from lamodel.search import driver
    from lamodel.search.driver import PATHS, SolveOptions, path_of, solve
    if total_work is not None:
        driver.TOTAL_WORK = total_work
    _tune(tuning)
    if without:
        _without(set(without))
    space = spec.get("dimension") == 3 or "_read" in spec
    if space:
        from families3d import read_case
        s = read_case(spec)
    else:
        s = structure_from_json(spec)
    t = time.perf_counter()
    o = solve(s, SolveOptions())
    total = time.perf_counter() - t
    h = o.history
    # the best: the first state within round-off (1e-9) of the final alpha, and its lane (a
    # later state lower by 1e-12 is not what found the collapse state)
    final = h[-1][1] if h else np.nan
    best = next((e for e in h if e[1] <= final + 1e-9 * max(1.0, abs(final))), None)
    word = best[2].replace("-", "+").split("+")[0] if best else ""
    row = dict(blocks=s.n_blocks, status=o.status, alpha=o.best.alpha if o.best else np.nan,
               path=path_of(o.best), best_by=PATHS.get(word, word), assoc=o.alpha_associative,
               t_first=h[0][0] if h else np.nan, t_best=best[0] if best else np.nan, total=total,
               lps=o.runs[0].iterations if o.runs else 0, lps_first=o.lps_first,
               lps_best=best[3] if best else np.nan)
    # the LP solves at the best state, in units of the first phase's (TOTAL_WORK's unit)
    row["best_lps_ratio"] = row["lps_best"] / row["lps_first"] if h and o.lps_first else np.nan
    # the search's LP work against the default run's size bound (WORK_PER_BLOCK: binds at 1)
    from lamodel.search.tuning import WORK_FLOOR_CONE, WORK_PER_BLOCK, WORK_PER_BLOCK_CONE
    bound = max(WORK_FLOOR_CONE, WORK_PER_BLOCK_CONE * s.n_blocks) if space else WORK_PER_BLOCK * s.n_blocks
    row["work_ratio"] = o.work / bound
    least = row["alpha"]
    if all_methods and space:  # the published methods in space, each certified and bounded
        from families3d import published3d
        for m, alpha in published3d(s).items():
            row[f"alpha_{m}"] = alpha
            if np.isfinite(alpha) and not (least <= alpha):
                least = alpha
    elif all_methods:
        from lamodel.search.methods import METHODS, run_method
        for m in METHODS[:-1]:  # lamodel's own is the run above
            r = run_method(m, s, SolveOptions())
            row[f"alpha_{m}"] = r.alpha_certified
            if np.isfinite(r.alpha_certified) and not (least <= r.alpha_certified):
                least = r.alpha_certified
    row["least"] = least
    # seconds of each phase and lane of the search (the plan's names), for the lane table
    row["phases"] = json.dumps({k: round(v, 4) for k, v in o.phases.items()})
    row["search_seconds"] = total
    queue.put(row)


def run_case(spec, all_methods, timeout, total_work=None, without=(), tuning=()):
    ctx = mp.get_context("spawn")
    queue = ctx.Queue()
    p = ctx.Process(target=_run, args=(spec, all_methods, total_work, queue, tuple(without), tuple(tuning)))
    t = time.perf_counter()
    p.start()
    try:
        row = queue.get(timeout=timeout)
    except Exception:
        row = dict(status="timeout", alpha=np.nan)
    p.join(5)
    if p.is_alive():
        p.kill()
    row["process"] = time.perf_counter() - t
    return row


def summarise(df):
    import pandas as pd
    rows = []
    for fam, g in df.groupby("family", sort=False):
        stable = g[g.status != "unstable"]
        ok = stable.status == "certified"
        gap = (stable.alpha / stable.least - 1.0).where(ok)
        rows.append(dict(family=fam, cases=len(g), stable=len(stable), certified=int(ok.sum()),
                         success=f"{ok.mean():.0%}" if len(stable) else "-",
                         t_first_med=stable.t_first.median(), t_best_med=stable.t_best.median(),
                         total_max=stable.process.max(), worst_gap=gap.max(),
                         best_lps_ratio_med=stable.best_lps_ratio.median(),
                         best_lps_ratio_max=stable.best_lps_ratio.max(),
                         work_ratio_max=stable.work_ratio.max(),
                         best_by=", ".join(f"{k} {v}" for k, v in stable.best_by[ok].value_counts().items())))
    return pd.DataFrame(rows)


def lane_table(df):
    """Per lane of the plan: on how many cases (and families) its state was the final best
    (runs.csv's ``path``), on how many it ran, and its median and largest share of the
    search's seconds where it ran (phases timed in the search's own thread; lanes beside
    it on engines of their own are counted in the phase that waits for them)."""
    import pandas as pd
    ok = df[df.status == "certified"]
    best = ok.groupby("best_by").agg(best_cases=("case", "size"), best_families=("family", "nunique"))
    shares = {}
    for _, r in df.iterrows():
        if not isinstance(r.get("phases"), str):
            continue
        for name, sec in json.loads(r["phases"]).items():
            shares.setdefault(name, []).append(sec / max(r["search_seconds"], 1e-9))
    timed = pd.DataFrame([dict(lane=k, ran=len(v), share_median=float(np.median(v)), share_max=max(v))
                          for k, v in shares.items()])
    return best.reset_index().rename(columns={"best_by": "lane (that reached the best)"}), timed


def main(argv=None):
    import pandas as pd
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="small sizes only")
    ap.add_argument("--families", default="", help="comma-separated families to run (default: all)")
    ap.add_argument("--all-below", type=int, default=300,
                    help="also run --method all on cases with at most this many blocks (default 300; 0: never)")
    ap.add_argument("--timeout", type=float, default=900.0, help="seconds a case may take (whole process)")
    ap.add_argument("--total-work", type=float, default=None,
                    help="the driver's TOTAL_WORK for this run (default: lamodel.search.tuning's; inf: no bound), "
                         "to show the bound's effect across the families")
    ap.add_argument("--lanes", action="store_true",
                    help="also print the lane table: which lane gave the final best, and each phase's share of the time")
    ap.add_argument("--max-blocks", type=int, default=None, help="only the cases with at most this many blocks")
    ap.add_argument("--cases", default="", help="comma-separated case names to run (default: all)")
    ap.add_argument("--without", default="",
                    help="comma-separated strategies left out of the plan (their names in runs.csv's path, "
                         "e.g. continuation): what the families lose without a lane")
    ap.add_argument("--tuning", action="append", default=[], metavar="NAME=VALUE",
                    help="a constant of lamodel.search.tuning set for this run (repeatable)")
    ap.add_argument("--compas", metavar="DIR", help="also the COMPAS sample assemblies of DIR (family compas)")
    ap.add_argument("--csv", default=str(ROOT / "results" / "families.csv"))
    ap.add_argument("--write", metavar="DIR", help="write each case's structure file (CASE.json) to DIR, solve none "
                    "(then: lamodel solve DIR/CASE.json)")
    args = ap.parse_args(argv)
    tuned = _assignments(args.tuning)
    all_below = args.all_below
    wanted = set(filter(None, args.families.split(",")))
    named = set(filter(None, args.cases.split(",")))
    from lamodel.io.files import atomic_write_text
    from lamodel.io.jsonspec import structure_from_json
    from families3d import cases3d, read_case
    rows = []
    for fam, name, build in cases(args.quick) + cases3d(args.quick, args.compas):
        if (wanted and fam not in wanted) or (named and name not in named):
            continue
        spec = build()
        if args.write:
            Path(args.write).mkdir(parents=True, exist_ok=True)
            atomic_write_text(Path(args.write) / f"{name}.json", json.dumps(spec))
            continue
        nb = (read_case(spec) if spec.get("dimension") == 3 or "_read" in spec else structure_from_json(spec)).n_blocks
        if args.max_blocks is not None and nb > args.max_blocks:
            continue
        row = dict(family=fam, case=name, **run_case(spec, nb <= all_below, args.timeout, args.total_work,
                                                     filter(None, args.without.split(",")), tuned))
        rows.append(row)
        print(f"{fam:9s} {name:26s} {nb:5d} blocks  {row['status']:13s} alpha {row.get('alpha', np.nan):.6f}  "
              f"{row.get('best_by', ''):24s} first {row.get('t_first', np.nan):6.2f} s  best "
              f"{row.get('t_best', np.nan):6.2f} s  process {row['process']:6.1f} s  LPs {row.get('lps', 0)}"
              f"  least {row.get('least', np.nan):.6f}  work/bound {row.get('work_ratio', np.nan):.3f}", flush=True)
    if args.write:
        print(f"structure files: {args.write}")
        return
    df = pd.DataFrame(rows)
    Path(args.csv).parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(args.csv, index=False)
    with pd.option_context("display.width", 200, "display.max_columns", 20):
        print(summarise(df).to_string(index=False, float_format=lambda v: f"{v:.3g}"))
        if args.lanes:
            best, timed = lane_table(df)
            print(best.to_string(index=False))
            print(timed.to_string(index=False, float_format=lambda v: f"{v:.3g}"))
    print(f"cases: {args.csv}")


if __name__ == "__main__":
    main()
