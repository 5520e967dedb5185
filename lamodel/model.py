"""The algebraic model of the seed's eq. (5) in Pyomo.

    alpha_c = min alpha
        s in S            : equilibrium (eq. 1-2) and the Coulomb yield rows (eq. 4)
        (u, xi) in K      : compatibility with the flow rule of the fictitious cohesive system
                            (cohesion -mu N from the real normal forces), fbar^T u = 1
        alpha = alpha_K   : alpha_K = -u^T f0 - xi^T N_mu s_N (eq. 5)

Each group of constraints has its own ``declare_*`` function acting on a Pyomo block ``b``,
so the same components are built

* on an ``AbstractModel`` (:func:`create_abstract_model`), instantiated from a Pyomo .dat
  file with ``create_instance('instances/wall33.dat')``;
* on a ``ConcreteModel`` from a :class:`~lamodel.structure.Structure` (:func:`create_model`);
* on a ``LimitAnalysisBlock`` placed inside anyone's model (``m.wall =
  LimitAnalysisBlock(structure=s)``), which is how other Pyomo studies import it.

Sign conventions are those of :mod:`lamodel.structure`.

Eq. (5) is a mathematical program with complementarity constraints in disguise: since
``alpha_K - alpha = sum_i xi_i * slack_i >= 0`` at every feasible point, the bilinear
equality is the complementarity of flow and yield. The constraint is declared as
``0 <= alpha_K - alpha <= epsilon`` with a mutable ``epsilon`` (0 gives eq. 5 exactly) so
that a solver can tighten it gradually.
"""
from __future__ import annotations

import numpy as np
from pyomo.common.config import Bool, ConfigBlock, ConfigValue, PositiveFloat
from pyomo.core.base.block import BlockData, declare_custom_block
from pyomo.environ import (AbstractModel, Any, BuildAction, ConcreteModel, Constraint, Expression, NonNegativeReals,
                           Objective, Param, Reals, Set, Var, minimize, inequality)

from .structure import YIELD_ROWS, Structure

BLOCK_PARAMS = ("x", "y", "dead_x", "dead_y", "live_x", "live_y")
CONTACT_PARAMS = ("block_a", "block_b", "cx", "cy", "nx", "ny", "d", "mu")


# --------------------------------------------------------------------------- declarations
def declare_sets(b, structure: Structure | None = None):
    """BLOCKS (movable), SUPPORTS (fixed), CONTACTS, and the four yield ROWS of eq. (4)."""
    s = structure
    b.BLOCKS = Set(ordered=True, dimen=1, initialize=None if s is None else s.blocks, doc="movable blocks")
    b.SUPPORTS = Set(ordered=True, dimen=1, initialize=None if s is None else s.supports, doc="fixed bodies")
    b.CONTACTS = Set(ordered=True, dimen=1, initialize=None if s is None else s.contacts, doc="contact interfaces")
    b.ROWS = Set(ordered=True, initialize=YIELD_ROWS, doc="yield rows of eq. (4): two sliding, two hinging")


def declare_params(b, structure: Structure | None = None, xi_factor: float = 100.0):
    """Block centroids and loads; contact ends, centres, normals, half-lengths, friction.

    Without a structure the parameters wait for data (an AbstractModel and a .dat file).
    """
    s = structure

    def param(index, values, doc, within=Reals):
        if s is None:
            return Param(index, within=within, doc=doc)
        return Param(index, within=within, doc=doc, initialize=values)

    def by_block(col):
        return None if s is None else {j: float(v) for j, v in zip(s.blocks, col)}

    def by_contact(col, cast=float):
        return None if s is None else {k: cast(v) for k, v in zip(s.contacts, col)}

    b.x = param(b.BLOCKS, by_block(s and s.centroid[:, 0]), "centroid x")
    b.y = param(b.BLOCKS, by_block(s and s.centroid[:, 1]), "centroid y")
    b.dead_x = param(b.BLOCKS, by_block(s and s.dead[:, 0]), "constant force f0, x")
    b.dead_y = param(b.BLOCKS, by_block(s and s.dead[:, 1]), "constant force f0, y")
    b.live_x = param(b.BLOCKS, by_block(s and s.live[:, 0]), "base live force fbar, x")
    b.live_y = param(b.BLOCKS, by_block(s and s.live[:, 1]), "base live force fbar, y")
    b.block_a = param(b.CONTACTS, by_contact(s and s.block_a, str), "block a (or a support); the force acts on a", Any)
    b.block_b = param(b.CONTACTS, by_contact(s and s.block_b, str), "block b (or a support); its opposite acts on b", Any)
    b.cx = param(b.CONTACTS, by_contact(s and s.centre[:, 0]), "contact centre x")
    b.cy = param(b.CONTACTS, by_contact(s and s.centre[:, 1]), "contact centre y")
    b.nx = param(b.CONTACTS, by_contact(s and s.normal[:, 0]), "unit normal from a to b, x")
    b.ny = param(b.CONTACTS, by_contact(s and s.normal[:, 1]), "unit normal from a to b, y")
    b.d = param(b.CONTACTS, by_contact(s and s.d), "half-length: largest eccentricity of N")
    b.mu = param(b.CONTACTS, by_contact(s and s.mu), "friction coefficient")
    # Block outlines (optional, for pictures only; no constraint uses them).
    if s is None:
        b.VERTICES = Set(dimen=2, ordered=True, doc="(body, vertex number), for pictures")
    else:
        b.VERTICES = Set(dimen=2, ordered=True, doc="(body, vertex number), for pictures",
                         initialize=[(body, i + 1) for body, v in s.polygons.items() for i in range(len(v))])
    vertices = None if s is None else {(body, i + 1): p for body, v in s.polygons.items() for i, p in enumerate(v)}
    b.vx = param(b.VERTICES, vertices and {key: float(p[0]) for key, p in vertices.items()}, "vertex x")
    b.vy = param(b.VERTICES, vertices and {key: float(p[1]) for key, p in vertices.items()}, "vertex y")
    b.xi_factor = Param(initialize=xi_factor, mutable=True, doc="room left by the bounds on xi")
    b.epsilon = Param(initialize=0.0, mutable=True, doc="allowed complementarity gap alpha_K - alpha")
    # Which contacts touch each block, found once (a rule scanning all contacts per block
    # would be quadratic in size).
    b._incidence = BuildAction(rule=_build_incidence)


