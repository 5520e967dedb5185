"""The command line: ``lamodel solve | study | compare | build | table1`` (one parser, one error style).

``scripts/solve.py``, ``scripts/compare.py``, ``scripts/build_instance.py`` and
``scripts/table1.py`` are thin shims over :func:`command` with their old names.

Every command reports bad input as one line ``<prog>: error: <message>`` on stderr with
exit status 2, never a traceback (``--debug`` shows one). Other exit statuses:

* solve: 0 a certified collapse multiplier was found; 3 none was (including a structure
  unstable under its dead load, or one no live load can collapse); 130 interrupted (what
  was certified so far is written); 1 an internal error;
* compare: 0 the results agree within the tolerance, 1 they differ;
* build: 0 the .dat file was written;
* study: 0 every variant certified, 3 some variant not certified;
* table1: 0 every wall certified, 3 some wall not certified.

Heavy libraries (Pyomo, HiGHS, matplotlib) load only inside the commands that need them,
so ``lamodel --help`` answers at once.
"""
from __future__ import annotations

import argparse
import os
import signal
import sys
import threading
import traceback
from pathlib import Path

EXIT_OK, EXIT_DIFFER, EXIT_BAD_INPUT, EXIT_NOT_CERTIFIED, EXIT_INTERRUPTED = 0, 1, 2, 3, 130
EXIT_CERTIFIED = EXIT_OK


