"""Studies built on the driver: variants of a structure, a friction study, the seed's Table 1.

These are the reusable parts of ``examples/friction_study.py``, ``examples/tie_force.py``
and ``scripts/table1.py``. Every multiplier they report is a certified collapse
multiplier of :func:`lamodel.search.driver.solve` (NaN when the driver certified none), so it is
the least collapse multiplier lamodel *found*: an upper bound on the true minimum α_c.

Variants of a structure are deep copies; the structure passed in is never modified.
"""
from __future__ import annotations

import copy
import os
import time
from pathlib import Path

import numpy as np
import pandas as pd

from .errors import InputError
from .output.modes import modes_from_flow
from .search.driver import Outcome, SolveOptions, solve
from .structure import Structure

#: Reference data shipped with the package (the seed's Table 1).
DATA = Path(__file__).resolve().parent / "data"

#: Columns of :func:`friction_study`.
FRICTION_COLUMNS = ("mu", "alpha_c", "alpha_associative", "certified", "n_sliding", "n_hinging", "seconds",
                    "status")

#: Published columns of the seed's Table 1 (references/table1.csv).
TABLE1_REFERENCE_COLUMNS = ("wall", "n_blocks", "ferris_tin_loi_2", "gilbert_4", "mihai_5", "seed")


# ------------------------------------------------------------------------- variants
def with_friction(structure: Structure, mu: float) -> Structure:
    """A copy of the structure with the friction coefficient mu on every contact."""
    mu = float(mu)
    if not np.isfinite(mu) or mu < 0:
        raise InputError(f"friction coefficient {mu}: expected a finite number >= 0")
    s = copy.deepcopy(structure)
    s.mu = np.full(s.n_contacts, mu)
    s.name = f"{structure.name}_mu{mu:g}"
    return s


def with_dead_force(structure: Structure, block: str, fx: float = 0.0, fy: float = 0.0,
                    name: str | None = None) -> Structure:
    """A copy of the structure with a constant force (fx, fy) added at the centroid of
    ``block`` to its dead load f0 (e.g. a tie force found by a user's study)."""
    index = structure.block_index()
    if block not in index:
        raise InputError(f"structure '{structure.name}': no movable block '{block}'; expected one of "
                         f"{', '.join(structure.blocks[:8])}{', ...' if structure.n_blocks > 8 else ''}")
    s = copy.deepcopy(structure)
    s.dead[index[block]] += (float(fx), float(fy))
    s.name = name or f"{structure.name}_{block}_force"
    return s


# ------------------------------------------------------------------------- one solve
def mode_counts(structure: Structure, xi) -> dict:
    """Contacts that slip (modes sliding, sliding+hinging), rotate (hinging,
    sliding+hinging) and open, in a mechanism's flow xi."""
    modes = modes_from_flow(structure, xi)
    return {"n_sliding": sum(m in ("sliding", "sliding+hinging") for m in modes),
            "n_hinging": sum(m in ("hinging", "sliding+hinging") for m in modes),
            "n_open": sum(m == "open" for m in modes)}


def outcome_row(outcome: Outcome) -> dict:
    """The certified multiplier, the associative bound and the mechanism's mode counts."""
    best = outcome.best
    row = {"alpha_c": best.alpha if best is not None else np.nan,
           "alpha_associative": outcome.alpha_associative,
           "certified": best is not None}
    if best is not None:
        row.update(mode_counts(outcome.structure, best.xi))
    else:
        row.update(n_sliding=0, n_hinging=0, n_open=0)
    row.update(seconds=outcome.wall_time_s, status=outcome.status)
    return row


# ------------------------------------------------------------------------- friction
def friction_study(structure: Structure, mus, options: SolveOptions | None = None, progress=None,
                   workers: int | None = None, scheduler: str | None = None) -> pd.DataFrame:
    """Certified collapse multiplier of the structure for each friction coefficient.

    The study spec ``{"vary": {"mu": mus}}`` (:mod:`lamodel.parametric`, as
    ``examples/friction_study.json``) run with these options: one solve per mu on a copy
    with that mu on every contact, its GA seed spawned from ``options.seed``; on
    ``workers`` local processes (default 1: this process) or on a Dask ``scheduler``.
    Columns: mu, alpha_c (NaN if none was certified), alpha_associative, certified,
    n_sliding, n_hinging (contacts that slip / rotate in the mechanism; a contact doing
    both counts in both), seconds, status. ``progress(row)`` is called after each solve.
    """
    from .parametric import run_study, study_from_dict
    mus = [float(m) for m in mus]
    if not mus:
        raise InputError("friction_study: no friction coefficients given; expected at least one mu")
    opt = options or SolveOptions()
    fields = ("starts", "time_limit", "pop_size", "generations", "chain", "xi_factor", "solver")
    spec = {"vary": {"mu": mus}, "seed": opt.seed, "options": {k: getattr(opt, k) for k in fields}}
    study = study_from_dict(spec, structure, where="friction_study")
    rename = lambda row: {**row, "alpha_c": row["alpha"]}  # noqa: E731
    df = run_study(study, workers=workers or (None if scheduler else 1), scheduler=scheduler, progress=False,
                   on_row=None if progress is None else (lambda row: progress(rename(row))))
    return df.rename(columns={"alpha": "alpha_c"})[list(FRICTION_COLUMNS)]


