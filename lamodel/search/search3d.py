"""Limit analysis in space, as the result folder and the methods table want it.

The search is the planar one (:func:`lamodel.search.driver.solve`) on the cone
formulation (:class:`lamodel.search.gap.problem3d.ConeProblem`): associative bound, gap
alternation, certification, descent, rescue and fallback chain, continuations, the GA
on perturbed cohesions, the stopping rule counted in program solves. :func:`solve3d`
runs it, or one of the methods beside it, each raw answer certified by the search's
certifier:

* ``gap`` without exploring: the gap alternation from the associative statics;
* ``successive``: successive cone programming (:func:`lamodel.search.published.successive_cone.successive_cone`);
* ``associative``: the associative cone program's own mechanism, certified (a collapse
  state only where it moves without dilatancy).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..structure3d import Structure3D
from .certify3d import CollapseState3D
from .options import Deadline, SolveOptions, Stopped

#: The methods of :func:`solve3d` besides the search ('all' or 'lamodel').
METHODS = ("gap", "successive")
#: The associative bound's own mechanism certified (a method on its own, not part of 'all').
ASSOCIATIVE = "associative"


@dataclass
class Result3D:
    """Outcome of :func:`solve3d`; forces and motions in the user's units."""

    status: str                      # one of lamodel.search.state.STATUSES, as in the plane
    state: CollapseState3D | None
    associative: float
    message: str = ""
    first_alpha: float = np.nan
    first_time: float = np.nan
    associative_time: float = np.nan
    seconds: float = 0.0
    history: list = field(default_factory=list)   # (seconds, alpha, source) of each improvement
    methods: dict = field(default_factory=dict)   # method -> {"raw", "certified", "own", "own_path", "seconds"}
    n_cone: int = 0                  # program solves (cone programs and certification LPs)
    n_lp: int = 0                    # of which certification LPs
    stalled: tuple | None = None     # nothing certified: the step nearest a collapse state (driver.Outcome)

    alpha = property(lambda self: np.nan if self.state is None else self.state.alpha,
                     doc="The certified multiplier (NaN: none).")
    N = property(lambda self: None if self.state is None else self.state.N, doc="Normal forces per point.")
    T1 = property(lambda self: None if self.state is None else self.state.T1, doc="Tangential forces along t1.")
    T2 = property(lambda self: None if self.state is None else self.state.T2, doc="Tangential forces along t2.")
    motions = property(lambda self: None if self.state is None else self.state.motions,
                       doc="(nb, 6) block motions at the centroids (fbar^T u = 1).")
    modes = property(lambda self: None if self.state is None else self.state.modes,
                     doc="Per point: stuck, opening or sliding.")
    path = property(lambda self: "" if self.state is None else self.state.source,
                    doc="How the reported state was found and certified.")


def solve3d(structure: Structure3D, method: str = "all", time_limit: float | None = None, explore: bool = True,
            seed: int = 0, stop=None, options: SolveOptions | None = None, on_associative=None) -> Result3D:
    """Least certified collapse multiplier of a 3D block assembly on the Coulomb cone.

    ``method``: 'all' (or 'lamodel'; 'gap' with ``explore``) runs the search
    (:func:`lamodel.search.driver.solve` with ``options``, else with ``time_limit`` and
    ``seed``); 'gap' without ``explore``, 'successive' and 'associative' run that method
    alone (see the module doc). ``stop()`` true ends it (status 'interrupted', the best
    certified state kept). Returns a :class:`Result3D`: alpha, the certified statics (N,
    T1, T2 per point), block motions (nb, 6), per-point modes and the path that certified
    it, in the user's units; ``methods`` gives each method's raw alpha, its certified
    alpha and path. ``on_associative``: the search's (:func:`lamodel.search.driver.solve`).
    """
    from ..errors import InputError
    structure.validate()
    if method not in ("all", "lamodel", ASSOCIATIVE) + METHODS:
        raise InputError(f"method '{method}' is not a 3D method; expected one of all, {', '.join(METHODS)}, "
                         f"{ASSOCIATIVE}")
    if method in ("all", "lamodel") or (method == "gap" and explore):
        opt = options or SolveOptions(time_limit=time_limit, seed=seed)
        return _searched(structure, opt, stop, on_associative)
    return _method(structure, method, Deadline.after(time_limit, stop))


