"""Parametric studies from a small JSON spec: variants of one structure, each solved by the
driver, locally or on a Dask cluster (:mod:`lamodel.search.executor`), as one tidy table.

A spec (paths relative to the spec's folder)::

    {"name": "wall33_friction",
     "structure": "../instances/wall33.dat",           # .dat or .json
     "seed": 0,                                        # root of every variant's seeds
     "options": {"starts": 0, "pop_size": 10, "generations": 5, "time_limit": 60},
     "vary": {"mu": {"from": 0.3, "to": 0.9, "step": 0.1},          # or a list, or a number
              "fc": [5000, 2000, 1000, "inf"],                       # compressive strengths
              "load_angle": [0, 5, 10],                              # degrees, counter-clockwise
              "dead_force": {"block": "b33", "fx": [0, -0.5], "fy": 0}},
     "random": {"count": 40, "mu": {"sd": 0.05, "per": "contact"}, "size": {"sd": 0.02}}}

Variants are every combination of the ``vary`` values (mu, fc, load_angle, dead_fx,
dead_fy in that order), each repeated ``random.count`` times with independent random perturbations.

* ``mu``: the friction coefficient of every contact.
* ``fc``: the compressive strength of every joint (:mod:`lamodel.formulation.joints`; in
  the structure's force per length squared); ``"inf"``: joints that never crush.
* ``load_angle``: every block's live force rotated by this angle (degrees,
  counter-clockwise; 0 is the structure's own live load), its magnitude kept.
* ``dead_force``: a constant force (dead_fx, dead_fy) added at a block's centroid.
* ``random.mu``: mu + sd·z, z standard normal, per contact (``per: "contact"``, default)
  or one z for the whole structure (``per: "structure"``), clipped at 0.
* ``random.size``: each block's size scaled by s = 1 + sd·z (z clipped to ±3) in place:
  its weight and live force scale with its area (s²), each joint's half-length with the
  smaller factor of its two bodies (supports do not change); positions are kept.

Variant i's randomness (perturbation and GA seed) comes from child i of
``SeedSequence(seed)``, so the table is the same for any number of workers, locally or
on Dask. One row per variant: the parameters, alpha (certified, NaN if none),
certified, alpha_associative, mode counts, seconds, status, ga_seed, and where it ran
(attempts, worker, error).
"""
from __future__ import annotations

import copy
import dataclasses
import json
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from .errors import InputError, OutputError
from .spec_values import check_keys, numbers, sd_of, strengths
from .structure import Structure
from .variants import (in_space, joint_places, with_block_sizes, with_dead_force, with_friction, with_load_angle,
                       with_strengths)

#: columns after the parameters, in this order
RESULT_COLUMNS = ("alpha", "certified", "alpha_associative", "n_sliding", "n_hinging", "n_open", "seconds",
                  "status", "ga_seed", "attempts", "worker", "error")
#: columns that depend on where and when a variant ran, not on the science
RUN_COLUMNS = ("seconds", "attempts", "worker", "error")
SPEC_KEYS = ("name", "structure", "seed", "options", "vary", "random", "description")
VARY_KEYS = ("mu", "fc", "load_angle", "dead_force")
OPTION_KEYS = ("starts", "time_limit", "pop_size", "generations", "chain", "xi_factor", "solver")
#: variants a study may ask for unless its runner allows more (``lamodel study --max-variants``)
MAX_VARIANTS = 10_000


@dataclass(frozen=True)
class Study:
    """A parsed spec: what every variant shares (sent once to each worker) and the grid."""

    name: str
    structure: Structure
    options: dict                 # SolveOptions fields shared by every variant
    grid: tuple = ()              # ((column, values), ...)
    dead_block: str | None = None
    random: dict | None = None    # {"count", "mu": {"sd", "per"}, "size": {"sd"}}
    seed: int = 0

    def count(self) -> int:
        """How many variants the study asks for (without listing them)."""
        return math.prod(len(values) for _, values in self.grid) * (self.random["count"] if self.random else 1)

    def variants(self) -> list[dict]:
        """The parameters of each variant, in table order."""
        rows = [{}]
        for column, values in self.grid:
            rows = [{**r, column: v} for r in rows for v in values]
        if self.dead_block is not None:
            rows = [{"dead_block": self.dead_block, **r} for r in rows]
        if self.random:
            rows = [{**r, "sample": k} for r in rows for k in range(self.random["count"])]
        return rows