class _Usage(Exception):
    """A malformed command line (reported as one line, exit 2)."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2 (argparse would print the whole usage)
        raise _Usage(message)


def _whole(minimum):
    def parse(text):
        try:
            v = int(text)
        except ValueError:
            v = None
        if v is None or v < minimum:
            raise argparse.ArgumentTypeError(f"expected a whole number >= {minimum}, got '{text}'")
        return v
    parse.__name__ = f"whole number >= {minimum}"
    return parse


def _positive_float(text):
    try:
        v = float(text)
    except ValueError:
        v = float("nan")
    if not v > 0 or v == float("inf"):
        raise argparse.ArgumentTypeError(f"expected a number of seconds > 0, got '{text}'")
    return v


def _tolerance(text):
    try:
        v = float(text)
    except ValueError:
        v = float("nan")
    if not v >= 0 or v == float("inf"):
        raise argparse.ArgumentTypeError(f"expected a finite tolerance >= 0, got '{text}'")
    return v


# ------------------------------------------------------------------------------- solve
def _solve_arguments(p):
    from .search.methods import CHOICES, SEED_GENERATIONS, SEED_POP_SIZE
    from .search.options import SOLVERS, SolveOptions

    p.add_argument("instance", help="a Pyomo .dat instance or a JSON polygon geometry")
    p.add_argument("--out", help="result folder, replaced as a whole (default: results/<instance name>/); "
                                 "a folder holding files lamodel did not write is refused")
    p.add_argument("--seed", type=int, default=SolveOptions.seed, help="random seed of the GA (default 0)")
    p.add_argument("--starts", type=_whole(0), default=None, metavar="K",
                   help="K Ipopt solves of eq. 5, one from each of the K best distinct certified collapse states "
                        "(runs.csv has a row for each: its result, or why it was skipped: fewer distinct states, "
                        "or the time limit). Default: up to 2, only when the model is small enough for a start "
                        "to take about a second; 0: LPs only")
    _where_arguments(p, "W threads for the GA's evaluations (each generation from one snapshot: the same answer "
                        "for any W) and W processes for the Ipopt starts. Default: the GA's evaluations one after "
                        "the other, warm (a serial run's answer), all cores for the Ipopt starts",
                     "run the GA's evaluations (as with --workers: the same answer) and the Ipopt starts "
                     "on this dask.distributed scheduler instead")
    p.add_argument("--time-limit", type=_positive_float, default=None, help="seconds for the whole search")
    p.add_argument("--pop-size", type=_whole(2), default=None,
                   help=f"GA population (default {SolveOptions.pop_size}; {SEED_POP_SIZE} for --method seed)")
    p.add_argument("--generations", type=_whole(1), default=None,
                   help=f"GA generations (default {SolveOptions.generations}; {SEED_GENERATIONS} for --method seed)")
    p.add_argument("--method", default="lamodel", choices=CHOICES,
                   help="lamodel: the certified search (default); associative: the associative LP (upper bound); "
                        "successive-lp: Gilbert et al. 2006; mpec: Ferris & Tin-Loi 2001; seed: the seed's GA on "
                        "eq. 5 with Ipopt; all: every method, compared in <out>/methods.csv. Each method's raw "
                        "answer is certified like every other")
    p.add_argument("--solver", default=SolveOptions.solver, choices=SOLVERS,
                   help="Ipopt through lamodel's bridge (default) or Pyomo's interface to an ipopt executable")
    p.add_argument("--plot", help="mechanism picture (.png, .svg, .pdf, ...; default <out>/mechanism.png, part of "
                                  "the result folder; elsewhere, in an existing folder)")
    p.add_argument("--no-plot", action="store_true", help="draw no picture")
    p.add_argument("--quiet", action="store_true",
                   help="print only the one-line result (warnings and errors still go to stderr)")
    p.add_argument("--prove", type=_positive_float, metavar="SECONDS", help="seconds for the proven lower bound "
                   "alpha_lower (default: a quarter of the search's time, at least 2 s)")
    _solve_study_arguments(p)


def _number_list(text):
    try:
        values = [float(x) for x in text.replace(" ", "").split(",") if x != ""]
    except ValueError:
        values = []
    if not values or not all(v == v and abs(v) != float("inf") for v in values):
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got '{text}'")
    return values


def _pair(text):
    values = _number_list(text)
    if len(values) != 2:
        raise argparse.ArgumentTypeError(f"expected two numbers FX,FY, got '{text}'")
    return values


def _solve_study_arguments(p):
    """Options of issue 14: report, animation, rolling load."""
    p.add_argument("--report", metavar="FILE.html", help="write one self-contained HTML report")
    p.add_argument("--animate", metavar="FILE.gif", help="write a GIF of the mechanism growing from rest")
    p.add_argument("--rolling", metavar="FX,FY", type=_pair,
                   help="a rolling point load (per axle) moved across the top; it replaces the file's live loads")
    p.add_argument("--axles", metavar="D1,D2,...", type=_number_list,
                   help="offsets of the axles from the lead axle (with --rolling; default 0)")
    p.add_argument("--positions", metavar="X1,X2,...", type=_number_list,
                   help="positions of the lead axle (default: the file's, else the midpoints of the top edges)")


def _solve(args, prog) -> int:
    painter = None
    if not (args.no_plot or args.report or args.animate):
        # matplotlib loads in a second process while this one reads and solves (the
        # report and the animation load it here anyway)
        from .output.painter import Painter
        painter = Painter()
    try:
        return _solve_with(args, prog, painter)
    finally:
        if painter is not None:
            painter.close()


def _solve_with(args, prog, painter) -> int:
    import warnings

    from .errors import InputError
    from .io import read
    from .io.files import ResultFolder, safe_folder_name
    from .output.folder import foreign_files
    from .search.driver import SolveOptions, solve

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        structure = read(args.instance)
    for w in caught:  # always shown (--quiet too): they change the answer; one line each
        if issubclass(w.category, UserWarning):
            print(f"{prog}: warning: {w.message}", file=sys.stderr)
    options = SolveOptions(seed=args.seed, starts=args.starts, workers=args.workers, ga_workers=args.workers,
                           time_limit=args.time_limit,
                           pop_size=args.pop_size or SolveOptions.pop_size,
                           generations=args.generations or SolveOptions.generations,
                           solver=args.solver, progress=not args.quiet, scheduler=args.scheduler)
    if args.scheduler:
        from .search.executor import check_scheduler
        check_scheduler(args.scheduler)  # fail at once, not after the first certificate
    structure = _with_rolling_option(structure, args)
    if args.method != "lamodel" and (structure.cases or structure.rolling is not None):
        raise InputError("--method other than lamodel takes one live load; expected no load cases or rolling load")
    # every output place is checked before the solve (InputError: one line, exit 2)
    out = Path(args.out) if args.out else Path("results") / safe_folder_name(structure.name)
    picture = None if args.no_plot else _picture_place(args.plot, out)
    _check_outputs(args, out)
    stage = ResultFolder(out, foreign_files).open()

    def beside(path):  # a file named inside the result folder is part of it
        return path is not None and Path(os.path.realpath(Path(path).parent)) == stage.final
    try:
        study, methods = None, None
        if args.method != "lamodel":
            outcome, results, methods = _solve_methods(args, structure, options)
        else:
            if structure.cases or structure.rolling is not None:
                study, outcome, extra = _run_study(structure, options, args)
            else:
                outcome, extra = solve(structure, options), {}
                from .output.report import lower_bound_columns
                extra = lower_bound_columns(outcome, args.prove)
            from .output.report import outcome_results
            results = outcome_results(outcome, dict(extra, method="lamodel"))
        dead_u = _explain_unstable(outcome)
        results.summary["message"] = outcome.message  # with the blocks that move under dead load, if unstable
        if painter is not None and beside(picture):  # drawn there while the tables are written here
            painter.start(outcome.structure, stage.path / Path(picture).name, _picture(outcome, results, dead_u))
        words = _words(outcome, results, dead_u)
        # everything that belongs to the result folder is written into the staging folder,
        # then swapped in as a whole; its files are named in summary.csv (so a later run
        # knows them as lamodel's)
        extras = {"picture": picture, "report": args.report, "animation": args.animate}
        for column, path in extras.items():
            results.summary[column] = Path(path).name if beside(path) else str(path or "")
        results.write_into(stage.path)
        if study is not None:
            study = _write_study(study, stage.path, structure)
        if methods is not None:
            _write_methods(methods, stage.path, out, structure)
        _write_extras(args, prog, outcome, results, words, study, dead_u,
                      {k: stage.path / Path(p).name for k, p in extras.items() if beside(p)}, painter)
        try:
            stage.commit()
        except OSError as exc:
            print(f"{prog}: error: cannot write the results to {out}: {exc.strerror or exc}", file=sys.stderr)
            return 1
    finally:
        stage.discard()
    outside = {k: Path(p) for k, p in extras.items() if p is not None and not beside(p)}
    _write_extras(args, prog, outcome, results, words, study, dead_u, outside, painter)
    shown = {k: out / Path(p).name if beside(p) else p for k, p in extras.items() if p is not None}
    if not args.quiet:
        import pandas as pd
        with pd.option_context("display.width", 160, "display.max_columns", 20, "display.max_colwidth", 60):
            print(results.to_text())
            if study is not None:
                print(f"\n{study['title']}:")
                print(study["table"].to_string(index=False, float_format=lambda v: f"{v:.6g}"))
        print()
        print("\n".join(words))
        print(f"results written to {out}/" + (f", picture {shown['picture']}" if picture else ""))
        if args.report:
            print(f"report written to {shown['report']}")
    if outcome.certified:
        print(f"{structure.name}: alpha = {max(results.alpha, 0.0):.6f} (certified collapse state; associative "
              f"bound {results.alpha_associative:.6f}) in {outcome.wall_time_s:.1f} s")
    else:
        print(f"{structure.name}: no certified collapse multiplier: {outcome.message}")
    if outcome.status == "interrupted":
        return EXIT_INTERRUPTED
    return EXIT_CERTIFIED if outcome.certified else EXIT_NOT_CERTIFIED


def _write_extras(args, prog, outcome, results, words, study, dead_u, paths, painter=None):
    """The picture, the animation and the HTML report, each to its path in ``paths``
    (keys picture, animation, report; a missing key: not in this phase); the picture by
    ``painter`` (:mod:`lamodel.output.painter`) if given."""
    if "picture" in paths:
        _draw(outcome.structure, outcome, results, paths["picture"], dead_u, painter)
    if "animation" in paths:
        _animate(outcome, results, paths["animation"], dead_u)
    if "report" in paths:
        from .output.html import write_report
        write_report(paths["report"], outcome.structure, results, words,
                     _picture_svg(outcome, results, dead_u), " ".join([prog.split()[0], *sys.argv[1:]]), args.instance,
                     study=None if study is None else (study["title"], study["key"], study["table"], study["svg"]))


def _picture_place(plot, out) -> Path:
    """Where the picture goes, checked before solving: a known format, a writable place.
    Beside the tables (the default) it is part of the result folder; elsewhere its folder
    must exist."""
    from .errors import InputError
    from .io.files import check_writable_folder

    path = Path(plot) if plot else Path(out) / "mechanism.png"
    ext = path.suffix.lower().lstrip(".")
    supported = ("png",)
    if ext != "png":  # any other format: ask matplotlib (0.6 s to load; png needs no asking)
        from matplotlib.backend_bases import FigureCanvasBase
        supported = FigureCanvasBase.get_supported_filetypes()
    if ext not in supported:
        raise InputError(f"{path}: unknown picture format '{path.suffix}'; expected one of "
                         f"{', '.join('.' + e for e in sorted(supported))}")
    final_out = Path(os.path.realpath(out))
    parent = Path(os.path.realpath(path.parent if str(path.parent) else "."))
    if parent == final_out:
        return final_out / path.name
    if os.path.isdir(path):
        raise InputError(f"{path}: is a folder; expected a picture file name")
    check_writable_folder(path.parent, f"--plot {path}")
    return path


def _solve_methods(args, structure, options):
    """--method other than lamodel: run it (or all of them); the result folder holds the
    certified state of the method (for all: of the best one) and, for all, methods.csv.
    Returns (outcome, results, the methods table or None)."""
    from .output.methods import method_results, methods_frame
    from .search.methods import SEED_GENERATIONS, SEED_POP_SIZE, best_of, run_methods

    def progress(r):
        if not args.quiet:
            print(f"  {r.method}: raw alpha {r.alpha_raw:.6f}, certified "
                  + (f"{r.alpha_certified:.6f}" if r.certified else "none") + f" ({r.seconds:.1f} s)", flush=True)

    found = run_methods(args.method, structure, options,
                        (args.pop_size or SEED_POP_SIZE, args.generations or SEED_GENERATIONS), progress)
    chosen = best_of(found)
    frame = None
    if args.method == "all":
        frame = methods_frame(found)
        frame.attrs["chosen"] = chosen.method
    return chosen.outcome(), method_results(chosen), frame


def _write_methods(frame, folder, out, structure):
    """methods.csv beside the result files (``folder``: the staging folder of ``out``)."""
    from .output.methods import methods_text, write_methods_csv
    write_methods_csv(frame, folder)
    print(f"Methods on '{structure.name}' (each raw answer certified; the folder holds "
          f"{frame.attrs.get('chosen', 'the best')}'s state):")
    print(methods_text(frame))
    print(f"methods table written to {out}/methods.csv")


def _draw(structure, outcome, results, path, dead_u=None, painter=None):
    if painter is not None:
        return painter.draw(structure, path, _picture(outcome, results, dead_u))
    from .output.plot import plot_mechanism
    return plot_mechanism(structure, path=str(path), **_picture(outcome, results, dead_u))


def _picture(outcome, results, dead_u=None) -> dict:
    """What every picture of a solve shows: the certified mechanism with the modes of
    contacts.csv and the thrust line, or the mechanism under dead load alone (highlighted),
    or the structure at rest."""
    import numpy as np

    from .output.modes import modes_from_mechanism
    from .output.words import moving_blocks
    s = outcome.structure
    if outcome.best is not None:
        best = outcome.best
        return dict(u=best.u.reshape(-1, 3), modes=results.modes(), alpha=best.alpha, certified=True,
                    thrust=(best.N, best.M))
    if dead_u is not None:
        moving = [b for b, m in zip(s.blocks, moving_blocks(s, dead_u)) if m]
        return dict(u=dead_u, modes=modes_from_mechanism(s, dead_u), highlight=moving,
                    title=f"{s.name}: unstable under dead load")
    return dict(u=np.zeros((s.n_blocks, 3)), modes=["unknown"] * s.n_contacts, alpha=None,
                certified=outcome.certified)


def _picture_svg(outcome, results, dead_u) -> str:
    import matplotlib.pyplot as plt

    from .output.html import svg_of
    from .output.plot import plot_mechanism
    fig, ax = plt.subplots(figsize=(9, 6))
    try:
        plot_mechanism(outcome.structure, path=None, ax=ax, **_picture(outcome, results, dead_u))
        return svg_of(fig)
    finally:
        plt.close(fig)


def _animate(outcome, results, path, dead_u):
    from .output.plot import animate_mechanism
    kw = _picture(outcome, results, dead_u)
    kw.pop("title", None)
    return animate_mechanism(outcome.structure, path=path, **kw)


def _words(outcome, results, dead_u) -> list:
    """The mechanism in words (:mod:`lamodel.output.words`)."""
    from .output.modes import modes_from_mechanism
    from .output.words import bound_words, describe
    s = outcome.structure
    if outcome.best is not None:
        return describe(s, outcome.best.u, results.modes(), outcome.best.alpha) + bound_words(results.summary)
    if dead_u is not None:
        return ["Under dead load alone (no live load):"] + describe(s, dead_u, modes_from_mechanism(s, dead_u))[1:]
    return [f"No mechanism: {outcome.message}."]


def _explain_unstable(outcome):
    """For a structure unstable under its dead load: the mechanism of the dead load alone
    (:mod:`lamodel.search.unstable`), its moving blocks named in the outcome's message."""
    if outcome.status != "unstable":
        return None
    from .output.words import moving_blocks
    from .search.unstable import dead_load_mechanism
    u = dead_load_mechanism(outcome.structure)
    if u is None:
        return None
    names = [b for b, m in zip(outcome.structure.blocks, moving_blocks(outcome.structure, u)) if m]
    shown = ", ".join(names[:20]) + (f", ... ({len(names)} blocks)" if len(names) > 20 else "")
    outcome.message += f"; the blocks that move under dead load alone: {shown}"
    return u