def _build_incidence(b):
    on_a = {j: [] for j in b.BLOCKS}
    on_b = {j: [] for j in b.BLOCKS}
    for k in b.CONTACTS:
        if b.block_a[k] in on_a:
            on_a[b.block_a[k]].append(k)
        if b.block_b[k] in on_b:
            on_b[b.block_b[k]].append(k)
    b._contacts_on_a, b._contacts_on_b = on_a, on_b


def _xi_upper(b, k, r):
    """Upper bound of xi (see Structure.xi_bounds): slips ~ U, hinge rotations ~ U / d."""
    mags = [np.hypot(b.live_x[j], b.live_y[j]) for j in b.BLOCKS]
    U = 1.0 / min(m for m in mags if m > 0)
    # an expression of the mutable xi_factor: changing it moves the bounds
    return (0.0, b.xi_factor * U if r.startswith("slide") else b.xi_factor * (U / b.d[k]))


def declare_variables(b):
    """s = (N, V, M, alpha) of eq. (3); block displacements u; flow multipliers xi."""
    b.N = Var(b.CONTACTS, bounds=(None, 0.0), initialize=0.0, doc="normal force, <= 0 in compression")
    b.V = Var(b.CONTACTS, initialize=0.0, doc="shear force along t = (-n_y, n_x)")
    b.M = Var(b.CONTACTS, initialize=0.0, doc="couple about the contact centre, on block a")
    b.alpha = Var(within=NonNegativeReals, initialize=0.0, doc="load multiplier")
    # alpha >= 0: without it the minimum is a collapse under the reversed live load.
    b.ux = Var(b.BLOCKS, within=Reals, initialize=0.0, doc="centroid displacement x")
    b.uy = Var(b.BLOCKS, within=Reals, initialize=0.0, doc="centroid displacement y")
    b.theta = Var(b.BLOCKS, within=Reals, initialize=0.0, doc="rotation about the centroid")
    b.xi = Var(b.CONTACTS, b.ROWS, bounds=_xi_upper, initialize=0.0, doc="flow multipliers of eq. (5)")


def _force_terms(b, j):
    """Resultant (fx, fy, m about the centroid) of the contact forces on block j."""
    fx = fy = m = 0
    for sign, ks in ((1.0, b._contacts_on_a[j]), (-1.0, b._contacts_on_b[j])):
        for k in ks:
            px = b.nx[k] * b.N[k] - b.ny[k] * b.V[k]  # N n + V t, t = (-ny, nx)
            py = b.ny[k] * b.N[k] + b.nx[k] * b.V[k]
            rx, ry = b.cx[k] - b.x[j], b.cy[k] - b.y[j]
            fx += sign * px
            fy += sign * py
            m += sign * (rx * py - ry * px + b.M[k])
    return fx, fy, m


