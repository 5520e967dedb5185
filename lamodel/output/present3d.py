"""One analysis of a structure in space, as ``lamodel solve`` runs it for a 3D input:
solve (:func:`lamodel.search.search3d.solve3d`: the search of
:func:`lamodel.search.driver.solve` on the cone formulation), write, present.

:func:`lamodel.analyse` hands a 3D structure (a 3D JSON, a COMPAS assembly, a mesh) to
:func:`analyse3d`, which writes the result folder with the planar one's guarantees
(:class:`lamodel.output.folder.ResultFolder`: every output place checked before solving,
the folder replaced as a whole, a user's own files kept): ``summary.csv``, ``blocks.csv``,
``contacts.csv`` (one row per contact point), ``runs.csv`` (:mod:`.results3d`), the
picture (:mod:`.plot3d`), ``methods.csv`` for ``--method all``, and the browser view
(:mod:`.view3d`) when asked. Ctrl-C, SIGTERM and SIGHUP end the search; its best certified
state is written.

Methods: ``lamodel`` (default: the certified search, as in the plane: gap alternation,
certification, descents, continuations, the GA with ``--workers``/``--scheduler``), ``associative`` (the associative cone program's mechanism certified),
``successive-lp`` (in space: successive cone programming), ``all`` (the three side by
side, with lamodel's search; the folder holds the least certified state).
"""
from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..search.options import Deadline
from ..search.state import INTERRUPTED, UNSTABLE

#: --method -> (solve3d's method, explore)
METHODS3D = {"lamodel": ("all", True), "associative": ("associative", False), "successive-lp": ("successive", False)}


@dataclass
class Analysis3D:
    """What :func:`analyse3d` did: the structure, the search's :class:`Result3D`, the
    summary row, the mechanism in words, the folder and the files written (picture, view),
    and the methods table for ``--method all``."""

    structure: object
    result: object
    summary: dict
    words: list
    folder: Path
    files: dict = field(default_factory=dict)
    methods: object = None

    certified = property(lambda self: self.result.state is not None,
                         doc="Whether the search certified a collapse state in space.")
    alpha = property(lambda self: float(self.result.alpha), doc="The certified multiplier (NaN: none).")
    interrupted = property(lambda self: self.result.status == INTERRUPTED,
                           doc="Whether a stop signal ended the search (its best state is written).")

    def line(self) -> str:
        """The one-line result, worded as for a planar structure."""
        r = self.result
        head = f"{self.structure.name}: "
        if not self.certified:
            return head + f"no certified collapse multiplier: {r.message}"
        from .methods import methods_took
        took = f"{self.summary['wall_time_s']:.1f} s" if self.methods is None else methods_took(self.methods)
        return head + f"alpha = {max(r.alpha, 0.0):.6f} (certified collapse state; associative bound " \
                      f"{r.associative:.6f}) in {took}"

    def text(self, quiet: bool = False) -> str:
        """The terminal's account of the solve: the methods table (``--method all``), then
        unless ``quiet`` the structure, the status, the mechanism in words and the files;
        the one-line result last."""
        from .methods import methods_text
        out = [] if self.methods is None else [
            f"Methods on '{self.structure.name}' (each raw answer certified; the folder holds "
            f"{self.summary['method']}'s state):", methods_text(self.methods),
            f"methods table written to {self.folder}/methods.csv"]
        if not quiet:
            s, r, sm = self.structure, self.result, self.summary
            out += [f"{s.name}: {s.n_blocks} blocks, {len(s.supports)} supports, {s.n_interfaces} interfaces, "
                    f"{s.n_points} contact points (3D)"]
            if sm.get("defaults_applied"):
                out.append(f"defaults applied (the input has no mechanical data): mu {sm['mu']:g}, unit weight "
                           f"{sm['unit_weight']:g}, live load ({sm['live_load'].replace(' ', ', ')}) per unit "
                           "weight")
            out.append(f"status: {r.status}; certified: {'yes' if self.certified else 'no'}"
                       + (f" (path {r.path}, residual {sm['residual']:.1e})" if self.certified else ""))
            files = [f"{k} {self.files[k]}" for k in ("picture", "view") if k in self.files]
            out += ["", *self.words, f"results written to {self.folder}/" + "".join(f", {f}" for f in files)]
        return "\n".join(out + [self.line()])