def _check_outputs(args, out):
    """--report and --animate: the right suffix, and a writable folder (or the result folder,
    which holds them then)."""
    from .errors import InputError
    from .io.files import check_writable_folder
    for option, path, suffixes in (("--report", args.report, (".html", ".htm")), ("--animate", args.animate, (".gif",))):
        if path is None:
            continue
        p = Path(path)
        if p.suffix.lower() not in suffixes:
            raise InputError(f"{path}: {option} writes a {suffixes[0]} file; expected a file name ending in {suffixes[0]}")
        if p.is_dir():
            raise InputError(f"{path}: is a folder; expected a file name for {option}")
        if os.path.realpath(p.parent) != os.path.realpath(out):
            check_writable_folder(p.parent, f"{option} {path}")


def _with_rolling_option(structure, args):
    """--rolling/--axles/--positions: a rolling load replacing the file's live loads, or
    new axles/positions for the file's own rolling load."""
    import dataclasses

    from .errors import InputError
    from .loads import RollingLoad
    if args.rolling is None and not (args.axles or args.positions):
        return structure
    if args.rolling is None and structure.rolling is None:
        raise InputError("--axles and --positions move a rolling load; expected --rolling FX,FY or a "
                         "'rolling_load' in the JSON")
    if not structure.polygons:
        raise InputError(f"{args.instance}: no block outlines; expected a JSON geometry (or a .dat with VERTICES) "
                         "to find the top of the structure for a rolling load")
    s = dataclasses.replace(structure)
    if args.rolling is not None:
        if not any(args.rolling):
            raise InputError("--rolling 0,0: expected a non-zero force per axle")
        s.live, s.live_m = structure.live * 0.0, structure.live_m * 0.0
        s.point_loads = [p for p in structure.point_loads if p.kind == "dead"]
        s.cases = {}
        base = RollingLoad(tuple(args.rolling))
    else:
        base = structure.rolling
    s.rolling = RollingLoad(base.force, tuple(args.axles) if args.axles else base.axles,
                            tuple(args.positions) if args.positions else base.positions)
    return s


