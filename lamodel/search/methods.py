"""Methods side by side: the published ways of computing a frictional collapse multiplier
(:mod:`.published`, each a strategy in its own room), run on the same model and put through
the same certification, and lamodel's certified search.

* ``associative`` — max alpha over S with associative (dilatant) flow: an upper bound;
* ``successive-lp`` — Gilbert, Casapulla & Ahmed (2006), Comput. Struct. 84:873-887;
* ``mpec`` — Ferris & Tin-Loi (2001), Int. J. Mech. Sci. 43:209-224, through Ipopt;
* ``seed`` — the seed paper's GA on eq. (5), each individual an Ipopt solve;
* ``lamodel`` — the certified search (:func:`lamodel.search.driver.solve`).

Every method returns a *raw* answer, reported as it is, then certified
(:mod:`.published.result`). Under ``all`` each method has an equal share of the time
left (``--time-limit``): none runs past its share, and every one reports.

Solver libraries load inside the methods (``lamodel --help`` lists :data:`CHOICES` at once).
"""
from __future__ import annotations

import dataclasses
import time

from ..structure import Structure
from .canonical import canonical, to_user
from .options import Deadline, SolveOptions
from .published.associative import Associative
from .published.mpec import MPEC
from .published.result import MethodResult, associative_lp, finish
from .published.seed import SeedGA
from .published.successive_cone import successive_cone
from .published.successive_lp import SuccessiveLP
from .tuning import IMPROVEMENT, SEED_GENERATIONS, SEED_POP_SIZE

__all__ = ["CHOICES", "METHODS", "MethodResult", "best_of", "run_method", "run_methods", "successive_cone",
           "SEED_GENERATIONS", "SEED_POP_SIZE"]

#: the methods, in the order of ``methods.csv``
METHODS = ("associative", "successive-lp", "mpec", "seed", "lamodel")
#: what ``--method`` accepts
CHOICES = METHODS + ("all",)
#: the published methods' strategies by name (the seed's GA is built with its budget)
STRATEGIES = {"associative": Associative(), "successive-lp": SuccessiveLP(), "mpec": MPEC()}


def lamodel_search(structure, options, lps, t0):
    """The default certified search; its answer is certified again like every method's."""
    from .driver import solve
    outcome = solve(structure, options)
    result = MethodResult("lamodel", structure, alpha_associative=outcome.alpha_associative, runs=outcome.runs,
                          iterations=int(sum(r.iterations for r in outcome.runs)), seed=options.seed)
    if outcome.best is None:
        return result.failed(outcome.message, t0, outcome.status)
    b = outcome.best
    run = next((i for i, r in enumerate(outcome.runs) if r.alpha_certified == b.alpha), 0)
    return finish(result, lps, (b.N, b.V, b.M, b.alpha, b.u, b.xi), t0, "certified search", run)


def run_method(name: str, structure: Structure, options: SolveOptions | None = None,
               seed_budget: tuple[int, int] | None = None) -> MethodResult:
    """Run one method (one of :data:`METHODS`) on the structure; ``options.time_limit``
    bounds this method alone. ``seed_budget`` = (population, generations) of the seed's GA."""
    from ..errors import InputError
    from .lp import LimitLPs
    if name not in METHODS:
        raise InputError(f"method '{name}' is unknown; expected one of {', '.join(CHOICES)}")
    opt = options or SolveOptions()
    structure.validate()
    opt.validate()
    t0 = time.perf_counter()
    deadline = Deadline.after(opt.time_limit)
    # every method works on the canonical order (the search puts the structure in it itself)
    work, order = (structure, None) if name == "lamodel" else canonical(structure)
    lps = LimitLPs(work)
    lps.deadline = deadline
    if name == "lamodel":
        return lamodel_search(structure, opt, lps, t0)
    status, message, assoc = associative_lp(lps)
    if assoc is None:
        return MethodResult(name, structure, notes=message, status=status, seconds=time.perf_counter() - t0,
                            iterations=lps.n_solves, seed=opt.seed)
    pop, gens = seed_budget or (None, None)  # either may be unset (None): the seed's own
    strategy = STRATEGIES.get(name) or SeedGA(pop or SEED_POP_SIZE, gens or SEED_GENERATIONS)
    result = strategy.method(work, opt, lps, assoc, t0, deadline)
    if order is not None:  # told in the user's order of blocks and contacts
        result.structure, result.state = structure, to_user(result.state, order)
    return result


def run_methods(name: str, structure: Structure, options: SolveOptions | None = None,
                seed_budget: tuple[int, int] | None = None, progress=None) -> list:
    """``name`` one of :data:`CHOICES`: that method, or (``all``) every method in turn, each
    within an equal share of the time left of ``options.time_limit`` (what one leaves
    goes to those after it). ``progress(result)`` is called after each."""
    opt = options or SolveOptions()
    names = METHODS if name == "all" else (name,)
    deadline = Deadline.after(opt.time_limit)
    out = []
    for i, m in enumerate(names):
        share = opt if opt.time_limit is None else dataclasses.replace(opt, time_limit=deadline.share(len(names) - i))
        out.append(run_method(m, structure, share, seed_budget))
        if progress is not None:
            progress(out[-1])
    return out


def best_of(results: list) -> MethodResult:
    """The method with the least certified alpha, or the first method when none is
    certified. Alphas within round-off of the least (IMPROVEMENT) are a tie: lamodel's
    search if it is among them (its state is the one the search descended), else the first
    listed: five methods agreeing to 1e-16 do not hand the result to whichever's last digit
    fell lower."""
    certified = [r for r in results if r.certified]
    if not certified:
        return results[0]
    least = min(r.alpha_certified for r in certified)
    tied = [r for r in certified if r.alpha_certified <= least + IMPROVEMENT * max(1.0, abs(least))]
    return next((r for r in tied if r.method == "lamodel"), tied[0])
