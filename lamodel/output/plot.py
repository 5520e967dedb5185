"""Pictures of collapse mechanisms: the blocks at rest and rigidly displaced by u.

A mechanism is small-displacement kinematics (block translations and rotations at the
centroids), so it is drawn amplified: by default the largest displacement of a vertex is
drawn as 10 % of the size of the structure. Hinges are marked by a dot at the pivot (the
end of the contact about which the two bodies rotate), a joint that crushes (at its
crushing cap: the mode ``crushing``) by a diamond at its pivot, sliding joints by a thick
line along the contact. Rendering uses matplotlib's Agg backend (no display needed); the file
format follows the extension of ``path`` (.png, .svg, .pdf, ...).
"""
from __future__ import annotations

import os

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.backend_bases import FigureCanvasBase  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import FancyArrowPatch  # noqa: E402
from matplotlib.path import Path as MplPath  # noqa: E402
from matplotlib.transforms import ScaledTranslation  # noqa: E402

from ..errors import InputError  # noqa: E402
from ..structure import Structure  # noqa: E402
from .kinematics import _block_motion, _point_motion, contact_kinematics, contact_modes, displace, pivots  # noqa: E402,F401
from .modes import MODES, RTOL, SLIDING, TURNING, modes_from_mechanism  # noqa: E402,F401


_BLOCK_REST = dict(facecolor="#e6e6e6", edgecolor="#9a9a9a", linewidth=0.6)
_SUPPORT = dict(facecolor="#5a5a5a", edgecolor="#303030", linewidth=0.8, hatch="///")
_BLOCK_MOVED = dict(facecolor="#f4a259", edgecolor="#7a3b00", linewidth=0.8, alpha=0.75)
_HINGE_COLOUR = "#c0392b"
_CRUSH_COLOUR = "#6e2c00"
_SLIDE_COLOUR = "#1f5fbf"
_HIGHLIGHT = "#e03030"
_DEAD_COLOUR = "#606060"
_LIVE_COLOUR = "#1e8449"
_THRUST_COLOUR = "#8e44ad"


def default_scale(structure: Structure, u) -> float:
    """The amplification that draws the largest vertex displacement as 10 % of the size."""
    s = structure
    biggest = np.hypot(u[:, 0], u[:, 1]).max(initial=0.0)
    for j, b in enumerate(s.blocks):
        if b in s.polygons and len(s.polygons[b]) >= 3:
            m = displace(s.polygons[b], s.centroid[j], u[j])
            biggest = max(biggest, np.hypot(m[:, 0], m[:, 1]).max())
    return 0.1 * s.size() / biggest if biggest > 0 else 1.0


