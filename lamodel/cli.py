"""The command line: ``lamodel solve | study | compare | build | bridge | table1``. It only parses;
the library does the work (``solve`` is :func:`lamodel.output.present.analyse`). The
scripts in ``scripts/`` are shims over :func:`command`. Bad input is one line on stderr,
exit status 2 (``--debug`` shows the traceback); :data:`lamodel.process.EXIT_HELP`, the
help's epilog, lists every exit status. Heavy libraries load only inside the commands
that need them, so ``lamodel --help`` answers at once.
"""
from __future__ import annotations

import argparse
import os
import sys
from contextlib import contextmanager

from .arguments import SEED, numbers, rolling_arguments, seconds, strength_arguments, tolerance, whole
from .io.options3d import add_input_arguments, check_build_options, input_options  # argparse only: light
from .process import (EXIT_BAD_INPUT, EXIT_HELP, EXIT_NOT_CERTIFIED, EXIT_OK, exit_now,  # noqa: F401 (scripts/)
                      exit_status, interrupted, run_reporting)
from .signals import unwatch_signals, watch_signals


class _Usage(Exception):
    """A malformed command line (reported as one line, exit 2)."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2 (argparse would print the whole usage)
        raise _Usage(message)


def _say(line):
    print(line, flush=True)


@contextmanager
def _log_to_stderr(verbose: int):
    """``--verbose``: the "lamodel" log on stderr, at INFO (phases, lanes, results) or, given
    twice, DEBUG (every step); written above the progress line, which stays."""
    if not verbose:
        yield
        return
    import logging

    from tqdm.contrib.logging import logging_redirect_tqdm
    log = logging.getLogger("lamodel")
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("%(asctime)s %(message)s", "%H:%M:%S"))
    level = log.level
    log.addHandler(handler)
    log.setLevel(logging.DEBUG if verbose > 1 else logging.INFO)
    try:
        with logging_redirect_tqdm([log]):
            yield
    finally:
        log.removeHandler(handler)
        log.setLevel(level)


def _where(p, workers_help, scheduler_help):
    """--workers N | --scheduler tcp://HOST:PORT (one or the other)."""
    g = p.add_mutually_exclusive_group()
    g.add_argument("--workers", type=whole(1), default=None, help=workers_help)
    g.add_argument("--scheduler", metavar="tcp://HOST:PORT", default=None, help=scheduler_help)


# ------------------------------------------------------------------------------- solve
def _solve_arguments(p):
    from .search.methods import CHOICES, SEED_GENERATIONS, SEED_POP_SIZE
    from .search.options import SOLVERS, SolveOptions
    a, o = p.add_argument, SolveOptions
    a("instance", help="a Pyomo .dat instance or a JSON polygon geometry; in 3D: a JSON of polyhedra, a COMPAS "
      "assembly or a mesh (.obj, .ply, .stl, .gltf, .glb)")
    a("--out", help="result folder, replaced as a whole (default: results/<instance name>/); a folder holding folders "
      "or links lamodel did not write is refused (a user's files in it are kept)")
    a("--seed", type=SEED, default=o.seed, help="random seed of the GA (default 0)")
    a("--starts", type=whole(0), metavar="K", help="K Ipopt solves of eq. 5, one from each of the K best distinct "
      "certified collapse states (runs.csv has a row for each: its result, or why it was skipped: fewer distinct "
      "states, or the time limit). Default: up to 2, only when a start takes about a second; 0: LPs only")
    _where(p, "W threads for the GA's evaluations and the continuation lanes (the same answer for any W) and W "
           "processes for the Ipopt starts. Default: the GA's evaluations one after the other, warm; all cores for "
           "the lanes and the Ipopt starts. With load cases or a rolling load: W of them solved at once, each "
           "search on one core",
           "run the GA's evaluations and the Ipopt starts on this dask.distributed scheduler instead")
    a("--time-limit", type=seconds, help="seconds for the whole search")
    a("--pop-size", type=whole(2), help=f"GA population (default {o.pop_size}; {SEED_POP_SIZE} for --method seed)")
    a("--generations", type=whole(1), help=f"GA generations (default {o.generations}; {SEED_GENERATIONS} for seed)")
    a("--method", default="lamodel", choices=CHOICES, help="lamodel: the certified search (default); associative: the "
      "associative LP (upper bound); successive-lp: Gilbert et al. 2006; mpec: Ferris & Tin-Loi 2001; seed: the seed's "
      "GA on eq. 5 with Ipopt; all: every method, compared in <out>/methods.csv. Every raw answer is certified")
    a("--solver", default=o.solver, choices=SOLVERS, help="Ipopt through lamodel's bridge (default) or Pyomo's "
      "interface to an ipopt executable")
    a("--plot", help="mechanism picture (.png, .svg, .pdf, ...; default <out>/mechanism.png)")
    a("--no-plot", action="store_true", help="draw no picture")
    a("--quiet", action="store_true", help="print only the one-line result (after the methods table with --method "
      "all; warnings and errors still go to stderr)")
    a("-v", "--verbose", action="count", default=0, help="log the search on stderr: its phases, lanes and what each "
      "certified; twice (-vv): every step and LP solve too")
    a("--report", metavar="FILE.html", help="write one self-contained HTML report")
    a("--animate", metavar="FILE.gif", help="write a GIF of the mechanism growing from rest")
    a("--prove", type=seconds, metavar="SECONDS", help="seconds for the proven lower bound alpha_lower in summary.csv")
    rolling_arguments(a)
    strength_arguments(a)
    a("--view", metavar="FILE.html", help="3D: one self-contained HTML page to turn the structure and its mechanism")
    add_input_arguments(p)