def refuse_planar_options(method, options, moving, report, animate):
    """InputError (one line) for what a 3D solve cannot honour."""
    if method not in METHODS3D and method != "all":
        raise InputError(f"--method {method}: a planar method; expected for a 3D structure one of lamodel, "
                         "associative, successive-lp, all")
    named = [("--rolling", moving[0]), ("--axles", moving[1]), ("--positions", moving[2]), ("--report", report),
             ("--animate", animate), ("--starts", options.starts)]
    from ..search.options import SolveOptions
    if options.solver != SolveOptions.solver:
        named.append(("--solver", options.solver))
    given = [flag for flag, value in named if value is not None]
    if given:
        raise InputError(f"{given[0]}: applies to planar structures only (rolling loads, Ipopt starts, the HTML "
                         "report); expected a 3D solve without it")


def refuse_spatial_options(inputs, view):
    """InputError for options of 3D inputs given with a planar one."""
    if view is not None:
        raise InputError(f"--view {view}: the browser view is drawn for 3D structures; expected a 3D input "
                         "(or --report FILE.html for a planar one)")
    if inputs:
        flag = "--" + sorted(inputs)[0].replace("_", "-")
        raise InputError(f"{flag}: applies to 3D inputs (COMPAS assemblies, meshes); expected a planar input "
                         "without it")


def _solve(s, method, options, stop, on_associative=None):
    """(Result3D kept in the folder, runs table, methods table or None, the method kept).
    The search shows its own progress line (``options.progress``); ``on_associative``:
    the search's (:func:`lamodel.search.driver.solve`)."""
    from ..search.search3d import solve3d
    from .results3d import methods_frame3d, runs_frame
    runs, done, iterations = [], {}, {}
    names = ["associative", "successive-lp", "lamodel"] if method == "all" else [method]
    deadline = Deadline.after(options.time_limit)
    for i, m in enumerate(names):
        which, explore = METHODS3D[m]
        # each method an equal share of the time left (what one leaves goes to those after it),
        # as in the plane; without a limit each is bounded by the search's counted work
        limit = deadline.share(len(names) - i)
        done[m] = r = solve3d(s, method=which, explore=explore, time_limit=limit, seed=int(options.seed), stop=stop,
                              options=replace(options, time_limit=limit) if m == "lamodel" else None,
                              on_associative=on_associative if m == "lamodel" else None)
        for v in r.methods.values():   # each method's own answer, certified, named as --method names it
            runs.append((m, v))
            iterations[m] = r.n_cone
        if r.status == INTERRUPTED:
            break
    table = runs_frame(runs)
    if method != "all":
        return done[method], table, None, method
    certified = {k: r for k, r in done.items() if r.state is not None}
    # the least certified alpha; on a tie the search's state (its path says how it was found)
    keep = min(certified, key=lambda k: (certified[k].alpha, k != "lamodel")) if certified else list(done)[-1]
    return done[keep], table, methods_frame3d(table, iterations), keep


def _unheld(structure) -> str:
    """The unstable verdict's blocks (:func:`lamodel.search.unstable.unheld_blocks3d`): the
    ones no statics holds under the dead load alone, for the user to look at."""
    from ..search.unstable import unheld_blocks3d
    from .extras import unheld_words
    names, complete = unheld_blocks3d(structure)
    return unheld_words(names, complete) if names else ""


