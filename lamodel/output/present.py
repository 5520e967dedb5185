"""One analysis of a structure, as ``lamodel solve`` runs it: read, solve, write, present.

:func:`analyse` is the command line's whole use case as a Python call::

    import lamodel
    a = lamodel.analyse("instances/wall33.dat", lamodel.SolveOptions(seed=0), out="results/wall33")
    print(a.text())            # the tables, the mechanism in words, where the files are
    a.alpha, a.certified       # the certified collapse multiplier

It writes the same result folder (``summary.csv``, ``blocks.csv``, ``contacts.csv``,
``runs.csv``, the picture, and ``cases.csv``/``rolling.csv``/``methods.csv`` when they
apply) as ``lamodel solve`` with the same options, with the same guarantees
(:class:`lamodel.output.folder.ResultFolder`: the folder is replaced as a whole, a user's
own files in it are kept), and returns what the command prints.
"""
from __future__ import annotations

import os
import warnings
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import InputError


@dataclass
class Analysis:
    """What :func:`analyse` did: the structure as solved, the driver's outcome, the four
    tables, the mechanism in words, and the files written (``folder`` and ``files``:
    picture, report, animation by name)."""

    structure: object
    outcome: object
    results: object
    words: list
    folder: Path
    files: dict = field(default_factory=dict)
    study: dict | None = None      # load cases or rolling load: key, title, table
    methods: object = None         # --method all: the methods table

    @property
    def certified(self) -> bool:
        """True when a collapse state was certified."""
        return bool(self.outcome.certified)

    @property
    def alpha(self) -> float:
        """The certified collapse multiplier (NaN when none was certified)."""
        return float(self.results.alpha)

    @property
    def interrupted(self) -> bool:
        """True when a signal stopped the search (the best certified state so far is written)."""
        return self.outcome.status == "interrupted" or bool(self.study and self.study.get("interrupted"))

    def line(self) -> str:
        """The one-line result."""
        name, r = self.structure.name, self.results
        if self.certified and self.study:  # the governing variant's, and the whole study's time
            key, table = self.study["key"], self.study["table"]
            label = r.summary[key].iloc[0] if key in r.summary else "?"
            label = f"x = {label:.6g}" if key == "position" else f"'{label}'"
            kind = "cases" if key == "case" else "positions"
            left = int((table["status"] == "not run").sum())
            stopped = f"; stopped: {left} of {len(table)} {kind} not run" if self.interrupted else ""
            return (f"{name}: alpha = {max(r.alpha, 0.0):.6f} (certified collapse state; associative bound "
                    f"{r.alpha_associative:.6f}; {key} {label} governs) in {self.study['seconds']:.1f} s for "
                    f"{len(table)} {kind}{stopped}")
        if self.certified:
            from .methods import methods_took
            took = f"{self.outcome.wall_time_s:.1f} s" if self.methods is None else methods_took(self.methods)
            return (f"{name}: alpha = {max(r.alpha, 0.0):.6f} (certified collapse state; associative bound "
                    f"{r.alpha_associative:.6f}) in {took}")
        return f"{name}: no certified collapse multiplier: {self.outcome.message}"

    def text(self, quiet: bool = False) -> str:
        """What ``lamodel solve`` prints when the solve ends (``quiet``: the methods table,
        if any, and the one-line result only)."""
        import pandas as pd
        out = []
        if self.methods is not None:
            from .methods import methods_text
            out += [f"Methods on '{self.structure.name}' (each raw answer certified; the folder holds "
                    f"{self.methods.attrs.get('chosen', 'the best')}'s state):", methods_text(self.methods),
                    f"methods table written to {self.folder}/methods.csv"]
        if not quiet:
            with pd.option_context("display.width", 160, "display.max_columns", 20, "display.max_colwidth", 60):
                out.append(self.results.to_text())
                if self.study is not None:
                    out += [f"\n{self.study['title']}:",
                            self.study["table"].to_string(index=False, float_format=lambda v: f"{v:.6g}")]
            out += ["", *self.words]
            picture = self.files.get("picture")
            out.append(f"results written to {self.folder}/" + (f", picture {picture}" if picture else ""))
            if "report" in self.files:
                out.append(f"report written to {self.files['report']}")
        out.append(self.line())
        return "\n".join(out)