def _solve(args, prog) -> int:
    from threadpoolctl import threadpool_limits

    from .output.present import analyse
    from .search.options import SolveOptions
    from .search.tuning import BLAS_THREADS
    options = SolveOptions(seed=args.seed, starts=args.starts, workers=args.workers, ga_workers=args.workers,
                           time_limit=args.time_limit, pop_size=args.pop_size or SolveOptions.pop_size,
                           generations=args.generations or SolveOptions.generations, solver=args.solver,
                           progress=not args.quiet, scheduler=args.scheduler)
    # the search's BLAS_THREADS for the whole command (the lower bound beside it and after it too)
    with threadpool_limits(BLAS_THREADS, user_api="blas"), _log_to_stderr(args.verbose):
        a = analyse(args.instance, options, args.out, method=args.method, seed_ga=(args.pop_size, args.generations),
                    picture=False if args.no_plot else (args.plot or True), report=args.report, animate=args.animate,
                    rolling=args.rolling, axles=args.axles, positions=args.positions, echo=None if args.quiet else _say,
                    view=args.view, inputs=input_options(args),
                    warn=lambda message: print(f"{prog}: warning: {message}", file=sys.stderr),
                    command=" ".join([prog.split()[0], *sys.argv[1:]]), prove=args.prove,
                    strengths={"fc": args.fc, "ft": args.ft, "cohesion": args.cohesion})
    print(a.text(quiet=args.quiet))
    return exit_status() if a.interrupted else EXIT_OK if a.certified else EXIT_NOT_CERTIFIED


# ------------------------------------------------------------------------------- study
def _study_arguments(p):
    from .parametric import MAX_VARIANTS
    a = p.add_argument
    a("spec", metavar="SPEC.json", help="study spec (see lamodel.parametric; examples/friction_study.json)")
    a("--out", help="folder for study.csv and study.png (default: results/<study name>/)")
    _where(p, "local worker processes, one variant each at a time (default: all cores)",
           "run the variants on this dask.distributed scheduler (its workers need lamodel importable)")
    a("--max-variants", type=whole(1), default=MAX_VARIANTS, metavar="N",
      help=f"run a study of up to N variants (default {MAX_VARIANTS}; a larger spec is refused)")
    a("--no-plot", action="store_true", help="draw no picture")
    a("--quiet", action="store_true", help="print only the last line")


def _study(args, prog) -> int:
    from .parametric import read_study, run_study_into
    study = read_study(args.spec)
    done = run_study_into(study, args.out, workers=args.workers, scheduler=args.scheduler, plot=not args.no_plot,
                          max_variants=args.max_variants, echo=None if args.quiet else _say)
    if not args.quiet:
        print(done.text())
    print(done.line())
    return exit_status() if done.interrupted else EXIT_OK if done.certified else EXIT_NOT_CERTIFIED


