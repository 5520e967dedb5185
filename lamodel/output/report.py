"""From what the driver found to the tables of the output contract (:mod:`lamodel.output.results`)."""
from __future__ import annotations

from dataclasses import asdict

import numpy as np
import pandas as pd

from ..search.driver import Outcome
from .modes import modes_from_flow
from .results import Results
from .words import stall_columns


def outcome_results(outcome: Outcome, extra_summary: dict | None = None) -> Results:
    """The four tables of a solve. Without a certified state, alpha, forces and the
    mechanism are NaN: nothing uncertified is reported as a collapse multiplier.

    Beyond the contract: contacts.csv has the joints' strengths ``fc``, ``ft``,
    ``cohesion``, ``thickness`` where the structure has some; blocks.csv has ``dead_m``,
    ``live_m`` (moments of the loads about the centroid, e.g. of point loads, so that an
    external checker can rebuild eq. 1);
    summary.csv has ``length_unit``, ``force_unit`` ("-" when the input gave none),
    ``residual`` and ``residual_condition`` (the largest relative violation of the
    conditions of a collapse state by the reported one, at most 1e-7, and which condition)
    and the columns of ``extra_summary`` (e.g. the governing load case)."""
    s, best = outcome.structure, outcome.best
    nb, nc = s.n_blocks, s.n_contacts
    if best is not None:
        u = best.u.reshape(-1, 3)
        N, V, M = best.N, best.V, best.M
        modes = modes_from_flow(s, best.xi)
    else:
        u = np.full((nb, 3), np.nan)
        N = V = M = np.full(nc, np.nan)
        modes = ["unknown"] * nc  # no mechanism: not "closed", which would claim one
    blocks = pd.DataFrame({
        "block": s.blocks, "x": s.centroid[:, 0], "y": s.centroid[:, 1],
        "dead_x": s.dead[:, 0], "dead_y": s.dead[:, 1], "live_x": s.live[:, 0], "live_y": s.live[:, 1],
        "ux": u[:, 0], "uy": u[:, 1], "theta": u[:, 2], "dead_m": s.dead_m, "live_m": s.live_m})
    contacts = pd.DataFrame({
        "contact": s.contacts, "block_a": s.block_a, "block_b": s.block_b,
        "cx": s.centre[:, 0], "cy": s.centre[:, 1], "nx": s.normal[:, 0], "ny": s.normal[:, 1],
        "d": s.d, "mu": s.mu, "N": N, "V": V, "M": M, "mode": modes})
    if getattr(s, "has_materials", False):  # the joints' strengths (lamodel.formulation.joints)
        from ..structure import STRENGTH_PARAMS
        for name in STRENGTH_PARAMS:
            contacts[name] = getattr(s, name)
    runs = pd.DataFrame([asdict(r) for r in outcome.runs],
                        columns=["start", "source", "alpha_ipopt", "status", "alpha_certified", "iterations",
                                 "seconds", "path"])
    # + 0.0 turns -0.0 (a structure with mu = 0) into 0: a multiplier has no signed zero
    runs[["alpha_ipopt", "alpha_certified"]] = runs[["alpha_ipopt", "alpha_certified"]].astype(float) + 0.0
    summary = {
        "instance": s.name,
        "alpha": best.alpha + 0.0 if best is not None else np.nan,
        "certified": best is not None,
        "alpha_associative": outcome.alpha_associative + 0.0,
        **stall_columns(outcome.stalled),
        "n_blocks": nb, "n_contacts": nc,
        "n_starts": len(outcome.runs),
        "n_certified": int(np.isfinite(runs["alpha_certified"].astype(float)).sum()) if len(runs) else 0,
        "wall_time_s": outcome.wall_time_s,
        "status": outcome.status, "message": outcome.message, "seed": outcome.seed,
        "length_unit": s.units.get("length", "-"), "force_unit": s.units.get("force", "-"),
        **_residual_columns(best),
        **(extra_summary or {}),
    }
    return Results.from_frames(summary, blocks, contacts, runs)


