"""The figures of studies (matplotlib, Agg): alpha against friction, per load case, along a
rolling load's path, and a parametric study's table as a plot or a distribution.

Each ``*_figure`` returns an open figure (for the HTML report); :func:`save_figure` and
:func:`save_open_figure` write one atomically.
"""
from __future__ import annotations

import os
from pathlib import Path

from typing import TYPE_CHECKING

import numpy as np

from ..io.files import atomic_write

if TYPE_CHECKING:
    import pandas as pd


def _pyplot():
    """matplotlib.pyplot on the Agg backend (no display needed)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def save_figure(path, draw, size=(6.4, 4.2)) -> str:
    """A matplotlib figure (Agg) drawn by ``draw(fig)``, saved atomically to ``path``
    (folders created; the format from the suffix); returns the path."""
    plt = _pyplot()

    path = Path(os.fspath(path))
    if path.parent and not path.parent.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
    fig = plt.figure(figsize=size, dpi=110)
    try:
        draw(fig)
        fig.tight_layout()
        atomic_write(path, lambda tmp: fig.savefig(tmp, format=path.suffix.lstrip(".") or "png"))
    finally:
        plt.close(fig)
    return str(path)


def save_open_figure(fig, path) -> str:
    """Save a figure atomically (format from the extension) and close it."""
    path = Path(os.fspath(path))
    try:
        atomic_write(path, lambda tmp: fig.savefig(tmp, format=path.suffix.lstrip(".") or "png"))
    finally:
        _pyplot().close(fig)
    return str(path)


def plot_friction_study(df: pd.DataFrame, path, title: str | None = None) -> str:
    """alpha_c and the associative bound against mu (matplotlib, Agg); returns the path."""
    def draw(fig):
        ax = fig.add_subplot()
        ok = df["certified"].astype(bool)
        ax.plot(df["mu"], df["alpha_associative"], "s--", color="#7f7f7f", label="associative bound")
        ax.plot(df["mu"], df["alpha_c"].where(ok), "o-", color="#c0392b", label=r"$\alpha_c$ (certified)")
        for i, mu in enumerate(df.loc[~ok, "mu"]):  # no line drawn across a mu without a certificate
            ax.axvline(mu, color="#c0392b", linestyle=":", linewidth=0.8, label="no certified $\\alpha$" if i == 0 else None)
        lo, hi = float(df["mu"].min()), float(df["mu"].max())
        ax.plot([lo, hi], [lo, hi], ":", color="#1f5fbf", linewidth=0.9, label=r"$\alpha = \mu$")
        ax.set_xlabel(r"friction coefficient $\mu$")
        ax.set_ylabel(r"load multiplier $\alpha$")
        ax.set_title(title or r"collapse multiplier against $\mu$")
        ax.grid(True, linewidth=0.3)
        ax.legend(loc="best", fontsize="small")
    return save_figure(path, draw)


def rolling_figure(df: pd.DataFrame, title: str | None = None, length_unit: str = ""):
    """A matplotlib figure: alpha against the position of the rolling load, the worst
    position starred, positions without a certified alpha dotted."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 3.8), dpi=110)
    ok = df["certified"].astype(bool)
    ax.plot(df["position"], df["alpha_c"].where(ok), "o-", color="#c0392b", ms=4,
            label=r"$\alpha_c$ (certified)")  # broken where a position has no certificate
    worst = df[df["governing"].astype(bool)]
    if len(worst):
        ax.plot(worst["position"], worst["alpha_c"], "*", color="black", ms=12,
                label=f"worst: x = {worst['position'].iloc[0]:.3g}, α = {worst['alpha_c'].iloc[0]:.4g}")
    for x in df.loc[~ok, "position"]:
        ax.axvline(x, color="#7f7f7f", linestyle=":", linewidth=0.8)
    a = df.loc[ok, "alpha_c"]
    if len(a) and a.min() > 0 and a.max() > 20 * a.min():  # near the supports alpha soars
        ax.set_yscale("log")
    ax.set_xlabel("position of the lead axle x" + (f" [{length_unit}]" if length_unit else ""))
    ax.set_ylabel(r"load multiplier $\alpha$")
    ax.set_title(title or "rolling load: collapse multiplier against position")
    ax.grid(True, linewidth=0.3)
    ax.legend(loc="best", fontsize="small")
    fig.tight_layout()
    return fig