# ----------------------------------------------------------------------------- compare
def _compare_arguments(p):
    p.add_argument("a", metavar="A", help="reference result: a result folder or its summary.csv, or the folder "
                   "(or adequacy.csv) of a bridge run's --adequacy")
    p.add_argument("b", metavar="B", help="result to compare with A")
    p.add_argument("--atol", type=tolerance, default=1e-5, help="absolute tolerance on alpha; forces are compared "
                   "with atol*max(1, max|N| of A), displacements with atol*max(1, max|u| of A) (default: %(default)g)")


def _compare(args, prog) -> int:
    from .bridges.compare import adequacy_path, compare_adequacy, read_adequacy
    from .output.compare import compare_results, print_comparison, read_result
    bridges = adequacy_path(args.a), adequacy_path(args.b)
    if all(bridges):  # two bridge runs: their adequacy tables
        table, differ = compare_adequacy(read_adequacy(bridges[0]), read_adequacy(bridges[1]), args.atol)
    else:
        table, differ = compare_results(read_result(args.a), read_result(args.b), args.atol)
    return print_comparison(table, differ, args.a, args.b, args.atol)


# ------------------------------------------------------------------------------- build
def _build_arguments(p):
    p.add_argument("geometry", help="JSON geometry file (see lamodel.io.jsonspec); in 3D: JSON, COMPAS or a mesh")
    p.add_argument("-o", "--output", help="output .dat file (default: next to the JSON, with .dat)")
    p.add_argument("--name", help="instance name (default: the JSON 'name' or the file stem)")
    add_input_arguments(p)


def _build(args, prog) -> int:
    import warnings

    from .io import build_dat
    from .output.tables3d import build_summary3d
    with warnings.catch_warnings():  # the reader's warnings (unknown fields, near-joints): one line each, as solve's
        warnings.showwarning = lambda message, *_, **__: print(f"{prog}: warning: {message}", file=sys.stderr)
        line = build_summary3d(args.geometry, **input_options(args))  # in space: the contacts summary; planar: None
        check_build_options(args, spatial=line is not None)
        print(line or build_dat(args.geometry, args.output, args.name))
    return EXIT_OK


# ------------------------------------------------------------------------------ bridge
def _bridge_arguments(p):
    a = p.add_argument
    a("bridge", metavar="BRIDGE.json", help="bridge description (see lamodel.bridges.description; "
      "instances/bridge_demo.json)")
    a("output", metavar="OUT.json", nargs="?", help="the block structure for lamodel solve (default: next to the "
      "description, <name>_blocks.json); its picture as built beside it (.png)")
    a("--no-passive", action="store_true", help="leave the fill's passive restraint out")
    a("--adequacy", metavar="FOLDER", help="also solve every load position: FOLDER/adequacy.csv, adequacy.png, "
      "mechanism.png (the governing mechanism with the fill) and report.html")
    a("--starts", type=whole(0), default=0, metavar="K", help="Ipopt starts per position with --adequacy (default 0)")
    a("--workers", type=whole(1), default=None, help="positions solved at once with --adequacy (default: all cores)")
    a("--positions", metavar="X1,X2,...", type=numbers(), help="positions of the lead axle, replacing the file's "
      "(default: the file's, else evenly from springing to springing)")