def plot_mechanism(structure: Structure, u, modes=None, alpha=None, certified=None, path="mechanism.png",
                   scale=None, ax=None, loads=True, thrust=None, highlight=None, title=None):
    """Draw the blocks at rest and displaced by the mechanism ``u``; save to ``path``.

    ``u`` is (n_blocks, 3): (u_x, u_y, theta) at each block centroid. ``modes`` (one of
    :data:`MODES` per contact) defaults to :func:`contact_modes` of ``u``. ``alpha`` and
    ``certified`` go into the title, e.g. "α = 0.63898 (certified)". ``scale`` multiplies
    u; by default the largest vertex displacement is drawn as 10 % of the structure's
    size. With ``ax`` the picture is drawn into that axes (and its figure saved if
    ``path`` is given). Returns ``path``.

    Also drawn: the joints numbered as in the mechanism in words (:func:`.words.joint_marks`)
    with each hinge's rotation sense and each slip's direction; with ``loads`` arrows for
    the dead (grey) and live (green, times alpha) loads, point loads where they act; with
    ``thrust = (N, M)`` the line of thrust of an arch (:func:`.words.thrust_line`);
    ``highlight`` (block ids) drawn in red; the displacement amplification in a caption.
    """
    s = structure
    u = _block_motion(s, u)
    if modes is None:
        modes = contact_modes(s, u)
    modes = list(modes)
    if len(modes) != s.n_contacts or any(m not in MODES for m in modes):
        bad = next((m for m in modes if m not in MODES), None)
        raise InputError(f"structure '{s.name}': {len(modes)} contact modes"
                         f"{'' if bad is None else f' including {bad!r}'}; expected one of "
                         f"{', '.join(MODES)} for each of the {s.n_contacts} contacts")
    if path is not None:
        ext = Path(path).suffix.lower().lstrip(".")
        supported = FigureCanvasBase.get_supported_filetypes()
        if ext not in supported:
            raise InputError(f"{path}: unsupported picture format '.{ext}'; expected one of "
                             f"{', '.join('.' + e for e in sorted(supported))}")

    with_polygon = [j for j, b in enumerate(s.blocks) if b in s.polygons and len(s.polygons[b]) >= 3]
    moved = {j: displace(s.polygons[s.blocks[j]], s.centroid[j], u[j]) for j in with_polygon}
    if scale is None:
        scale = default_scale(s, u)

    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(8, 6))
    supports = [s.polygons[b] for b in s.supports if b in s.polygons]
    if supports:
        ax.add_collection(PolyCollection(supports, **_SUPPORT, zorder=1))
    if with_polygon:
        rest = [s.polygons[s.blocks[j]] for j in with_polygon]
        ax.add_collection(PolyCollection(rest, **_BLOCK_REST, zorder=1))
        shifted = [s.polygons[s.blocks[j]] + scale * moved[j] for j in with_polygon]
        moved_style = dict(_BLOCK_MOVED)
        if highlight:
            marked = set(highlight)
            moved_style["facecolor"] = [_HIGHLIGHT if s.blocks[j] in marked else _BLOCK_MOVED["facecolor"]
                                        for j in with_polygon]
        ax.add_collection(PolyCollection(shifted, **moved_style, zorder=2))
    no_polygon = np.array([j for j in range(s.n_blocks) if j not in moved], dtype=int)
    if no_polygon.size:
        g = s.centroid[no_polygon]
        ax.plot(g[:, 0], g[:, 1], "+", color="#9a9a9a", ms=6, zorder=1)
        ax.plot(g[:, 0] + scale * u[no_polygon, 0], g[:, 1] + scale * u[no_polygon, 1], "+",
                color="#7a3b00", ms=8, zorder=3)

    # contact markers, drawn on the displaced picture, carried by block a
    ia, _ = s.contact_blocks()
    legend = []
    joint = np.arange(s.n_contacts) < s.n_contacts - getattr(s, "restraints", 0)  # restraints: no joints
    sliding = np.array([m in SLIDING for m in modes], dtype=bool) & joint
    hinging = np.array([m in TURNING for m in modes], dtype=bool) & joint
    if sliding.any():
        k = np.flatnonzero(sliding)
        ends = [s.centre[k] - s.d[k, None] * s.tangent[k], s.centre[k] + s.d[k, None] * s.tangent[k]]
        ends = [e + scale * _point_motion(s, u, ia[k], e) for e in ends]
        ax.add_collection(LineCollection(np.stack(ends, axis=1), colors=_SLIDE_COLOUR, linewidths=3.5,
                                         zorder=4, capstyle="round"))
        legend.append(Line2D([], [], color=_SLIDE_COLOUR, lw=3.5, label="sliding"))
    # a crushing mark only where the joint can crush (a closing dry joint is a hinge drawn wrong)
    strong = np.isinf(s.fc) if getattr(s, "fc", None) is not None else np.ones(s.n_contacts, bool)
    crushing = np.array([m.startswith("crushing") for m in modes], dtype=bool) & hinging & ~strong
    for kind, marker, colour, label in ((hinging & ~crushing, "o", _HINGE_COLOUR, "hinge"),
                                        (crushing, "D", _CRUSH_COLOUR, "crushing (joint at its crushing cap)")):
        if kind.any():
            k = np.flatnonzero(kind)
            p = pivots(s, u)[k]
            p = p + scale * _point_motion(s, u, ia[k], p)
            ax.plot(p[:, 0], p[:, 1], marker, color=colour, ms=6, mec="white", mew=0.8, ls="", zorder=5)
            legend.append(Line2D([], [], marker=marker, ls="", color=colour, mec="white", label=label))
    extent = [p for p in s.polygons.values()] or [s.centroid]
    _joint_numbers(ax, s, u, modes, scale, ia)
    if loads:
        extent += _load_arrows(ax, s, alpha, legend)
    if thrust is not None:
        _thrust(ax, s, *thrust, legend)
    if highlight:
        legend.append(Line2D([], [], marker="s", ls="", color=_HIGHLIGHT, label="moving under dead load"))

    if title is None:
        title = s.name
        if alpha is not None:
            title += f":  α = {alpha + 0.0:.5g}"  # + 0.0: -0.0 (mu = 0) is drawn as 0
            if certified is not None:
                title += " (certified)" if certified else " (NOT certified)"
    ax.set_title(title)
    ax.set_aspect("equal")
    ax.update_datalim(np.vstack(extent))
    ax.margins(0.03)
    ax.autoscale_view()
    length = f" [{s.units['length']}]" if s.units.get("length") else ""
    ax.set_xlabel("x" + length + (f"      (displacements drawn × {scale:.3g})" if np.any(u) else ""))
    ax.set_ylabel("y" + length)
    if legend:
        # beside the drawing, never over it (and matplotlib's "best" place cost 1.2 s of a
        # 2 s picture of wall33)
        ax.legend(handles=legend, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0,
                  fontsize="small", framealpha=0.8)
    if path is not None:
        from ..io.files import atomic_write
        fmt = os.path.splitext(str(path))[1].lstrip(".").lower() or "png"
        atomic_write(path, lambda tmp: ax.figure.savefig(tmp, format=fmt, dpi=150, bbox_inches="tight"))
    if own:
        plt.close(fig)
    return path