def analyse3d(structure, options, out, *, method="lamodel", seed_ga=None, picture=True, report=None,
              animate=None, moving=(None, None, None), view=None, echo=None, prove=None, strengths=None):
    """Solve a :class:`lamodel.structure3d.Structure3D` and write its result folder (see the
    module doc); what :func:`lamodel.analyse` does for a 3D input. ``view``: a .html path
    for the browser view (inside ``out`` it is part of the folder). ``prove``: seconds for
    the proven lower bound ``alpha_lower`` (default: :func:`lamodel.bound.lower.default_budget`).
    ``strengths``: the what-ifs on the joints' strengths already applied, named in the view.
    Returns an :class:`Analysis3D`."""
    from ..bound.beside import BoundBeside
    from ..io.files import safe_folder_name
    from ..signals import catch_sigint, restore_sigint
    from .folder import ResultFolder, check_output_file, foreign_files, in_folder, picture_place
    from .results3d import bound_columns3d, summary_row, write_results3d
    from .words import bound_words, stall_words
    import pandas as pd
    from .words3d import describe3d

    refuse_planar_options(method, options, moving, report, animate)
    if options.scheduler:
        from ..search.executor import check_scheduler
        check_scheduler(options.scheduler)  # fail at once, not after the first certificate
    out = Path(out) if out else Path("results") / safe_folder_name(structure.name)
    extras = {"picture": picture_place(None if picture is True else picture, out) if picture else None,
              "view": view}
    if view is not None:
        check_output_file("view", view, (".html", ".htm"), out)
    stage = ResultFolder(out, foreign_files).open()
    inside = {k: p for k, p in extras.items() if p is not None and in_folder(p, stage.final)}
    outside = {k: Path(p) for k, p in extras.items() if p is not None and k not in inside}
    try:
        stop = threading.Event()
        caught = catch_sigint(stop.set)
        t0 = time.perf_counter()
        # the default bound runs beside the search, from its associative multiplier
        beside = BoundBeside(structure, enabled=prove is None)
        try:
            with beside:
                result, runs, methods, kept = _solve(structure, method, options, stop.is_set, beside.start)
        finally:
            restore_sigint(caught)
        if result.status == UNSTABLE:
            result.message += _unheld(structure)
        if echo is not None and methods is not None:
            for _, row in methods.iterrows():
                cert = "none" if not row["certified"] else f"{row['alpha_certified']:.6f}"
                echo(f"  {row['method']}: raw alpha {row['alpha_raw']:.6f}, certified {cert}")
        extra = {"seed": int(options.seed), "time_limit": options.time_limit if options.time_limit else np.nan}
        extra |= {k: (Path(p).name if k in inside else str(p or "")) for k, p in extras.items()}
        summary = summary_row(structure, result, kept, extra)
        summary["wall_time_s"] = time.perf_counter() - t0
        summary |= bound_columns3d(structure, result, summary["wall_time_s"], prove, beside)
        words = (describe3d(structure, result.motions, result.modes) + bound_words(pd.DataFrame([summary]))
                 + stall_words(structure, result.stalled))
        write_results3d(stage.path, structure, result, summary, runs, methods)
        _draw({k: stage.path / Path(p).name for k, p in inside.items()}, structure, result, strengths)
        stage.publish()
    finally:
        stage.discard()
    _draw(outside, structure, result, strengths)
    shown = {k: out / Path(p).name for k, p in inside.items()} | outside
    return Analysis3D(structure, result, summary, words, out, shown, methods)


def _draw(paths: dict, s, result, strengths=None):
    """The picture (plot3d) and the browser view (view3d, its inputs with the joints'
    strengths and the what-ifs ``strengths``) at their paths."""
    if "picture" in paths:
        from .plot3d import plot_structure3d
        alpha = f"alpha = {result.alpha:.6f}" if result.state is not None else result.status.replace("_", " ")
        plot_structure3d(s, paths["picture"], motions=result.motions, title=f"{s.name}: {alpha}")
    if "view" in paths:
        from .materials import strength_inputs
        from .view3d import write_view3d
        write_view3d(s, paths["view"], motions=result.motions, modes=result.modes,
                     normal=None if result.state is None else result.state.N,
                     title=f"{s.name}: alpha = {result.alpha:.6f}" if result.state is not None else s.name,
                     inputs=strength_inputs(s, strengths))
