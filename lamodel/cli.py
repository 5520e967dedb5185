"""Command line: ``python scripts/solve.py INSTANCE [options]``.

Exit status: 0 a certified collapse multiplier was found; 3 none was (including a
structure unstable under its dead load, or one no live load can collapse); 2 bad input;
130 interrupted (what was certified so far is written).
"""
from __future__ import annotations

import argparse
import os
import sys
import traceback
from pathlib import Path

EXIT_CERTIFIED, EXIT_BAD_INPUT, EXIT_NOT_CERTIFIED, EXIT_INTERRUPTED = 0, 2, 3, 130


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2 (argparse would print the whole usage)
        raise _Usage(message)


class _Usage(Exception):
    pass


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


def solve_parser() -> argparse.ArgumentParser:
    from .driver import SolveOptions

    p = _Parser(prog="solve.py", description="Minimum collapse multiplier of a frictional block assembly "
                                              "(seed eq. 5), certified by LP.")
    p.add_argument("instance", help="a Pyomo .dat instance or a JSON polygon geometry")
    p.add_argument("--out", help="result folder (default: results/<instance name>/)")
    p.add_argument("--seed", type=int, default=0, help="random seed of the GA (default 0)")
    p.add_argument("--starts", type=_whole(0), default=SolveOptions.starts,
                   help=f"Ipopt solves of eq. 5 (default {SolveOptions.starts}; 0: LPs only)")
    p.add_argument("--workers", type=_whole(1), default=None, help="worker processes (default: all cores)")
    p.add_argument("--time-limit", type=_positive_float, default=None, help="seconds for the whole search")
    p.add_argument("--pop-size", type=_whole(2), default=SolveOptions.pop_size,
                   help=f"GA population (default {SolveOptions.pop_size})")
    p.add_argument("--generations", type=_whole(1), default=SolveOptions.generations,
                   help=f"GA generations (default {SolveOptions.generations})")
    p.add_argument("--solver", default="lamodel_ipopt", choices=("lamodel_ipopt", "ipopt"),
                   help="Ipopt through lamodel's bridge (default) or Pyomo's interface to an ipopt executable")
    p.add_argument("--plot", help="mechanism picture (.png, .svg or .pdf; default <out>/mechanism.png)")
    p.add_argument("--no-plot", action="store_true", help="draw no picture")
    p.add_argument("--quiet", action="store_true", help="print only the one-line result")
    p.add_argument("--debug", action="store_true", help="show tracebacks")
    return p


def load_structure(path: str):
    """A Structure from a .dat or a .json file (InputError otherwise)."""
    from .errors import InputError
    ext = Path(path).suffix.lower()
    if Path(path).is_dir():
        raise InputError(f"{path}: is a folder; expected a .dat instance or a .json geometry file")
    if not Path(path).is_file():
        raise InputError(f"{path}: no such file; expected a .dat instance or a .json geometry")
    if ext == ".json":
        from .geometry import structure_from_json
        return structure_from_json(path)
    if ext == ".dat":
        from .datfile import read_dat
        return read_dat(path)
    raise InputError(f"{path}: unknown file type '{ext}'; expected .dat (Pyomo data) or .json (polygons)")


def solve_main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    debug = "--debug" in argv
    try:
        args = solve_parser().parse_args(argv)
    except _Usage as exc:
        print(f"solve.py: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    try:
        return _solve(args)
    except KeyboardInterrupt:
        print("solve.py: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception as exc:
        from .errors import InputError
        if debug:
            traceback.print_exc()
        if isinstance(exc, InputError):
            print(f"solve.py: error: {exc}", file=sys.stderr)
            return EXIT_BAD_INPUT
        print(f"solve.py: internal error: {type(exc).__name__}: {exc} (run with --debug for the traceback)",
              file=sys.stderr)
        return 1


def _solve(args) -> int:
    import warnings

    import pandas as pd

    from .driver import SolveOptions, solve
    from .errors import InputError
    from .report import outcome_results

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        structure = load_structure(args.instance)
    for w in caught:  # one line each, without Python's source-line echo
        if not args.quiet and issubclass(w.category, UserWarning):
            print(f"solve.py: warning: {w.message}", file=sys.stderr)
    out = Path(args.out) if args.out else Path("results") / structure.name
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: exists and is not a folder; expected a folder for the result files")
    for name in ("summary.csv", "blocks.csv", "contacts.csv", "runs.csv"):
        if (out / name).is_dir():
            raise InputError(f"{out / name}: is a folder; expected room for the result file")
    options = SolveOptions(seed=args.seed, starts=args.starts, workers=args.workers, time_limit=args.time_limit,
                           pop_size=args.pop_size, generations=args.generations,
                           solver=args.solver, progress=not args.quiet)
    outcome = solve(structure, options)
    results = outcome_results(outcome)
    try:
        results.write(out)
    except OSError as exc:
        print(f"solve.py: error: cannot write the results to {out}: {exc.strerror or exc}", file=sys.stderr)
        return 1
    picture = None
    if not args.no_plot:
        picture = _draw(structure, outcome, results, args.plot or out / "mechanism.png")
    if not args.quiet:
        with pd.option_context("display.width", 160, "display.max_columns", 20, "display.max_colwidth", 60):
            print(results.to_text())
        print(f"results written to {out}/" + (f", picture {picture}" if picture else ""))
    if outcome.certified:
        print(f"{structure.name}: alpha = {max(outcome.best.alpha, 0.0):.6f} (certified collapse state; associative bound "
              f"{outcome.alpha_associative:.6f}) in {outcome.wall_time_s:.1f} s")
    else:
        print(f"{structure.name}: no certified collapse multiplier: {outcome.message}")
    if outcome.status == "interrupted":
        return EXIT_INTERRUPTED
    return EXIT_CERTIFIED if outcome.certified else EXIT_NOT_CERTIFIED


def _draw(structure, outcome, results, path):
    import numpy as np

    from .plot import plot_mechanism
    path = Path(path)
    if path.parent and not path.parent.exists():
        os.makedirs(path.parent, exist_ok=True)
    if outcome.best is not None:
        u, modes = outcome.best.u.reshape(-1, 3), results.modes()  # the modes contacts.csv reports
        alpha = outcome.best.alpha
    else:
        u, modes, alpha = np.zeros((structure.n_blocks, 3)), ["closed"] * structure.n_contacts, None
    return plot_mechanism(structure, u, modes=modes, alpha=alpha, certified=outcome.certified, path=str(path))
