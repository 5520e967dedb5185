"""Every tuned constant and tolerance of the search and of the lower bound, in one place:
each with why in at most three lines, its measurements in docs/method/evidence.md under its
name. "Round-off margin": a tolerance no measurement chose (see that page)."""
from __future__ import annotations

# ============================================================================== HiGHS
#: Feasibility tolerances (primal and dual) of every LP whose alpha is reported or
#: certified (the search's and the certifications', in the plane and in space): HiGHS's
#: default 1e-7 moves alpha by ~2e-6 on a 200-block wall.
LP_TOLERANCE = 1e-9
#: ... and of the cold interior-point start (then the warm simplex clean-up reaches
#: LP_TOLERANCE): at 1e-9 IPX's crossover is "imprecise" on large models and the dual
#: simplex clean-up takes minutes.
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
#: perturbation): this many simplex iterations a row of the statics. Counted, not timed: a
#: seed gives the same answer on any machine and with any workers.
CERTIFY_CAP_ROWS = 2.0
#: A capped solve also stops after CAP_BACKSTOP times the time its cap takes at the LP's
#: mean warm speed over CAP_BACKSTOP_SAMPLE iterations (before the sample: its longest cold
#: solve), CAP_BACKSTOP_MIN s at least: only a pathological solve meets it.
CAP_BACKSTOP, CAP_BACKSTOP_MIN, CAP_BACKSTOP_SAMPLE = 2.0, 2.0, 200

# ===================================================================== gap alternation
#: rho ladders of the gap step min alpha + rho (alpha_K - alpha): the main one, the low one
#: tried when the main one certifies nothing, and the one that goes on from where a ladder
#: stalled (the gap, and the flows on slack rows, shrink with rho).
RHO_MAIN = (1e3, 1e4)
RHO_LOW = (2.0, 10.0, 100.0, 1e3)
RHO_HIGH = (1e5, 1e6, 1e7)
#: The continuation starts: the penalty raised from a low rho, so that the statics can first
#: move far from the associative state's mechanism; two ladders, side by side, because each
#: certifies a lower alpha only about half of the time.
RHO_CONTS = ((10.0, 100.0, 1e3, 1e4), (30.0, 300.0, 1e3, 1e4))
#: The slow continuation's ladder: rho doubled from 1 to 256, then 1e3, 1e4 (the MPEC's
#: relaxation sequence in the penalty's terms: the statics follows one family of mechanisms
#: down where the quick ladders jump past it).
RHO_SLOW = tuple(2.0 ** k for k in range(9)) + (1e3, 1e4)
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
#: Flows (in space: strains) below this fraction of the largest are zero (they cost
#: compatibility <= this).
FLOW_TOL = 1e-9
#: A stalled mechanism whose flows on slack rows are all below this fraction of its largest
#: is certified without them; its compatibility then errs by about that much, within
#: RESIDUAL_TOLERANCE (the residual check decides).
NEAR_FLOW = 1e-7

# =================================================================== which rows are held
#: Relative thresholds on slack that call a yield row active (it may flow), tightest first:
#: the certification of an Ipopt point tries all, the search's near-active certifications
#: SEARCH_ACTIVE (measured without 1e-4), descents the first two.
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
#: The fixed-point fallback where the gap alternation stalls without a certificate
#: (search/gap/chains.py: FixedPoint): at most FALLBACK_STEPS steps a chain without a certificate,
#: and once certified at most FALLBACK_PATIENCE steps without improvement.
FALLBACK_STEPS, FALLBACK_PATIENCE = 60, 8
#: The dilatancy continuation (search/gap/dilatancy.py): the fictitious systems whose sliding
#: dilates by t mu, from t = 1 (the associative system) down to the seed's t = 0, the gap
#: alternation tracking the statics at each t; 9 steps certified a wall 4 and 19 did not.
DILATANCY_STEPS = (0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3, 0.2, 0.1)
#: Mechanism/gap steps a rho at each t of the continuation (a path to follow, not an
#: optimum to reach): without a cap a t can take tens of slow steps that move alpha by
#: 1e-6 each.
DILATANCY_TRACK = 10
#: The seed's fixed-point chain has converged when the cohesions repeat to these (relative,
#: absolute) tolerances: round-off margins.
CHAIN_RTOL, CHAIN_ATOL = 1e-9, 1e-12
#: Where the seed's chain cycles, or has certified nothing after FALLBACK_PATIENCE steps,
#: it goes on averaged, c <- (1 - w) c + w c_new (a Krasnoselskii-Mann step, w this):
#: the unrelaxed chain oscillates on domes; acceleration and vertex choices did not help.
CHAIN_RELAXATION = 0.2
#: A certified state satisfies every condition of a collapse state to this relative accuracy
#: (certify.residuals, certify3d.residuals), scaled and in the user's units: two orders above
#: LP_TOLERANCE, and a bound on what the flows dropped by NEAR_FLOW may cost.
RESIDUAL_TOLERANCE = 1e-7
#: A block whose own load is below this fraction of the mean block load is *light*: its
#: equilibrium rows and its contacts' forces get scales of their own in the LPs
#: (formulation.scaling.light_scales), else HiGHS's absolute tolerances lose it.
LIGHT_BLOCK = 1e-3
#: A block smaller than this fraction of the structure's size is refused: its contacts and
#: centroid, computed in double precision among coordinates of the structure's size, are
#: off by about 1e-16 / (this ratio) of its own size.
SIZE_RESOLUTION = 1e-8

