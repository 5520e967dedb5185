"""Studies built on the driver: a friction study, load cases, a rolling load, the seed's Table 1.

These are the reusable parts of ``examples/friction_study.py``, ``examples/tie_force.py``
and ``scripts/table1.py``. Every multiplier they report is a certified collapse
multiplier of :func:`lamodel.search.driver.solve` (NaN when the driver certified none), so it is
the least collapse multiplier lamodel *found*: an upper bound on the true minimum α_c.

The variants they solve are deep copies (:mod:`lamodel.variants`); the structure passed in
is never modified.
"""
from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd

from .errors import InputError
from .mirror import image_on, mirror_loads, mirror_of
from .output.rows import outcome_row
from .search.driver import SolveOptions, solve
from .search.state import CERTIFIED, INTERRUPTED, NOT_CERTIFIED, Run
from .search.tuning import MIRROR_GAIN, RETRY_WORK
from .solve_all import solve_all
from .structure import Structure

#: Reference data shipped with the package (the seed's Table 1).
DATA = Path(__file__).resolve().parent / "data"

#: Columns of :func:`friction_study`.
FRICTION_COLUMNS = ("mu", "alpha_c", "alpha_associative", "certified", "n_sliding", "n_hinging", "seconds",
                    "status")

#: Published columns of the seed's Table 1 (references/table1.csv).
TABLE1_REFERENCE_COLUMNS = ("wall", "n_blocks", "ferris_tin_loi_2", "gilbert_4", "mihai_5", "seed")


# ------------------------------------------------------------------------- friction
def friction_study(structure: Structure, mus, options: SolveOptions | None = None, progress=None,
                   workers: int | None = None, scheduler: str | None = None) -> pd.DataFrame:
    """Certified collapse multiplier of the structure for each friction coefficient.

    The study spec ``{"vary": {"mu": mus}}`` (:mod:`lamodel.parametric`, as
    ``examples/friction_study.json``) run with these options: one solve per mu on a copy
    with that mu on every contact, its GA seed spawned from ``options.seed``; on
    ``workers`` local processes (default: all cores, as ``--workers``; 1: in this process)
    or on a Dask ``scheduler``.
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
    df = run_study(study, workers=workers, scheduler=scheduler, progress=False,
                   on_row=None if progress is None else (lambda row: progress(rename(row))))
    return df.rename(columns={"alpha": "alpha_c"})[list(FRICTION_COLUMNS)]


# ------------------------------------------------------------------------- load cases, rolling load
#: Columns of :func:`load_case_study` (after ``case``) and :func:`rolling_study` (after
#: ``position`` and ``blocks``).
VARIANT_COLUMNS = ("alpha_c", "alpha_associative", "certified", "n_sliding", "n_hinging", "seconds", "status",
                   "governing")


def _variant_study(key, labels, variants, options, progress, same_blocks=False):
    """Solve every variant (:func:`.solve_all.solve_all`: ``options.workers`` of them at once);
    a table (one row each, the least certified alpha marked ``governing``) and the outcomes
    by label. A stop signal (Ctrl-C, SIGTERM, SIGHUP) ends the study: each solve under way
    keeps its best certified state (``interrupted``), the variants not begun are ``not run``.

    ``same_blocks``: the variants differ only in their live loads (load cases, positions
    of a rolling load). A variant the search left uncertified is then solved again with
    the certified variants' mechanisms as its first candidates (the nearest in the list
    first: a mechanism of the same blocks is compatible under any load, and where a
    statics holds its rows it is a collapse state of that variant,
    :func:`lamodel.search.gap.phases.given_mechanisms`) and RETRY_WORK times the work.
    Before that and after it, on a mirror-symmetric structure, a variant whose mirror image
    (the other variant whose live loads are its own reflected) certified a lower alpha, or
    that certified none, takes the image of that state (:mod:`lamodel.mirror`): mirror
    images get the same alpha."""
    rows, outcomes = [None] * len(labels), {}

    def one(i, outcome):
        outcomes[labels[i]] = outcome
        rows[i] = {key: labels[i], **outcome_row(outcome)}
        if progress is not None:
            progress(rows[i])
    solve_all(variants, options, one, labels=[f"{key} {label}" for label in labels])
    rows = [row or {key: label, "alpha_c": np.nan, "alpha_associative": np.nan, "certified": False, "n_sliding": 0,
                    "n_hinging": 0, "n_open": 0, "seconds": 0.0, "status": "not run"}
            for label, row in zip(labels, rows)]
    # mirror images first (a state of the same structure reflected), then the second try, and
    # the mirror again for what the second try certified
    for again in (_from_the_mirror, _from_the_others, _from_the_mirror):
        if same_blocks and not any(r["status"] in ("interrupted", "not run") for r in rows):
            again(key, labels, variants, options, progress, rows, outcomes)
    df = pd.DataFrame(rows)
    alpha = df["alpha_c"].where(df["certified"].astype(bool))
    df["governing"] = False
    if alpha.notna().any():
        df.loc[alpha.idxmin(), "governing"] = True
    return df, outcomes


def _from_the_mirror(key, labels, variants, options, progress, rows, outcomes):
    """The mirror pass of :func:`_variant_study` (``same_blocks``): each variant whose
    mirror image certified an alpha lower by MIRROR_GAIN (or that certified none) takes
    the image of that state, re-checked on it by the residual test (:func:`.mirror.image_on`),
    in the list's order (a pair ends with the lower of its two)."""
    planar = len(variants) > 1 and isinstance(variants[0], Structure)
    reflection = mirror_of(variants[0]) if planar else None  # (a reflection in the plane)
    if reflection is None:
        return
    for i, label in enumerate(labels):
        j = next((j for j, sj in enumerate(variants) if j != i and mirror_loads(variants[i], sj, reflection)), None)
        mine = outcomes[label]
        if j is None or outcomes[labels[j]].status != CERTIFIED or mine.status not in (CERTIFIED, NOT_CERTIFIED):
            continue
        theirs = outcomes[labels[j]].best
        if mine.status == CERTIFIED and mine.best.alpha <= theirs.alpha + MIRROR_GAIN * max(1.0, abs(theirs.alpha)):
            continue
        image = image_on(variants[i], theirs, reflection)
        if image is None:
            continue
        seconds = rows[i]["seconds"]
        outcomes[label] = replace(mine, best=image, status=CERTIFIED, stalled=None,
                                  message=f"certified collapse state: the mirror image of {labels[j]}'s",
                                  runs=[*mine.runs, Run(len(mine.runs), "mirror", alpha_certified=image.alpha,
                                                        status=CERTIFIED, path="mirror")])
        rows[i] = {key: label, **outcome_row(outcomes[label]), "seconds": seconds}
        if progress is not None:
            progress(rows[i])