# ------------------------------------------------------------------------- the spec
def study_from_dict(spec: dict, structure: Structure, where: str = "study spec") -> Study:
    """A Study from a parsed spec and its (already read) base structure."""
    from .loads import one_live_load
    check_keys(spec, SPEC_KEYS, where)
    one_live_load(structure, "study")
    from .search.options import SolveOptions
    options = spec.get("options", {})
    check_keys(options, OPTION_KEYS, f"{where}: options")
    SolveOptions(**options)  # one line on a bad option, before any worker starts
    seed = spec.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise InputError(f"{where}: seed is {seed!r}; expected a whole number >= 0")
    vary = spec.get("vary", {})
    check_keys(vary, VARY_KEYS, f"{where}: vary")
    grid, dead_block = [], None
    if "mu" in vary:
        mus = numbers(vary["mu"], f"{where}: vary.mu")
        if min(mus) < 0:
            raise InputError(f"{where}: vary.mu has {min(mus):g}; expected friction coefficients >= 0")
        grid.append(("mu", mus))
    if "fc" in vary:
        fcs = strengths(vary["fc"], f"{where}: vary.fc")
        if min(fcs) <= 0:
            raise InputError(f"{where}: vary.fc has {min(fcs):g}; expected compressive strengths > 0")
        ft = np.asarray(getattr(structure, "ft", None) if getattr(structure, "ft", None) is not None else [],
                        dtype=float)[:joint_places(structure)]
        if ft.size and min(fcs) < ft.max():   # checked here, not found by every variant's worker
            raise InputError(f"{where}: vary.fc has {min(fcs):g}, below the tensile strength {ft.max():g} of "
                             f"'{structure.name}'; expected compressive strengths >= ft")
        grid.append(("fc", fcs))
    if "load_angle" in vary:
        grid.append(("load_angle", numbers(vary["load_angle"], f"{where}: vary.load_angle")))
    if in_space(structure):  # what a study changes in space: mu, fc, the load's heading, mu at random
        sizes = isinstance(spec.get("random"), dict) and "size" in spec["random"]
        for key, planar in (("dead_force", "dead_force" in vary), ("random.size", sizes)):
            if planar:
                raise InputError(f"{where}: {key} varies planar structures only; expected mu, fc, load_angle "
                                 f"(about the vertical) or random.mu for '{structure.name}' in space")
    if "dead_force" in vary:
        force = vary["dead_force"]
        check_keys(force, ("block", "fx", "fy"), f"{where}: vary.dead_force")
        dead_block = str(force.get("block", ""))
        if dead_block not in structure.block_index():
            raise InputError(f"{where}: vary.dead_force.block '{dead_block}' is not a movable block of "
                             f"'{structure.name}'; expected one of {', '.join(structure.blocks[:6])}, ...")
        grid.append(("dead_fx", numbers(force.get("fx", 0.0), f"{where}: vary.dead_force.fx")))
        grid.append(("dead_fy", numbers(force.get("fy", 0.0), f"{where}: vary.dead_force.fy")))
    random = None
    if "random" in spec:
        r = spec["random"]
        check_keys(r, ("count", "seed", "mu", "size"), f"{where}: random")
        count = r.get("count")
        if isinstance(count, bool) or not isinstance(count, int) or count < 1:
            raise InputError(f"{where}: random.count is {count!r}; expected a whole number >= 1")
        if "seed" in r:
            if "seed" in spec and spec["seed"] != r["seed"]:
                raise InputError(f"{where}: seed {spec['seed']} and random.seed {r['seed']} differ; expected one seed")
            seed = r["seed"]
            if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
                raise InputError(f"{where}: random.seed is {seed!r}; expected a whole number >= 0")
        if "mu" not in r and "size" not in r:
            raise InputError(f"{where}: random perturbs nothing; expected 'mu' and/or 'size'")
        random = {"count": count}
        if "mu" in r:
            per = r["mu"].get("per", "contact") if isinstance(r["mu"], dict) else None
            random["mu"] = {"sd": sd_of(r["mu"], f"{where}: random.mu"), "per": per}
            if per not in ("contact", "structure"):
                raise InputError(f"{where}: random.mu.per is {per!r}; expected 'contact' or 'structure'")
        if "size" in r:
            random["size"] = {"sd": sd_of(r["size"], f"{where}: random.size")}
    name = str(spec.get("name") or structure.name)
    return Study(name, structure, dict(options), tuple((c, tuple(v)) for c, v in grid), dead_block, random, seed)