# ============================================ the canonical order (search/canonical.py)
#: Centroids, vertices and joint positions equal within this fraction of the structure's
#: size (loads: of the largest load) compare equal when the blocks and contacts are put in
#: their canonical order: far above round-off of written coordinates, far below any joint.
CANONICAL_TOLERANCE = 1e-6

# ================================================================= the GA and the driver
#: GA genes: log-perturbations of the cohesions, within +-Z_MAX; the initial population's
#: spreads cycle through Z_INIT (small, medium and large perturbations).
Z_MAX, Z_INIT = 3.0, (0.1, 0.3, 1.0)
#: GA stopping rule: a population's worth of evaluations (measured: fewer missed a half
#: block sliding out alone on a tied wall), and this many times the LP solves of the first
#: certificate, without improvement.
STALL_WORK = 3.0
#: Without a time limit the whole search stops at this many times the LP solves of its first
#: phase (first certificate and stability): counted, not timed, so a default run's work grows
#: like its first certificate's; a time limit is the user's cap instead.
TOTAL_WORK = 10.0
#: ... and at WORK_PER_BLOCK times the number of blocks of LP work (iterations times rows,
#: HighsLP.work: counted, about proportional to time), about a minute per thousand blocks;
#: the first certificate at FIRST_WORK times it.
WORK_PER_BLOCK = 4.0e5
#: Without a time limit the first certificate (the alternation, then its fallback lanes)
#: ends at FIRST_WORK times that work bound (in space, the cone programs' bound below), each
#: lane with what the alternation left of it: twice the most measured when it was set.
FIRST_WORK = 8.0
#: A study's variant whose search certified nothing is solved again from the other variants'
#: mechanisms with the work bounds times this: on the three-span bridge (docs/bridges.md) twice
#: the bounds alone certified a position the default left, and the second try 2 of 3 stalled.
RETRY_WORK = 2.0
#: A study's variant takes its mirror image's state (lamodel.mirror) when that state's alpha
#: is lower than its own by more than this (relative): the digits tables print.
MIRROR_GAIN = 1e-6
#: Once the first certificate's main lane (plan.IF_STALLED) certifies, the lane beside it
#: may spend this many times the LP work the main lane took: at 4 the dilatancy lane's lower
#: state of a 510-block wall (mu 0.9) was lost.
SIDE_LANE_SHARE = 8.0
#: BLAS threads while the search runs (numpy's dot products of its LP-sized vectors): more
#: threads spin between products and cost CPU but save no time, and one thread makes those sums
#: the same on any machine.
BLAS_THREADS = 1
#: Threads of HiGHS's task scheduler (one per process, made by its first solve): the search's
#: LPs are serial simplex solves, and the scheduler's idle threads spin between them, taking
#: a core from the search beside it (side by side, a fifth of the CPU time for nothing).
HIGHS_THREADS = 1
#: While waiting for a parallel evaluation the search checks its deadline this often (s).
EVALUATION_SLICE = 0.1
#: Contexts (one structure's prepared data) a worker process keeps: a few structures at a time.
CONTEXTS_KEPT = 4
#: Seconds a Dask scheduler has to answer a TCP connection before --scheduler is refused.
SCHEDULER_TIMEOUT = 3.0
#: Seconds between two redraws of the progress line (a display rate, nothing depends on it).
PROGRESS_REFRESH = 0.5
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
#: Clarabel's tolerances on the non-dimensional problem (its default is 1e-8), and its
#: tolerance on the ratio kappa / tau that decides infeasibility.
CONE_TOLERANCE, CONE_KTRATIO = 1e-9, 1e-8
#: How many recent mechanisms keep the cohesions they are least-alpha_K for (a certificate
#: polishes to that optimum).
MECHANISMS_REMEMBERED = 16
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
#: ... converged where the capacities reproduce themselves to SUCCESSIVE_CONE_C_TOL of the
#: largest, or alpha moves by less than SUCCESSIVE_CONE_ALPHA_TOL (times max(1, alpha)).
SUCCESSIVE_CONE_C_TOL, SUCCESSIVE_CONE_ALPHA_TOL = 1e-7, 1e-8
#: In space a row counts as held (``ConeProblem.active_rows``) within this fraction of the
#: statics' largest entry whatever tighter tolerance is asked: an interior-point statics
#: holds its active rows to ~1e-8 only.
CONE_ACTIVE = 1e-6
#: In space, the same bound on the cone programs' work (Clarabel's iterations times
#: rows^1.5, ConePrograms.work: about a minute per thousand blocks), at least
#: WORK_FLOOR_CONE (about 10 s: a cone program costs far more than an LP).
WORK_PER_BLOCK_CONE, WORK_FLOOR_CONE = 3.5e6, 6.0e8
#: The alignment of a conic mechanism's sliding directions (certify3d.align): its first LP by
#: the interior point method, at most ALIGN_IPM_CAP iterations, each next one warm, at most
#: ALIGN_CAP_ROWS simplex iterations a row (a cold dual simplex can wander for minutes).
ALIGN_IPM_CAP = 50
ALIGN_CAP_ROWS = 2.0