def _run_study(structure, options, args):
    """Load cases or a rolling load: one solve per case / position; the governing outcome."""
    from .studies import governing, load_case_study, rolling_study
    quiet = args.quiet

    def progress(row):
        if not quiet:
            key = "case" if "case" in row else "position"
            value = row[key] if key == "case" else f"x = {row[key]:.6g}"
            alpha = f"{row['alpha_c']:.6f}" if row["certified"] else f"none ({row['status']})"
            print(f"  {value}: alpha = {alpha}", flush=True)

    from dataclasses import replace
    quiet_options = replace(options, progress=False)
    if structure.cases:
        df, outcomes = load_case_study(structure, quiet_options, progress=progress)
        key, title = "case", f"Load cases ({len(df)})"
    else:
        df, outcomes = rolling_study(structure, quiet_options, progress=progress)
        key, title = "position", f"Rolling load ({len(df)} positions)"
    label = governing(df, key)
    chosen = label if label is not None else next(iter(outcomes))
    extra = {key: chosen, "governing": label is not None}
    return {"key": key, "title": title, "table": df}, outcomes[chosen], extra


def _write_study(study, out, structure):
    """cases.csv or rolling.csv (and rolling.png) next to the result files; the plot as SVG
    for the report."""
    from .output.html import svg_of
    from .studies import cases_figure, rolling_figure, save_open_figure, write_csv
    df = study["table"]
    units = {"length_unit": structure.units.get("length", "-"), "force_unit": structure.units.get("force", "-")}
    write_csv(df.assign(**units), Path(out) / ("cases.csv" if study["key"] == "case" else "rolling.csv"))
    if study["key"] == "case":
        fig = cases_figure(df)
    else:
        fig = rolling_figure(df, f"{structure.name}: rolling load", structure.units.get("length", ""))
        save_open_figure(rolling_figure(df, f"{structure.name}: rolling load", structure.units.get("length", "")),
                         Path(out) / "rolling.png")
    svg = svg_of(fig)
    import matplotlib.pyplot as plt
    plt.close(fig)
    return dict(study, svg=svg)


