"""The certified search in space: the seed's method on the Coulomb cone (eq. 5 in 3D).

The steps have the shape of the planar engine's (:mod:`lamodel.search.gap`), with conic
programs (Clarabel, :mod:`.cone`) where the planar one has LPs:

* **statics**: max alpha over S (the associative bound), or min ``alpha + rho w^T s_f`` over
  S (the gap step), or min alpha with the flowing points held (certification);
* **mechanism**: the fictitious cohesive system for cohesions ``c = -mu N`` (max alpha with
  ``||T|| <= c``); its equilibrium duals are the mechanism of least alpha_K for that N;
* **gap**: for a mechanism with strains q, ``alpha_K(N) - alpha = w(q)^T s_f >= 0`` is linear
  in the statics (:func:`lamodel.formulation.space.gap_weights`);
* **certify**: the points the mechanism opens or slides are held, least alpha over S; then
  exact on fixed cones with HiGHS and re-checked (:mod:`.certify3d`), in the non-dimensional
  units and again in the user's.

Two methods run from the associative statics: the gap alternation (rho 1e3 then 1e4) and
the successive cone method (Portioli et al.; Wang & Beyer: the friction capacity of each
point fixed at mu times its previous normal force, relaxed, at most 10 cone programs), each
raw answer certified. Exploring follows while it improves: continuation ladders (rho
raised from 2 and from 10), descents from certified states (the mechanism restricted to
the points their statics lets flow) and perturbed cohesions ``c exp(sigma z)``.
:func:`solve3d` keeps the least certified alpha.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..formulation.space import Formulation3D, scaled, scales
from ..structure3d import Structure3D
from .certify3d import (CollapseState3D, align, exact_state, passes, polish_mechanism, project_mechanism,
                        residuals, statics_lp)
from .cone import ConePrograms

#: rho ladder of the gap step (as the planar engine's main ladder).
RHO_MAIN = (1e3, 1e4)
#: Continuation ladders from the associative statics: a low rho first lets alpha fall far
#: before the gap is squeezed out (the extruded wall55: 0.557520 from the first, where the
#: main ladder certifies 0.558310).
RHO_CONTS = ((2.0, 10.0, 100.0, 1e3), (10.0, 100.0, 1e3, 1e4))
#: Exploring (continuations, descents, perturbations) stops after this many times the cone
#: programs it took to the first certificate (and at least PATIENCE_MIN) without improvement.
PATIENCE, PATIENCE_MIN = 3, 12
#: Least alpha over S above this (times max(1, alpha)) means unstable under the dead load
#: alone: an interior-point answer of 0 is exact only to its tolerance (1e-8 measured on the
#: 816-block wall).
STABLE_TOLERANCE = 1e-6
#: Perturbations of the best cohesions tried at most (patience ends them first), and their
#: spreads (with patience 400 the extruded wall55 reached the planar best 0.557416).
PERTURB_STEPS, PERTURB_SIGMAS = 60, (0.1, 0.3, 1.0)
#: Most descent steps from a certified state.
DESCENT_STEPS = 10
#: A gap below GAP_CERTIFY * max(1, alpha) is worth a certification.
GAP_CERTIFY = 1e-5
#: Thresholds (fractions of the largest strain) above which a conic mechanism's point
#: counts as opening or sliding, tried in turn: an interior-point answer is exact to ~1e-8.
FLOW_TOLS = (1e-6, 1e-4, 1e-3, 1e-2)
#: Successive cone method: relaxation of the friction capacities and the most cone programs.
SUCCESSIVE_RELAXATION = 0.5
#: Up to this many contact points the exact LP on fixed cones is tried first, then the held
#: cone program's own statics; beyond, the other way round (the LP's cold solve grows
#: fastest: 2-4 s at 2,900 points, measured under load).
LP_FIRST_POINTS = 1500
SUCCESSIVE_STEPS = 10
METHODS = ("gap", "successive")
#: The associative bound's own mechanism certified (a method on its own, not part of 'all').
ASSOCIATIVE = "associative"


@dataclass
class Result3D:
    """Outcome of :func:`solve3d`; forces and motions in the user's units."""

    status: str                      # 'certified', 'unstable', 'no collapse', 'none certified', 'interrupted'
    state: CollapseState3D | None
    associative: float
    message: str = ""
    first_alpha: float = np.nan
    first_time: float = np.nan
    associative_time: float = np.nan
    seconds: float = 0.0
    history: list = field(default_factory=list)   # (seconds, alpha, source) of each improvement
    methods: dict = field(default_factory=dict)   # method -> {"raw": alpha, "certified": alpha, "seconds": s}
    n_cone: int = 0
    n_lp: int = 0

    @property
    def alpha(self) -> float:
        return np.nan if self.state is None else self.state.alpha

    @property
    def N(self):
        return None if self.state is None else self.state.N

    @property
    def T1(self):
        return None if self.state is None else self.state.T1

    @property
    def T2(self):
        return None if self.state is None else self.state.T2

    @property
    def motions(self):
        """(nb, 6) block motions at the centroids (fbar^T u = 1)."""
        return None if self.state is None else self.state.motions

    @property
    def modes(self):
        return None if self.state is None else self.state.modes

    @property
    def path(self) -> str:
        """How the reported state was found and certified."""
        return "" if self.state is None else self.state.source


