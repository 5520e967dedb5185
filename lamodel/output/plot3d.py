"""A picture (PNG, SVG, PDF) of a 3D structure and, optionally, a mechanism: matplotlib's
mplot3d on the Agg backend (no display needed).

Supports are dark grey, blocks light; with motions the blocks at rest are drawn faint and
the moving ones displaced (amplified), coloured by macro-block (blocks moving together);
live loads are arrows at the centroids.
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from ..structure3d import Structure3D  # noqa: E402
from .motion3d import check_motions, default_amplification, displaced, macro_blocks  # noqa: E402

_SUPPORT = "#6b6b6b"
_BLOCK = "#e8dcc8"
_EDGE = "#5a4a3a"


def _faces(vertices, faces):
    v = np.asarray(vertices)
    return [v[f] for f in faces]


def plot_structure3d(s: Structure3D, path, motions=None, amplification: float | None = None,
                     title: str | None = None, elev: float = 22, azim: float = -60, dpi: int = 110,
                     loads: bool = True) -> str:
    """Draw the structure (and the mechanism ``motions`` (nb, 6), amplified) to ``path``;
    ``loads``: the live loads as arrows at the centroids."""
    u = check_motions(s, motions)
    amp = default_amplification(s, u) if amplification is None else float(amplification)
    label = macro_blocks(s, u)
    cmap = plt.get_cmap("tab10")
    idx = s.block_index()
    fig = plt.figure(figsize=(7, 5.5))
    ax = fig.add_subplot(projection="3d")
    # supports first and beneath: mplot3d sorts polygons by depth within a collection only,
    # and a large ground slab would otherwise be painted over the blocks standing on it
    ax.computed_zorder = False
    ground = [f for b, (v, faces) in s.polyhedra.items() if b not in idx for f in _faces(v, faces)]
    ax.add_collection3d(Poly3DCollection(ground, facecolors=_SUPPORT, edgecolors="#404040", linewidths=0.25,
                                         zorder=1))
    polys, colours = [], []
    for b, (v, faces) in s.polyhedra.items():
        j = idx.get(b)
        if j is None:
            continue
        moving = u is not None and label[j] >= 0
        if moving:
            polys += _faces(displaced(v, s.centroid[j], u[j], amp), faces)
            colours += [matplotlib.colors.to_hex(cmap(label[j] % 10))] * len(faces)
        else:
            polys += _faces(v, faces)
            colours += [_BLOCK] * len(faces)
    ax.add_collection3d(Poly3DCollection(polys, facecolors=colours, edgecolors=_EDGE, linewidths=0.25, zorder=2))
    pts = np.vstack([np.asarray(v) for v, _ in s.polyhedra.values()])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    if u is not None:
        moved = [displaced(v, s.centroid[idx[b]], u[idx[b]], amp) for b, (v, _) in s.polyhedra.items() if b in idx]
        allp = np.vstack([pts] + moved)
        lo, hi = allp.min(axis=0), allp.max(axis=0)
    live = np.linalg.norm(s.live, axis=1)
    if loads and live.max() > 0:
        scale = 0.08 * s.size() / live.max()
        ax.quiver(*s.centroid.T, *(s.live * scale).T, color="#1e8449", linewidth=0.8, arrow_length_ratio=0.3,
                  zorder=3)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(np.maximum(hi - lo, 1e-3 * (hi - lo).max()))
    ax.view_init(elev=elev, azim=azim)
    ax.set_axis_off()
    text = title or s.name
    if u is not None:
        text += f" (mechanism x {amp:.3g})"
    ax.set_title(text, fontsize=10)
    fig.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return str(path)