def cases_figure(df: pd.DataFrame, title: str | None = None):
    """A matplotlib bar chart of alpha per load case, the governing case in red."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 3.2), dpi=110)
    ok = df["certified"].astype(bool)
    colours = ["#c0392b" if g else "#7f8c8d" for g in df["governing"].astype(bool)]
    ax.bar(df["case"].astype(str), df["alpha_c"].where(ok, 0.0), color=colours)
    ax.set_ylabel(r"load multiplier $\alpha$")
    ax.set_title(title or "collapse multiplier per load case (governing in red)")
    fig.tight_layout()
    return fig


def plot_study(df: pd.DataFrame, study, path) -> str:
    """A :class:`lamodel.parametric.Study`'s table as a figure: alpha against the first
    varied parameter (one line per combination of the others; with random samples, the
    samples and their median), or, when only random
    perturbations vary, the distribution of alpha (histogram and ECDF, with the 5 %, 50 %
    and 95 % quantiles). Returns the path."""
    varied = [c for c, _ in study.grid]
    ok = df[df["certified"]]

    def draw(fig):
        if not varied:
            _plot_distribution(fig, ok["alpha"].to_numpy(), study, len(df))
        else:
            _plot_against(fig.add_subplot(), df, varied, study)
    return save_figure(path, draw, size=(9.0 if not varied else 6.4, 4.2))


def _plot_distribution(fig, alpha, study, total):
    ax1, ax2 = fig.subplots(1, 2)
    if alpha.size == 0:
        ax1.text(0.5, 0.5, "no certified variant", ha="center", transform=ax1.transAxes)
        return
    q = np.quantile(alpha, [0.05, 0.5, 0.95])
    ax1.hist(alpha, bins=max(5, min(30, alpha.size // 2)), color="#c0392b", alpha=0.75)
    x = np.sort(alpha)
    ax2.step(x, np.arange(1, x.size + 1) / x.size, where="post", color="#c0392b")
    for ax in (ax1, ax2):
        for v, label, style in zip(q, ("5 %", "median", "95 %"), (":", "--", ":")):
            ax.axvline(v, color="#1f5fbf", linestyle=style, linewidth=1.0, label=f"{label} {v:.4f}")
        ax.set_xlabel(r"certified collapse multiplier $\alpha_c$")
        ax.grid(True, linewidth=0.3)
    from matplotlib.ticker import MaxNLocator
    ax1.yaxis.set_major_locator(MaxNLocator(integer=True))
    ax1.set_ylabel("variants")
    ax2.set_ylabel(r"fraction of variants with $\alpha_c \leq$ x")
    ax2.legend(loc="lower right", fontsize="small")
    fig.suptitle(f"{study.name}: {alpha.size} of {total} variants certified")


#: Why a variant has no certified alpha, by its status (study.csv's ``status``).
NO_ALPHA = {"unstable": "unstable under dead load", "no_collapse": "no collapse under this live load",
            "not_certified": "nothing certified in the time", "interrupted": "stopped before a certificate",
            "failed": "failed", "not run": "not run (study stopped)"}
#: A parameter's axis is logarithmic when its positive values span more than this factor.
LOG_SPAN = 10.0


def parameter_axis(values, column: str):
    """Where a study's parameter values go on the x axis: (positions, log, where infinity
    is drawn or None). The compressive strength fc goes on a logarithmic axis when its
    finite values span more than a decade (:data:`LOG_SPAN`); an infinite fc (no crushing)
    is drawn apart, beyond the largest finite value."""
    v = np.asarray(values, dtype=float)
    finite = v[np.isfinite(v)]
    log = bool(column == "fc" and finite.size and finite.min() > 0 and finite.max() > LOG_SPAN * finite.min())
    at_infinity = None
    if np.isinf(v).any():
        if not finite.size:
            at_infinity = 1.0
        elif log:
            at_infinity = finite.max() * 10 ** max(0.5, 0.15 * np.log10(finite.max() / finite.min()))
        else:
            at_infinity = finite.max() + 0.2 * ((finite.max() - finite.min()) or abs(finite.max()) or 1.0)
    return np.where(np.isinf(v), at_infinity if at_infinity is not None else np.nan, v), log, at_infinity


def _plot_against(ax, df, varied, study):
    x, others = varied[0], varied[1:]
    positions, log, at_infinity = parameter_axis(df[x], x)
    df = df.assign(_x=positions, _far=np.isinf(df[x].to_numpy(dtype=float)))
    groups = df.groupby(others, sort=False) if others else [((), df)]
    for k, (key, g) in enumerate(groups):
        key = key if isinstance(key, tuple) else (key,)
        label = ", ".join(f"{c} = {_value(v)}" for c, v in zip(others, key))
        color = f"C{k}"
        ok = g[g["certified"]]
        near = g[~g["_far"]]   # the line is not drawn on to the point at infinity
        if study.random:
            ax.plot(ok["_x"], ok["alpha"], ".", color=color, alpha=0.35, markersize=4)
            med = ok.groupby("_x")["alpha"].median()
            ax.plot(med.index, med.to_numpy(), "o-", color=color, label=(label + ": " if label else "") + "median")
        else:  # the line broken where a variant has no certified alpha: nothing is drawn there
            ax.plot(near["_x"], near["alpha"].where(near["certified"].astype(bool)), "o-", color=color,
                    label=label or r"$\alpha_c$ (certified)")
            far = g[g["_far"] & g["certified"].astype(bool)]
            if len(far):
                ax.plot(far["_x"], far["alpha"], "D", color=color, markersize=8, markerfacecolor="none",
                        label=f"{x} = ∞" + (f" ({label})" if label else "") + ": "
                        + ", ".join(f"α = {a:.4g}" for a in far["alpha"]))
        if not others and not study.random:
            ax.plot(near["_x"], near["alpha_associative"], "s--", color="#7f7f7f", label="associative bound")
            ax.plot(g.loc[g["_far"], "_x"], g.loc[g["_far"], "alpha_associative"], "s", color="#7f7f7f")
    _no_alpha(ax, df, x, others)
    if log:
        ax.set_xscale("log")
    if at_infinity is not None:
        _infinity_tick(ax, df, at_infinity)
    unit = ""
    if x == "fc":
        from .materials import stress_unit
        unit = stress_unit(getattr(study.structure, "units", None))
    scale = ", log scale" if log else ""
    ax.set_xlabel({"mu": r"friction coefficient $\mu$",
                   "fc": r"compressive strength $f_c$" + (f" [{unit}]" if unit else "") + scale
                   + ("; ∞: no crushing" if at_infinity is not None else ""),
                   "load_angle": "live-load angle (degrees)",
                   "dead_fx": f"dead force $f_x$ on {study.dead_block}",
                   "dead_fy": f"dead force $f_y$ on {study.dead_block}"}.get(x, x))
    ax.set_ylabel(r"load multiplier $\alpha$")
    ax.set_title(f"{study.name}: collapse multiplier against {x.replace('_', ' ')}")
    ax.grid(True, linewidth=0.3)
    ax.legend(loc="best", fontsize="small")


def _value(v) -> str:
    return "∞" if np.isinf(v) else f"{v:g}"


#: Variants named at most in one legend entry of a missing alpha (more: counted).
NAMED_VARIANTS = 4


def _no_alpha(ax, df, x, others):
    """A dotted line at each value where a variant has no certified alpha, one legend entry
    per status saying why (:data:`NO_ALPHA`) and for which variants, the statuses written
    along the line."""
    none = df[~df["certified"].astype(bool)]
    status = none["status"].where(none["status"].notna() & (none["status"] != ""), "unknown").astype(str)
    styles = (":", "-.", "--", (0, (1, 3)), (0, (5, 2, 1, 2)), (0, (3, 3)))
    for k, (word, g) in enumerate(none.groupby(status, sort=False)):
        named = list(dict.fromkeys(
            f"{x} = {_value(r[x])}" + (" (" + ", ".join(f"{c} = {_value(r[c])}" for c in others) + ")" if others else "")
            for _, r in g.iterrows()))
        shown = ", ".join(named[:NAMED_VARIANTS]) + (f" and {len(named) - NAMED_VARIANTS} more"
                                                      if len(named) > NAMED_VARIANTS else "")
        label = f"no α: {NO_ALPHA.get(word, word.replace('_', ' '))}: {shown}"
        for i, pos in enumerate(dict.fromkeys(g["_x"])):
            ax.axvline(pos, color="#c0392b" if k == 0 else "#7f7f7f", linestyle=styles[k % len(styles)],
                       linewidth=1.0, label=label if i == 0 else None)
    for pos, g in none.groupby("_x", sort=False):   # every status at that value, in one text
        words = ", ".join(dict.fromkeys(status[g.index].str.replace("_", " ")))
        ax.annotate(words, xy=(pos, 0.98), xycoords=("data", "axes fraction"), rotation=90, ha="right", va="top",
                    fontsize="x-small", color="#555555")


def _infinity_tick(ax, df, at_infinity):
    """The point at infinity: a tick labelled ∞ and a break (two short slashes) on the axis
    between it and the largest finite value."""
    from matplotlib.ticker import FixedLocator, FuncFormatter
    finite = df.loc[~df["_far"], "_x"].to_numpy(dtype=float)
    lo, hi = ax.get_xlim()
    ticks = [t for t in ax.get_xticks() if lo <= t <= (finite.max() if finite.size else lo)]
    shown = ax.xaxis.get_major_formatter()
    minor = [t for t in ax.xaxis.get_minorticklocs() if lo <= t <= (finite.max() if finite.size else lo)]
    ax.xaxis.set_major_locator(FixedLocator(ticks + [at_infinity]))
    ax.xaxis.set_minor_locator(FixedLocator(minor))
    ax.xaxis.set_major_formatter(FuncFormatter(lambda t, i: "∞" if np.isclose(t, at_infinity) else shown(t, i)))
    if finite.size:
        gap = np.sqrt(finite.max() * at_infinity) if ax.get_xscale() == "log" else (finite.max() + at_infinity) / 2
        for y in (0.0, 1.0):   # the axis broken there: two slashes on each spine
            for shift in (-0.006, 0.006):
                ax.plot([gap], [y], transform=ax.get_xaxis_transform(), marker=[(-1 + shift * 100, -2),
                        (1 + shift * 100, 2)], markersize=9, color="#444444", clip_on=False, linestyle="none")
        ax.set_xlim(lo, hi)
