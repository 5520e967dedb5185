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
import sys
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
    from .search.options import SOLVERS, SolveOptions

    p.add_argument("instance", help="a Pyomo .dat instance or a JSON polygon geometry")
    p.add_argument("--out", help="result folder (default: results/<instance name>/)")
    p.add_argument("--seed", type=int, default=SolveOptions.seed, help="random seed of the GA (default 0)")
    p.add_argument("--starts", type=_whole(0), default=SolveOptions.starts,
                   help=f"Ipopt solves of eq. 5 (default {SolveOptions.starts}; 0: LPs only)")
    _where_arguments(p, "worker processes for the Ipopt starts (default: all cores)",
                     "run the Ipopt starts on this dask.distributed scheduler instead")
    p.add_argument("--time-limit", type=_positive_float, default=None, help="seconds for the whole search")
    p.add_argument("--pop-size", type=_whole(2), default=SolveOptions.pop_size,
                   help=f"GA population (default {SolveOptions.pop_size})")
    p.add_argument("--generations", type=_whole(1), default=SolveOptions.generations,
                   help=f"GA generations (default {SolveOptions.generations})")
    p.add_argument("--solver", default=SolveOptions.solver, choices=SOLVERS,
                   help="Ipopt through lamodel's bridge (default) or Pyomo's interface to an ipopt executable")
    p.add_argument("--plot", help="mechanism picture (.png, .svg or .pdf; default <out>/mechanism.png)")
    p.add_argument("--no-plot", action="store_true", help="draw no picture")
    p.add_argument("--quiet", action="store_true", help="print only the one-line result")


def _solve(args, prog) -> int:
    import warnings

    import pandas as pd

    from .errors import InputError
    from .io import read
    from .output.report import outcome_results
    from .search.driver import SolveOptions, solve

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        structure = read(args.instance)
    for w in caught:  # one line each, without Python's source-line echo
        if not args.quiet and issubclass(w.category, UserWarning):
            print(f"{prog}: warning: {w.message}", file=sys.stderr)
    out = Path(args.out) if args.out else Path("results") / structure.name
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: exists and is not a folder; expected a folder for the result files")
    for name in ("summary.csv", "blocks.csv", "contacts.csv", "runs.csv"):
        if (out / name).is_dir():
            raise InputError(f"{out / name}: is a folder; expected room for the result file")
    options = SolveOptions(seed=args.seed, starts=args.starts, workers=args.workers, time_limit=args.time_limit,
                           pop_size=args.pop_size, generations=args.generations,
                           solver=args.solver, progress=not args.quiet, scheduler=args.scheduler)
    if args.scheduler and args.starts > 0:
        from .search.executor import check_scheduler
        check_scheduler(args.scheduler)  # fail at once, not after the GA
    outcome = solve(structure, options)
    results = outcome_results(outcome)
    try:
        results.write(out)
    except OSError as exc:
        print(f"{prog}: error: cannot write the results to {out}: {exc.strerror or exc}", file=sys.stderr)
        return 1
    picture = None
    if not args.no_plot:
        picture = _draw(structure, outcome, results, args.plot or out / "mechanism.png")
    if not args.quiet:
        with pd.option_context("display.width", 160, "display.max_columns", 20, "display.max_colwidth", 60):
            print(results.to_text())
        print(f"results written to {out}/" + (f", picture {picture}" if picture else ""))
    if outcome.certified:
        print(f"{structure.name}: alpha = {max(outcome.best.alpha, 0.0):.6f} (certified collapse state; associative "
              f"bound {outcome.alpha_associative:.6f}) in {outcome.wall_time_s:.1f} s")
    else:
        print(f"{structure.name}: no certified collapse multiplier: {outcome.message}")
    if outcome.status == "interrupted":
        return EXIT_INTERRUPTED
    return EXIT_CERTIFIED if outcome.certified else EXIT_NOT_CERTIFIED


def _draw(structure, outcome, results, path):
    import os

    import numpy as np

    from .output.plot import plot_mechanism
    path = Path(path)
    if path.parent and not path.parent.exists():
        os.makedirs(path.parent, exist_ok=True)
    if outcome.best is not None:
        u, modes = outcome.best.u.reshape(-1, 3), results.modes()  # the modes contacts.csv reports
        alpha = outcome.best.alpha
    else:
        u, modes, alpha = np.zeros((structure.n_blocks, 3)), ["closed"] * structure.n_contacts, None
    return plot_mechanism(structure, u, modes=modes, alpha=alpha, certified=outcome.certified, path=str(path))


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
    p.add_argument("--starts", type=_whole(0), default=2,
                   help="Ipopt solves of eq. 5 per wall (default 2; 0: LPs only)")
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
    print(f"written to {args.out} (seed {args.seed}, starts {args.starts})")
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
    argv = list(sys.argv[1:] if argv is None else argv)
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
    """The ``lamodel`` console script."""
    return command(None, argv)


def solve_main(argv=None) -> int:
    """``lamodel-solve`` and ``scripts/solve.py``: the solve command under its old name."""
    return command("solve", argv, prog="solve.py")


if __name__ == "__main__":
    sys.exit(main())
