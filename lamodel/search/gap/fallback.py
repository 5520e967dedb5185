"""Where the gap alternation stalls without a certificate: the seed's fixed-point chain
from there, every mechanism certified.

Why the alternation stalls. The gap step minimises ``alpha + rho w(xi)^T lambda`` over S
for the mechanism xi of least alpha_K at the current normal forces; the mechanism step
takes that mechanism again at the new forces. It is block-coordinate descent on the
bilinear gap ``slack(s)^T xi`` (eq. 5: alpha_K - alpha), and it stops at a partial
optimum wherever the least-alpha_K mechanism flows on a row that no admissible statics
can hold together with its other rows (``min_S w(xi)^T lambda > 0`` for that xi, at every
rho). Measured at mu = 0.9 (running bond, 4 x 1.75 blocks, live load = weight): the seed's
33-block panel stalls at gap 4.1e-3 with one hinge row flowing on slack, a 20 x 25 wall
(510 blocks) at gap 7.8e-4 with 30 rows; rho up to 1e7 leaves both gaps unchanged, and
the rows their statics hold admit no mechanism (the restricted cohesive LP is unbounded
at every tolerance of :meth:`~.starts.Starts.certify_near`). The alternation only ever
reads the cohesive LP's duals; its statics, where the other mechanisms are, is unused.

The fallback (:func:`fallback`). The chain ``c <- -mu N(cohesive statics for c)`` from
the stalled statics' cohesions, the associative statics' and zero cohesion
(:meth:`~.starts.Starts.chain`): each step's mechanism is
certified (its flow rows held, min alpha over S: feasible means an exact collapse state,
whatever the chain's forces) and descended. A step costs a mechanism LP and, for a flow
pattern not seen before, a certification.

Termination. Each chain ends after at most FALLBACK_STEPS steps, and earlier: once it
certified and then did not improve for FALLBACK_PATIENCE steps; at a fixed point (the
cohesions repeat); at a cycle (the cohesions repeat those of an earlier step: the warm
LPs would go round it again); where the cohesive LP has no optimum (infeasible: zero
cohesion cannot carry an arch's dead load; unbounded: no mechanism). At a fixed point
``c = -mu N`` the cohesive LP's own statics is admissible (``|V| <= c = -mu N``) and holds
every row its mechanism flows on (complementary slackness), so the certification cannot
fail there. A chain therefore ends without a certificate only at a cycle, at an LP without
optimum, or after FALLBACK_STEPS steps that neither converge nor certify.

Why no method here is proven to certify every structure. A collapse state is a statics
s of S with zero gap ``g(s) = alpha_K(-mu N(s)) - alpha(s)``; g >= 0 on S, and g is
concave (alpha_K is the least of affine functions of N, one a mechanism), so finding its
zero is a concave minimisation over a polyhedron, equivalently a disjointly constrained
bilinear program (statics x mechanisms) or a linear complementarity problem. A collapse
state is a fixed point of the chain's set-valued map (Kakutani's theorem gives one on a
compact convex set of cohesions where the cohesive LP keeps an optimum), but the gap
alternation is the successive
linearisation of g (it ends at a vertex pair that may have g > 0) and the chain is a
fixed-point iteration (it may cycle). Methods that end finitely with a certificate are
enumerative in the worst case: branch and bound over the complementarity of each yield
row, e.g. as a mixed-integer LP (rows held or not) that HiGHS solves. Measured on the
seed's 33-block panel at mu = 0.9 (332 binaries, bounds 10 times the associative statics'
slacks and 100 times its mechanism's flows, which a certified state meets): HiGHS found
no feasible point in 1640 nodes (4.5 s of CPU), where the search's first certificate takes
under a second. Such
a method cannot be the default run's fallback within its budget. Measured on 694 chains
(100 random walls of 2-10 courses of random block lengths at mu 0.8-1.3, 58 arches,
portals, walls with openings and point loads at mu 0.35-1.3, each from zero cohesion,
the associative statics and the gap alternation's stall; 260 GA-like perturbed cohesions
of the 33-block panel at mu 0.9, a 10 x 10 wall at mu 0.9 and a 6 x 5 wall at mu 1.0) no
chain cycled: every one certified, except the 38 from zero cohesion on
arches and portals, whose cohesive LP is infeasible (they cannot stand without friction).

Other ways measured and not used (running bond, 4 x 1.75 blocks, live load = weight; each
mechanism certified as here):

* The chain through the analytic centre of the cohesive LP's optimal face (interior
  point without crossover: a choice among the degenerate optima that does not depend on a
  basis) from zero cohesion: 510 blocks at mu = 0.9 certified 0.543378 at its 14th step
  (5.6 s), but 1,020 blocks at mu = 0.9 nothing in 30 steps (86 s) and 2,040 blocks
  nothing in 30 (408 s): the map is no contraction there (the cohesions still move 5-30 %
  a step, also averaged with weight 1/2). Choosing instead, among the optimal statics, the
  one whose normal forces give back the cohesions best (least sum ``|c + mu N|``, both LPs
  by the interior point method): 510 blocks certified 0.535344 at step 9 (13 s) and the
  residual fell to 4e-4 of the cohesions in 30 steps, but at 1,020 blocks it stayed at
  0.05-0.15 for 30 steps (190 s) and nothing certified, as with the simplex
  (``CHAIN_RELAXATION`` in :mod:`lamodel.search.tuning`).
* Where the dilatancy continuation stalls on the 2,040-block wall at mu = 1.0 (gap 1.7e-5,
  nearly all of it on three hinge rows with compression 1e-2 of their contact's normal
  force), no statics holds its mechanism's rows: the least sum of the lambdas holding them
  would zero is 7.4 (all 1,210 rows it flows on) and 1.5 (the 882 flowing above 1e-6 of
  the largest), and forbidding the rows that cannot be held, round after round, raised
  alpha_K from 0.517 to 0.997 in 8 rounds without a certificate. Such a stall is a local
  minimum of the concave gap, not a blind spot of the alternation: at the one of another
  run (gap 1.9e-5, 1,494 rows flowing, 99 % of the gap on three head joints' hinge rows)
  the least-alpha_K mechanism is unique (cohesions perturbed by up to 1e-6 of themselves
  move its flows by at most 1.1e-9 of the largest), so near the stall the gap is that one
  mechanism's affine function, and a gap step from it (rho 10, 1e3, 1e5) gives statics
  whose gaps are 5.6e-5 to 6.9e-5, 1.9e-5 and 1.7e-5. The chain from zero cohesion on the
  same wall flows on 1,531 rows at its second step and on 5,300-8,500 at each later one,
  alpha_K going 0.54, 0.34, 0.46, 0.46, 0.42, 0.34 ... without settling (14 steps, about
  65 s each), and every certification's first LP stops at its iteration cap; with
  ``--time-limit 2400`` the search certifies nothing either.
* Mechanisms of one block (all other blocks still), the Armadillo vault of the
  elastic-plastic entry below: with the associative statics' cohesions the least alpha_K
  of the 155 bounded ones is 0.728 (the next 0.781), none certified; the gap alternation
  restricted to the motions of that block ends at alpha_K 0.464 with gap 1.4e-2, above the
  associative bound 0.4508, which no collapse state exceeds. The averaged chain does reach
  mechanisms of that one block (alpha_K 0.311, 0.229, 0.166), but on cohesions no
  admissible statics has.
* Ferris & Tin-Loi's relaxed MPEC with Ipopt (``--method mpec``) certified neither the
  105-block wall at mu = 0.9 (18 s) nor the 510-block one (208 s).
* Complementary pivoting on eq. (5)'s conditions (yield slack of the statics against flow
  of the mechanism; statics pivots and mechanism pivots alternate, as in Lemke's method,
  on sparse LUs with product-form updates). Its mechanism bases are singular wherever
  sliding contacts leave normal forces statically indeterminate (a fixed cohesion fixes V,
  not N): from the associative basis, 10 dependent columns of 250 on the 33-block panel at
  mu = 0.9 and 214 of 4,399 on the 20 x 25 wall (2 and 12 after exchanging the collinear
  slide rows of open contacts). With a small dilatancy (1e-6 to 1e-2) the bases are
  regular, but the path from the associative state (its mechanism's dilatant opening
  imposed and scaled down to zero) closed into a loop back to its start (14 pivots), and
  Lemke's start from a covering vector ended on a secondary ray at its first pivot (5 of 5
  random vectors).
* The dilatancy homotopy followed exactly: t from 1 (the associative LP, a unique state once
  yield rows and objective are perturbed by 1e-7 and 1e-6) down to 0, through exact collapse
  states of each system of dilatancy t; where a flow reaches zero (bisection on t) a statics
  pivot, and the entering flow's growth gives the direction of t, so that folds are
  followed. The 33-block panel at mu = 0.9 reached t = 0 for 3 of 4 perturbations (174-250
  events, 4-5 s) and certified 0.726538, 0.758389 and 0.685714; the fourth went round
  without end. The 510-block wall at mu = 0.9 was at t = 0.704 after 7,870 events (20 min),
  going back and forth there; the 105-block wall at mu = 0.9 came down to t = 0.232 and then
  went back above t = 1 (after 8,500 events, 4 min; still there after 29,900, 13 min), which
  an exactly followed path cannot do: with bases this degenerate the path jumps between
  branches at round-off. Perturbed by 1e-5 and 1e-4 instead, it reached t = 0 (4,745 events,
  195 s), but no mechanism of the unperturbed system flows on its final rows (the restricted
  cohesive LP is unbounded): a collapse state of the perturbed problem only. Every
  evaluation is a sparse LU of the whole mechanism basis (t changes every sliding column).
  Moving one contact's dilatancy at a time (rank-one changes, events in closed form) took
  the 33-block panel to zero dilatancy in 1-2 s for 2 of 4 perturbations, but onto singular
  mechanism bases (the indeterminacy above): no certificate.
* The elastic-plastic load path: two elastic points a contact (normal stiffness
  proportional to d, tangential 0.4 of it), opening and Coulomb slip without dilatancy as
  plastic strains, the load raised by control of ``fbar^T u`` (Newton with return mapping).
  Where the path reaches a plateau every rate is plastic, so its statics is (for the exact
  law) a collapse state of eq. (5), the one its loading selects. Opening must be plastic (an opened end
  does not close freely): with reversible gaps 30 % of the last increment's deformation on
  the 20 x 25 wall at mu = 0.9 lies outside the fictitious system's kinematics (ends
  closing that opened earlier). With the exact contact law Newton cycles at scale
  (the 40 x 25 wall at mu = 0.9 sticks at alpha 0.299: a load step of 1e-6 takes the
  slipping points from 249 to 730); with it smoothed (a softplus normal force, the
  friction clipped by ``(1 + a^40)^(-1/40)``) the path goes on. Measured: the seed's
  33-block panel levels off at 0.640377 and its near-active rows certify 0.638982 (4 s);
  at mu = 0.9 at 0.646873, certified 0.645963, the chain from it 0.617364; 10 x 10 blocks
  at mu = 0.9 at 0.59685 after 600 steps (45 s), certified 0.593491 (0.584514 descended);
  20 x 25 at mu = 0.9 still rising at 0.533823 after 800 steps (460 s), nothing certified
  from it; 80 x 25 at mu = 0.9 at alpha 0.224 after 600 s (24 steps; these two beside
  each other). In space, the same law on the cone point by point (the Armadillo vault of
  366 blocks and 4,761 points): the path peaks at alpha 0.229 (associative bound
  0.450771) in 55 s and gets no further in 300 s (controlled by ``fbar^T u`` it stops there;
  by arc length it wanders between 0.221 and 0.227); nothing near the peak is certified
  (its near-active points, its motion, the chain from its cohesions). A path to its plateau
  takes hundreds of steps, each a Newton solve of the whole structure: at scale far more
  than the search's first certificate.
"""
from __future__ import annotations

import numpy as np

from ..tuning import FALLBACK_PATIENCE, FALLBACK_STEPS


def fallback(starts, statics, from_zero=False, source="fixed-point", until=None):
    """The fixed-point chain from the cohesions ``-mu N`` of each statics given (scaled
    units; None is skipped) and, with ``from_zero``, from zero cohesion (the weakest
    fictitious system: the chain from below), on :class:`~.starts.Starts` ``starts``.
    Chains from different starts reach different fixed points (the 33-block panel at
    mu = 0.9: 0.685714 from its stall and from the associative statics, 0.617364 from
    zero cohesion). ``until()``: True stops the chains. Returns the least certified state
    (or None)."""
    p = starts.problem
    cohesions = [-p.mu * p.N_of(x) for x in statics if x is not None]
    if from_zero:
        cohesions.append(np.zeros(p.nc))
    best = None
    for c in cohesions:
        st = starts.chain(c, FALLBACK_STEPS, source=source, patience=FALLBACK_PATIENCE, until=until)
        if st is not None and (best is None or st.alpha < best.alpha):
            best = st
    return best