def _bridge(args, prog) -> int:
    import dataclasses
    import warnings
    from pathlib import Path

    from .bridges import bridge_spec, case_name, case_positions, positions, read_bridge
    from .bridges.description import distinct_positions
    from .bridges.picture import plot_bridge
    from .errors import InputError
    from .io.jsonspec import structure_from_spec, structure_to_json
    with warnings.catch_warnings():  # unknown fields: one line each
        warnings.showwarning = lambda message, *_, **__: print(f"{prog}: warning: {message}", file=sys.stderr)
        bridge = read_bridge(args.bridge)
        if args.positions:
            bridge = dataclasses.replace(bridge, positions=distinct_positions(args.positions, "--positions"))
        try:
            spec = bridge_spec(bridge, passive=not args.no_passive)
        except InputError as exc:  # name the file, as the reader's messages do
            raise InputError(str(exc).replace(f"bridge '{bridge.name}'", str(args.bridge), 1)) from None
        structure = structure_from_spec(spec, args.bridge)   # checked before it is written
    off = [x for x in positions(bridge) if case_name(x) not in structure.cases]
    if off:  # every axle beyond the springings: no block loaded, no case
        print(f"{prog}: warning: lead-axle position(s) {', '.join(f'{x:g}' for x in off)} load no block (every "
              "axle beyond the springings); left out", file=sys.stderr)
    if not structure.cases:  # (its file would be solved under the default live load, not an axle)
        raise InputError(f"{args.bridge}: no lead-axle position loads the bridge; expected positions between the "
                         "springings")
    if args.output and args.output.endswith(("/", os.sep)):
        raise InputError(f"{args.output}: a folder; expected the path of the block structure's JSON file")
    out = Path(args.output or Path(args.bridge).with_name(f"{Path(args.bridge).stem}_blocks.json"))
    _bridge_outputs(Path(args.bridge), out, args.adequacy)
    try:
        structure_to_json(spec, out)
    except OSError as exc:
        raise InputError(f"{out}: cannot write it ({exc.strerror}); expected a writable path") from None
    picture = plot_bridge(bridge, out.with_suffix(".png"), passive=not args.no_passive)
    _say(f"{out}: {len(structure.blocks)} blocks, {structure.n_contacts} contacts ({structure.restraints} passive "
         f"restraints), {len(structure.cases)} load position{'s' if len(structure.cases) != 1 else ''}; picture {picture}")
    if not args.adequacy:
        return EXIT_OK
    from .bridges.adequacy import adequacy_run, write_adequacy
    from .bridges.report import write_bridge_report
    from .search.options import SolveOptions
    where = case_positions(bridge)

    def said(row):  # each position as it ends
        alpha = f"{row['alpha_c']:.6f}" if row["certified"] else f"none ({row['status']})"
        _say(f"  x = {where[row['case']]:.6g}: adequacy {alpha}")
    table, outcomes = adequacy_run(bridge, SolveOptions(starts=args.starts, workers=args.workers),
                                   passive=not args.no_passive, progress=said)
    files = write_adequacy(bridge, table, args.adequacy, outcomes, passive=not args.no_passive)
    files.append(write_bridge_report(Path(args.adequacy) / "report.html", bridge, table, outcomes,
                                     Path(args.bridge).read_text(encoding="utf-8"),
                                     " ".join([prog.split()[0], *sys.argv[1:]]),
                                     passive=not args.no_passive))
    _say(table.to_string(index=False))
    for x, outcome in outcomes.items():  # why a position has no factor, as lamodel solve says it
        if outcome is not None and outcome.best is None and outcome.message:
            _say(f"x = {x:.6g}: {outcome.message}")
    _say(f"written: {', '.join(files)}")
    return EXIT_OK if table["certified"].all() else EXIT_NOT_CERTIFIED


def _bridge_outputs(bridge, out, adequacy) -> None:
    """The bridge command's outputs checked before any work: the structure (JSON) and its
    picture beside it (.png) neither the description nor each other, their folder and the
    adequacy folder made (InputError naming the path otherwise)."""
    from pathlib import Path

    from .errors import InputError
    picture = out.with_suffix(".png")
    if out.suffix.lower() == ".png" or out.is_dir():
        raise InputError(f"{out}: {'a folder' if out.is_dir() else 'the picture path'}; expected the path of the "
                         "block structure's JSON file (its picture is written beside it, .png)")
    for path in (out, picture):
        if path.exists() and path.resolve() == bridge.resolve():
            raise InputError(f"{path}: the bridge description itself; expected another output path (the "
                             "description is never overwritten)")
    for folder in [out.parent] + ([Path(adequacy)] if adequacy else []):
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"{folder}: cannot make this folder ({exc.strerror}); expected a writable folder") from None
    if not os.access(out.parent, os.W_OK):
        raise InputError(f"{out.parent}: not writable; expected a writable folder for {out.name}")


