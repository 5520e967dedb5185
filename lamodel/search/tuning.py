"""Every tuned constant and tolerance of the search, in one place.

Each says what it decides and the measurement behind it. "Round-off margin" marks a
tolerance that only absorbs floating-point error (no measurement chose it: any value
well above round-off and well below the effects it separates gives the same answers).
The search runs on the non-dimensional problem (:mod:`lamodel.formulation.scaling`):
forces O(1) per block, lengths O(1) for the structure, so absolute and relative
tolerances mean the same on 30 and 3000 blocks.
"""
from __future__ import annotations

# ============================================================================== HiGHS
#: Feasibility tolerances (primal and dual) of every LP whose alpha is reported or
#: certified. HiGHS's default 1e-7 moves alpha by ~2e-6 on a 200-block wall (measured);
#: at 1e-9 simplex and IPM agree to 1e-10.
LP_TOLERANCE = 1e-9
#: ... and of the cold interior-point start (then the warm simplex clean-up reaches
#: LP_TOLERANCE): at 1e-9 IPX's crossover is "imprecise" on large models (2040 blocks: dual
#: infeasibility 6e-6) and HiGHS falls back to a dual simplex clean-up of 44,000 iterations
#: (150 s); from the 1e-7 crossover basis the warm primal simplex takes a few iterations.
IPM_TOLERANCE = 1e-7
#: LPs with more columns than this (the search's and the published methods' alike) start
#: cold with the interior point method plus crossover: a cold simplex start on a large,
#: degenerate statics LP takes minutes (820-block wall: 104 s against 7.5 s).
IPM_COLUMNS = 1500
#: LPs with at most this many columns run in the calling thread: every solve takes
#: milliseconds and HiGHS's interrupt callback suffices, where a thread costs ~1 ms a solve.
INLINE_COLUMNS = IPM_COLUMNS
#: While HiGHS runs in a worker thread the caller checks the deadline this often (s): a stop
#: takes effect within a slice even where HiGHS calls no interrupt callback (crossover).
WAIT_SLICE = 0.05
#: At interpreter exit, wait at most this long (s) for abandoned HiGHS solves to end.
ABANDONED_EXIT_WAIT = 5.0
#: A primal recomputed from the final basis (HighsLP.exact_x) is kept only if its basic
#: equality rows and its bounds hold to this, relative to its largest entry: round-off margin.
BASIS_TOLERANCE = 1e-9
#: Cap of a statics LP that may be hard (certification, hold and the first gap step of a
#: perturbation): this many simplex iterations a row of the statics. Warm solves mostly take a
#: few iterations, the hardest of the 255- and 510-block running-bond walls up to 1.9 a row.
#: Counted, not timed: a seed gives the same answer on any machine and with any workers.
CERTIFY_CAP_ROWS = 2.0
#: A capped solve also stops after CAP_BACKSTOP times the time its cap takes at the LP's
#: mean warm speed (measured over CAP_BACKSTOP_SAMPLE iterations; CAP_BACKSTOP_MIN s at
#: least): HiGHS's dual simplex on near-singular bases once took 25 s for 241 iterations
#: where 6,000 take 4 s (1020 blocks). Only such a pathological solve meets it. Before the
#: sample: CAP_BACKSTOP times the LP's longest cold solve (CAP_BACKSTOP_MIN s at least); a
#: fixed 4 s cut every certification of the chain from zero cohesion on a 2,040-block wall
#: (cold solve 16 s, 2,200-3,600 of its 12,240 iterations) and, cut solves being left out
#: of the sample, went on cutting them.
CAP_BACKSTOP, CAP_BACKSTOP_MIN, CAP_BACKSTOP_SAMPLE = 2.0, 2.0, 200