def _where_arguments(p, workers_help, scheduler_help):
    """--workers N | --scheduler tcp://HOST:PORT (one or the other)."""
    g = p.add_mutually_exclusive_group()
    g.add_argument("--workers", type=_whole(1), default=None, help=workers_help)
    g.add_argument("--scheduler", metavar="tcp://HOST:PORT", default=None, help=scheduler_help)


# ------------------------------------------------------------------------------- study
def _study_arguments(p):
    p.add_argument("spec", metavar="SPEC.json", help="study spec (see lamodel.parametric; "
                                                      "examples/friction_study.json)")
    p.add_argument("--out", help="result folder for study.csv and study.png (default: results/<study name>/)")
    _where_arguments(p, "local worker processes, one variant each at a time (default: all cores)",
                     "run the variants on this dask.distributed scheduler (its workers need lamodel importable)")
    p.add_argument("--no-plot", action="store_true", help="draw no picture")
    p.add_argument("--quiet", action="store_true", help="print only the last line")


def _study(args, prog) -> int:
    import pandas as pd

    from .errors import InputError
    from .parametric import read_study, run_study, write_study

    study = read_study(args.spec)
    out = Path(args.out) if args.out else Path("results") / study.name
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: exists and is not a folder; expected a folder for the study files")
    n = len(study.variants())
    if not args.quiet:
        print(f"study {study.name}: {n} variants of '{study.structure.name}'", flush=True)
    df = run_study(study, workers=args.workers, scheduler=args.scheduler)
    try:
        written = write_study(df, study, out, plot=not args.no_plot)
    except OSError as exc:
        print(f"{prog}: error: cannot write the study to {out}: {exc.strerror or exc}", file=sys.stderr)
        return 1
    if not args.quiet:
        shown = [c for c in df.columns if c not in ("status", "ga_seed", "worker", "error")]
        with pd.option_context("display.width", 200, "display.max_columns", 30, "display.max_rows", 60):
            print(df[shown].to_string(index=False, float_format=lambda v: f"{v:.6g}"))
        print("written: " + ", ".join(written))
    ok = df["certified"]
    retried = int((df["attempts"] > 1).sum())
    least = f"; least alpha {df.loc[ok, 'alpha'].min():.6f}" if ok.any() else ""
    print(f"study {study.name}: {int(ok.sum())} of {n} variants certified{least}"
          + (f"; {retried} retried after a failure" if retried else "")
          + (f"; {int((df['error'] != '').sum())} failed" if (df["error"] != "").any() else ""))
    return EXIT_OK if ok.all() else EXIT_NOT_CERTIFIED