def save_figure(path, draw, size=(6.4, 4.2)) -> str:
    """A matplotlib figure (Agg) drawn by ``draw(fig)``, saved atomically to ``path``
    (folders created; the format from the suffix); returns the path."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path = Path(os.fspath(path))
    if path.parent and not path.parent.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
    fig = plt.figure(figsize=size, dpi=110)
    try:
        draw(fig)
        fig.tight_layout()
        _atomic(path, lambda tmp: fig.savefig(tmp, format=path.suffix.lstrip(".") or "png"))
    finally:
        plt.close(fig)
    return str(path)


def plot_friction_study(df: pd.DataFrame, path, title: str | None = None) -> str:
    """alpha_c and the associative bound against mu (matplotlib, Agg); returns the path."""
    def draw(fig):
        ax = fig.add_subplot()
        ok = df["certified"].astype(bool)
        ax.plot(df["mu"], df["alpha_associative"], "s--", color="#7f7f7f", label="associative bound")
        ax.plot(df.loc[ok, "mu"], df.loc[ok, "alpha_c"], "o-", color="#c0392b", label=r"$\alpha_c$ (certified)")
        if (~ok).any():
            for mu in df.loc[~ok, "mu"]:
                ax.axvline(mu, color="#c0392b", linestyle=":", linewidth=0.8)
        lo, hi = float(df["mu"].min()), float(df["mu"].max())
        ax.plot([lo, hi], [lo, hi], ":", color="#1f5fbf", linewidth=0.9, label=r"$\alpha = \mu$")
        ax.set_xlabel(r"friction coefficient $\mu$")
        ax.set_ylabel(r"load multiplier $\alpha$")
        ax.set_title(title or r"collapse multiplier against $\mu$")
        ax.grid(True, linewidth=0.3)
        ax.legend(loc="best", fontsize="small")
    return save_figure(path, draw)


# ------------------------------------------------------------------------- load cases, rolling load
#: Columns of :func:`load_case_study` (after ``case``) and :func:`rolling_study` (after
#: ``position`` and ``blocks``).
VARIANT_COLUMNS = ("alpha_c", "alpha_associative", "certified", "n_sliding", "n_hinging", "seconds", "status",
                   "governing")


def _variant_study(key, labels, variants, options, progress):
    """Solve every variant; a table (one row each, the least certified alpha marked
    ``governing``) and the outcomes by label."""
    rows, outcomes = [], {}
    for label, structure in zip(labels, variants):
        outcome = solve(structure, options or SolveOptions())
        outcomes[label] = outcome
        row = {key: label, **outcome_row(outcome)}
        rows.append(row)
        if progress is not None:
            progress(row)
    df = pd.DataFrame(rows)
    alpha = df["alpha_c"].where(df["certified"].astype(bool))
    df["governing"] = False
    if alpha.notna().any():
        df.loc[alpha.idxmin(), "governing"] = True
    return df, outcomes


def governing(df: pd.DataFrame, key: str):
    """The label of the governing row of a load-case or rolling table (None if none certified)."""
    hit = df.loc[df["governing"].astype(bool), key]
    return None if hit.empty else hit.iloc[0]


def load_case_study(structure: Structure, options: SolveOptions | None = None, progress=None):
    """alpha per named load case of the structure (:mod:`lamodel.loads`); the least
    certified one governs. Returns (table, outcomes by case name)."""
    from .loads import case_structure
    names = list(structure.cases)
    if not names:
        raise InputError(f"structure '{structure.name}': no load cases; expected live point loads with a 'case'")
    df, outcomes = _variant_study("case", names, [case_structure(structure, n) for n in names], options, progress)
    return df[["case", *VARIANT_COLUMNS]], outcomes


def rolling_study(structure: Structure, options: SolveOptions | None = None, positions=None, progress=None):
    """alpha for each position of the structure's rolling load (given positions, else its
    own, else the midpoints of the top edges); the least certified one governs (the worst
    position). Returns (table, outcomes by position)."""
    from .loads import rolling_positions, rolling_structure
    if structure.rolling is None:
        raise InputError(f"structure '{structure.name}': no rolling load; expected a 'rolling_load' in the JSON")
    positions = [float(x) for x in (positions if positions is not None else rolling_positions(structure))]
    if not positions:
        raise InputError(f"structure '{structure.name}': no position for the rolling load on the top of the "
                         "structure; expected 'positions' in the 'rolling_load'")
    variants = [rolling_structure(structure, x) for x in positions]
    df, outcomes = _variant_study("position", positions, variants, options, progress)
    df.insert(1, "blocks", [" ".join(dict.fromkeys(p.block for p in v.point_loads if p.case == "rolling"))
                            for v in variants])
    return df[["position", "blocks", *VARIANT_COLUMNS]], outcomes


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def rolling_figure(df: pd.DataFrame, title: str | None = None, length_unit: str = ""):
    """A matplotlib figure: alpha against the position of the rolling load, the worst
    position starred, positions without a certified alpha dotted."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 3.8), dpi=110)
    ok = df["certified"].astype(bool)
    ax.plot(df.loc[ok, "position"], df.loc[ok, "alpha_c"], "o-", color="#c0392b", ms=4,
            label=r"$\alpha_c$ (certified)")
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