def declare_equilibrium(b):
    """Eq. (1)-(2): f0 + alpha fbar + contact forces = 0 for every block (forces, moment).

    ``extra_x``/``extra_y`` are further constant forces at the centroids, zero until a
    user's study sets them (``m.wall.extra_x['b33'] = -m.T`` for a tie whose force T is a
    decision): they belong to f0, so they enter both the equilibrium and alpha_K of eq. (5).
    """
    b.extra_x = Expression(b.BLOCKS, initialize=0.0, doc="user's constant force at the centroid, x (part of f0)")
    b.extra_y = Expression(b.BLOCKS, initialize=0.0, doc="user's constant force at the centroid, y (part of f0)")

    def force_x(b, j):
        return _force_terms(b, j)[0] + b.dead_x[j] + b.extra_x[j] + b.alpha * b.live_x[j] == 0

    def force_y(b, j):
        return _force_terms(b, j)[1] + b.dead_y[j] + b.extra_y[j] + b.alpha * b.live_y[j] == 0

    def moment(b, j):
        # loads act at the centroid: no moment of their own
        return _force_terms(b, j)[2] == 0

    b.equilibrium_x = Constraint(b.BLOCKS, rule=force_x)
    b.equilibrium_y = Constraint(b.BLOCKS, rule=force_y)
    b.equilibrium_moment = Constraint(b.BLOCKS, rule=moment)


def declare_yield(b):
    """Eq. (4): mu N +- V <= 0 (Coulomb), d N -+ M <= 0 (no tension, eccentricity <= d)."""
    def rule(b, k, r):
        return yield_row(b, k, r) <= 0

    b.yield_condition = Constraint(b.CONTACTS, b.ROWS, rule=rule)


def yield_row(b, k, r):
    """Value of yield row r at contact k; its negative is the slack."""
    return {"slide+": b.mu[k] * b.N[k] + b.V[k],
            "slide-": b.mu[k] * b.N[k] - b.V[k],
            "hinge+": b.d[k] * b.N[k] - b.M[k],
            "hinge-": b.d[k] * b.N[k] + b.M[k]}[r]


def _displacement_at(b, j, px, py):
    """Displacement at point p of block j (zero for a support): u + theta k x (p - x_G)."""
    if j not in b._contacts_on_a:
        return 0.0, 0.0, 0.0
    return (b.ux[j] - b.theta[j] * (py - b.y[j]), b.uy[j] + b.theta[j] * (px - b.x[j]), b.theta[j])


def relative_displacement(b, k):
    """Opening, slip and relative rotation of block b with respect to block a at contact k."""
    ax, ay, at = _displacement_at(b, b.block_a[k], b.cx[k], b.cy[k])
    bx, by, bt = _displacement_at(b, b.block_b[k], b.cx[k], b.cy[k])
    dx, dy = bx - ax, by - ay
    return (b.nx[k] * dx + b.ny[k] * dy, -b.ny[k] * dx + b.nx[k] * dy, bt - at)


def declare_kinematics(b):
    """(u, xi) in K: the flow rule of the fictitious cohesive system, and fbar^T u = 1.

    The cohesive sliding rows have gradient (0, +-1, 0): slip without opening (the real
    non-associative Coulomb flow); the hinge rows (d, 0, -+1): rotation about an edge,
    opening d times the rotation. xi >= 0 keeps every opening non-negative.
    """
    def opening(b, k):
        return relative_displacement(b, k)[0] == b.d[k] * (b.xi[k, "hinge+"] + b.xi[k, "hinge-"])

    def slip(b, k):
        return relative_displacement(b, k)[1] == b.xi[k, "slide+"] - b.xi[k, "slide-"]

    def rotation(b, k):
        return relative_displacement(b, k)[2] == b.xi[k, "hinge-"] - b.xi[k, "hinge+"]

    b.flow_opening = Constraint(b.CONTACTS, rule=opening)
    b.flow_slip = Constraint(b.CONTACTS, rule=slip)
    b.flow_rotation = Constraint(b.CONTACTS, rule=rotation)
    b.normalisation = Constraint(
        rule=lambda b: sum(b.live_x[j] * b.ux[j] + b.live_y[j] * b.uy[j] for j in b.BLOCKS) == 1)


def kinematic_multiplier(b):
    """alpha_K = -u^T f0 - xi^T N_mu s_N (eq. 5): the work of the dead loads plus the
    dissipation on the fictitious cohesion -mu N."""
    dead_work = sum((b.dead_x[j] + b.extra_x[j]) * b.ux[j] + (b.dead_y[j] + b.extra_y[j]) * b.uy[j]
                    for j in b.BLOCKS)
    dissipation = sum(b.mu[k] * b.N[k] * (b.xi[k, "slide+"] + b.xi[k, "slide-"]) for k in b.CONTACTS)
    return -dead_work - dissipation


def declare_bilinear(b):
    """The bilinear condition of eq. (5), written 0 <= alpha_K - alpha <= epsilon."""
    b.complementarity = Constraint(rule=lambda b: inequality(0, kinematic_multiplier(b) - b.alpha, b.epsilon))