# ============================================== certification in space (search/certify3d.py)
#: Facets of the pyramid inscribed in a stuck point's cone in the certification LP.
PYRAMID_FACETS = 4
#: Half-angle (rad) of the fan a sliding point's force (and slip) may take about its
#: direction in the certification LPs, and the cost of leaving the fan's centre.
FAN, FAN_COST = 1e-7, 1e-7
#: Forces within this of zero (or of the cone) count as such when a mechanism is fitted.
CONTACT_TOL = 1e-9
#: Largest number of block motions (6 a moving block) on which a mechanism is polished.
MECHANISM_POLISH_COLUMNS = 900
#: Facets of the pyramid inscribed in a stuck point's cone in :func:`certify3d.align`, its
#: steps, the largest turn (rad) of a sliding direction in one step, and the turn below which
#: it stops.
ALIGN_FACETS, ALIGN_STEPS, ALIGN_TURN, ALIGN_DONE = 16, 8, 1e-2, 1e-13
#: Coefficients of the alignment LP below this are round-off (the problem is non-dimensional).
ALIGN_ROUND_OFF = 1e-15
#: Iterative refinements of a mechanism's projection (certify3d.project_mechanism), and
#: Newton steps of its polish (certify3d.polish_mechanism): safety bounds.
PROJECTION_REFINEMENTS, POLISH_NEWTON_STEPS = 4, 40