# ------------------------------------------------------------------ annotations
def _arrows(ax, tails, vectors, colour, width=1.0, head=4.0):
    """Arrows from ``tails`` along ``vectors`` (data coordinates), as one collection:
    a patch an arrow took 3 of the 7 s of a 1,020-block wall's picture (two per block, the
    loads), drawn twice by the tight bounding box. ``width`` (the shaft) and ``head`` (its
    width and length) in points."""
    tails, vectors = np.asarray(tails, float).reshape(-1, 2), np.asarray(vectors, float).reshape(-1, 2)
    if len(tails):
        head = head / width  # quiver sizes heads in shaft widths
        ax.quiver(tails[:, 0], tails[:, 1], vectors[:, 0], vectors[:, 1], angles="xy", scale_units="xy", scale=1,
                  units="inches", width=width / 72.0, headwidth=head, headlength=1.1 * head,
                  headaxislength=head, color=colour, zorder=6)


def _label(ax, p, text, offset, colour):
    """``text`` at the data point p, shifted by ``offset`` points: a text on an offset
    transform (an annotation checks its anchor and lays itself out again at every draw:
    1 s of the 7 s above, for its 1,100 joint numbers)."""
    shift = ScaledTranslation(offset[0] / 72.0, offset[1] / 72.0, ax.figure.dpi_scale_trans)
    ax.text(p[0], p[1], text, transform=ax.transData + shift, fontsize=7, color=colour, fontweight="bold",
            zorder=7, clip_on=True)


def _joint_numbers(ax, s, u, modes, scale, ia):
    """The joints' numbers (as in the words), each hinge's rotation sense (a curved arrow
    turning as b turns relative to a) and each slip's direction (b relative to a); none
    for more than PICTURE_NUMBERS marks (they would cover the drawing)."""
    from .words import joint_marks, numbered_in_picture
    marks = joint_marks(s, u, modes)
    if not numbered_in_picture(marks):
        return
    size = s.size()
    index = {c: k for k, c in enumerate(s.contacts)}
    slides = []  # (point, unit direction) of each slip's arrow
    for m in marks:
        k = index[m.contact]
        p = m.point + scale * _point_motion(s, u, ia[k:k + 1], m.point[None, :])[0]
        if m.kind == "hinge":
            r = 0.025 * size
            if m.vector[0] != 0:  # an arc around the hinge, turning as b turns relative to a
                sense = 1.0 if m.vector[0] > 0 else -1.0
                a = np.radians(120.0 + sense * np.linspace(-70.0, 70.0, 24))
                arc = MplPath(p + r * np.column_stack([np.cos(a), np.sin(a)]))
                ax.add_artist(FancyArrowPatch(path=arc, arrowstyle="-|>", mutation_scale=9, color=_HINGE_COLOUR,
                                             lw=1.0, zorder=6))
            _label(ax, p, str(m.number), (4, 4), _HINGE_COLOUR)
        else:
            if np.any(m.vector):
                slides.append((p, m.vector / np.hypot(*m.vector)))
            _label(ax, p, str(m.number), (-10, 4), _SLIDE_COLOUR)
    if slides:
        _arrows(ax, [p for p, _ in slides], [0.05 * size * v for _, v in slides], _SLIDE_COLOUR, width=1.2,
                head=6.0)