# ----------------------------------------------------------------------------- compare
def _compare_arguments(p):
    p.add_argument("a", metavar="A", help="reference result: a result folder or its summary.csv")
    p.add_argument("b", metavar="B", help="result to compare with A")
    p.add_argument("--atol", type=_tolerance, default=1e-5,
                   help="absolute tolerance on alpha; forces are compared with atol*max(1, max|N| of A), "
                        "displacements with atol*max(1, max|u| of A) (default: %(default)g)")


def _compare(args, prog) -> int:
    from .output.compare import compare_results, print_comparison
    from .output.results import Results

    a, b = Results.read(args.a), Results.read(args.b)
    table, differ = compare_results(a, b, args.atol)
    return print_comparison(table, differ, args.a, args.b, args.atol)


# ------------------------------------------------------------------------------- build
def _build_arguments(p):
    p.add_argument("geometry", help="JSON geometry file (see lamodel.io.jsonspec)")
    p.add_argument("-o", "--output", help="output .dat file (default: next to the JSON, with .dat)")
    p.add_argument("--name", help="instance name (default: the JSON 'name' or the file stem)")


def _build(args, prog) -> int:
    from .io.datfile import write_dat
    from .io.jsonspec import structure_from_json

    output = Path(args.output) if args.output else Path(args.geometry).with_suffix(".dat")
    structure = structure_from_json(args.geometry, name=args.name)
    write_dat(structure, output)
    print(f"{output}: {structure.n_blocks} blocks, {len(structure.supports)} supports, "
          f"{structure.n_contacts} contacts")
    return EXIT_OK