def declare_objective(b):
    b.min_alpha = Objective(rule=lambda b: b.alpha, sense=minimize)


def declare_limit_analysis(b, structure: Structure | None = None, objective: bool = True,
                           xi_factor: float = 100.0):
    """All components of eq. (5) on block b, in the order of the seed's equations."""
    declare_sets(b, structure)
    declare_params(b, structure, xi_factor)
    declare_variables(b)
    declare_equilibrium(b)
    declare_yield(b)
    declare_kinematics(b)
    declare_bilinear(b)
    if objective:
        declare_objective(b)
    return b


# ---------------------------------------------------------------------- the three faces
def create_abstract_model() -> AbstractModel:
    """The model without data: ``create_abstract_model().create_instance('x.dat')``."""
    return declare_limit_analysis(AbstractModel(name="lamodel"))


def create_model(structure: Structure, objective: bool = True, xi_factor: float = 100.0) -> ConcreteModel:
    """The model of a Structure, ready to solve."""
    return declare_limit_analysis(ConcreteModel(name=structure.name), structure.validate(), objective, xi_factor)


def _structure(value):
    if not isinstance(value, Structure):
        raise TypeError(f"expected a lamodel Structure, got {type(value).__name__}")
    return value.validate()


@declare_custom_block(name="LimitAnalysisBlock", rule="build")
class LimitAnalysisBlockData(BlockData):
    """The limit-analysis model of one structure as a Block inside a user's model.

    ``m.wall = LimitAnalysisBlock(structure=s, objective=False)`` declares the sets,
    variables and constraints of eq. (5) on ``m.wall``; the user adds variables,
    constraints and an objective of their own around it (IDAES's CONFIG + build pattern).
    """

    CONFIG = ConfigBlock()
    CONFIG.declare("structure", ConfigValue(domain=_structure, description="the block assembly (lamodel.Structure)"))
    CONFIG.declare("objective", ConfigValue(default=True, domain=Bool, description="declare min alpha on the block"))
    CONFIG.declare("xi_factor", ConfigValue(default=100.0, domain=PositiveFloat,
                                            description="room left by the upper bounds on xi"))

    def build(self, *index):
        self.config = self.CONFIG(self.parent_component()._lamodel_config)
        if self.config.structure is None:
            raise TypeError("LimitAnalysisBlock needs structure=<lamodel Structure>")
        declare_limit_analysis(self, self.config.structure, self.config.objective, self.config.xi_factor)


def _take_config(init):
    """Let LimitAnalysisBlock(...) accept the CONFIG options as keywords."""
    def __init__(self, *args, **kwargs):
        self._lamodel_config = {k: kwargs.pop(k) for k in list(kwargs) if k in LimitAnalysisBlockData.CONFIG}
        init(self, *args, **kwargs)
    return __init__


LimitAnalysisBlock.__init__ = _take_config(LimitAnalysisBlock.__init__)  # noqa: F821 (made by the decorator)


# ------------------------------------------------------------- values in and out of a model
def set_state(b, structure: Structure, N, V, M, alpha, u, xi):
    """Load forces, multiplier, mechanism and flow (lamodel's array layout) into the model."""
    nc = structure.n_contacts
    for k, c in enumerate(structure.contacts):
        b.N[c].set_value(float(N[k]), skip_validation=True)
        b.V[c].set_value(float(V[k]), skip_validation=True)
        b.M[c].set_value(float(M[k]), skip_validation=True)
        for r, row in enumerate(YIELD_ROWS):
            b.xi[c, row].set_value(float(xi[r * nc + k]), skip_validation=True)
    for j, blk in enumerate(structure.blocks):
        b.ux[blk].set_value(float(u[3 * j]), skip_validation=True)
        b.uy[blk].set_value(float(u[3 * j + 1]), skip_validation=True)
        b.theta[blk].set_value(float(u[3 * j + 2]), skip_validation=True)
    b.alpha.set_value(float(alpha), skip_validation=True)


def get_state(b, structure: Structure):
    """(N, V, M, alpha, u, xi) of the model, in lamodel's array layout."""
    val = lambda v: 0.0 if v.value is None else float(v.value)  # noqa: E731
    cs, bs = structure.contacts, structure.blocks
    N = np.array([val(b.N[c]) for c in cs])
    V = np.array([val(b.V[c]) for c in cs])
    M = np.array([val(b.M[c]) for c in cs])
    xi = np.array([val(b.xi[c, row]) for row in YIELD_ROWS for c in cs])
    u = np.array([val(v) for blk in bs for v in (b.ux[blk], b.uy[blk], b.theta[blk])])
    return N, V, M, val(b.alpha), u, xi