def analyse(source, options=None, out=None, *, method: str = "lamodel", seed_ga=None, picture=True,
            report=None, animate=None, rolling=None, axles=None, positions=None, echo=None, warn=None,
            command: str | None = None, prove: float | None = None, view=None, inputs: dict | None = None,
            strengths: dict | None = None):
    """Read a structure, solve it, write its result folder and its pictures: what
    ``lamodel solve`` does, with the same files and words.

    ``source``: a .dat or .json path, or a :class:`lamodel.structure.Structure`.
    ``options``: :class:`lamodel.search.options.SolveOptions` (default ones).
    ``out``: the result folder (default ``results/<structure name>/``), replaced as a
    whole; a folder holding folders or links lamodel did not write is refused.
    ``method``: ``lamodel`` (the certified search), or a method of
    :mod:`lamodel.search.methods` or ``all`` (their table in ``methods.csv``);
    ``seed_ga``: (population, generations) of the ``seed`` method (default the seed's).
    ``picture``: True for ``<out>/mechanism.png``, False for none, or a path (a
    matplotlib format; inside ``out`` it is part of the folder). ``report`` (.html) and
    ``animate`` (.gif): paths, likewise. ``rolling`` (FX, FY), ``axles``, ``positions``:
    a rolling load (:func:`lamodel.loads.with_rolling`). ``echo(line)`` receives the
    progress lines of load cases, rolling positions and methods; ``warn(message)`` the
    input's warnings (default: Python warnings). ``command`` is named in the report.
    ``prove``: seconds for the proven lower bound ``alpha_lower`` in summary.csv
    (:func:`lamodel.bound.lower_bound`; default a share of the search's own time).
    ``strengths``: what-ifs ``{"fc", "ft", "cohesion"}`` (None: the file's) on every joint
    of a structure, planar or in space (:func:`lamodel.variants.with_strengths`).

    A 3D input (a 3D JSON, a COMPAS assembly, a mesh, or a Structure3D) is solved in space
    (:func:`lamodel.output.present3d.analyse3d`, an :class:`~lamodel.output.present3d.Analysis3D`
    is returned): ``inputs`` are the 3D readers' options (mu, unit_weight, live_load,
    supports, supports_below, units, tolerance, contact_points) and ``view`` a .html path
    for the browser view.

    Every output place is checked before solving (InputError, one line). A signal that
    stops the search (Ctrl-C, SIGTERM, SIGHUP) still writes the best certified state
    (:attr:`Analysis.interrupted`). :class:`lamodel.errors.OutputError` when the folder
    cannot be written.
    """
    from ..io import dimension
    from ..search.options import SolveOptions
    from . import present3d
    options = options or SolveOptions()
    painter = None
    dim = dimension(source) if isinstance(source, (str, os.PathLike)) else getattr(source, "dimension", 2)
    if picture and not (report or animate) and dim == 2:
        # the planar picture's matplotlib loads in a second process while this one reads and
        # solves (a structure in space draws its own; the report and the animation load it here)
        from .painter import Painter
        painter = Painter()
    try:
        structure = _read(source, warn, inputs)
        asked = {k: v for k, v in (strengths or {}).items() if v is not None}
        if asked:
            structure = _with_strengths(structure, asked, source)
        if prove is not None and getattr(structure, "has_materials", False):
            said = ("--prove: the proven lower bound knows dry joints only; alpha_lower is not computed for "
                    "joints with strengths")
            if warn is not None:
                warn(said)
            else:
                warnings.warn(said, stacklevel=2)
        if getattr(structure, "dimension", 2) == 3:  # in space: its own use case
            return present3d.analyse3d(structure, options, out, method=method, seed_ga=seed_ga, picture=picture,
                                       report=report, animate=animate, moving=(rolling, axles, positions),
                                       view=view, echo=echo, prove=prove, strengths=asked)
        present3d.refuse_spatial_options(inputs, view)
        return _analyse(structure, source, options, out, method, seed_ga, picture, report, animate,
                        (rolling, axles, positions), echo, command, painter, prove, asked)
    finally:
        if painter is not None:
            painter.close()


