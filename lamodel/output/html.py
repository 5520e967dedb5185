"""One self-contained HTML report of a solve: plain HTML, the pictures as inline SVG.

Sections: the result (summary), the mechanism (picture and words), the load cases or the
rolling load (table and plot) when there are any, the joints that move, the inputs and
units (with the joints' strengths: :mod:`lamodel.output.materials`), lamodel's version and the command. Nothing is fetched from elsewhere: the file can
be mailed or archived as it is.
"""
from __future__ import annotations

import datetime
import html
import io

import numpy as np
import pandas as pd

from ..io.files import atomic_write_text

#: The reports' stylesheet (also the bridge report's, :mod:`lamodel.bridges.report`).
STYLE = """
body { font-family: sans-serif; max-width: 1100px; margin: 1.5em auto; color: #222; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; border-bottom: 1px solid #ccc; margin-top: 1.6em; }
table { border-collapse: collapse; font-size: 0.9em; margin: 0.5em 0; }
th, td { border: 1px solid #ccc; padding: 2px 8px; text-align: right; }
th { background: #f2f2f2; } td:first-child, th:first-child { text-align: left; }
tr.governing td { background: #fde8d8; font-weight: bold; }
.words { background: #f8f8f8; padding: 0.6em 1em; white-space: pre-wrap; font-family: monospace; }
.meta { color: #666; font-size: 0.85em; } figure { margin: 0.5em 0; } svg { max-width: 100%; height: auto; }
"""


def svg_of(fig) -> str:
    """A matplotlib figure as an inline <svg> element (no XML prologue)."""
    buf = io.StringIO()
    fig.savefig(buf, format="svg", bbox_inches="tight")
    text = buf.getvalue()
    return text[text.find("<svg"):]


def table_html(df: pd.DataFrame, highlight=None) -> str:
    """A plain HTML table; rows where ``highlight`` is True get class 'governing'."""
    def cell(v):
        if isinstance(v, (float, np.floating)):
            return "" if np.isnan(v) else f"{v:.6g}"
        return html.escape(str(v))
    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in df.columns)
    rows = []
    for i, (_, r) in enumerate(df.iterrows()):
        cls = ' class="governing"' if highlight is not None and bool(highlight.iloc[i]) else ""
        rows.append(f"<tr{cls}>" + "".join(f"<td>{cell(v)}</td>" for v in r) + "</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(rows)}</tbody></table>"


def report_html(structure, results, words, picture_svg, command, source, study=None, strengths=None) -> str:
    """The report's text. ``study`` is None or (title, key column, table, plot svg);
    ``strengths``: the what-ifs on the joints' strengths given on the command line
    (:func:`lamodel.output.materials.strength_inputs`)."""
    from .materials import strength_inputs
    s = structure
    summary = results.summary.T.reset_index()
    summary.columns = ["quantity", "value"]
    parts = ["<h2>Result</h2>", table_html(summary),
             "<h2>Mechanism</h2>", f"<figure>{picture_svg}</figure>",
             f'<div class="words">{html.escape(chr(10).join(words))}</div>']
    if study is not None:
        title, key, df, plot_svg = study
        parts += [f"<h2>{html.escape(title)}</h2>", table_html(df, df["governing"].astype(bool)),
                  f"<figure>{plot_svg}</figure>" if plot_svg else ""]
    moving = results.contacts[~results.contacts["mode"].isin(["closed", "unknown"])]
    cols = ["contact", "block_a", "block_b", "mode", "N", "V", "M"]
    known = results.certified or not (results.contacts["mode"] == "unknown").any()
    parts += ["<h2>Joints that move</h2>",
              table_html(moving[cols]) if len(moving) else
              "<p>none</p>" if known else "<p>unknown: no collapse state was certified</p>"]
    units = s.units or {}
    lo, hi = (f"{v:.4g}" for v in (s.mu.min(), s.mu.max()))
    mu = lo if lo == hi else f"{lo} to {hi}"
    inputs = pd.DataFrame([
        ("input file", source), ("movable blocks", s.n_blocks), ("supports", len(s.supports)),
        ("contacts", s.n_contacts), ("friction mu", mu),
        ("length unit", units.get("length", "- (dimensionless)")),
        ("force unit", units.get("force", "- (dimensionless)")),
        ("total dead load (fx, fy)", f"({s.dead[:, 0].sum():.6g}, {s.dead[:, 1].sum():.6g})"),
        ("total live load (fx, fy), times alpha", f"({s.live[:, 0].sum():.6g}, {s.live[:, 1].sum():.6g})"),
        ("point loads", len(s.point_loads)), *strength_inputs(s, strengths)], columns=["input", "value"])
    parts += ["<h2>Inputs and units</h2>", table_html(inputs)]
    if s.point_loads:
        loads = pd.DataFrame([{"block": p.block, "x": p.at[0], "y": p.at[1], "fx": p.force[0], "fy": p.force[1],
                               "kind": p.kind, "case": p.case or "(all)"} for p in s.point_loads])
        parts.append(table_html(loads))
    return page(f"lamodel: {s.name}", f"Limit analysis of {s.name}", command, parts)


def page(title: str, heading: str, command: str, parts) -> str:
    """A whole report page: its heading, lamodel's version, the time and the command, then
    ``parts`` (HTML), with the reports' stylesheet."""
    from .. import __version__
    meta = (f'<p class="meta">lamodel {html.escape(__version__)} &middot; '
            f"{datetime.datetime.now().isoformat(timespec='seconds')} &middot; command: "
            f"<code>{html.escape(command)}</code></p>")
    body = "\n".join([f"<h1>{html.escape(heading)}</h1>", meta, *parts])
    return (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8"><title>{html.escape(title)}'
            f"</title><style>{STYLE}</style></head><body>\n{body}\n</body></html>\n")


def write_report(path, *args, **kwargs) -> str:
    """Write :func:`report_html` atomically to ``path``; returns the path."""
    atomic_write_text(path, report_html(*args, **kwargs))
    return str(path)