def _residual_columns(best) -> dict:
    """The reported state's largest residual (see lamodel.search.certify.residuals): about
    1e-12 for an exact certificate, up to 1e-7 for one certified without flows below that
    fraction (README, "What it does")."""
    if best is None or not best.residual:
        return {"residual": np.nan, "residual_condition": ""}
    worst = max(best.residual, key=best.residual.get)
    return {"residual": float(best.residual[worst]) + 0.0, "residual_condition": worst}


def lower_bound_columns(outcome: Outcome, prove: float | None = None, beside=None) -> dict:
    """summary.csv's columns of the proven lower bound (:func:`lamodel.bound.lower_bound`)
    after a search: ``alpha_lower`` (no collapse state below it under this load pattern;
    NaN when nothing was proved), ``proven_global`` (alpha is the global minimum within
    1e-6 relative), ``alpha_lower_seconds`` and ``alpha_lower_check`` (the exact check of
    its certificates). The top of the searched range is the certified alpha (else the
    associative bound). ``prove``: seconds for the bound (the branch-and-bound);
    default :func:`lamodel.bound.lower.default_budget`. ``beside``: the default bound
    started beside the search (:class:`lamodel.bound.beside.BoundBeside`), used if it ran."""
    upper = outcome.best.alpha if outcome.best is not None else outcome.alpha_associative
    ok = outcome.status in ("certified", "not_certified")
    return bound_columns(outcome.structure, upper if ok else np.nan, outcome.best is not None,
                         outcome.wall_time_s, prove, beside)


def _stoppable_bound(structure, upper: float, limits: dict):
    """:func:`lamodel.bound.lower_bound` under ``limits``, ended by a stop signal as a search
    is (it keeps what it proved: the bound is anytime), so that the run still writes the
    state its search certified (the command then exits with 128 + the signal)."""
    import threading

    from ..bound.lower import lower_bound
    from ..search.options import Deadline
    from ..signals import catch_sigint, restore_sigint, stop_signal
    stop = threading.Event()
    if stop_signal() is not None:   # a signal that stopped the search: no bound after it
        stop.set()
    caught = catch_sigint(stop.set)
    try:
        rest = {k: v for k, v in limits.items() if k != "budget"}
        return lower_bound(structure, upper, deadline=Deadline.after(limits.get("budget"), stop.is_set), **rest)
    finally:
        restore_sigint(caught)


def bound_columns(structure, upper: float, certified: bool, search_seconds: float,
                  prove: float | None = None, beside=None) -> dict:
    """The columns of :func:`lower_bound_columns` for any structure (plane or space) whose
    search took ``search_seconds`` and gave ``upper`` (NaN: no bound is computed).
    ``beside``: a :class:`~lamodel.bound.beside.BoundBeside` the search started (its
    bound, topped by the associative multiplier, replaces the default one; with ``prove``
    it is stopped: the branch-and-bound searches below the certified alpha only)."""
    from ..bound.lower import default_budget, proves
    lb = None
    if beside is not None:
        if np.isfinite(upper) and prove is None:
            lb = beside.finish(search_seconds)
        else:
            beside.stop()
    if not np.isfinite(upper) or getattr(structure, "has_materials", False):
        # the bound's branch-and-bound knows dry joints only: none with the joints' strengths
        return {"alpha_lower": np.nan, "proven_global": False, "alpha_lower_seconds": 0.0,
                "alpha_lower_check": "none"}
    if lb is None:
        limits = {"budget": prove} if prove is not None else default_budget(search_seconds, structure)
        lb = _stoppable_bound(structure, upper, limits)
    return {"alpha_lower": lb.alpha_lower + 0.0, "proven_global": certified and proves(lb.alpha_lower, upper),
            "alpha_lower_seconds": lb.time, "alpha_lower_check": lb.exact_check}