def _read(source, warn, inputs=None):
    from ..io import read
    if not isinstance(source, (str, os.PathLike)):
        return source
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            return read(source, **(inputs or {}))
    finally:  # shown before the solve (they change the answer), and before a reading error they may explain
        for w in caught:
            if warn is not None and issubclass(w.category, UserWarning):
                warn(str(w.message))
            else:
                warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


def _with_strengths(structure, asked, source):
    """:func:`lamodel.variants.with_strengths` for the what-ifs ``asked`` (--fc, --ft,
    --cohesion): an ft above an fc is refused naming the option that set it, and the file
    when the other one is the file's."""
    import numpy as np

    from ..validation import first
    from ..variants import in_space, joint_places, with_strengths
    fc, ft = asked.get("fc"), asked.get("ft")
    if fc is not None and ft is not None and ft > fc:
        raise InputError(f"--ft is {ft:g}, above --fc {fc:g}; expected a tensile strength at most the compressive one")
    if (fc is None) != (ft is None):
        n = joint_places(structure)
        own = np.asarray(structure.ft if ft is None else structure.fc, dtype=float)[:n]
        i = first(own > fc) if ft is None else first(ft > own)
        if i is not None:
            where = str(source) if isinstance(source, (str, os.PathLike)) else f"structure '{structure.name}'"
            owner = f"interface '{structure.interfaces[structure.point_interface[i]]}'" if in_space(structure) \
                else f"contact '{structure.contacts[i]}'"
            said = f"--fc is {fc:g}, below the ft {own[i]:g}" if ft is None else f"--ft is {ft:g}, above the fc {own[i]:g}"
            raise InputError(f"{said} that {where} gives {owner}; expected a tensile strength at most the compressive "
                             f"one (give {'--ft' if ft is None else '--fc'} too)")
    return with_strengths(structure, **asked)


def _analyse(structure, source, options, out, method, seed_ga, picture, report, animate, moving, echo, command,
             painter, prove=None, strengths=None):
    from ..io.files import safe_folder_name
    from ..loads import the_live_load, with_rolling
    from ..search.driver import solve
    from .extras import explain_unstable, words_of, write_extras, write_study_files
    from .folder import ResultFolder, check_output_file, foreign_files, in_folder, picture_place
    from .report import outcome_results

    source = str(source) if isinstance(source, (str, os.PathLike)) else structure.name
    structure = with_rolling(structure, *moving, source=source)
    if options.scheduler:
        from ..search.executor import check_scheduler
        check_scheduler(options.scheduler)  # fail at once, not after the first certificate
    _check_resolution(structure)
    if method != "lamodel":  # one load case, or one position of a rolling load (a bridge's): under it
        structure = the_live_load(structure, f"method {method}")
    # every output place is checked before the solve
    out = Path(out) if out else Path("results") / safe_folder_name(structure.name)
    extras = {"picture": picture_place(None if picture is True else picture, out) if picture else None,
              "report": report, "animation": animate}
    for what, suffixes in (("report", (".html", ".htm")), ("animation", (".gif",))):
        if extras[what] is not None:
            check_output_file(what, extras[what], suffixes, out)
    stage = ResultFolder(out, foreign_files).open()
    inside = {k: p for k, p in extras.items() if p is not None and in_folder(p, stage.final)}
    outside = {k: Path(p) for k, p in extras.items() if p is not None and k not in inside}
    staged = {k: stage.path / Path(p).name for k, p in inside.items()}
    drawing = painter is not None and "picture" in staged

    def draw(outcome, results, dead_u):
        """The picture, drawn in the painter's process while this one goes on."""
        from .extras import picture_of
        painter.start(outcome.structure, staged["picture"], picture_of(outcome, results, dead_u))
    try:
        study, methods, dead_u = None, None, _UNKNOWN
        if method != "lamodel":
            outcome, results, methods = _run_methods(method, structure, options, seed_ga, echo)
        else:
            extra = {}
            if structure.cases or structure.rolling is not None:
                from ..studies import governing_study
                study, outcome, extra = governing_study(structure, options, _study_progress(echo))
            else:
                from ..bound.beside import BoundBeside
                from .report import lower_bound_columns
                # the default bound runs beside the search, from its associative multiplier
                beside = BoundBeside(structure, enabled=prove is None)
                with beside:
                    outcome = solve(structure, options, on_associative=beside.start)
                dead_u = explain_unstable(outcome)
                if drawing:  # drawn while the lower bound is proved (the picture does not show it)
                    draw(outcome, outcome_results(outcome), dead_u)
                    drawing = False
                extra = lower_bound_columns(outcome, prove, beside)
            results = outcome_results(outcome, dict(extra, method="lamodel"))
        if dead_u is _UNKNOWN:
            dead_u = explain_unstable(outcome)
        results.summary["message"] = outcome.message  # with the blocks that move under dead load, if unstable
        if drawing:  # drawn there while the tables are written here
            draw(outcome, results, dead_u)
        words = words_of(outcome, results, dead_u)
        # everything in the result folder is written into the staging folder, then swapped
        # in as a whole; its files are named in summary.csv (a later run knows them as lamodel's)
        for column, path in extras.items():
            results.summary[column] = Path(path).name if column in inside else str(path or "")
        results.write_into(stage.path)
        if study is not None:
            study = write_study_files(study, stage.path, structure)
        if methods is not None:
            from .methods import write_methods_csv
            write_methods_csv(methods, stage.path)
        command = command or f"lamodel.analyse({str(source)!r})"
        write_extras(staged, outcome, results, words, dead_u, study, source, command, painter, strengths)
        stage.publish()
    finally:
        stage.discard()
    write_extras(outside, outcome, results, words, dead_u, study, source, command, painter, strengths)
    shown = {k: out / Path(p).name for k, p in inside.items()} | outside
    return Analysis(structure, outcome, results, words, out, shown, study, methods)


