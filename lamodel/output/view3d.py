"""An interactive view of a 3D structure and its mechanism: ONE self-contained HTML file
(plotly, with its JavaScript embedded: it opens offline, with no network).

The reader turns and zooms the structure; the blocks at rest are faint, the moving blocks
drawn displaced and coloured by macro-block (blocks moving together); a slider sets the
amplification (0 = at rest). Contact points whose mode is opening or sliding are marked;
with the joints' strengths, the points whose normal force sits on its crushing cap
(``N = -f_c A``) or on its tensile cap (``N = f_t A``, where f_t > 0) are marked by their
own diamonds (only points that can crush or take tension: a dry point never is); live
loads are arrows from the block centroids.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..search.tuning import RESIDUAL_TOLERANCE
from ..structure3d import Structure3D
from .motion3d import check_motions, default_amplification, displaced, macro_blocks

_PALETTE = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22"]
_MODE_COLOURS = {"open": "#d62728", "opening": "#d62728", "slide": "#1f5fbf", "sliding": "#1f5fbf"}
_CAP_MARKS = (("crushing", "#6e2c00", "at the crushing cap (N = -fc A)"),
              ("tension", "#e67e22", "at the tensile cap (N = ft A)"))
STEPS = (0.0, 0.25, 0.5, 1.0, 1.5, 2.0)


def points_on_caps(s: Structure3D, N) -> dict:
    """The points whose normal force ``N`` (np,) sits on a cap, {"crushing": mask, "tension":
    mask}: within the certified state's accuracy (RESIDUAL_TOLERANCE of the largest force)
    of ``-f_c A`` where f_c is finite, of ``f_t A`` where f_t > 0."""
    N = np.asarray(N, dtype=float)
    none = np.zeros(s.n_points, dtype=bool)
    if not s.has_materials or not np.isfinite(N).all():
        return {"crushing": none, "tension": none}
    crush, pull, _ = s.caps()
    slack = RESIDUAL_TOLERANCE * max(np.abs(N).max(), 1e-300)
    return {"crushing": np.isfinite(crush) & (N < 0) & (N <= crush + slack),
            "tension": (s.ft > 0) & (N > 0) & (N >= pull - slack)}


def _mesh(vertex_lists, face_lists):
    """x, y, z, i, j, k of one Mesh3d from several polyhedra (faces fanned into triangles)."""
    xyz, tri, base = [], [], 0
    for v, faces in zip(vertex_lists, face_lists):
        v = np.asarray(v, dtype=float)
        xyz.append(v)
        tri += [(base + f[0], base + f[t], base + f[t + 1]) for f in faces for t in range(1, len(f) - 1)]
        base += len(v)
    xyz = np.vstack(xyz) if xyz else np.zeros((0, 3))
    tri = np.array(tri, dtype=int).reshape(-1, 3)
    return xyz, tri


def _mesh_trace(go, xyz, tri, colour, opacity, name):
    return go.Mesh3d(x=xyz[:, 0], y=xyz[:, 1], z=xyz[:, 2], i=tri[:, 0], j=tri[:, 1], k=tri[:, 2],
                     color=colour, opacity=opacity, flatshading=True, name=name, showlegend=True,
                     lighting=dict(ambient=0.55, diffuse=0.8, specular=0.1), hoverinfo="name")


#: The share of the page's width the 3D scene takes when the inputs' box is shown beside it.
INPUTS_COLUMN = 0.74
#: Characters a line of the inputs' box (longer values wrap), to fit its column.
INPUTS_WIDTH = 40


def inputs_text(inputs) -> str:
    """The inputs' box as HTML lines: a title, then ``name: value`` a row, long values
    wrapped at INPUTS_WIDTH characters (continuation lines indented)."""
    import html
    import textwrap
    lines = ["<b>inputs</b>"]
    for k, v in inputs:
        wrapped = textwrap.wrap(f"{k}: {v}", INPUTS_WIDTH, subsequent_indent="  ") or [f"{k}:"]
        lines += [html.escape(line).replace("  ", "&nbsp;&nbsp;", 1) for line in wrapped]
    return "<br>".join(lines)


def write_view3d(s: Structure3D, path, motions=None, modes=None, amplification: float | None = None,
                 title: str | None = None, normal=None, inputs=None) -> str:
    """Write the interactive view of ``s`` (and of the mechanism ``motions`` (nb, 6), with
    contact-point ``modes`` (np,) such as "open", "slide", and the points' normal forces
    ``normal`` (np,), < 0 in compression, whose caps are marked) to the HTML file ``path``.
    ``inputs``: rows (name, value) written in a box in a column right of the scene (the
    joints' strengths, :func:`lamodel.output.materials.strength_inputs`)."""
    import plotly.graph_objects as go

    u = check_motions(s, motions)
    amp = default_amplification(s, u) if amplification is None else float(amplification)
    label = macro_blocks(s, u)
    idx = s.block_index()
    traces = []
    sup = [b for b in s.polyhedra if b not in idx]
    xyz, tri = _mesh([s.polyhedra[b][0] for b in sup], [s.polyhedra[b][1] for b in sup])
    traces.append(_mesh_trace(go, xyz, tri, "#707070", 1.0, "supports"))
    still = [b for b in s.blocks if label[idx[b]] < 0]
    moving = [b for b in s.blocks if label[idx[b]] >= 0]
    if still:
        xyz, tri = _mesh([s.polyhedra[b][0] for b in still], [s.polyhedra[b][1] for b in still])
        traces.append(_mesh_trace(go, xyz, tri, "#e8dcc8", 1.0, "blocks at rest"))
    if moving:
        xyz, tri = _mesh([s.polyhedra[b][0] for b in moving], [s.polyhedra[b][1] for b in moving])
        traces.append(_mesh_trace(go, xyz, tri, "#cccccc", 0.25, "moving blocks, at rest"))
    groups = sorted({int(label[idx[b]]) for b in moving})
    first_moving = len(traces)

    def moved_traces(a):
        out = []
        for g in groups:
            members = [b for b in moving if label[idx[b]] == g]
            verts = [displaced(s.polyhedra[b][0], s.centroid[idx[b]], u[idx[b]], a) for b in members]
            xyz, tri = _mesh(verts, [s.polyhedra[b][1] for b in members])
            out.append(_mesh_trace(go, xyz, tri, _PALETTE[g % len(_PALETTE)], 1.0,
                                   f"macro-block {g + 1} ({len(members)} blocks)"))
        return out

    traces += moved_traces(amp)
    if modes is not None:
        modes = np.asarray(modes).astype(str)
        for mode, colour in _MODE_COLOURS.items():
            hit = modes == mode
            if hit.any():
                p = s.point[hit]
                traces.append(go.Scatter3d(x=p[:, 0], y=p[:, 1], z=p[:, 2], mode="markers", name=f"{mode} contacts",
                                           marker=dict(size=3, color=colour)))
    if normal is not None:
        on = points_on_caps(s, normal)
        caps = dict(zip(("crushing", "tension"), s.caps()[:2]))
        for kind, colour, label in _CAP_MARKS:
            hit = on[kind]
            if hit.any():
                p = s.point[hit]
                text = [f"N = {n:.6g}, cap {c:.6g}" for n, c in zip(np.asarray(normal, float)[hit], caps[kind][hit])]
                traces.append(go.Scatter3d(x=p[:, 0], y=p[:, 1], z=p[:, 2], mode="markers",
                                           name=f"{label}: {int(hit.sum())} points", text=text, hoverinfo="text",
                                           marker=dict(size=6, color=colour, symbol="diamond")))
    live = np.linalg.norm(s.live, axis=1)
    if live.max() > 0:   # arrows: a shaft from the centroid, a dot at the head (many: off, in the legend)
        shown = True if s.n_blocks <= 60 else "legendonly"
        tip = s.centroid + s.live * (0.06 * s.size() / live.max())
        seg = np.full((3 * s.n_blocks, 3), np.nan)
        seg[0::3], seg[1::3] = s.centroid, tip
        traces.append(go.Scatter3d(x=seg[:, 0], y=seg[:, 1], z=seg[:, 2], mode="lines", name="live loads",
                                   line=dict(color="#1e8449", width=4), hoverinfo="skip",
                                   visible=shown, legendgroup="live"))
        traces.append(go.Scatter3d(x=tip[:, 0], y=tip[:, 1], z=tip[:, 2], mode="markers", showlegend=False,
                                   marker=dict(size=2, color="#1e8449", symbol="diamond"), hoverinfo="skip",
                                   visible=shown, legendgroup="live"))
    fig = go.Figure(data=traces)
    if groups:   # the slider restyles the displaced blocks' coordinates (no frames, no timers)
        which = list(range(first_moving, first_moving + len(groups)))
        steps = []
        for f in STEPS:
            moved = moved_traces(f * amp)
            steps.append(dict(method="restyle", label=f"{f:g}",
                              args=[{"x": [t.x for t in moved], "y": [t.y for t in moved], "z": [t.z for t in moved]},
                                    which]))
        fig.update_layout(sliders=[dict(active=STEPS.index(1.0), steps=steps, x=0.05, len=0.9,
                                        currentvalue=dict(prefix=f"amplification (1 = x {amp:.3g}): "))])
    # the inputs' box has a column of its own on the right (over the scene it hid axis labels);
    # the camera far enough for the x axis' labels above the slider
    scene_x = [0.0, INPUTS_COLUMN] if inputs else [0.0, 1.0]
    fig.update_layout(title=title or s.name, scene=dict(aspectmode="data", xaxis_title="x", yaxis_title="y",
                                                        zaxis_title="z", domain=dict(x=scene_x, y=[0.0, 1.0]),
                                                        camera=dict(eye=dict(x=1.1, y=-1.9, z=1.1))),
                      margin=dict(l=0, r=0, t=40, b=0), legend=dict(x=0.0, y=0.95))
    if inputs:
        fig.add_annotation(text=inputs_text(inputs), xref="paper", yref="paper", x=1.0, y=0.9, xanchor="right",
                           yanchor="top", align="left", showarrow=False, font=dict(size=11),
                           bgcolor="rgba(255,255,255,0.8)", bordercolor="#cccccc", borderwidth=1)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.write_html(str(path), include_plotlyjs=True, full_html=True, include_mathjax=False,
                   default_height="96vh", default_width="100%",
                   config=dict(displaylogo=False))
    return str(path)