def _load_arrows(ax, s, alpha, legend):
    """Dead and live loads as arrows: body loads from the centroids, point loads ending
    where they act. Lengths are proportional to the forces (the largest 12 % of the size);
    live loads are drawn times alpha when alpha is known. Returns the arrow ends."""
    factor = alpha if alpha is not None and np.isfinite(alpha) and alpha > 0 else 1.0
    body = {"dead": s.dead.copy(), "live": s.live.copy()}
    points = []
    for p in s.point_loads:
        j = s.block_index().get(p.block)
        if j is None:
            continue
        body[p.kind][j] -= p.force  # the rest of the block's load acts at its centroid
        points.append((p.kind, np.array(p.at, dtype=float), np.array(p.force, dtype=float)))
    arrows = []
    for kind in ("dead", "live"):
        f = body[kind] * (factor if kind == "live" else 1.0)
        for j in np.flatnonzero(np.hypot(f[:, 0], f[:, 1]) > 1e-12 * max(1.0, np.abs(f).max())):
            arrows.append((kind, s.centroid[j], f[j], False))
    arrows += [(kind, at, f * (factor if kind == "live" else 1.0), True) for kind, at, f in points]
    if not arrows:
        return []
    biggest = max(np.hypot(*f) for _, _, f, _ in arrows)
    length = 0.12 * s.size() / biggest
    ends = []
    for kind in ("dead", "live"):
        colour = _DEAD_COLOUR if kind == "dead" else _LIVE_COLOUR
        from_centroids = [(at, length * f) for k, at, f, at_point in arrows if k == kind and not at_point]
        _arrows(ax, [at for at, _ in from_centroids], [v for _, v in from_centroids], colour, width=0.7)
        ends += [e for at, v in from_centroids for e in (at, at + v)]
        at_points = [(at - length * f, length * f) for k, at, f, at_point in arrows if k == kind and at_point]
        # point loads end where they act, heavier
        _arrows(ax, [t for t, _ in at_points], [v for _, v in at_points], colour, width=1.6, head=6.0)
        ends += [e for t, v in at_points for e in (t, t + v)]
    force = f" [{s.units['force']}]" if s.units.get("force") else ""
    kinds = {k for k, *_ in arrows}
    if "dead" in kinds:
        legend.append(Line2D([], [], color=_DEAD_COLOUR, marker=">", label="dead load" + force))
    if "live" in kinds:
        legend.append(Line2D([], [], color=_LIVE_COLOUR, marker=">",
                             label="live load" + (" × α" if factor != 1.0 else "") + force))
    return [np.array(ends)]


def _thrust(ax, s, N, M, legend):
    """The line of thrust of an arch: the centres of pressure of its ring joints."""
    from .words import thrust_line
    line = thrust_line(s, N, M)
    if line is None or not len(line[0]):
        return
    p = line[0]
    ax.plot(p[:, 0], p[:, 1], "-", marker="x", ms=4, color=_THRUST_COLOUR, lw=1.2, zorder=3)
    legend.append(Line2D([], [], color=_THRUST_COLOUR, marker="x", label="line of thrust"))


def animate_mechanism(structure: Structure, u, path, modes=None, alpha=None, certified=None, frames: int = 20,
                      thrust=None, highlight=None) -> str:
    """A GIF of the mechanism growing from rest to the picture's amplification
    (matplotlib.animation with Pillow); written atomically. Returns ``path``."""
    import secrets

    from matplotlib.animation import FuncAnimation, PillowWriter

    from ..io.files import new_file, remove_quietly
    s = structure
    u = _block_motion(s, u)
    full = default_scale(s, u)
    fig, ax = plt.subplots(figsize=(7, 5))

    def frame(i):
        ax.clear()
        f = i / max(frames - 1, 1)
        plot_mechanism(s, u, modes=modes, alpha=alpha, certified=certified, path=None, scale=max(f, 1e-9) * full,
                       ax=ax, thrust=thrust, highlight=highlight)
        return []

    path = Path(path)
    # the temporary file keeps .gif (PIL picks the format from it) and gets the umask's mode
    tmp = (path.parent or Path(".")) / f".{path.stem}.{secrets.token_hex(4)}.gif"
    os.close(new_file(tmp))
    try:
        FuncAnimation(fig, frame, frames=frames, blit=False).save(tmp, writer=PillowWriter(fps=8), dpi=90)
        os.replace(tmp, path)
    except BaseException:
        remove_quietly(tmp)
        raise
    finally:
        plt.close(fig)
    return str(path)
