"""Rounds, alpha-intervals and a spatial branch-and-bound on the normal forces.

A **node** is a region of statics: alpha in ``[a, b]`` and ``lo <= -N <= hi``. Every
collapse state in it has ``alpha = alpha_coh(-mu N) >= alpha_coh(mu Nmin)`` (the seed's
first theorem; alpha_coh never decreases as a cohesion grows), where ``Nmin_k <= -N_k``
holds throughout the node. So:

* **round**: B = alpha_coh(mu Nmin) proves that the node holds no collapse state with
  alpha < B; its a is raised to B and the Nmin LPs, now on the narrower ``[B, b]``, are
  solved again (only for the contacts that slide in the cohesive mechanism: no other
  cohesion can raise B). A node whose B exceeds its top b holds no collapse state at all
  (excluded), and so does a node whose statics are empty (an exact Farkas certificate).
* **alpha-interval**: a node is split at the middle of ``[a, b]``; each half has its own
  Nmin.
* **branching**: a node is split on the normal-force range of the contact whose cohesion
  raises B fastest (its flow in the node's cohesive mechanism times its range), at the
  middle of that range (the maximum ``-N_k`` from an LP). The problem is an LP with one
  reverse-convex constraint, ``alpha_coh(-mu N(s)) <= alpha_s``; this partition of the
  normal-force space is the classical branch-and-bound for it.

Nodes are processed lowest bound first; the bound of the search is the least bound of
the nodes still open (or U when none is). Every number that decides is a checked one
(:mod:`.exact`): Nmin from exactly dual-feasible points, B from exactly rebuilt statics.
"""
from __future__ import annotations

import heapq
import itertools
import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from ..search.options import Deadline
from ..search.tuning import ALPHA_SPLIT, BOUND_ROUND_TOL, CANDIDATE_FLOW, PROVEN_TOL, SCREEN_LPS, SCREEN_MIN, SCREEN_TOL
from .exact import ExactData, floor_float
from .lps import BoundLPs
from .plane import pair_bound
from .space import BoundLPs3D, ExactData3D



class OutOfTime(Exception):
    """The budget ran out (every bound so far stays proven)."""


@dataclass
class Node:
    a: float
    b: float
    lo: np.ndarray
    hi: np.ndarray
    nmin: np.ndarray                  # checked lower bounds of -N_k in the node
    rate: np.ndarray | None = None    # d alpha_coh / d Nmin_k of the last cohesive mechanism
    fresh: set = field(default_factory=set)  # contacts whose nmin was computed at this a, box
    depth: int = 0

    def child(self, **kw) -> "Node":
        out = Node(self.a, self.b, self.lo.copy(), self.hi.copy(), self.nmin.copy(), self.rate, set(),
                   self.depth + 1)
        for k, v in kw.items():
            setattr(out, k, v)
        return out


@dataclass
class Progress:
    """Counts of the search (what LowerBound reports)."""

    rounds: int = 0
    nodes: int = 0
    excluded: int = 0
    alpha_splits: int = 0
    n_splits: int = 0
    checks_failed: int = 0
    lps: int = 0