def _searched(structure, opt, stop, on_associative=None) -> Result3D:
    from .driver import solve
    out = solve(structure, opt, stop, on_associative)
    best = out.best
    alpha = np.nan if best is None else best.alpha
    run = out.runs[0] if out.runs else None
    r = Result3D(out.status, best, out.alpha_associative, out.message,
                 *out.first, associative_time=out.phases.get("associative", np.nan), seconds=out.wall_time_s,
                 history=[h[:3] for h in out.history],
                 n_cone=run.iterations if run is not None else 0, n_lp=out.certification_lps, stalled=out.stalled)
    # its path as summary.csv gives it: how the state was found and certified
    r.methods["lamodel"] = {"raw": alpha, "certified": alpha, "own": alpha, "own_path": r.path,
                            "seconds": run.seconds if run is not None else out.wall_time_s}
    return r


def _method(structure, method, deadline) -> Result3D:
    """One method on the search's pieces (:class:`lamodel.search.gap.GapSearch`)."""
    from .budget import Budget
    from .gap import GapSearch
    from .gap.phases import associative, stable
    from .published.successive_cone import successive_cone
    from .state import CERTIFIED, INTERRUPTED, NO_COLLAPSE, NOT_CERTIFIED, UNSTABLE, unstable_message
    t0 = time.perf_counter()
    eng = GapSearch(structure, Budget(deadline))
    # a method may spend what the default search may spend (its counted work bound), no more:
    # successive cone programming ran 896 s on a tower, and the methods after it waited
    eng.budget.bound(None, eng.budget.whole_bound())
    p, out, raw = eng.problem, Result3D(NOT_CERTIFIED, None, np.nan), np.nan
    bounded = False
    try:
        kind, out.associative, x0 = associative(eng)
        if kind == "unstable":
            out.status, out.message = UNSTABLE, unstable_message()
        elif kind == "unbounded":
            out.status, out.associative = NO_COLLAPSE, np.inf
            out.message = "the associative program is unbounded: the statics carries any multiple of the live load"
        elif kind != "ok":
            out.message = f"associative cone program: {kind}"
        elif method == "gap":
            _, x = eng.alternation.alternate(x0)
            raw = float(x[-1])
        elif method == "successive":
            _, raw = successive_cone(eng, x0)
        else:
            res = p.cone.associative()
            raw = res.alpha
            if res.u is not None:
                eng.certifier.certify(res.u, p.flows(res.u), ASSOCIATIVE)
    except Stopped:
        if eng.budget.expired():
            out.status = INTERRUPTED
        else:  # its work bound: what it certified stands, once the structure is known to stand
            bounded = True
    if eng.record.best is not None and out.status != INTERRUPTED:
        eng.budget.end()  # the verdict's program is not the method's work
        try:
            standing = stable(eng)
        except Stopped:
            standing, out.status = None, INTERRUPTED
        if not standing and out.status != INTERRUPTED:
            out.status, out.message = (UNSTABLE, unstable_message()) if standing is False else (
                NOT_CERTIFIED, "the least-alpha statics failed: whether it stands under dead load is not known")
            eng.record.withdraw()
    rec = eng.record
    out.state = rec.best_user
    if out.state is not None and out.status != INTERRUPTED:
        out.status, out.message = CERTIFIED, "least certified collapse multiplier of the method" + (
            " (it ended at its work bound)" if bounded else "")
    elif bounded and out.status == NOT_CERTIFIED:
        out.message = ("no collapse state certified within its work bound (the default search's); the associative "
                       f"multiplier {out.associative:.6g} bounds alpha_c")
    elif out.status == INTERRUPTED:
        out.message = ("stopped: the best certified state so far" if out.state is not None
                       else "stopped before any collapse state was certified")
    elif out.status == NOT_CERTIFIED and not out.message:
        out.message = f"no collapse state certified; the associative multiplier {out.associative:.6g} bounds alpha_c"
    if rec.first is not None:
        out.first_alpha, out.first_time = rec.first
    out.history = [h[:3] for h in rec.history]
    out.associative_time = rec.phases.get("associative", np.nan)
    out.seconds = time.perf_counter() - t0
    out.n_cone, out.n_lp = p.n_lps(), p.n_lp
    own = out.alpha
    out.methods[method] = {"raw": raw, "certified": own, "own": own, "own_path": out.path, "seconds": out.seconds}
    return out