# ======================================== the published methods (search/published/)
#: Their lane in the default run (plan.PUBLISHED, after the GA) may spend this many times the
#: search's LP work so far (its LPs have 4 rows a contact more than the search's; the 50-stone
#: wall where it gives the best needs 3.5, less gives nothing there: benchmarks/lanes.py).
PUBLISHED_SHARE = 4.0
#: The slow continuation (plan.SLOW, after the published methods) may spend this many times
#: the LP work so far (at most times the whole-search bound), beyond that bound: its ladder
#: ends by itself in 40-80 LP solves (docs/method/evidence.md, "The slow continuation").
SLOW_SHARE = 0.1
#: ... on structures of at most this many blocks: it lowered alpha on walls of 80 to 135 blocks, on
#: none of 160 to 320 and by 5e-7 on 1 of 23 of 500-520, and took up to a tenth of a large wall's run.
SLOW_BLOCKS = 300
#: The MPEC (plan.MPEC, last) runs on structures of at most this many blocks, each of its
#: NLPs at most MPEC_LANE_ITERATIONS Ipopt iterations: an iteration costs about as many
#: seconds as 2.4 (blocks / 1020)^1.8 (docs/method/evidence.md, "The MPEC's lane").
MPEC_LANE_BLOCKS, MPEC_LANE_ITERATIONS = 150, 60
#: Its LPs (the start's mechanism, the certification and descent of its answer) may spend
#: this many times the search's LP work so far (at most times the whole-search bound).
MPEC_SHARE = 1.0
#: successive LP: stop when max |N_k - N_{k-1}| <= this fraction of the largest block load
SLP_TOLERANCE = 1e-8
#: successive LP: at most this many LPs after the associative one
SLP_MAX_ITERATIONS = 300
#: successive LP (Gilbert et al. 2006, parameters as in Wang & Beyer's implementation): the
#: negative fictitious friction -a mu, a = SLP_ALPHA0 at the first LP, times SLP_ALPHA_FACTOR
#: at each next one, down to SLP_ALPHA_MIN
SLP_ALPHA0, SLP_ALPHA_FACTOR, SLP_ALPHA_MIN = 0.3, 0.5, 1e-3
#: successive LP: the normal forces carried over are SLP_BETA N_k + (1 - SLP_BETA) N_{k-1}
SLP_BETA = 0.6
#: successive LP: the small cohesion c0, a fraction of the largest |N| of the associative LP
SLP_COHESION = 1e-5
#: MPEC: the relaxation rho (as a fraction of max(1, alpha)), divided by 10 from stage to
#: stage as Ferris & Tin-Loi do, then 0 (eq. 5 exactly)
MPEC_LADDER = (1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 0.0)
#: seed: default GA budget (population, generations); each individual is one Ipopt solve
SEED_POP_SIZE, SEED_GENERATIONS = 4, 2
#: seed: the epsilon ladder of each individual's Ipopt solve of eq. (5) (fractions of
#: max(1, alpha); the last stage is eq. 5 exactly)
SEED_LADDER = (0.0,)
#: seed: an Ipopt point whose largest residual exceeds this is infeasible for eq. (5): its
#: fitness is penalised (the GA needs a number for every individual)
SEED_FEASIBILITY = 1e-5
#: seed: the GA's genes multiply the associative cohesions, within [0, SEED_GENE_MAX]; the
#: first population's are log-normal with this SEED_SPREAD about 1
SEED_GENE_MAX, SEED_SPREAD = 3.0, 0.3
#: the certification's own descent (certify.descend): at most this many LP pairs
CERTIFY_DESCENT_STEPS = 50

# ====================================================== the lower bound (lamodel/bound/)
#: alpha - alpha_lower <= PROVEN_TOL * max(1, alpha): a proven global minimum
PROVEN_TOL = 1e-6
#: lower_bound's seconds when none are given (the Python call; the command line's are
#: --prove's), and its alpha-splits: while b - a > (U - a_root) / ALPHA_SPLIT
BOUND_SECONDS, ALPHA_SPLIT = 10.0, 8
#: the relative shrink of the cohesions and half-lengths in the bound's cohesive LP (room
#: for the exact rebuild)
BOUND_MARGIN = 1e-9
#: The default bound, the root's rounds to their fixed point, is guarded by at most
#: LPS_PER_CONTACT LPs per contact (counted: the same on any machine) and BOUND_SHARE of the
#: search's own seconds, at least BOUND_FLOOR_SECONDS: a quarter of the search's cost at most.
LPS_PER_CONTACT, BOUND_FLOOR_SECONDS, BOUND_SHARE = 16, 2.0, 0.25
#: In space the root proves nothing (a block can rest on any three of its points), so the
#: default branches: at most LPS_PER_POINT LPs per contact point and MAX_LPS_3D in all, with
#: BOUND_SHARE of the search's seconds, at least BOUND_FLOOR_SECONDS_3D.
LPS_PER_POINT, MAX_LPS_3D, BOUND_FLOOR_SECONDS_3D = 32, 128, 1.0
#: a cohesion's flow below this fraction of the largest does not make it a candidate of a
#: round (the bound's own tolerance, not the search's FLOW_TOL)
CANDIDATE_FLOW = 1e-7
#: a round that raises a node's alpha by less than this (relative) ends the node's rounds
BOUND_ROUND_TOL = 1e-12
#: the screen (BranchAndBound._can_raise) runs before a round of more than SCREEN_MIN
#: Nmin LPs, at most SCREEN_LPS cohesive LPs; it calls a round useless only when the
#: cohesive LP at the screen's normal forces stays within SCREEN_TOL (relative to U) of a.
SCREEN_MIN, SCREEN_LPS, SCREEN_TOL = 4, 8, 1e-9
#: sides added to the polygon of the planar bound per call
BOUND_MAX_CUTS = 8
#: in space: sides of the circumscribed pyramid of the Coulomb cone in the Nmin LPs
BOUND_PYRAMID = 8
#: in space: directions of the inscribed zonotope of the cohesive disk (a 16-gon: within
#: 1.9 %), and the margin its radius stays below 1 by (room for the exact rebuild)
ZONES, ZONE_MARGIN = 8, 1e-7
#: Seconds past its time guard that the lower bound beside the search is waited for: its LPs
#: check the guard inside HiGHS (milliseconds), so only a thread that cannot end waits so long.
LATE_SECONDS = 5.0