class BranchAndBound:
    """The lower-bound search on one structure with an upper bound U."""

    def __init__(self, structure, upper: float, deadline: Deadline, alpha_split=ALPHA_SPLIT, tol=None, max_nodes=None,
                 pairs="none", max_lps=None, eager_root=False):
        self.s = structure
        self.U = float(upper)
        self.deadline = deadline
        if getattr(structure, "dimension", 2) == 3:
            self.lps, self.exact = BoundLPs3D(structure), ExactData3D(structure)
        else:
            self.lps, self.exact = BoundLPs(structure), ExactData(structure)
        self.exact.opening_from(self.lps.opening_motion)
        self.mu = structure.mu
        self.nc = self.lps.nc  # contacts in the plane, contact points in space
        self.tol = tol if tol is not None else PROVEN_TOL * max(1.0, abs(self.U))
        self.alpha_split = alpha_split   # alpha-split while b - a > (U - a_root) / alpha_split
        self.progress = Progress()
        self.root_bound = None
        self.max_nodes = max_nodes  # a count, not seconds: the same answer on any machine
        self.max_lps = max_lps      # likewise
        self.out_of_budget = False
        # the polygon bound of two contacts (plane.py) after the rounds: "none", "root" or
        # "all" nodes. Measured on 15 random trilithons at 60 nodes: either gained on as many
        # as it lost against "none" ("all" with 1.5-2.5x the LPs), so it is not the default
        self.pairs = pairs
        self.eager_root = eager_root
        # the screen only where nothing follows the root's rounds (the default bound): when
        # nodes are branched on, the Nmin a round proves also places the splits
        self.screen = max_nodes == 1

    # ------------------------------------------------------------------ time
    def _check_time(self):
        if self.deadline.expired() or (self.max_lps is not None and self.lps.n_solves >= self.max_lps):
            self.out_of_budget = True
            raise OutOfTime()

    # ------------------------------------------------------------------ one node
    def _nmin(self, node, k, seen=None) -> bool:
        """Recompute Nmin_k in the node; False when the node is proven empty. ``seen``:
        lowered to the ``-N`` of every statics the LPs find (an upper bound of each Nmin).

        While Nmin_k is 0, a feasibility LP first asks whether contact k can be open
        (N_k = 0) at some statics of the node: then Nmin_k = 0 needs no certificate, and
        the LP costs a tenth of the minimisation's simplex iterations (running-bond walls,
        where every bed joint can be open at alpha = 0)."""
        self._check_time()
        if node.nmin[k] == 0 and node.lo[k] == 0:
            shut = node.hi.copy()
            shut[k] = 0.0
            ans = self.lps.normal_force(None, node.a, node.b, node.lo, shut, deadline=self.deadline)
            if ans.status == "optimal":
                node.fresh.add(k)
                if seen is not None:
                    np.minimum(seen, ans.x, out=seen)
                return True
            self._check_time()
        ans = self.lps.normal_force(k, node.a, node.b, node.lo, node.hi, deadline=self.deadline)
        node.fresh.add(k)
        if ans.status == "infeasible":
            if self.exact.empty(ans.y, node.a, node.b, node.lo, node.hi):
                return False
            self.progress.checks_failed += 1
            return True
        if ans.status != "optimal":
            self._check_time()
            return True
        if seen is not None:
            np.minimum(seen, ans.x, out=seen)
        q = self.exact.dual_bound(ans.y, k, node.a, node.b, node.lo, node.hi)
        if q is None or q < Fraction(ans.value) - Fraction(1, 10 ** 6) * max(1, abs(ans.value)):
            self.progress.checks_failed += 1
        if q is not None:
            node.nmin[k] = max(node.nmin[k], floor_float(q))
        return True

    def _cohesive(self, node):
        """The checked alpha_coh(mu Nmin) of the node (or -inf), and its mechanism's rates."""
        self._check_time()
        c = [self.exact.mu[k] * Fraction(float(node.nmin[k])) for k in range(self.nc)]
        cf = np.array([floor_float(v) for v in c])
        ans = self.lps.cohesive(cf, deadline=self.deadline)
        if ans.status != "optimal":
            return -math.inf, None
        rate = ans.slide_rate * self.mu
        if not ans.value > node.a:
            return ans.value, rate  # no news: nothing to prove
        q = self.exact.cohesive_bound(ans, self.lps.cohesive_limits(cf), c, self.lps.d_shrunk)
        if q is None:
            self.progress.checks_failed += 1
            return -math.inf, rate
        return floor_float(q), rate

    def process(self, node, everything=False) -> bool:
        """Rounds on a node until they stall; False when the node is excluded.

        ``everything``: the first round solves the Nmin LP of every contact; otherwise
        only those the cohesive mechanism slides on (all of them when the cohesive LP has
        no mechanism to show, e.g. no frictionless statics at all)."""
        self.progress.nodes += 1
        todo = set(range(self.nc)) if everything else None
        while True:
            if todo is None:
                B, node.rate = self._cohesive(node)
                if B > node.b:
                    return False
                if B > node.a + BOUND_ROUND_TOL * max(1.0, abs(node.a)):
                    node.a = B
                    node.fresh = set()
                    self.progress.rounds += 1
                if node.rate is None:
                    todo = set(range(self.nc))
                else:
                    top = node.rate.max(initial=0.0)
                    todo = {int(k) for k in np.flatnonzero(node.rate > CANDIDATE_FLOW * top)} if top > 0 else set()
                todo -= node.fresh
                if not todo:
                    if node.rate is None:
                        return True
                    found = self._pair(node)
                    if found != "raised":
                        return found != "excluded"
                    continue  # the polygon raised a: new rounds
            if self.screen and len(todo) > SCREEN_MIN and not self._can_raise(node, todo):
                # the round would raise nothing: its LPs are not solved, and the rounds end
                # here as they would after it (the cohesive LP at alpha_coh = a is often
                # degenerate: another of its mechanisms would only ask the same again)
                node.fresh |= todo
                found = self._pair(node)
                if found != "raised":
                    return found != "excluded"
                todo = None
                continue
            todo -= node.fresh
            if not self._round(node, todo):
                return False
            todo = None

    def _can_raise(self, node, todo) -> bool:
        """Whether a round on ``todo`` could raise the node's a, deciding lazily. Every
        statics of the node bounds each Nmin from above (Nmin_k <= its -N_k), so the least
        ``-N`` over the statics found, ``ub``, does too, and alpha_coh never decreases in a
        cohesion: when alpha_coh(mu max(nmin, ub)) does not exceed a, no round can. Else
        the Nmin of the contacts its mechanism slides on are computed (proven, kept: the
        round skips them) and the test repeats, at most SCREEN_LPS times. The first statics
        minimises the ``-N`` of ``todo`` weighted by the node's mechanism. A decision, not a
        proof: the node keeps only what was proven."""
        rate = node.rate if node.rate is not None else np.ones(self.nc)
        w = {int(k): float(max(rate[k], CANDIDATE_FLOW)) for k in todo}
        self._check_time()
        ans = self.lps.normal_force(w, node.a, node.b, node.lo, node.hi, deadline=self.deadline)
        if ans.status != "optimal":
            return True
        ub = ans.x.copy()
        members = np.zeros(self.nc, bool)
        members[list(todo)] = True
        for _ in range(SCREEN_LPS):
            self._check_time()
            # the round moves only the Nmin of todo: the others stay at nmin
            top = self.lps.cohesive(self.mu * np.where(members, np.maximum(node.nmin, ub), node.nmin),
                                    deadline=self.deadline)
            if top.status != "optimal" or top.slide_rate is None:
                return True
            if not top.value > node.a + SCREEN_TOL * max(1.0, abs(self.U)):
                return False
            r = top.slide_rate
            pending = [int(k) for k in np.flatnonzero(members & (r > CANDIDATE_FLOW * r.max(initial=0.0)))
                       if k not in node.fresh]
            if not pending:
                return True   # its sliding contacts are proven: the round decides
            for k in pending:
                if not self._nmin(node, k, seen=ub):
                    return True   # an empty node: the round finds it again and excludes it
                ub[k] = min(ub[k], node.nmin[k]) if node.nmin[k] > 0 else ub[k]
        return True

    def _round(self, node, todo) -> bool:
        """Nmin of the contacts ``todo``; False when the node is proven empty."""
        for k in sorted(todo):
            if not self._nmin(node, k):
                return False
        return True

    def _pair(self, node) -> str:
        """The polygon bound of the two contacts the mechanism slides on most
        (:mod:`.plane`): "excluded", "raised" (a raised, ``fresh`` emptied) or "same"."""
        if self.pairs == "none" or (self.pairs == "root" and node.depth) or node.rate is None \
                or np.count_nonzero(node.rate > 0) < 2:
            return "same"
        i, j = (int(k) for k in np.argsort(-node.rate)[:2])
        B = pair_bound(self, node, i, j)
        if B > node.b:
            return "excluded"
        if B > node.a + BOUND_ROUND_TOL * max(1.0, abs(node.a)):
            node.a = B
            node.fresh = set()
            self.progress.rounds += 1
            return "raised"
        return "same"

    # ------------------------------------------------------------------ branching
    def _split_contact(self, node):
        """(k, s): the contact to branch on and the split point, or None."""
        if node.rate is None:
            return None
        order = np.argsort(-node.rate)
        best = None
        for k in order[:4]:
            if not node.rate[k] > 0:
                break
            self._check_time()
            ans = self.lps.normal_force(int(k), node.a, node.b, node.lo, node.hi, maximize=True,
                                        deadline=self.deadline)
            if ans.status != "optimal":
                continue
            width = min(ans.value, node.hi[k]) - node.nmin[k]
            if width > 1e-9 * max(1.0, ans.value) and (best is None or node.rate[k] * width > best[0]):
                best = (node.rate[k] * width, int(k), node.nmin[k] + 0.5 * width)
        return None if best is None else best[1:]

    def branch(self, node, root_a):
        """Children of an open node (alpha halves while wide, else a normal-force split)."""
        wide = node.b - node.a > (self.U - root_a) / self.alpha_split
        split = None if wide else self._split_contact(node)
        if split is None:
            if not node.b - node.a > self.tol:
                return []
            m = 0.5 * (node.a + node.b)
            self.progress.alpha_splits += 1
            return [node.child(b=m), node.child(a=m)]
        k, s = split
        self.progress.n_splits += 1
        low, high = node.child(), node.child()
        low.hi[k] = s
        high.lo[k] = s
        high.nmin[k] = max(high.nmin[k], s)
        return [low, high]

    # ------------------------------------------------------------------ the search
    def run(self, lower: float = 0.0):
        """Best-first search; returns (L, open nodes). Stops at the deadline, anytime."""
        nc = self.nc
        root = Node(float(lower), self.U, np.zeros(nc), np.full(nc, np.inf), np.zeros(nc))
        counter = itertools.count()
        heap = []
        L = lower
        in_hand = math.inf
        try:
            if not self.process(root, everything=self.eager_root):
                self.progress.lps = self.lps.n_solves
                self.root_bound = self.U
                return self.U, []
            self.root_bound = L = min(self.U, root.a)
            heap.append((root.a, next(counter), root))
            while heap:
                L = min(self.U, heap[0][0])
                if self.U - L <= self.tol or (self.max_nodes is not None and self.progress.nodes >= self.max_nodes):
                    break
                _, _, node = heapq.heappop(heap)
                in_hand = node.a  # its region is covered by nothing else until its children are in
                kids = self.branch(node, self.root_bound)
                if not kids:  # nothing left to split: its bound is final
                    heapq.heappush(heap, (node.a, next(counter), node))
                    break
                for kid in kids:
                    if self.process(kid):
                        heapq.heappush(heap, (kid.a, next(counter), kid))
                    else:
                        self.progress.excluded += 1
                in_hand = math.inf
            L = min(self.U, heap[0][0]) if heap else self.U
        except OutOfTime:
            if self.root_bound is None:
                L = max(L, root.a)  # the root's own rounds so far
            else:
                # open nodes and the one in hand (popped, children not all in) bound the rest
                L = min([self.U, in_hand] + [n.a for _, _, n in heap])
        self.progress.lps = self.lps.n_solves
        return min(self.U, L), [n for _, _, n in heap]
