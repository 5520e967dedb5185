"""What a solve shows besides its tables: the mechanism picture, its animation, the
mechanism in words, the HTML report, and the figure of a load-case or rolling-load study.

Every picture of a solve shows the same thing (:func:`picture_of`): the certified
mechanism with the modes of contacts.csv and the thrust line; or, for a structure
unstable under its dead load, the mechanism of the dead load alone, its moving blocks
highlighted; or the structure at rest.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np


def explain_unstable(outcome):
    """For a structure unstable under its dead load: the mechanism of the dead load alone
    (:mod:`lamodel.search.unstable`), its moving blocks named in the outcome's message.
    None for any other outcome."""
    if outcome.status != "unstable":
        return None
    from ..search.unstable import dead_load_mechanism
    from .words import moving_blocks
    u = dead_load_mechanism(outcome.structure)
    if u is None:
        return None
    names = [b for b, m in zip(outcome.structure.blocks, moving_blocks(outcome.structure, u)) if m]
    outcome.message += unheld_words(names)
    return u


#: Block ids named at most in the one-line unstable verdict (the rest counted).
SHOWN_UNHELD = 10


def unheld_words(names, complete=True) -> str:
    """The end of the unstable verdict's line: the count of the blocks that move under dead
    load alone and the first few ids (``complete``: the list is all of them)."""
    n = len(names)
    shown = ", ".join(names[:SHOWN_UNHELD]) + (", ..." if n > SHOWN_UNHELD else "")
    return (f"; the blocks that move under dead load alone: {shown} ({n} block{'s' if n != 1 else ''}"
            f"{'' if complete else ', and maybe more'})")


def picture_of(outcome, results, dead_u=None) -> dict:
    """The keyword arguments of :func:`lamodel.output.plot.plot_mechanism` for a solve
    (see the module doc); ``dead_u`` from :func:`explain_unstable`."""
    from .modes import modes_from_mechanism
    from .words import moving_blocks
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


def words_of(outcome, results, dead_u=None) -> list:
    """The mechanism in words (:mod:`lamodel.output.words`), one line each."""
    from .modes import modes_from_mechanism
    from .words import bound_words, describe, stall_words
    s = outcome.structure
    if outcome.best is not None:
        return describe(s, outcome.best.u, results.modes(), outcome.best.alpha, outcome.best.N) + \
            bound_words(results.summary)
    if dead_u is not None:
        return ["Under dead load alone (no live load):"] + describe(s, dead_u, modes_from_mechanism(s, dead_u))[1:]
    return [f"No mechanism: {outcome.message}."] + stall_words(s, outcome.stalled)


def picture_svg(outcome, results, dead_u=None) -> str:
    """The picture of :func:`picture_of` as SVG text (for the HTML report)."""
    import matplotlib.pyplot as plt

    from .html import svg_of
    from .plot import plot_mechanism
    fig, ax = plt.subplots(figsize=(9, 6))
    try:
        plot_mechanism(outcome.structure, path=None, ax=ax, **picture_of(outcome, results, dead_u))
        return svg_of(fig)
    finally:
        plt.close(fig)


def write_extras(paths: dict, outcome, results, words, dead_u=None, study=None, source="", command="",
                 painter=None, strengths=None):
    """The picture, the animation and the HTML report, each to its path in ``paths``
    (keys picture, animation, report; a missing key: not written); the picture by
    ``painter`` (:class:`lamodel.output.painter.Painter`) if given. ``study``: the
    load-case or rolling table of :func:`write_study_files`; ``source``, ``command`` and
    the what-ifs on the joints' ``strengths`` are named in the report."""
    picture = picture_of(outcome, results, dead_u)
    if "picture" in paths:
        if painter is not None:
            painter.draw(outcome.structure, paths["picture"], picture)
        else:
            from .plot import plot_mechanism
            plot_mechanism(outcome.structure, path=str(paths["picture"]), **picture)
    if "animation" in paths:
        from .plot import animate_mechanism
        animate_mechanism(outcome.structure, path=paths["animation"],
                          **{k: v for k, v in picture.items() if k != "title"})
    if "report" in paths:
        from .html import write_report
        write_report(paths["report"], outcome.structure, results, words, picture_svg(outcome, results, dead_u),
                     command, str(source),
                     study=None if study is None else (study["title"], study["key"], study["table"], study["svg"]),
                     strengths=strengths)


def write_study_files(study: dict, folder, structure) -> dict:
    """cases.csv or rolling.csv (and rolling.png) in ``folder``; returns ``study`` with the
    figure as SVG (key ``svg``, for the report). ``study``: the dict of
    :func:`lamodel.studies.governing_study`."""
    from ..io.files import write_csv
    from .figures import cases_figure, rolling_figure, save_open_figure
    from .html import svg_of
    df = study["table"]
    units = {"length_unit": structure.units.get("length", "-"), "force_unit": structure.units.get("force", "-")}
    write_csv(df.assign(**units), Path(folder) / ("cases.csv" if study["key"] == "case" else "rolling.csv"))
    title, length = f"{structure.name}: rolling load", structure.units.get("length", "")
    if study["key"] == "case":
        fig = cases_figure(df)
    else:
        fig = rolling_figure(df, title, length)
        save_open_figure(rolling_figure(df, title, length), Path(folder) / "rolling.png")
    try:
        return dict(study, svg=svg_of(fig))
    finally:
        import matplotlib.pyplot as plt
        plt.close(fig)