def _from_the_others(key, labels, variants, options, progress, rows, outcomes):
    """The second pass of :func:`_variant_study` (``same_blocks``): each uncertified
    variant solved again from the certified variants' mechanisms, nearest first."""
    certified = [i for i, label in enumerate(labels) if outcomes[label].status == CERTIFIED]
    for i, (label, structure) in enumerate(zip(labels, variants)):
        if outcomes[label].status != NOT_CERTIFIED or not certified:
            continue
        nearest = sorted(certified, key=lambda j: (abs(j - i), j))
        before = rows[i]["seconds"]  # the first pass's: the row counts both
        outcome = solve(structure, options or SolveOptions(), mechanisms=[outcomes[labels[j]].best for j in nearest],
                        work_scale=RETRY_WORK)
        if outcome.status == INTERRUPTED:
            break
        if outcome.status != CERTIFIED:
            continue
        outcomes[label] = outcome
        rows[i] = {key: label, **outcome_row(outcome)}
        rows[i]["seconds"] += before
        if progress is not None:
            progress(rows[i])


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
    df, outcomes = _variant_study("case", names, [case_structure(structure, n) for n in names], options, progress,
                                  same_blocks=True)
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
    df, outcomes = _variant_study("position", positions, variants, options, progress, same_blocks=True)
    df.insert(1, "blocks", [" ".join(dict.fromkeys(p.block for p in v.point_loads if p.case == "rolling"))
                            for v in variants])
    return df[["position", "blocks", *VARIANT_COLUMNS]], outcomes


def governing_study(structure: Structure, options: SolveOptions | None = None, progress=None):
    """A structure's load cases, or its rolling load's positions, each solved: returns
    (study, the governing outcome, summary columns). ``study`` has the ``key`` ("case"
    or "position"), a ``title`` and the ``table``; the governing outcome is the least
    certified one (the first when none is certified); the summary columns name it
    (``case`` or ``position``) and say whether it governs. ``progress(row)`` after each
    solve; a stop signal ends it (``study["interrupted"]``, the rest ``not run``);
    ``study["seconds"]``: the whole study's."""
    from dataclasses import replace
    t0 = time.perf_counter()
    quiet = replace(options or SolveOptions(), progress=False)
    if structure.cases:
        df, outcomes = load_case_study(structure, quiet, progress=progress)
        key, title = "case", f"Load cases ({len(df)})"
    else:
        df, outcomes = rolling_study(structure, quiet, progress=progress)
        key, title = "position", f"Rolling load ({len(df)} positions)"
    label = governing(df, key)
    chosen = label if label is not None else next(iter(outcomes))
    study = {"key": key, "title": title, "table": df, "interrupted": bool((df["status"] == "interrupted").any()),
             "seconds": time.perf_counter() - t0}
    return study, outcomes[chosen], {key: chosen, "governing": label is not None}


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


def table1_into(path, options: SolveOptions | None = None, echo=None) -> pd.DataFrame:
    """:func:`table1`, printed through ``echo(line)`` as each wall ends and as a whole,
    and written to the CSV file ``path`` (``lamodel table1``). Returns the table."""
    from .io.files import write_csv
    say = echo or (lambda line: None)
    options = options or SolveOptions()
    df = table1(options, progress=lambda r: say(f"  {r['wall']}: alpha = {r['lamodel']:.6f} "
                                                f"({'certified' if r['certified'] else 'NOT certified'}, "
                                                f"{r['seconds']:.1f} s)"))
    with pd.option_context("display.width", 160, "display.max_columns", 20):
        say(df.to_string(index=False, formatters={
            c: (lambda v: f"{v:.6f}") for c in ("lamodel", "alpha_associative")} | {
            c: (lambda v: f"{v:.5f}") for c in ("ferris_tin_loi_2", "gilbert_4", "mihai_5", "seed")} | {
            "seconds": lambda v: f"{v:.1f}"}))
    write_csv(df, path)
    say(f"written to {path} (seed {options.seed}, starts {'default' if options.starts is None else options.starts})")
    return df