# ===================================================================== gap alternation
#: rho ladders of the gap step min alpha + rho (alpha_K - alpha): the main one (wall33 and
#: wall55 reach Table 1 from it), the low one tried when the main one certifies nothing, and
#: the one that goes on from where a ladder stalled (the gap, and the flows on slack rows,
#: shrink with rho: 2040 blocks).
RHO_MAIN = (1e3, 1e4)
RHO_LOW = (2.0, 10.0, 100.0, 1e3)
RHO_HIGH = (1e5, 1e6, 1e7)
#: The continuation starts: the penalty raised from a low rho, so that the statics can first
#: move far from the associative state's mechanism. Measured at 1020 blocks: the main ladder
#: certifies 0.445755; these stall near 0.4448 and, pushed on with RHO_HIGH, certify
#: 0.444911-0.444968 about half of the time (the degenerate LPs' vertices depend on their warm
#: bases), hence two ladders. They run side by side, one a lane (Starts.continuations), each
#: from the state after the first phase with half the work left.
RHO_CONTS = ((10.0, 100.0, 1e3, 1e4), (30.0, 300.0, 1e3, 1e4))
#: A mechanism whose gap is below GAP_CERTIFY * max(1, alpha) is worth a certification LP.
GAP_CERTIFY = 1e-6
#: Below this gap (times max(1, alpha)) a mechanism flowing on slack rows triggers a hold
#: step: near convergence the least-alpha_K mechanism flows 1e-8..3e-7 of its largest flow on
#: a few slack rows (1020 blocks) and the gap step stalls at a gap ~1e-8.
GAP_HOLD = 1e-6
#: Below this gap (times max(1, alpha)) a mechanism step forbids flow on slack rows (2040
#: blocks: flows ~3e-7 of the largest on heavily compressed rows held the gap near 4e-8).
GAP_FORBID = 1e-6
#: The alternation stops a rho when alpha + rho gap falls by less than this (relative):
#: round-off margin.
STALL = 1e-9
#: Flows below this fraction of the largest are zero (they cost compatibility <= this).
FLOW_TOL = 1e-9
#: A stalled mechanism whose flows on slack rows are all below this fraction of its largest
#: is certified without them (1020 blocks: 4e-8..6e-8, gap 4e-9, and no statics holds them);
#: its compatibility then errs by about that much, within RESIDUAL_TOLERANCE (the residual
#: check decides).
NEAR_FLOW = 1e-7

# =================================================================== which rows are held
#: Relative thresholds on slack that call a yield row active (it may flow), tightest first.
#: The certification of an Ipopt point tries all of them; the search's own near-active
#: certifications try SEARCH_ACTIVE of them (1e-4 left out: the search's ladder was measured
#: without it), descents the first two.
ACTIVE_TOLERANCES = (1e-9, 1e-7, 1e-5, 1e-4, 1e-3)
SEARCH_ACTIVE = tuple(t for t in ACTIVE_TOLERANCES if t != 1e-4)
#: A gap step with flow on slack rows forbidden lets flow only where the slack is below this
#: (relative): the loosest of the ladder.
FORBID_ACTIVE = ACTIVE_TOLERANCES[-1]
#: Pressure step: how many of the most pushing held rows are released one by one, then how
#: many of the top ones together.
PRESSURE_SINGLE, PRESSURE_GROUPS = 8, (2, 4, 8)
#: Caps on steps (safety bounds, not tuned: every run measured so far ends on its own stall
#: rule first): mechanism/gap steps per rho, descent steps from a certified state.
ALTERNATION_MAX_STEPS, DESCENT_MAX_STEPS = 200, 30
#: A held lambda "pushes" when its reduced cost is below -PUSH: round-off margin.
PUSH = 1e-12

