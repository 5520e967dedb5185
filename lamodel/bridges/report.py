"""The report page of a bridge's adequacy run (``lamodel bridge --adequacy``: report.html),
one self-contained HTML file an assessor can file or mail: the result (governing position,
adequacy factor, collapse load per axle), the bridge as built, the factor against the load
position (plot and table), the governing mechanism drawn with the fill and in words, the
description as the user wrote it, lamodel's version and the command. Pictures inline (SVG);
nothing is fetched from elsewhere.
"""
from __future__ import annotations

import html

import pandas as pd

from ..io.files import atomic_write_text
from ..output.html import page, svg_of, table_html
from .description import Bridge


def bridge_report_html(bridge: Bridge, table: pd.DataFrame, outcomes: dict, description: str, command: str,
                       passive: bool = True) -> str:
    """The page's text (module doc); ``outcomes`` by position (:func:`.adequacy.adequacy_run`),
    ``description`` the bridge file's text."""
    import matplotlib.pyplot as plt

    from .adequacy import adequacy_figure
    from ..output.modes import modes_from_flow
    from ..output.words import describe
    from .picture import draw_bridge, draw_governing
    force = bridge.units.get("force", "")
    length = bridge.units.get("length", "")
    governing = table.loc[table["governing"].astype(bool)]
    certified = int(table["certified"].astype(bool).sum())
    left = int((table["status"] == "not run").sum())
    rows = [("positions solved", f"{len(table) - left} of {len(table)} ({certified} certified)"
             + ("; stopped by a signal, the rest not run" if left else ""))]
    outcome, position = None, None
    if len(governing):
        g = governing.iloc[0]
        position, outcome = float(g["position"]), outcomes.get(float(g["position"]))
        rows += [("governing lead-axle position", f"x = {position:g} {length}".strip()),
                 ("adequacy factor", f"{g['adequacy']:.6f}"),
                 ("collapse load per axle", f"{g['collapse_load']:.6g} {force}".strip()),
                 ("mechanism", g["mechanism"])]
    else:
        rows.append(("adequacy factor", "none certified"))
    parts = ["<h2>Result</h2>", table_html(pd.DataFrame(rows, columns=["quantity", "value"])),
             "<p>Every factor is the collapse multiplier of the axle group at a certified collapse state "
             "(an upper bound on the least one: the search is not exhaustive).</p>"]
    figures = []
    try:
        fig, ax = plt.subplots(figsize=(10, 4.5))
        figures.append(fig)
        draw_bridge(ax, bridge, lead=position, passive=passive)
        parts += ["<h2>The bridge as built</h2>", f"<figure>{svg_of(fig)}</figure>"]
        fig = adequacy_figure(bridge, table)
        figures.append(fig)
        parts += ["<h2>Adequacy factor against the load position</h2>", f"<figure>{svg_of(fig)}</figure>",
                  table_html(table, table["governing"].astype(bool))]
        why = [f"x = {x:g}: {o.message}" for x, o in outcomes.items()   # positions without a factor, and why
               if o is not None and o.best is None and o.message]
        if why:
            parts.append(f'<div class="words">{html.escape(chr(10).join(why))}</div>')
        if outcome is not None and outcome.best is not None:
            fig, ax = plt.subplots(figsize=(10, 5))
            figures.append(fig)
            draw_governing(ax, bridge, outcome, position, passive)
            best, s = outcome.best, outcome.structure
            words = describe(s, best.u, modes_from_flow(s, best.xi), best.alpha, best.N)
            parts += ["<h2>Governing mechanism</h2>", f"<figure>{svg_of(fig)}</figure>",
                      f'<div class="words">{html.escape(chr(10).join(words))}</div>']
    finally:
        for fig in figures:
            plt.close(fig)
    parts += ["<h2>Description</h2>", f'<div class="words">{html.escape(description)}</div>']
    return page(f"lamodel: bridge {bridge.name}", f"Masonry arch bridge: {bridge.name}", command, parts)


def write_bridge_report(path, *args, **kwargs) -> str:
    """Write :func:`bridge_report_html` atomically to ``path``; returns the path."""
    atomic_write_text(path, bridge_report_html(*args, **kwargs))
    return str(path)