# ------------------------------------------------------------------------------ table1
def _table1_arguments(p):
    a = p.add_argument
    a("--out", default="results/table1.csv", help="CSV file (default results/table1.csv)")
    a("--seed", type=SEED, default=0, help="random seed of the GA (default 0)")
    a("--starts", type=whole(0), default=None, metavar="K", help="K Ipopt solves of eq. 5 per wall, from the best "
      "distinct certified states (default: only when cheap, see solve --help; 0: LPs only)")
    a("--workers", type=whole(1), default=None, help="worker processes (default: all cores)")


def _table1(args, prog) -> int:
    from .search.options import SolveOptions
    from .studies import table1_into
    df = table1_into(args.out, SolveOptions(seed=args.seed, starts=args.starts, workers=args.workers), echo=_say)
    return EXIT_OK if df["certified"].all() else EXIT_NOT_CERTIFIED


#: command -> (help, declare the arguments, run)
COMMANDS = {
    "solve": ("minimum collapse multiplier of a block assembly (seed eq. 5), certified by LP",
              _solve_arguments, _solve),
    "study": ("a parametric study from a JSON spec: one certified alpha per variant, as a table and a plot",
              _study_arguments, _study),
    "compare": ("compare two result folders, planar or in space (exit 0 agree, 1 differ, 2 bad input)", _compare_arguments, _compare),
    "build": ("write the .dat instance of a JSON polygon geometry (in 3D: its contacts summary)", _build_arguments,
              _build),
    "bridge": ("build a masonry arch bridge's blocks, fill and load positions from its description (and its "
               "adequacy factor against the load position)", _bridge_arguments, _bridge),
    "table1": ("the seed's Table 1 with lamodel's certified alpha", _table1_arguments, _table1),
}


def _parser(prog="lamodel", command=None) -> argparse.ArgumentParser:
    kw = dict(epilog=EXIT_HELP, formatter_class=argparse.RawDescriptionHelpFormatter)
    top = "Limit analysis of dry masonry block assemblies with Coulomb friction."
    sentence = lambda text: text[0].upper() + text[1:] + "."  # noqa: E731
    p = _Parser(prog=prog, description=sentence(COMMANDS[command][0]) if command else top, **kw)
    sub = None if command else p.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name, (text, arguments, _) in COMMANDS.items():  # one command under its own name: the scripts/ shims
        if command in (None, name):
            sp = p if command else sub.add_parser(name, help=text, description=sentence(text), **kw)
            arguments(sp)
            sp.add_argument("--debug", action="store_true", help="show tracebacks")
    return p


def command(name: str | None, argv=None, prog: str = "lamodel") -> int:
    """Run one command (``name``) or the whole ``lamodel`` command line (``name=None``);
    returns the exit status. SIGINT, SIGTERM and SIGHUP end it with 128 + the signal
    (:mod:`lamodel.process`)."""
    from .signals import stop_signal
    old = watch_signals()
    try:
        return _command(name, list(sys.argv[1:] if argv is None else argv), prog)
    except KeyboardInterrupt:  # e.g. while the parser imports the search's choices
        return interrupted(prog)
    except Exception:  # outside a command (the parser's imports): a bug, unless a signal broke an import
        if stop_signal() is None:
            raise
        return interrupted(prog)
    finally:
        unwatch_signals(old)


def _command(name, argv, prog):
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
    prog = f"lamodel {name}" if prog == "lamodel" else prog
    return run_reporting(lambda: COMMANDS[name][2](args, prog), prog, args.debug)


def main(argv=None) -> int:
    """The ``lamodel`` command line; returns its exit status."""
    return command(None, argv)


def solve_main(argv=None) -> int:
    """``lamodel-solve`` and ``scripts/solve.py``: the solve command under its old name."""
    return command("solve", argv, prog="solve.py")


def run():
    """The ``lamodel`` console script."""
    exit_now(main())


def run_solve():
    """The ``lamodel-solve`` console script."""
    exit_now(solve_main())


if __name__ == "__main__":
    exit_now(main())