# ====================================================== what counts as better, or stable
#: A certified alpha is a new best only below best - IMPROVEMENT * max(1, |alpha|);
#: the hold step, too, must lower alpha by this much: round-off margin.
IMPROVEMENT = 1e-12
#: A descent step (and the GA's stopping rule) must lower alpha by this much (relative to
#: max(1, alpha)): round-off margin, above IMPROVEMENT so that a descent does not loop on
#: states that differ by round-off.
DESCENT_STEP = 1e-10
#: A ladder "stalled below the best" when its statics' alpha is below the best certified
#: one by this (relative): then it goes on (RHO_HIGH, near-active certification).
BELOW_BEST = 1e-9
#: Stable under dead load: min alpha over S is at most this (non-dimensional): round-off.
STABLE_ALPHA = 1e-9
#: The fallback where the gap alternation stalls without a certificate (search/gap/
#: fallback.py): the seed's fixed-point chain from the stall, at most FALLBACK_STEPS steps
#: without a certificate (measured at mu = 0.9: the 20 x 25 running-bond wall certifies at
#: step 15 from its stall, the 33-block panel at step 4), and once certified at most
#: FALLBACK_PATIENCE steps without improvement (the 33-block panel: 0.666030 at step 4,
#: 0.617364 at step 6, then a fixed point at 0.645963). benchmarks/families.py shows the
#: path that certified each case.
FALLBACK_STEPS, FALLBACK_PATIENCE = 60, 8
#: The dilatancy continuation (Starts.dilatancy): the fictitious systems whose sliding
#: dilates by t mu, from t = 1 (the associative system: its optimum is a collapse state)
#: down to the seed's t = 0, the gap alternation tracking the statics at each t, steps of
#: 0.1. Measured (4, 9 and 19 steps): wall55, a multi-leaf section at mu = 0.9 and running-
#: bond walls of 48-105 blocks at mu 0.9-1.0 end at the same alpha with each; the 510-block
#: running-bond wall at mu = 1.0 is certified at 0.568109 with 9 steps only (4 and 19 end
#: at t = 0 without a certificate), where every other start of the search certifies at
#: best 0.816327. The quick families keep every alpha; their LP solves grow by 6 % (10,610
#: to 11,232). Where the continuation stalls at t = 0 the seed's chain from the stall
#: follows (FALLBACK_STEPS, FALLBACK_PATIENCE): alone from the associative statics the
#: continuation stalls on the 10 x 10 and 12 x 6 running-bond walls at mu = 0.9, and the
#: chain certifies 0.587003 and 0.579043; on the 510-block wall at mu = 1.0, with the
#: search's LPs on other bases (the stability test run on a copy of them), it stalled and
#: the chain certified 0.558544 (the default run: 0.568109 from the continuation itself).
#: The quick families keep every alpha, path and LP count (11,232 LP solves), the
#: running-bond walls of 510 to 2,040 blocks that certify (mu 0.3-1.0) their alphas.
#: (Measured with the continuation starts one after the other; in the lanes of
#: Starts.continuations the 510-block wall at mu = 1.0 gets 0.565153 from the chain from
#: zero cohesion, warm from the first ladder's end, and 0.564967 from the GA.)
DILATANCY_STEPS = (0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3, 0.2, 0.1)
#: Mechanism/gap steps a rho at each t of the continuation (a path to follow, not an
#: optimum to reach): in space a t took up to 65 steps of about 2 s on the Armadillo vault
#: without a cap, where alpha moved by 1e-6 a step; the planar walls take 5-13 (their
#: alphas are the same with this cap).
DILATANCY_TRACK = 10
#: The seed's fixed-point chain has converged when the cohesions repeat to these (relative,
#: absolute) tolerances: round-off margins.
CHAIN_RTOL, CHAIN_ATOL = 1e-9, 1e-12
#: Where the seed's chain cycles, or has certified nothing after FALLBACK_PATIENCE steps,
#: it goes on averaged, c <- (1 - w) c + w c_new (a Krasnoselskii-Mann step): on a dome of
#: 3 rings of 12 voussoirs the unrelaxed chain oscillates (alpha_K 0.488-0.505, steps of
#: 10-30 % of c for 60 steps) and nothing certifies; averaged with w = 0.2 from step 8 the
#: chain from zero cohesion certified 0.500013 and the search 0.499882, its certificates
#: turning the sliding directions (certify3d.align; the default run: 88.5 s of CPU, 1,964
#: solves, measured under load); without that turn the dome is not certified. The seed's
#: walls and the planar tests keep their alphas and LP counts. Anderson acceleration of the
#: chain (type II, memory 5 with full steps, memory 10 with half steps) does not converge
#: where averaging is needed: on the 1,020-block running-bond wall at mu = 0.9, from zero
#: cohesion, the fixed-point residual |c_new - c| stays at 0.25-0.40 of the largest
#: cohesion over 40-60 steps and no step certifies (the cohesive LP's optimal statics jump
#: between vertices of a degenerate LP: the chain's map is set-valued, not smooth). Choosing,
#: among the cohesive LP's optimal statics (alpha within 1e-7 of alpha_K), the one whose
#: normal forces give back the cohesions best (least sum |c + mu N|, a second LP each step,
#: warm) makes the chain converge on the smaller walls: the 20 x 25 running-bond wall at
#: mu = 0.9 (510 blocks) certifies from zero cohesion at step 6-11, 0.535211-0.535695 in
#: the end (the plain chain: residual 0.2 of the largest cohesion after 40 steps, 0.537132;
#: the default run 0.537148); but on the 1,020-block wall at mu 0.9 that LP takes
#: 11,000-39,000 simplex iterations a step, the residual is still 0.05 after 25 steps
#: (355 s; averaged with w = 0.5: 0.017 after 30 steps, 211 s; from the gap alternation's
#: stall, 20 steps in 466 s, alpha_K wandering 0.36-0.52) and nothing is certified; in
#: space (interior-point solutions: no vertex to choose) it leaves the dome of 3 x 12
#: voussoirs oscillating as before and the Armadillo's chain infeasible at its second
#: program. Not kept: it does not certify the walls the default run leaves uncertified.
CHAIN_RELAXATION = 0.2
#: A certified state must satisfy every condition of a collapse state to this relative
#: accuracy (lamodel.search.certify.residuals), in the scaled frame and in the user's. Two
#: orders above LP_TOLERANCE, so that states recomputed from an exact basis pass; a bound
#: on what the flows dropped by NEAR_FLOW may cost.
RESIDUAL_TOLERANCE = 1e-7
#: A block whose own load is below this fraction of the mean block load is *light*: its
#: equilibrium rows and its contacts' forces get scales of their own in the LPs
#: (formulation.scaling.light_scales). Without them HiGHS's tolerances, absolute on the
#: mean load, hold such a block to a fraction of its own load only: measured, a block with
#: 1e-10 of the largest load certified nothing, and one with 1e-12 (a 1e-3 m block on a
#: 1e3 m one) was refused. Every block of the instances and of the families benchmark
#: carries more than 0.5 of the mean, so they are solved exactly as without the scales.
LIGHT_BLOCK = 1e-3
#: A block smaller than this fraction of the structure's size is refused: its contacts and
#: centroid, computed in double precision among coordinates of the structure's size, are
#: off by about 1e-16 / (this ratio) of its own size. Measured (a block b x 4b beside one
#: of 1 x 0.5 on the ground, closed form 0.25): b = 1e-10 certified 0.25000004, 1e-12
#: 0.250044, 1e-15 0.194 (its contact with the ground clipped); 1e-8 keeps that error
#: near 1e-8, below the residual test's 1e-7.
SIZE_RESOLUTION = 1e-8