_UNKNOWN = object()  # explain_unstable not asked yet


def _check_resolution(structure):
    """Refuse a structure with blocks too small beside the whole for double-precision
    geometry (:func:`lamodel.search.certify.unresolved_blocks`): no certificate could
    place their contacts."""
    from ..search.certify import SIZE_RESOLUTION, unresolved_blocks
    small = unresolved_blocks(structure)
    if small:
        shown = ", ".join(f"'{b}'" for b in small[:5]) + (f" and {len(small) - 5} more" if len(small) > 5 else "")
        many = len(small) > 1
        raise InputError(f"{structure.name}: block{'s' if many else ''} {shown} {'are' if many else 'is'} smaller "
                         f"than {SIZE_RESOLUTION:g} times the structure's size, beyond what double precision can "
                         f"resolve: {'their' if many else 'its'} contacts cannot be placed accurately enough to "
                         "certify a collapse state; expected blocks at least that large (or the small blocks analysed "
                         "on their own)")


def _study_progress(echo):
    if echo is None:
        return None

    def progress(row):
        key = "case" if "case" in row else "position"
        value = row[key] if key == "case" else f"x = {row[key]:.6g}"
        alpha = f"{row['alpha_c']:.6f}" if row["certified"] else f"none ({row['status']})"
        echo(f"  {value}: alpha = {alpha}")
    return progress


def _run_methods(method, structure, options, seed_ga, echo):
    """A method other than lamodel (or all of them): the result folder holds the certified
    state of the method (for all: of the best one). Returns (outcome, results, the
    methods table or None)."""
    from ..search.methods import best_of, run_methods
    from .methods import method_results, methods_frame

    def progress(r):
        if echo is not None:
            echo(f"  {r.method}: raw alpha {r.alpha_raw:.6f}, certified "
                 + (f"{r.alpha_certified:.6f}" if r.certified else "none") + f" ({r.seconds:.1f} s)")

    found = run_methods(method, structure, options, seed_ga, progress)
    chosen = best_of(found)
    frame = None
    if method == "all":
        frame = methods_frame(found)
        frame.attrs["chosen"] = chosen.method
    return chosen.outcome(), method_results(chosen), frame