def read_study(path) -> Study:
    """A Study from a JSON spec file; its structure path is relative to the spec's folder."""
    from .io import read
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{path}: no such file; expected a study spec (.json)")
    try:
        spec = json.loads(p.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(f"{path}: not a JSON study spec ({exc})") from None
    except RecursionError:
        raise InputError(f"{path}: JSON nested too deeply to read; expected a JSON study spec") from None
    if not isinstance(spec, dict) or "structure" not in spec:
        raise InputError(f"{path}: 'structure' is missing; expected the path of a .dat or .json structure")
    where = Path(spec["structure"])
    structure = read(where if where.is_absolute() else p.parent / where)
    spec.setdefault("name", p.stem)
    return study_from_dict(spec, structure, where=str(path))


# ------------------------------------------------------------------------- variants
def variant_structure(study: Study, params: dict, rng: np.random.Generator) -> tuple[Structure, dict]:
    """The structure of one variant and what its random draw was (summary columns)."""
    s, drawn = study.structure, {}
    if "mu" in params:
        s = with_friction(s, params["mu"])
    if "fc" in params:
        s = with_strengths(s, fc=params["fc"])
    if "load_angle" in params:
        s = with_load_angle(s, params["load_angle"])
    if study.dead_block is not None:
        s = with_dead_force(s, study.dead_block, params["dead_fx"], params["dead_fy"], name=s.name)
    r = study.random or {}
    if "mu" in r:
        n = joint_places(s)  # (restraints keep no friction)
        z = rng.standard_normal(n if r["mu"]["per"] == "contact" else 1)
        s = copy.deepcopy(s)
        s.mu = np.array(s.mu, dtype=float)
        s.mu[:n] = np.maximum(s.mu[:n] + r["mu"]["sd"] * z, 0.0)
        drawn.update(mu_mean=float(s.mu[:n].mean()), mu_min=float(s.mu[:n].min()))
    if "size" in r:
        f = 1.0 + r["size"]["sd"] * np.clip(rng.standard_normal(s.n_blocks), -3, 3)
        s = with_block_sizes(s, f)
        drawn.update(size_min=float(f.min()), size_max=float(f.max()))
    return s, drawn


def solve_variant(study: Study, params: dict, seed: np.random.SeedSequence) -> dict:
    """One row of the table: a pure function of (study, params, seed)."""
    from .search.driver import SolveOptions, solve
    from .output.rows import outcome_row
    words = seed.generate_state(5)  # [GA seed, perturbation stream...]: pure, unlike spawn()
    ga_seed = int(words[0])
    structure, drawn = variant_structure(study, params, np.random.default_rng(words[1:]))
    # one process per variant: the parallelism is across variants (no nested pools)
    opts = SolveOptions(**study.options, seed=ga_seed, workers=1, progress=False)
    row = outcome_row(solve(structure, opts))
    row["alpha"] = row.pop("alpha_c")
    return {**params, **drawn, **row, "ga_seed": ga_seed}


# ------------------------------------------------------------------------- running
def run_study(study: Study, workers: int | None = None, scheduler: str | None = None, executor=None,
              progress: bool | None = None, on_row=None) -> pd.DataFrame:
    """Solve every variant (on ``executor``, or a fresh one with ``workers`` local processes
    or on ``scheduler``); the table in variant order. ``progress``: a tqdm bar on stderr
    (default: only when stderr is a terminal); ``on_row(row)`` after each variant.

    A stop signal (Ctrl-C, SIGTERM, SIGHUP: :data:`lamodel.signals.STOP_SIGNALS`)
    ends the study: the table holds the variants done (one the signal stopped has status
    ``interrupted`` and its best certified state), the others have status ``not run``, and
    ``df.attrs["interrupted"]`` is True."""
    import sys

    from tqdm import tqdm

    from .search.executor import Executor
    from .signals import RAISE, catch_sigint, clear_stop_signal, restore_sigint, stop_signal
    variants = study.variants()
    if progress is None:
        progress = sys.stderr.isatty()
    bar = tqdm(total=len(variants), desc=f"study {study.name}", unit="variant", file=sys.stderr,
               disable=not progress, dynamic_ncols=True)
    best, rows = [math.inf], {}

    def done(res):
        row = rows[res.index] = _row(variants[res.index], res)
        if row["certified"] and row["alpha"] < best[0]:
            best[0] = row["alpha"]
            bar.set_postfix_str(f"least alpha {best[0]:.6f}")
        bar.update()
        if on_row is not None:
            on_row(row)
        if stop_signal() is not None:  # it stopped a variant solved in this process
            raise KeyboardInterrupt

    own = executor is None
    clear_stop_signal()
    old = catch_sigint(RAISE)  # the study's main thread waits on its workers
    results = None
    try:
        ex = executor or Executor(workers=workers, scheduler=scheduler, preload=("lamodel.search.driver",))
        try:
            results = ex.map(solve_variant, variants, shared=study, seed=study.seed, progress=done)
        finally:
            if own:
                ex.close()
    except KeyboardInterrupt:
        pass
    finally:
        restore_sigint(old)
        bar.close()
    if results is not None:  # every variant ran (on Dask, attempts are known only now)
        df = _table([_row(v, r) for v, r in zip(variants, results)])
    else:
        df = _table([rows.get(i) or {**v, "alpha": np.nan, "certified": False, "status": "not run"}
                     for i, v in enumerate(variants)])
    df.attrs["interrupted"] = results is None
    return df


def _row(params, res) -> dict:
    if res.ok:
        row = dict(res.value)
    else:  # every attempt failed: the variant is in the table, without a multiplier
        row = {**params, "alpha": np.nan, "certified": False, "alpha_associative": np.nan, "status": "failed"}
    worker = res.worker or (res.lost[-1] if res.lost else "")
    row.update(attempts=res.attempts, worker=worker, error=res.error,
               seconds=row.get("seconds", res.seconds))
    return row


def _table(rows) -> pd.DataFrame:
    df = pd.DataFrame(rows)
    params = [c for c in df.columns if c not in RESULT_COLUMNS]
    for c in RESULT_COLUMNS:
        if c not in df.columns:
            df[c] = np.nan
    df["certified"] = df["certified"].astype(bool)
    return df[params + list(RESULT_COLUMNS)]


def parameter_columns(df: pd.DataFrame) -> list[str]:
    return [c for c in df.columns if c not in RESULT_COLUMNS]


# ------------------------------------------------------------------------- files
def write_study(df: pd.DataFrame, study: Study, out, plot: bool = True) -> list[str]:
    """study.csv (atomic) and study.png in the folder ``out``; the paths written."""
    from .io.files import write_csv
    from .output.figures import plot_study
    out = Path(os.fspath(out))
    written = [write_csv(df, out / "study.csv")]
    if plot:
        written.append(plot_study(df, study, out / "study.png"))
    return written


@dataclass
class StudyRun:
    """A study run into its folder (:func:`run_study_into`): the table, the files written,
    and whether a signal stopped it."""

    study: Study
    table: pd.DataFrame
    folder: Path
    written: list

    @property
    def interrupted(self) -> bool:
        """True when a stop signal ended the study before every variant ran."""
        return bool(self.table.attrs.get("interrupted"))

    @property
    def certified(self) -> bool:
        """True when every variant has a certified multiplier."""
        return bool(self.table["certified"].all())

    def text(self) -> str:
        """The table (without where each variant ran; with its status, which says why a
        variant has no alpha) and the files written."""
        shown = [c for c in self.table.columns if c not in ("ga_seed", "worker", "error")]
        with pd.option_context("display.width", 200, "display.max_columns", 30, "display.max_rows", 60):
            table = self.table[shown].to_string(index=False, float_format=lambda v: f"{v:.6g}")
        return table + "\nwritten: " + ", ".join(self.written)

    def line(self) -> str:
        """The one-line result."""
        df, n = self.table, len(self.table)
        ok = df["certified"]
        retried = int((df["attempts"].fillna(0) > 1).sum())
        failed = int((df["error"].fillna("") != "").sum())
        not_run = int((df["status"] == "not run").sum())
        least = f"; least alpha {df.loc[ok, 'alpha'].min():.6f}" if ok.any() else ""
        return (f"study {self.study.name}: {int(ok.sum())} of {n} variants certified{least}"
                + (f"; {retried} retried after a failure" if retried else "")
                + (f"; {failed} failed" if failed else "")
                + (f"; interrupted, {not_run} not run" if self.interrupted else ""))


def run_study_into(study: Study, out=None, workers: int | None = None, scheduler: str | None = None,
                   plot: bool = True, max_variants: int | None = None, echo=None) -> StudyRun:
    """Run a study into a folder, as ``lamodel study`` does: ``out`` (default
    ``results/<study name>/``, the name made safe) gets ``study.csv`` and ``study.png``.

    The number of variants is told (``echo(line)``) before any starts; more than
    ``max_variants`` is refused (InputError). Rows are appended to ``study.partial.csv``
    as the variants finish; at the end (also after a stop signal: the rows done, the
    others marked ``not run``) the table is written whole to ``study.csv`` and the
    partial file removed. :class:`lamodel.errors.OutputError` when the folder cannot be
    written."""
    import csv

    from .io.files import safe_folder_name
    out = Path(out) if out else Path("results") / safe_folder_name(study.name)
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: exists and is not a folder; expected a folder for the study files")
    n = study.count()
    if max_variants is not None and n > max_variants:
        raise InputError(f"study {study.name}: the spec asks for {n} variants, more than {max_variants}; "
                         f"expected --max-variants {n} (or a smaller spec) to run them")
    if scheduler is not None:
        from .search.executor import check_scheduler
        check_scheduler(scheduler)  # before the folder is made
    if echo is not None:
        echo(f"study {study.name}: {n} variants of '{study.structure.name}'")
    try:
        out.mkdir(parents=True, exist_ok=True)
        partial = out / "study.partial.csv"
        with open(partial, "w", newline="", encoding="utf-8") as fh:
            writer = []

            def stream(row):  # the columns of the first row that finishes
                if not writer:
                    writer.append(csv.DictWriter(fh, fieldnames=list(_table([row]).columns), extrasaction="ignore"))
                    writer[0].writeheader()
                writer[0].writerow(row)
                fh.flush()
            df = run_study(study, workers=workers, scheduler=scheduler, on_row=stream)
        written = write_study(df, study, out, plot=plot)
        partial.unlink()
    except OSError as exc:
        raise OutputError(exc.errno, f"cannot write the study to {out}: {exc.strerror or exc}") from None
    return StudyRun(study, df, out, written)


def with_options(study: Study, **options) -> Study:
    """The same study with some solve options changed."""
    return dataclasses.replace(study, options={**study.options, **options})