# ================================================================= the GA and the driver
#: GA genes: log-perturbations of the cohesions, within +-Z_MAX; the initial population's
#: spreads cycle through Z_INIT (small, medium and large perturbations).
Z_MAX, Z_INIT = 3.0, (0.1, 0.3, 1.0)
#: GA stopping rule: a population's worth of evaluations (measured: fewer missed a half
#: block sliding out alone on a tied wall), and this many times the LP solves of the first
#: certificate, without improvement.
STALL_WORK = 3.0
#: Without a time limit the whole search stops at this many times the LP solves of its first
#: phase (first certificate and stability; counted, not timed: the work is bounded by what
#: the structure's first certificate costs, so a default run's time grows like that
#: certificate's; a time limit is the user's cap instead). Measured (benchmarks/families.py
#: --quick, with and without the bound): all 37 cases reach their best within 4.75 times
#: (median 0.2-1.3 per family) and end with the same alpha under this bound as without it;
#: the 1020-block running-bond wall (mu 0.65) reaches 0.444923 at 8.2 times (424 LPs, a
#: continuation start) and its GA 0.444912 only at 22.8 times; with 10 times (520 LPs) its
#: default run took 71 s, whole process (66.7 s of CPU, on a machine shared with others).
#: With the continuation lanes side by side (Starts.continuations): the quick families
#: reach their best within 9.93 times (the 10 x 10 wall at mu = 0.9, its GA) and every alpha
#: is the same at 30 times (11,141 and 15,379 LP solves in all); the 1020-block wall
#: (mu 0.65) ends with 0.444967 after 457 LPs, 53.7-54.7 s whole process (93 s of CPU).
TOTAL_WORK = 10.0
#: ... and at WORK_PER_BLOCK times the number of blocks of LP work (simplex and interior-point
#: iterations times the LP's rows, :attr:`lamodel.search.highs.HighsLP.work`: counted, and
#: about proportional to time: 1.4e-7 to 1.6e-7 CPU seconds a unit measured on the 1020- and
#: 2040-block running-bond walls), about a minute per thousand blocks; the continuations and
#: the chain from zero cohesion end between two LP solves once it is spent, the first
#: certificate at FIRST_WORK times it (below). Measured (benchmarks/families.py --quick):
#: no case reaches a quarter of it (work/bound at most 0.226; 0.185 with the dilatancy continuation
#: run after the chains instead of beside them), every alpha as without it.
#: 1020 blocks (mu 0.65): the whole run 4.0e8 units (bound 4.08e8), its best 0.444923 at
#: 3.6e8, as without it.
#: 510 blocks (20 x 25, mu 0.9): the bound ends the search right after its first phase (427
#: LPs), 0.538064 in 27 s of CPU; without it 0.536905 (the GA, at LP 3269) in 221 s. 2040
#: blocks (mu 0.65): the first phase alone is 7.2e8 units (118,000 iterations of 6120 rows,
#: 100 s of CPU); the search ends after 97 LPs (142 s of CPU) with 0.419543, where the
#: continuation starts alone ran 470+ LPs of 2-10 s each before.
WORK_PER_BLOCK = 4.0e5
#: Without a time limit the first certificate (the alternation, then its two fallback lanes:
#: the rescue and the chains, the dilatancy continuation) ends at FIRST_WORK times that work
#: bound (in space, the cone programs' bound below), each lane with what the alternation
#: left of it. Measured: the 1,020-block running-bond walls at mu 0.9 and 1.0 get theirs
#: from the chain from zero cohesion at 3.7 and 4.0 times it, the 2,040-block wall at mu 0.9
#: from the dilatancy continuation at 4.7 times (its lane's own work 4.3), at mu 0.65 at 0.9
#: times, every case of benchmarks/families.py --quick below 0.2 times; twice the most
#: measured when it was set (4.0). Without it a structure no start
#: certifies runs every chain and the continuation to their ends: on the 2,040-block wall at
#: mu 0.9 the chain from zero cohesion took 124 LP solves in 700 s, another 60 steps 600 s,
#: the dilatancy continuation 750 s, none certified.
FIRST_WORK = 8.0
#: BLAS threads while the search runs (numpy's dot products of its LP-sized vectors; HiGHS
#: and Clarabel do not use BLAS). OpenBLAS splits a dot product of more than 10,000 entries
#: over its threads, which then spin for a while after it (measured: a core kept busy
#: through 5 ms pauses between products of 10,001 entries, idle at 9,000), and the search
#: makes one every few LP solves: on the 1,020-block running-bond wall (mu 0.65, 11,825
#: columns) the default run took 96.9-97.4 s of CPU with two BLAS threads and 77.9-80.2 s
#: with one, whole process 74.2-74.9 s against 72.4-73.9 s (same alpha, same LPs); on a
#: machine of many cores every thread spins. One thread also leaves the second core to the
#: lower bound beside the search, and makes those sums (OpenBLAS splits them over as many
#: threads as the machine has, each split rounding its own way) the same on any machine.
BLAS_THREADS = 1
#: While waiting for a parallel evaluation the search checks its deadline this often (s).
EVALUATION_SLICE = 0.1
#: Ipopt starts when --starts is not given.
DEFAULT_STARTS = 2
#: Without a time limit and without --starts, a start runs only if estimated to take at
#: most this many seconds (the default run stays fast; ask with --starts for more).
POLISH_SECONDS = 1.0
#: With a time limit, the Ipopt starts may have at most this share of it (a start estimated
#: to take longer is skipped); the search runs in the rest.
POLISH_SHARE = 0.5
#: The GA's fitness of a genome that certifies nothing: this plus the best alpha (worse than
#: any certified state; alpha is a multiplier of order 1).
NO_CERTIFICATE = 10.0