# ------------------------------------------------------------------------------ table1
def _table1_arguments(p):
    p.add_argument("--out", default="results/table1.csv", help="CSV file (default results/table1.csv)")
    p.add_argument("--seed", type=int, default=0, help="random seed of the GA (default 0)")
    p.add_argument("--starts", type=_whole(0), default=None, metavar="K",
                   help="K Ipopt solves of eq. 5 per wall, from the best distinct certified states "
                        "(default: only when cheap, see solve --help; 0: LPs only)")
    p.add_argument("--workers", type=_whole(1), default=None, help="worker processes (default: all cores)")


def _table1(args, prog) -> int:
    import pandas as pd

    from .search.options import SolveOptions
    from .studies import table1, write_csv

    options = SolveOptions(seed=args.seed, starts=args.starts, workers=args.workers)
    df = table1(options, progress=lambda r: print(f"  {r['wall']}: alpha = {r['lamodel']:.6f} "
                                                  f"({'certified' if r['certified'] else 'NOT certified'}, "
                                                  f"{r['seconds']:.1f} s)", flush=True))
    with pd.option_context("display.width", 160, "display.max_columns", 20):
        print(df.to_string(index=False, formatters={
            c: (lambda v: f"{v:.6f}") for c in ("lamodel", "alpha_associative")} | {
            c: (lambda v: f"{v:.5f}") for c in ("ferris_tin_loi_2", "gilbert_4", "mihai_5", "seed")} | {
            "seconds": lambda v: f"{v:.1f}"}))
    write_csv(df, args.out)
    starts = "default" if args.starts is None else args.starts
    print(f"written to {args.out} (seed {args.seed}, starts {starts})")
    return EXIT_OK if df["certified"].all() else EXIT_NOT_CERTIFIED


#: command -> (help, declare the arguments, run)
COMMANDS = {
    "solve": ("minimum collapse multiplier of a block assembly (seed eq. 5), certified by LP",
              _solve_arguments, _solve),
    "study": ("a parametric study from a JSON spec: one certified alpha per variant, as a table and a plot",
              _study_arguments, _study),
    "compare": ("compare two result folders (exit 0 agree, 1 differ, 2 bad input)", _compare_arguments, _compare),
    "build": ("write the Pyomo .dat instance of a JSON polygon geometry", _build_arguments, _build),
    "table1": ("the seed's Table 1 with lamodel's certified alpha", _table1_arguments, _table1),
}


def _parser(prog="lamodel", command=None) -> argparse.ArgumentParser:
    if command is not None:  # one command under its own name (the scripts/ shims)
        text, arguments, _ = COMMANDS[command]
        p = _Parser(prog=prog, description=text[0].upper() + text[1:] + ".")
        arguments(p)
        p.add_argument("--debug", action="store_true", help="show tracebacks")
        return p
    p = _Parser(prog=prog, description="Limit analysis of dry masonry block assemblies with Coulomb friction.")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name, (text, arguments, _) in COMMANDS.items():
        sp = sub.add_parser(name, help=text, description=text[0].upper() + text[1:] + ".")
        arguments(sp)
        sp.add_argument("--debug", action="store_true", help="show tracebacks")
    return p