class ConeSearch:
    """The 3D search on one structure (non-dimensional inside); see the module doc."""

    def __init__(self, structure: Structure3D, time_limit: float | None = None, verbose: bool = False,
                 threads: int = 1, stop=None, on_best=None):
        self.user = structure
        self.on_best = on_best   # a callable (alpha, source) told of each improvement
        self.t0 = time.perf_counter()
        self.end = None if time_limit is None else self.t0 + float(time_limit)
        self.stop = stop   # a callable: True ends the search (a signal), the best state kept
        self.verbose = verbose
        self.F, self.L = scales(structure)
        self.form = Formulation3D.of(scaled(structure, self.F, self.L))
        self.form_user = Formulation3D.of(structure)
        self.cone = ConePrograms(self.form, threads)
        self.np = self.form.np
        self.mu = self.form.mu
        self.best: CollapseState3D | None = None       # scaled units
        self.best_user: CollapseState3D | None = None
        self.first = None
        self.history = []
        self.n_lp = 0
        self.solves_at_first = self.solves_at_best = 0
        self._certified = {}
        self._cohesive_cache = {}
        self.patience = None   # cone programs without improvement that end exploring (None: the rule)

    # --------------------------------------------------------------- bookkeeping
    def elapsed(self) -> float:
        return time.perf_counter() - self.t0

    def left(self):
        return None if self.end is None else max(self.end - time.perf_counter(), 1e-3)

    def stopped(self) -> bool:
        """A stop was asked for (Ctrl-C, SIGTERM, SIGHUP, a caller's predicate)."""
        return self.stop is not None and bool(self.stop())

    def expired(self) -> bool:
        return self.stopped() or (self.end is not None and time.perf_counter() >= self.end)

    def _log(self, msg):
        if self.verbose:
            print(f"{self.elapsed():8.2f} {msg}", flush=True)

    # --------------------------------------------------------------- the pieces
    def N_of(self, x):
        return x[:self.np]

    def statics(self, w=None, **held):
        """min alpha + w^T s_f over S with points held (a ConeResult)."""
        return self.cone.statics(w, time_limit=self.left(), **held)

    def mechanism(self, N):
        """The cohesive program for c = -mu N: (result, strains q of its mechanism)."""
        res = self.cohesive(-self.mu * N)
        if not res.ok or res.u is None:
            return res, None
        return res, self.form.strains(res.u)

    def cohesive(self, c):
        """The cohesive program for cohesions c, remembered (the gap search's first mechanism
        step and the successive method's first program are the same)."""
        key = np.asarray(c, float).tobytes()
        if key not in self._cohesive_cache:
            self._cohesive_cache = {key: self.cone.cohesive(c, time_limit=self.left())} | dict(
                list(self._cohesive_cache.items())[-7:])
        return self._cohesive_cache[key]

    def gap(self, q, x) -> float:
        return float(self.form.gap_weights(self._clean(q)) @ x[:3 * self.np])

    def _clean(self, q):
        q = q.copy()
        q[:self.np] = np.maximum(q[:self.np], 0.0)  # openings of a conic mechanism are >= 0 up to its tolerance
        return q

    # ------------------------------------------------------------- certification
    def certify(self, u, source, x=None, c=None):
        """The points the mechanism u opens or slides held, least alpha over S, then exact
        (see the module doc). ``x``: the statics that came with u (the cohesive program's),
        whose tangential forces give the sliding directions when nothing better does;
        ``c``: the cohesions u is the least-alpha_K mechanism for (then it is polished to
        that optimum exactly, which fixes its slip directions). Tries the thresholds
        FLOW_TOLS in turn; the first certified state (or None)."""
        n = self.np
        q = self.form.strains(u)
        U = np.abs(q).max()
        if not U > 0:
            return None
        first = None   # the first flow pattern whose exact motion keeps it
        for tol in FLOW_TOLS:
            qn, slip = q[:n], np.hypot(q[n:2 * n], q[2 * n:])
            opening = qn > tol * U
            sliding = (slip > tol * U) & ~opening
            # the slips of a conic answer are exact to its tolerance only; directions that
            # no rigid motion makes can make the held statics infeasible (four points of one
            # face sliding in directions 1e-8 apart): the nearest exact motion gives them
            exact = project_mechanism(self.form, u, ~(opening | sliding), sliding)
            if exact is None:
                continue
            qe = self.form.strains(exact)
            slip_e = np.hypot(qe[n:2 * n], qe[2 * n:])
            if np.any(qe[:n][opening] <= 0) or np.any(slip_e[sliding] <= 0):
                continue
            first = first or (opening, sliding, exact)
            if c is not None:
                polished = polish_mechanism(self.form, exact, ~(opening | sliding), sliding, c)
                if polished is not None:
                    polished = project_mechanism(self.form, polished, ~(opening | sliding), sliding)
                if polished is not None:
                    qp = self.form.strains(polished)
                    slip_p = np.hypot(qp[n:2 * n], qp[2 * n:])
                    if np.all(qp[:n][opening] > 0) and np.all(slip_p[sliding] > 0):
                        exact, qe, slip_e = polished, qp, slip_p
            # sliding directions: the (polished) mechanism's, then the statics' forces
            dirs = [np.column_stack([qe[n:2 * n], qe[2 * n:]]) / np.where(slip_e > 0, slip_e, 1.0)[:, None]]
            if x is not None:
                T = np.column_stack([x[n:2 * n], x[2 * n:3 * n]])
                Tn = np.hypot(T[:, 0], T[:, 1])
                if np.all(Tn[sliding] > 0) and np.all((T * dirs[0]).sum(1)[sliding] > 0):
                    dirs.append(np.where(sliding[:, None], T / np.where(Tn > 0, Tn, 1.0)[:, None], dirs[0]))
            for sdir in dirs:
                key = (opening.tobytes(), sliding.tobytes(), np.round(sdir[sliding], 9).tobytes())
                if key in self._certified:
                    st = self._certified[key]
                else:
                    st = self._certify(opening, sliding, sdir, exact, source)
                    self._certified[key] = st
                if st is not None:
                    return st
        if first is not None and x is not None and not self.expired():
            # no statics holds the conic slip directions: turn them until a statics and a
            # mechanism agree (certify3d.align), then the exact LP and the held program
            opening, sliding, exact = first
            got = align(self.form, opening, sliding, exact, self.N_of(x))
            self.n_lp += 1
            if got is not None:
                sdir, moved = got
                moved = project_mechanism(self.form, moved, ~(opening | sliding), sliding)
                if moved is not None:
                    return self._certify(opening, sliding, sdir, moved, source + "+align")
        return None

    def _certify(self, opening, sliding, sdir, u, source):
        if self.expired():
            return None
        # the least alpha with the points held, on the cone (Clarabel); its forces orient
        # the stuck points' pyramids in the exact LP (without it: the LP alone)
        res = self.statics(opening=opening, sliding=sliding, slide_dir=sdir)
        n = self.np
        ref = np.column_stack([res.x[n:2 * n], res.x[2 * n:3 * n]]) if res.ok else None
        cands = [("lp", None), ("cone", res.x if res.ok else None)]
        if self.np > LP_FIRST_POINTS:
            cands.reverse()
        for tag, cand in cands:
            if tag == "lp":
                self.n_lp += 1
                cand = statics_lp(self.form, opening, sliding, sdir, ref)
            if cand is None:
                continue
            self.n_lp += 1
            st = exact_state(self.form, cand, u, f"{source}+certify-{tag}")
            if st is not None and self._record(st):
                return st
        return None

    def _record(self, st: CollapseState3D) -> bool:
        """Keep a certified state (scaled units) if it passes in the user's units too."""
        user = self.to_user(st)
        if not passes(user.residual):
            self._log(f"  rejected alpha {st.alpha:.7f} in the user's units")
            return False
        if self.best is None or st.alpha < self.best.alpha - 1e-12 * max(1.0, st.alpha):
            self.best, self.best_user = st, user
            t = self.elapsed()
            self.solves_at_best = self.cone.n_solves
            if self.first is None:
                self.first = (st.alpha, t)
                self.solves_at_first = self.cone.n_solves
            self.history.append((t, st.alpha, st.source))
            if self.on_best is not None:
                self.on_best(user.alpha, st.source)
            self._log(f"  certified alpha {st.alpha:.7f}  {st.source}")
        return True

    def to_user(self, st: CollapseState3D) -> CollapseState3D:
        """A scaled state in the user's units (fbar^T u = 1 there), re-checked there."""
        F, L = self.F, self.L
        u = st.u.reshape(-1, 6).copy()
        u[:, :3] *= L
        u = u.ravel() / (F * L)
        q = st.q * L / (F * L)
        out = CollapseState3D(alpha=st.alpha, N=st.N * F, T1=st.T1 * F, T2=st.T2 * F, u=u, q=q, source=st.source)
        out.residual = residuals(self.form_user, out.N, out.T1, out.T2, out.alpha, out.u, out.q)
        return out

    # -------------------------------------------------------------------- methods
    def associative(self):
        return self.cone.associative(time_limit=self.left())

    def alternate(self, x, rhos=RHO_MAIN, source="gap", max_steps=60):
        """Mechanism step / gap step from the statics x until alpha + rho gap stops falling;
        certifies whenever the gap is small. Returns (best certified state or None, last x)."""
        best = None
        for rho in rhos:
            obj_prev = np.inf
            for _ in range(max_steps):
                if self.expired():
                    return best, x
                alpha = float(x[-1])
                res, q = self.mechanism(self.N_of(x))
                if q is None:
                    break
                gap = self.gap(q, x)
                self._log(f"  {source} rho {rho:g} alpha {alpha:.7f} alpha_as {res.alpha:.7f} gap {gap:.2e}")
                if gap <= GAP_CERTIFY * max(1.0, alpha):
                    st = self.certify(res.u, source, res.x, -self.mu * self.N_of(x))
                    if st is not None and (best is None or st.alpha < best.alpha):
                        best = st
                    if st is not None and abs(st.alpha - alpha) <= 1e-9 * max(1.0, alpha):
                        return best, x  # certified at this statics' alpha: the gap is closed
                obj = alpha + rho * gap
                if obj >= obj_prev - 1e-9 * max(1.0, abs(obj_prev)):
                    break
                obj_prev = obj
                nxt = self.statics(w=rho * self.form.gap_weights(self._clean(q)))
                if not nxt.ok:
                    break
                x = nxt.x
        return best, x

    def patience_over(self) -> bool:
        """No improvement over PATIENCE times the cone programs it took to the first
        certificate (PATIENCE_MIN at least), or the time limit: exploring stops. Counted
        in programs, not seconds, so that the answer does not depend on the machine."""
        if self.expired():
            return True
        if self.first is None:
            return False
        since = self.cone.n_solves - self.solves_at_best
        return since > (max(PATIENCE * self.solves_at_first, PATIENCE_MIN) if self.patience is None else self.patience)

    def continuations(self, x):
        """The gap alternation from x on each ladder of RHO_CONTS; the least certified (or None)."""
        best = None
        for rhos in RHO_CONTS:
            if self.patience_over():
                break
            st, _ = self.alternate(x, rhos=rhos, source="continuation")
            if st is not None and (best is None or st.alpha < best.alpha):
                best = st
        return best

    def descend(self, st, steps=DESCENT_STEPS):
        """From a certified state: the mechanism of least alpha_K for its cohesions among
        those flowing only where its statics allows (opening where N = 0, slip on the cone),
        certified; again while alpha falls. The current mechanism is one of them."""
        for _ in range(steps):
            if self.patience_over():
                break
            scale = max(np.abs(st.N).max(), 1e-300)
            may_open = -st.N <= 1e-9 * scale
            may_slip = -self.mu * st.N - np.hypot(st.T1, st.T2) <= 1e-9 * scale
            res = self.cone.cohesive(-self.mu * st.N, may_open=may_open, may_slip=may_slip, time_limit=self.left())
            if not res.ok or res.u is None:
                break
            nxt = self.certify(res.u, st.source.split("+")[0] + "+descend", res.x, -self.mu * st.N)
            if nxt is None or nxt.alpha >= st.alpha - 1e-10 * max(1.0, st.alpha):
                break
            st = nxt
        return st

    def perturbed(self, c, source="perturb"):
        """Cohesions c (the best state's, perturbed): the cohesive mechanism certified and
        descended, then the gap alternation from the statics of its gap step."""
        res = self.cohesive(c)
        if not res.ok or res.u is None:
            return None
        best = self.certify(res.u, source, res.x, c)
        if best is not None:
            best = self.descend(best)
        nxt = self.statics(w=RHO_MAIN[0] * self.form.gap_weights(self._clean(self.form.strains(res.u))))
        if nxt.ok:
            best = _least(best, self.alternate(nxt.x, source=source)[0])
        return best

    def successive(self, x, steps=SUCCESSIVE_STEPS, relax=SUCCESSIVE_RELAXATION, source="successive"):
        """The successive cone method from the statics x: cohesions c = -mu N fixed from the
        previous normal forces (relaxed), one cohesive cone program a step; every step's
        mechanism certified. Returns (best certified state or None, last raw alpha)."""
        best, raw, prev = None, np.nan, np.inf
        c = -self.mu * self.N_of(x)
        for k in range(steps):
            if self.expired():
                break
            res = self.cohesive(c)
            if not res.ok or res.u is None:
                break
            raw = res.alpha
            st = self.certify(res.u, source, res.x, c)
            if st is not None and (best is None or st.alpha < best.alpha):
                best = st
            c_new = -self.mu * self.N_of(res.x)
            self._log(f"  successive step {k + 1} alpha {raw:.7f} certified {st.alpha if st else np.nan:.7f}")
            # converged: the capacities reproduce themselves, or alpha no longer moves
            if np.abs(c_new - c).max() <= 1e-7 * max(np.abs(c).max(), 1e-300) or \
                    abs(raw - prev) <= 1e-8 * max(1.0, abs(raw)):
                break
            prev = raw
            c = (1 - relax) * c + relax * c_new
        return best, raw