# ==================================================================== Ipopt on eq. (5)
#: The epsilon ladder of the relaxed bilinear condition 0 <= alpha_K - alpha <= epsilon, as
#: fractions of max(1, alpha); the last stage is eq. (5) exactly.
EPSILON_LADDER = (1e-3, 1e-5, 0.0)
#: Ipopt options for the warm-started ladder (its start points are nearly feasible).
IPOPT_OPTIONS = {"tol": 1e-8, "acceptable_tol": 1e-6, "constr_viol_tol": 1e-9, "mu_init": 1e-6,
                 "bound_push": 1e-8, "bound_frac": 1e-8, "max_iter": 150, "mumps_pivot_order": 0,
                 # Ipopt relaxes bounds by 1e-8 by default: a tension N = +1e-8 on an open joint
                 # times xi at its bound makes a fake, lower alpha_K (measured on wall55: 4.5e-5).
                 "bound_relax_factor": 0.0}
#: ... and those of every warm-started stage after the first (the previous stage's point and
#: multipliers pushed into the bounds no further than this).
IPOPT_WARM_OPTIONS = {"warm_start_init_point": "yes", "warm_start_bound_push": 1e-9,
                      "warm_start_mult_bound_push": 1e-9}
#: Estimated seconds of one Ipopt start: IPOPT_ITERATIONS iterations of IPOPT_SECONDS_1020
#: (nb / 1020)^IPOPT_GROWTH each (measured with Debian's Ipopt 3.11 and sequential MUMPS:
#: 12 ms at 55 blocks, 2.4 s at 1020).
IPOPT_ITERATIONS, IPOPT_SECONDS_1020, IPOPT_GROWTH = 250, 2.4, 1.8

