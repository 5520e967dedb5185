"""The picture of a bridge as built, before any solve: the rings' voussoirs, the
abutments and piers, the fill up to the road, the passive restraints and one axle position with its
dispersal through the fill (matplotlib, Agg)."""
from __future__ import annotations

import math

import numpy as np

from ..output.figures import save_figure
from .build import positions
from .deck import deck_bed, deck_blocks, layout
from .description import Bridge
from .fill import restraints


def draw_bridge(ax, bridge: Bridge, lead: float | None = None, passive: bool = True):
    """Draw the bridge on a matplotlib axis; the axles at ``lead`` (default: a quarter of the
    way through the description's positions)."""
    from matplotlib.patches import Polygon
    blocks = deck_blocks(bridge)
    bed = deck_bed(bridge)
    ext = np.array([p for _, p, _ in bed] + [bed[-1][2]])
    feet = np.vstack([b["vertices"] for b in blocks["foundations"] if not b["id"].startswith("ground")])
    left, right = feet[:, 0].min(), feet[:, 0].max()
    fill = np.vstack([[[left, ext[0, 1]]], ext, [[right, ext[-1, 1]]], [[right, bridge.road], [left, bridge.road]]])
    ax.add_patch(Polygon(fill, closed=True, facecolor="#f3e5c0", edgecolor="none", label="fill"))
    for b in blocks["voussoirs"]:
        ax.add_patch(Polygon(b["vertices"], closed=True, facecolor="#d9a066", edgecolor="#5b3a1a", lw=0.6))
    for b in blocks["backing"]:
        ax.add_patch(Polygon(b["vertices"], closed=True, facecolor="#c9a27a", edgecolor="#5b3a1a", lw=0.6))
    for b in blocks["foundations"]:   # a support hatched (the ground darker); a block as masonry
        ground = b["id"].startswith("ground")
        ax.add_patch(Polygon(b["vertices"], closed=True, edgecolor="#404040", lw=0.6,
                             facecolor="#7f7f7f" if ground else "#bfbfbf" if b["support"] else "#c9a27a",
                             hatch="xx" if ground else "//" if b["support"] else None))
    ax.plot(fill[-2:, 0], fill[-2:, 1], color="black", lw=1.5)
    size = min(part.span for part, _ in layout(bridge))   # arrows drawn to the shortest span's scale
    if passive:
        for r in restraints(bridge):
            x, y = r["at"]
            ax.annotate("", xy=(x, y), xytext=(x - 0.06 * size * r["direction"][0], y),
                        arrowprops=dict(arrowstyle="->", color="#2e86c1", lw=0.8))
    lead = positions(bridge)[len(positions(bridge)) // 4] if lead is None else lead
    tan = math.tan(math.radians(bridge.spread))
    for offset in bridge.axles:
        x0, depth = lead + offset, bridge.road - ext[:, 1].min()
        ax.annotate("", xy=(x0, bridge.road), xytext=(x0, bridge.road + 0.12 * size),
                    arrowprops=dict(arrowstyle="-|>", color="#c0392b", lw=1.5))
        for s in (-1, 1):
            ax.plot([x0 + s * bridge.patch / 2, x0 + s * (bridge.patch / 2 + depth * tan)],
                    [bridge.road, bridge.road - depth], color="#c0392b", lw=0.6, ls="--")
    ax.set_aspect("equal")
    ax.autoscale_view()
    unit = f" [{bridge.units['length']}]" if bridge.units.get("length") else ""
    ax.set_xlabel("x" + unit)
    ax.set_ylabel("y" + unit)
    ax.set_title(f"{bridge.name}: as built (axle at x = {lead:g}; blue: passive restraint)", fontsize="small")


def plot_bridge(bridge: Bridge, path, passive: bool = True) -> str:
    """The picture of the bridge as built, written to ``path`` (PNG, SVG, PDF)."""
    return save_figure(path, lambda fig: draw_bridge(fig.add_subplot(111), bridge, passive=passive), size=(8.0, 4.0))