# ======================================================= reading 3D inputs (io/joints3d.py)
#: Facets that meet within these multiples of the geometric tolerance, but not within it,
#: are near-joints, told in a warning with the least multiple that joins them (100 reaches
#: the joints of a file written in single precision).
NEAR_JOINT_FACTORS = (10.0, 100.0)
#: The "no block is a support" error counts the blocks whose lowest point is within this
#: fraction of the structure's size above the lowest one (a course of blocks on one level,
#: not one point; benchmarks/compas_samples.py takes the same level as supports).
SUPPORT_LEVEL = 1e-3
#: A point load may lie this fraction of its block's size off the block (beyond the geometric
#: tolerance), in the plane and in space: coordinates rounded to 4 digits pass; its moment moves by 0.1 %.
LOAD_POINT_SLACK = 1e-3
#: A Farkas mechanism of the dead load (search/unstable.py): blocks whose largest vertex
#: motion is below this fraction of the largest one are at rest (an interior-point answer
#: is exact to ~1e-8).
DEAD_LOAD_REST = 1e-6
#: The blocks no statics holds are gathered from at most this many dead-load mechanisms
#: (each a cone program, the previous ones' blocks held fixed). Measured on compas_cra's Armadillo
#: at tolerance 1e-6: 28 blocks from 14 mechanisms, 2.5 s; at 1e-5: 10 blocks.
DEAD_LOAD_ROUNDS = 20

# ============================================== single-block mechanisms (search/gap/single.py)
#: Blocks of least own multiplier tried as mechanisms of that block alone, and the sides of
#: the polygon inscribed in the cone that ranks them in space (a ranking, not a certificate).
SINGLE_BLOCKS, SINGLE_BLOCK_FACETS = 4, 8

# ============================================================================ materials
#: Facets a half of a crushing joint's N-M domain (formulation/joints.py) on the sin^2 grid,
#: and below its first vertex a fan stepping down by CRUSHING_FAN_RATIO to CRUSHING_FLOOR:
#: the inscribed polygon keeps >= 99.04% of the stress block's moment, eq. (4) as fc -> inf.
CRUSHING_FACETS = 16
CRUSHING_FLOOR = 1e-7
CRUSHING_FAN_RATIO = 16.0

#: A planar joint whose crushing force 2 d b f_c passes this many times the loads takes eq. 4's
#: rows (f_c infinite): the stress block's moment is within |N| / (2 d b f_c) of the cone's, below
#: round-off, where its polygon's facets of that size pass HiGHS's limits (f_c 1e18: 'Empty').
CRUSHING_FAR = 1e12
#: A tensile or cohesion force (in space also a crushing cap) beyond this many times the loads (dead
#: and live forces' sum) is infinite in the programs: never reached; rows of 1e20 failed Clarabel, and
#: of 1.5e9 times the loads HiGHS (a planar stack 'unstable'). States are checked against the real ones.
CAP_FAR = 1e6

# ------------------------------------------------------------- joints' strengths in space
#: The dry certificate (lamodel.search.gap.dry): a dry state is within the crushing caps when no
#: joint passes its cap by more than this share of its capacity (a dry hinge overshoots the stress
#: block by |N| / (2 d b f_c) of its moment: measured in docs/method/materials.md).
DRY_WITHIN_CAPS = 1e-6

# ===================================================================== bridges
#: Lead-axle positions of a bridge's load when its file gives none: evenly across the span,
#: springing to springing (lamodel.bridges.description).
BRIDGE_POSITIONS = 21
#: Samples per extrados chord where the dispersed surface load is integrated (midpoint
#: rule): the forces sum to the axle's to round-off, each chord's share to ~1/this.
BRIDGE_SAMPLES = 400
#: ... and over each abutment (beyond the springings, at one depth: that share only scales the
#: ring's) at most this many, the step widened past them: a deep fill or a wide spread would
#: otherwise sample out to it (fill depth 1e6: 5e8 samples). Typical bridges stay well below.
BRIDGE_SAMPLES_BEYOND = 200_000
#: Boussinesq's dispersal is sampled this many fill depths beyond the patch: past 10 depths
#: a strip's stress carries under 0.05 % of its load (left out; the rest is scaled up).
BOUSSINESQ_REACH = 10.0
#: A knife-edge load on a ring without fill is spread over this fraction of the span, so
#: that its pressure stays finite: round-off margin.
BRIDGE_KNIFE_EDGE = 1e-4