# ================================================== in space (search/gap/problem3d.py)
#: Least alpha over S at or below this (non-dimensional) counts as zero in space: an
#: interior-point answer of 0 is exact only to its tolerance (1e-8 measured on the
#: 816-block out-of-plane wall), where an LP vertex is exact (STABLE_ALPHA).
STABLE_ALPHA_CONE = 1e-6
#: Thresholds (fractions of the largest strain) above which a conic mechanism's point
#: counts as opening or sliding, tried in turn by a certificate: an interior-point answer
#: is exact to ~1e-8; the first is the flow pattern of a mechanism.
CONE_FLOW_TOLS = (1e-6, 1e-4, 1e-3, 1e-2)
#: Up to this many contact points the exact LP on fixed cones is tried first, then the held
#: cone program's own statics; beyond, the other way round (the LP's cold solve grows
#: fastest: 2-4 s at 2,900 points, measured under load).
CONE_LP_FIRST_POINTS = 1500
#: Sliding directions of a certificate's key are compared to this many decimals: conic
#: slips differ by their tolerance (~1e-8) from solve to solve for one mechanism.
CONE_DIRECTION_DECIMALS = 6
#: Successive cone programming (Portioli et al.; Wang & Beyer): the friction capacities
#: c = -mu N of the previous normal forces, relaxed by this, at most this many programs.
SUCCESSIVE_CONE_RELAXATION, SUCCESSIVE_CONE_STEPS = 0.5, 10
#: In space a row counts as held (``ConeProblem.active_rows``) within this fraction of the
#: statics' largest entry whatever tighter tolerance is asked: an interior-point statics
#: holds its active rows to ~1e-8 only. Measured (816-block out-of-plane wall): at 1e-9 the
#: alternation saw 52 rows flowing "on slack" at gap 2e-8, its hold step took alpha from
#: 0.017857 to 0 and the first certificate came after 16 programs (43 s) instead of 3.
CONE_ACTIVE = 1e-6
#: In space, the same bound on the cone programs' work, counted as Clarabel's iterations
#: times rows^1.5 (:attr:`lamodel.search.cone.ConePrograms.work`): with rows alone a unit
#: cost 1.1e-6 CPU s at 33-111 blocks and 4.1e-6 at 816 (the factorisations fill in); with
#: rows^1.5 it costs 1.7e-8 to 3.6e-8 from 33 to 816 blocks (the facade, the extruded
#: wall33 and wall55, the 816-block out-of-plane wall). WORK_PER_BLOCK_CONE is about a
#: minute per thousand blocks at 1.7e-8 s a unit, as in the plane; a cone program costs
#: far more than an LP, so small structures get at least WORK_FLOOR_CONE (about 10 s):
#: with no bound the extruded wall55 reaches its 0.557416 after 2.4e8 units (8.7 s) and
#: the facade its 0.108696 after 4.8e8 (8.4 s); the 816-block wall's first certificate (its
#: best, 0.017857) comes after 10 s and without the bound its run took 134 cone programs,
#: 278 s of CPU (lamodel.search.driver.solve on instances/facade.json and the cases of
#: benchmarks/solve3d.py).
WORK_PER_BLOCK_CONE, WORK_FLOOR_CONE = 3.5e6, 6.0e8
#: The alignment of a conic mechanism's sliding directions (certify3d.align), tried by
#: ConeProblem.certificates only where no held statics certified the first flow pattern of
#: a mechanism whose cohesions are known, once a pattern (a pure evaluation forgets which):
#: its first LP starts by the interior point method, at most ALIGN_IPM_CAP iterations, each
#: next one from the last one's basis, at most ALIGN_CAP_ROWS simplex iterations a row; its
#: work counts in the search's (certify3d.lp_work). Measured on the extruded wall33: first
#: LPs (1,250-1,650 columns, 1,900-6,100 rows) that HiGHS's dual simplex took up to 254 s
#: of CPU on (a "solve error" after wandering) the interior point method finds infeasible in
#: 9-21 iterations (0.04-0.13 s); an aligned pattern takes 3-5 LPs, its warm ones at most
#: 0.10 simplex iterations a row (the domes of 4 x 6 and 3 x 12). The rule, measured on the
#: default runs of benchmarks/solve3d.py (under load): calls / aligned / LPs / solves in all
#: wall33 11/0/11/152 (141 without), wall55 8/0/8/160 (152), vault 1/0/1/122 (121), facade
#: 1/0/1/149 (148), dome3x8 29/0/29/1255 (1226), every alpha unchanged; dome3x6 82/44/233/
#: 2771 (3400; 0.459717, was 0.465441), dome4x6 28/22/99/2226 (certified, none certified
#: without), dome3x12 0.499882 (none without). A gate on how far the cohesive statics' normal
#: forces are from giving back the cohesions (the chain's fixed-point residual at the sliding
#: points) does not separate: patterns aligned at 0.009-0.26 of the largest cohesion, ones
#: with no statics from 0.022 up; a failed call costs one capped LP.
ALIGN_IPM_CAP = 50
ALIGN_CAP_ROWS = 2.0