def command(name: str | None, argv=None, prog: str = "lamodel") -> int:
    """Run one command (``name``) or the whole ``lamodel`` command line (``name=None``);
    returns the exit status."""
    global _sigint_seen
    old = None
    try:
        _sigint_seen = False
        old = _watch_sigint()
        return _command(name, list(sys.argv[1:] if argv is None else argv), prog)
    except KeyboardInterrupt:  # e.g. while the parser imports the search's choices
        print(f"{prog}: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception:
        if not _sigint_seen:
            raise
        print(f"{prog}: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    finally:
        if old is not None:
            signal.signal(signal.SIGINT, old)


_sigint_seen = False


def _on_sigint(signum, frame):
    global _sigint_seen
    _sigint_seen = True
    raise KeyboardInterrupt


def _watch_sigint():
    """Ctrl-C raises KeyboardInterrupt as usual, and is remembered: an extension module
    interrupted while it loads (numpy's C core) re-raises it as an ImportError, which
    must still end the run as an interrupt (130), not as an internal error. Returns the
    previous handler, or None when nothing was changed (not the main thread, or SIGINT
    ignored or handled by the program that called us)."""
    if threading.current_thread() is not threading.main_thread():
        return None
    if signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
        return None
    return signal.signal(signal.SIGINT, _on_sigint)


def _command(name, argv, prog):
    debug = "--debug" in argv
    try:
        args = _parser(prog, name).parse_args(argv)
    except _Usage as exc:
        if name is None and prog == "lamodel" and argv and argv[0] in COMMANDS:
            prog = f"lamodel {argv[0]}"
        print(f"{prog}: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return EXIT_BAD_INPUT
    name = name or args.command
    if name is None:
        _parser(prog).print_help()
        return EXIT_BAD_INPUT
    if prog == "lamodel":
        prog = f"lamodel {name}"
    try:
        return COMMANDS[name][2](args, prog)
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception as exc:
        if _sigint_seen:  # an import that Ctrl-C broke (see _watch_sigint)
            print(f"{prog}: interrupted", file=sys.stderr)
            return EXIT_INTERRUPTED
        from .errors import InputError
        if debug:
            traceback.print_exc()
        if isinstance(exc, InputError):
            print(f"{prog}: error: {' '.join(str(exc).split())}", file=sys.stderr)
            return EXIT_BAD_INPUT
        print(f"{prog}: internal error: {type(exc).__name__}: {exc} (run with --debug for the traceback)",
              file=sys.stderr)
        return 1


def main(argv=None) -> int:
    """The ``lamodel`` command line; returns its exit status."""
    return command(None, argv)


def exit_now(status: int):
    """End a command-line process with ``status`` once its work is done: the atexit
    handlers run and the standard streams are flushed, then the process exits without
    CPython's teardown of every loaded module (0.2 s with pandas, SciPy and HiGHS loaded:
    a tenth of a seed wall's whole run). Every file lamodel writes is complete and
    synced before this point (:mod:`lamodel.io.files`).

    The usual ``sys.exit(status)`` instead when called from inside another program (a
    test runner's runpy, a notebook: more than the script's top level and the console
    script's wrapper below this call), or when a worker process or a non-daemon thread
    is still there (a pool shutting down: the usual exit waits for it)."""
    import atexit
    import threading
    depth, frame = 0, sys._getframe(1)
    while frame is not None and depth <= 2:
        depth, frame = depth + 1, frame.f_back
    busy = any(t is not threading.main_thread() and not t.daemon for t in threading.enumerate())
    if frame is not None or busy or _children_alive():
        sys.exit(status)
    try:
        atexit._run_exitfuncs()
    finally:
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):  # a closed pipe: nothing more can reach it
                pass
        os._exit(status)


def _children_alive() -> bool:
    if "multiprocessing" not in sys.modules:
        return False
    import multiprocessing
    return bool(multiprocessing.active_children())


def run():
    """The ``lamodel`` console script."""
    exit_now(main())


def run_solve():
    """The ``lamodel-solve`` console script."""
    exit_now(solve_main())


def solve_main(argv=None) -> int:
    """``lamodel-solve`` and ``scripts/solve.py``: the solve command under its old name."""
    return command("solve", argv, prog="solve.py")


if __name__ == "__main__":
    sys.exit(main())
