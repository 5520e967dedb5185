"""The picture of a bridge as built, before any solve: the ring's voussoirs, the
abutments, the fill up to the road, the passive restraints and one axle position with its
dispersal through the fill (matplotlib, Agg)."""
from __future__ import annotations

import math

import numpy as np

from ..output.figures import save_figure
from .build import positions
from .description import Bridge
from .fill import restraints
from .backing import backing_blocks
from .ring import abutments, extrados, voussoirs


def draw_bridge(ax, bridge: Bridge, lead: float | None = None, passive: bool = True):
    """Draw the bridge on a matplotlib axis; the axles at ``lead`` (default: a quarter of the
    way through the description's positions)."""
    from matplotlib.patches import Polygon
    ext = extrados(bridge)
    abut = {b["id"]: np.array(b["vertices"]) for b in abutments(bridge)}
    left, right = abut["abutment_left"], abut["abutment_right"]
    ground = abut.pop("ground", None)   # under abutments that are blocks
    if ground is not None:
        ax.add_patch(Polygon(ground, closed=True, facecolor="#7f7f7f", edgecolor="#404040", hatch="xx", lw=0.6))
    fill = np.vstack([[[left[:, 0].min(), left[:, 1].max()]], ext, [[right[:, 0].max(), right[:, 1].max()]],
                      [[right[:, 0].max(), bridge.road], [left[:, 0].min(), bridge.road]]])
    ax.add_patch(Polygon(fill, closed=True, facecolor="#f3e5c0", edgecolor="none", label="fill"))
    for b in voussoirs(bridge):
        ax.add_patch(Polygon(b["vertices"], closed=True, facecolor="#d9a066", edgecolor="#5b3a1a", lw=0.6))
    for b in backing_blocks(bridge):
        ax.add_patch(Polygon(b["vertices"], closed=True, facecolor="#c9a27a", edgecolor="#5b3a1a", lw=0.6))
    rigid = bridge.abutment_kind == "rigid"   # a support hatched; a block as masonry
    for v in abut.values():
        ax.add_patch(Polygon(v, closed=True, facecolor="#bfbfbf" if rigid else "#c9a27a", edgecolor="#404040",
                             hatch="//" if rigid else None, lw=0.6))
    ax.plot(fill[-2:, 0], fill[-2:, 1], color="black", lw=1.5)
    if passive:
        for r in restraints(bridge):
            x, y = r["at"]
            ax.annotate("", xy=(x, y), xytext=(x - 0.06 * bridge.span * r["direction"][0], y),
                        arrowprops=dict(arrowstyle="->", color="#2e86c1", lw=0.8))
    lead = positions(bridge)[len(positions(bridge)) // 4] if lead is None else lead
    tan = math.tan(math.radians(bridge.spread))
    for offset in bridge.axles:
        x0, depth = lead + offset, bridge.road - ext[:, 1].min()
        ax.annotate("", xy=(x0, bridge.road), xytext=(x0, bridge.road + 0.12 * bridge.span),
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
