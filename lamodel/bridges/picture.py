"""The pictures of a bridge (matplotlib, Agg): as built, before any solve (the rings'
voussoirs, the abutments and piers, the fill up to the road, the passive restraints and one
axle position with its dispersal through the fill), and its governing collapse mechanism
drawn with the fill (:func:`plot_governing`)."""
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
    ext, fill = _fill(bridge, blocks)
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


def _fill(bridge: Bridge, blocks):
    """(the extrados under the fill, the fill's outline up to the road)."""
    bed = deck_bed(bridge)
    ext = np.array([p for _, p, _ in bed] + [bed[-1][2]])
    feet = np.vstack([b["vertices"] for b in blocks["foundations"] if not b["id"].startswith("ground")])
    left, right = feet[:, 0].min(), feet[:, 0].max()
    return ext, np.vstack([[[left, ext[0, 1]]], ext, [[right, ext[-1, 1]]], [[right, bridge.road],
                                                                             [left, bridge.road]]])


def plot_governing(bridge: Bridge, outcome, path, position: float, passive: bool = True) -> str:
    """The governing collapse mechanism drawn with the fill (:func:`draw_governing`),
    written to ``path``; returns it."""
    return save_figure(path, lambda fig: draw_governing(fig.add_subplot(111), bridge, outcome, position, passive),
                       size=(10.0, 5.0))


def draw_governing(ax, bridge: Bridge, outcome, position: float, passive: bool = True):
    """The governing collapse mechanism on ``ax``: the fill as built (it does not move: it
    is forces on the ring), the blocks at rest and displaced with their hinges, slides,
    loads and line of thrust (:func:`lamodel.output.plot.plot_mechanism`), and the passive
    restraints the collapse state takes to their capacity (blue arrows; the others pale)."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch, Polygon

    from ..output.modes import modes_from_flow
    from ..output.plot import plot_mechanism
    s, best = outcome.structure, outcome.best
    modes = modes_from_flow(s, best.xi)
    _, fill = _fill(bridge, deck_blocks(bridge))
    ax.add_patch(Polygon(fill, closed=True, facecolor="#f3e5c0", edgecolor="none", zorder=0))
    ax.plot(fill[-2:, 0], fill[-2:, 1], color="black", lw=1.5, zorder=0)
    plot_mechanism(s, best.u.reshape(-1, 3), modes=modes, alpha=best.alpha, certified=True, ax=ax, path=None,
                   thrust=(best.N, best.M),
                   title=f"{bridge.name}: governing mechanism, axle at x = {position:g} (adequacy {best.alpha:.4f})")
    held = restraints(bridge) if passive else []
    joints = s.n_contacts - getattr(s, "restraints", 0)
    if not held or len(held) != s.restraints:
        return
    size = min(part.span for part, _ in layout(bridge))
    for r, mode in zip(held, modes[joints:]):
        full = "crushing" in mode   # the restraint at its capacity
        x, y = r["at"]
        ax.annotate("", xy=(x, y), xytext=(x - 0.06 * size * r["direction"][0], y),
                    arrowprops=dict(arrowstyle="->", color="#2e86c1" if full else "#aed6f1", lw=1.4 if full else 0.6),
                    zorder=6)
    legend = ax.get_legend()
    extra = [Patch(facecolor="#f3e5c0", label="fill (forces on the ring)"),
             Line2D([], [], color="#2e86c1", lw=1.4, label="passive restraint at capacity")]
    ax.legend(handles=[*(legend.legend_handles if legend is not None else []), *extra], loc="upper left",
              bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize="small", framealpha=0.8)