def save_open_figure(fig, path) -> str:
    """Save a figure atomically (format from the extension) and close it."""
    path = Path(os.fspath(path))
    try:
        _atomic(path, lambda tmp: fig.savefig(tmp, format=path.suffix.lstrip(".") or "png"))
    finally:
        _pyplot().close(fig)
    return str(path)


# ------------------------------------------------------------------------- Table 1
def read_table1(path=None) -> pd.DataFrame:
    """The seed's Table 1 (package data ``lamodel/data/table1.csv``)."""
    path = Path(path) if path is not None else DATA / "table1.csv"
    try:
        ref = pd.read_csv(path)
    except (OSError, pd.errors.ParserError) as exc:
        raise InputError(f"{path}: cannot read the reference table ({exc})") from None
    missing = [c for c in TABLE1_REFERENCE_COLUMNS if c not in ref.columns]
    if missing:
        raise InputError(f"{path}: column '{missing[0]}' is missing; expected {', '.join(TABLE1_REFERENCE_COLUMNS)}")
    return ref[list(TABLE1_REFERENCE_COLUMNS)]


def table1(options: SolveOptions | None = None, instances=None, reference=None, progress=None) -> pd.DataFrame:
    """The seed's Table 1 with lamodel's certified multiplier beside the published ones.

    Each wall of the reference table is the seed's panel built by
    :func:`lamodel.geometry.seed_instances` (or read from ``instances/<wall>.dat`` when a
    folder ``instances`` is given) and solved with :func:`lamodel.search.driver.solve`.
    Columns: the reference columns, then lamodel (certified alpha, NaN if none),
    alpha_associative, certified, seconds.
    """
    from .geometry import seed_instances
    from .io.datfile import read_dat
    from .io.jsonspec import structure_from_json

    specs = seed_instances()
    ref = read_table1(reference)
    rows = []
    for rec in ref.to_dict("records"):
        wall = str(rec["wall"])
        if instances is not None:
            where = Path(instances) / f"{wall}.dat"
            structure = read_dat(where)
        elif wall in specs:
            where, structure = f"the seed's {wall}", structure_from_json(specs[wall])
        else:
            raise InputError(f"Table 1 names wall '{wall}'; expected one of {', '.join(specs)} or a folder of instances")
        if structure.n_blocks != int(rec["n_blocks"]):
            raise InputError(f"{where}: {structure.n_blocks} blocks; the reference table says {rec['n_blocks']}")
        t = time.perf_counter()
        outcome = solve(structure, options or SolveOptions())
        best = outcome.best
        row = dict(rec, lamodel=best.alpha if best is not None else np.nan,
                   alpha_associative=outcome.alpha_associative, certified=best is not None,
                   seconds=time.perf_counter() - t)
        rows.append(row)
        if progress is not None:
            progress(row)
    return pd.DataFrame(rows, columns=[*TABLE1_REFERENCE_COLUMNS, "lamodel", "alpha_associative", "certified",
                                       "seconds"])


# ------------------------------------------------------------------------- files
def _atomic(path: Path, write):
    """Call write(tmp) on a temporary file in path's folder, then rename it over path."""
    from .io.files import atomic_write
    return atomic_write(path, write)


def write_csv(df: pd.DataFrame, path) -> str:
    """Write a table as CSV atomically (a reader never sees a partial file); folders are
    created. Floats are written in their shortest round-trip form (read back exactly)."""
    path = Path(os.fspath(path))
    path.parent.mkdir(parents=True, exist_ok=True)
    _atomic(path, lambda tmp: df.to_csv(tmp, index=False))
    return str(path)