def solve3d(structure: Structure3D, method: str = "all", time_limit: float | None = None,
            explore: bool = True, patience: int | None = None, seed: int = 0, verbose: bool = False,
            threads: int = 1, stop=None, on_best=None) -> Result3D:
    """Least certified collapse multiplier of a 3D block assembly on the Coulomb cone.

    ``method``: 'gap' (the gap alternation), 'successive' (the successive cone method),
    'all' (both, the least certified alpha kept) or 'associative' (the associative bound's
    own mechanism, certified: a collapse state only where it slides without dilatancy);
    ``explore`` then adds the continuation
    ladders of the gap alternation, a descent from each method's certified state and
    perturbations of the best cohesions (random, from ``seed``), until ``patience`` cone
    programs pass without improvement (default: PATIENCE times those to the first
    certificate, PATIENCE_MIN at least) or ``time_limit``, or until ``stop()`` is true (then the
    status is 'interrupted', the best certified state kept); ``on_best(alpha, path)`` is told of
    each better certified state. Returns a :class:`Result3D`: alpha, the
    certified statics (N, T1, T2 per point), block motions (nb, 6), per-point modes
    (stuck / opening / sliding) and the path that certified it, all in the user's units;
    ``methods`` gives each method's raw alpha, its own certified alpha and path (``own``,
    ``own_path``: before exploring) and the certified alpha after exploring.
    """
    structure.validate()
    methods = METHODS if method == "all" else (method,)
    for m in methods:
        if m not in METHODS + (ASSOCIATIVE,):
            from ..errors import InputError
            raise InputError(f"method '{m}' is not a 3D method; expected one of all, {', '.join(METHODS)}, "
                             f"{ASSOCIATIVE}")
    eng = ConeSearch(structure, time_limit=time_limit, verbose=verbose, threads=threads, stop=stop,
                     on_best=on_best)
    eng.patience = patience
    assoc = eng.associative()
    out = Result3D(status="none certified", state=None, associative=assoc.alpha if assoc.ok else np.nan,
                   associative_time=eng.elapsed())
    if assoc.status == "infeasible":
        out.status = "unstable"
        out.message = "no statically admissible state carries the dead load alone: not in equilibrium"
        return _finish(eng, out)
    if assoc.status == "unbounded":
        out.status, out.associative = "no collapse", np.inf
        out.message = "the associative program is unbounded: the statics carries any multiple of the live load"
        return _finish(eng, out)
    if not assoc.ok:
        out.message = f"associative cone program: {assoc.status}"
        return _finish(eng, out)
    eng._log(f"associative alpha {assoc.alpha:.7f}")
    found = {}
    for m in methods:  # each method's own answer first, certified
        t = time.perf_counter()
        if m == "gap":
            st, x = eng.alternate(assoc.x)
            raw = float(x[-1])
        elif m == "successive":
            st, raw = eng.successive(assoc.x)
        else:
            st = eng.certify(assoc.u, ASSOCIATIVE, assoc.x) if assoc.u is not None else None
            raw = assoc.alpha
        found[m] = st
        own = np.nan if st is None else st.alpha
        out.methods[m] = {"raw": raw, "certified": own, "own": own, "own_path": "" if st is None else st.source,
                          "seconds": time.perf_counter() - t}
    if explore:
        # then, while they keep improving (see ConeSearch.patience_over): continuation
        # ladders, descents
        steps = [("gap", lambda: eng.continuations(assoc.x))] if "gap" in methods else []
        steps += [(m, lambda m=m: found[m] and eng.descend(found[m])) for m in methods]
        if "gap" in methods:  # the best cohesions perturbed, c exp(sigma z), sigma 0.1 / 0.3 / 1
            rng = np.random.default_rng(seed)
            steps += [("gap", lambda k=k: eng.best and eng.perturbed(-eng.mu * eng.best.N * np.exp(
                PERTURB_SIGMAS[k % 3] * rng.standard_normal(eng.np)))) for k in range(PERTURB_STEPS)]
        for m, step in steps:
            # the continuations run also when the methods certified nothing: a ladder from a
            # low rho reaches collapse states where the main one stalls (a dome of 3 rings of
            # 8 voussoirs: the main ladder stalls at gap 1e-3, the one from rho 2 certifies)
            if eng.patience_over() or (eng.best is None and m != "gap"):
                break
            t = time.perf_counter()
            found[m] = _least(found[m], step())
            out.methods[m]["certified"] = np.nan if found[m] is None else found[m].alpha
            out.methods[m]["seconds"] += time.perf_counter() - t
    if eng.stopped():
        out.status = "interrupted"
    if eng.best is not None and not eng.expired():
        # stable under the dead load alone: some admissible statics has alpha = 0
        low = eng.statics()
        if low.ok and low.alpha > STABLE_TOLERANCE * max(1.0, eng.best.alpha):
            out.status = "unstable"
            out.message = (f"no statically admissible state carries the dead load alone (least alpha "
                           f"{low.alpha:.6g} > 0): the structure is not in equilibrium without live load")
            eng.best = eng.best_user = None
    return _finish(eng, out)


def _least(a, b):
    return b if a is None or (b is not None and b.alpha < a.alpha) else a


def _finish(eng: ConeSearch, out: Result3D) -> Result3D:
    out.state = eng.best_user
    out.history = list(eng.history)
    out.seconds = eng.elapsed()
    out.n_cone, out.n_lp = eng.cone.n_solves, eng.n_lp
    if eng.first is not None:
        out.first_alpha, out.first_time = eng.first
    if out.status == "interrupted":
        out.message = ("stopped by a signal: the best certified state so far" if out.state is not None
                       else "stopped by a signal before any collapse state was certified")
    elif out.state is not None:
        out.status = "certified"
        out.message = "least certified collapse multiplier found"
    elif out.status == "none certified" and not out.message:
        out.message = f"no collapse state certified; the associative multiplier {out.associative:.6g} bounds alpha_c"
    return out