# ============================================================================ materials
#: Facets a half of a crushing joint's N-M domain (lamodel.formulation.joints), m on the
#: sin^2 grid: the inscribed polygon's moment capacity is at least 1 - sin^2(pi / (2 m))
#: of the stress block's at every N, 0.96% at 16 (0.24% at 32), below the scatter of a
#: masonry strength. Alone, the grid kept that 0.96% at small N / N_c whatever f_c (its
#: first chord): with f_c = 1e9 the arch, the portal and wall33 came out 0.7% low
#: (0.245837 for 0.247538, 0.637335 for 0.638982), and its blunt tip lets an open joint
#: overlap at no cost. Below the grid's first vertex a fan of vertices goes down by
#: CRUSHING_FAN_RATIO to CRUSHING_FLOOR: the loss at fraction x is then at most
#: max((r - 1)^2 / (4 r) x / (1 - x), x_1), x_1 the smallest vertex fraction (1.5e-7
#: here): f_c -> inf gives eq. (4) back. Measured (benchmarks/materials.py, f_c = 1e9 on wall33 and wall55,
#: f_c = 4 on wall55): a fan by 4 to 1e-7 (9 facets) gave 0.638982 and 0.557416 but
#: certified nothing at f_c = 4, in the default work bound or in 120 s (the search came
#: within a gap of 1e-9 of a state whose mechanism also flowed on facets of the fan, nearly
#: parallel, that the statics could not hold); by 4 to 1e-4 (3 facets) 0.639927, 0.562852
#: (the tip still blunt) and 0.341784; by 16 to 1e-7 (4 facets) 0.638982, 0.557416 and
#: 0.343088. Each facet is a row of the statics and of the fictitious LP: 2 + 2 (16 + 4) =
#: 42 rows a contact against 4.
CRUSHING_FACETS = 16
CRUSHING_FLOOR = 1e-7
CRUSHING_FAN_RATIO = 16.0
