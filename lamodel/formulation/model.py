"""The algebraic model of the seed's eq. (5) in Pyomo::

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

Sign conventions are those of :mod:`lamodel.structure`. Every coefficient comes from the
matrices of :mod:`lamodel.formulation.matrices` (the one place where eq. 1-5 is written);
each constraint is one row of them, so the model is built in time linear in its size.

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
from pyomo.core.expr.numeric_expr import LinearExpression, MonomialTermExpression
from pyomo.environ import (AbstractModel, Any, BuildAction, ConcreteModel, Constraint, Expression, NonNegativeReals,
                           Objective, Param, Reals, Set, Var, minimize, inequality)

from ..solvers import bridge  # noqa: F401  registers SolverFactory('lamodel_ipopt') for the users of the model
from ..structure import BLOCK_MOMENT_PARAMS, BLOCK_PARAMS, CONTACT_PARAMS, YIELD_ROWS, Structure
from .matrices import Formulation, row_names, xi_bounds

__all__ = ["BLOCK_PARAMS", "CONTACT_PARAMS", "LimitAnalysisBlock", "create_abstract_model", "create_model",
           "declare_limit_analysis", "get_state", "kinematic_multiplier", "relative_displacement", "set_state",
           "yield_row"]


# --------------------------------------------------------------------------- declarations
def declare_sets(b, structure: Structure | None = None):
    """BLOCKS (movable), SUPPORTS (fixed), CONTACTS, and the yield ROWS: the four of eq. (4),
    or with the joints' strengths those of :func:`~.matrices.row_names`."""
    s = structure
    b.BLOCKS = Set(ordered=True, dimen=1, initialize=None if s is None else s.blocks, doc="movable blocks")
    b.SUPPORTS = Set(ordered=True, dimen=1, initialize=None if s is None else s.supports, doc="fixed bodies")
    b.CONTACTS = Set(ordered=True, dimen=1, initialize=None if s is None else s.contacts, doc="contact interfaces")
    b.ROWS = Set(ordered=True, initialize=YIELD_ROWS if s is None else row_names(s),
                 doc="yield rows of eq. (4): two sliding, two hinging (or the facets of a joint with strengths)")


def declare_params(b, structure: Structure | None = None, xi_factor: float = 100.0):
    """Block centroids and loads; contact ends, centres, normals, half-lengths, friction.

    Without a structure the parameters wait for data (an AbstractModel and a .dat file);
    the matrices of eq. (1)-(5) are then made from them once the data are in
    (:func:`_build_formulation`).
    """
    s = structure
    docs = {"x": "centroid x", "y": "centroid y", "dead_x": "constant force f0, x", "dead_y": "constant force f0, y",
            "live_x": "base live force fbar, x", "live_y": "base live force fbar, y",
            "dead_m": "moment of f0 about the centroid (point loads; default 0)",
            "live_m": "moment of fbar about the centroid (point loads; default 0)",
            "block_a": "block a (or a support); the force acts on a",
            "block_b": "block b (or a support); its opposite acts on b", "cx": "contact centre x",
            "cy": "contact centre y", "nx": "unit normal from a to b, x", "ny": "unit normal from a to b, y",
            "d": "half-length: largest eccentricity of N", "mu": "friction coefficient"}
    if s is not None:
        block_cols = dict(zip(BLOCK_PARAMS, (s.centroid[:, 0], s.centroid[:, 1], s.dead[:, 0], s.dead[:, 1],
                                             s.live[:, 0], s.live[:, 1])))
        block_cols.update(dead_m=s.dead_m, live_m=s.live_m)
        contact_cols = dict(zip(CONTACT_PARAMS, (s.block_a, s.block_b, s.centre[:, 0], s.centre[:, 1],
                                                 s.normal[:, 0], s.normal[:, 1], s.d, s.mu)))
    def data(values):  # without a structure, the values come later from a .dat file
        return {} if s is None else {"initialize": values()}

    for name in BLOCK_PARAMS:
        b.add_component(name, Param(b.BLOCKS, within=Reals, doc=docs[name],
                                    **data(lambda: dict(zip(s.blocks, map(float, block_cols[name]))))))
    for name in BLOCK_MOMENT_PARAMS:  # optional in a .dat file: old files stay valid
        b.add_component(name, Param(b.BLOCKS, within=Reals, default=0.0, doc=docs[name],
                                    **data(lambda: dict(zip(s.blocks, map(float, block_cols[name]))))))
    for name in CONTACT_PARAMS:
        text = name in ("block_a", "block_b")
        b.add_component(name, Param(b.CONTACTS, within=Any if text else Reals, doc=docs[name], **data(
            lambda: dict(zip(s.contacts, map(str if text else float, contact_cols[name]))))))
    # Block outlines (optional, for pictures only; no constraint uses them).
    corners = {} if s is None else {(body, i + 1): p for body, v in s.polygons.items() for i, p in enumerate(v)}
    b.VERTICES = Set(dimen=2, ordered=True, doc="(body, vertex number), for pictures", **data(lambda: list(corners)))
    b.vx = Param(b.VERTICES, within=Reals, doc="vertex x", **data(lambda: {k: float(p[0]) for k, p in corners.items()}))
    b.vy = Param(b.VERTICES, within=Reals, doc="vertex y", **data(lambda: {k: float(p[1]) for k, p in corners.items()}))
    b.xi_factor = Param(initialize=xi_factor, mutable=True, doc="room left by the bounds on xi")
    b.epsilon = Param(initialize=0.0, mutable=True, doc="allowed complementarity gap alpha_K - alpha")
    b._structure = s
    b._formulation_action = BuildAction(rule=_build_formulation)


def _structure_of_params(b) -> Structure:
    """The Structure held by the parameters of b (the AbstractModel + .dat route)."""
    blocks, contacts = list(b.BLOCKS), list(b.CONTACTS)
    col = lambda name, ids: [b.component(name)[i] for i in ids]  # noqa: E731
    polygons = {}
    for body, i in b.VERTICES:
        polygons.setdefault(body, []).append((i, b.vx[body, i], b.vy[body, i]))
    return Structure(
        name=b.name, blocks=blocks, centroid=np.column_stack([col("x", blocks), col("y", blocks)]),
        dead=np.column_stack([col("dead_x", blocks), col("dead_y", blocks)]),
        live=np.column_stack([col("live_x", blocks), col("live_y", blocks)]),
        dead_m=col("dead_m", blocks), live_m=col("live_m", blocks),
        supports=list(b.SUPPORTS), contacts=contacts, block_a=col("block_a", contacts),
        block_b=col("block_b", contacts),
        centre=np.column_stack([col("cx", contacts), col("cy", contacts)]).reshape(-1, 2),
        normal=np.column_stack([col("nx", contacts), col("ny", contacts)]).reshape(-1, 2),
        d=col("d", contacts), mu=col("mu", contacts),
        polygons={k: [(x, y) for _, x, y in sorted(v)] for k, v in polygons.items()}).validate()


def _build_formulation(b):
    """The matrices of eq. (1)-(5) of the structure, made once (linear in its size)."""
    s = b._structure if b._structure is not None else _structure_of_params(b)
    b._formulation = Formulation.of(s)
    b._xi_base = xi_bounds(s, 1.0)
    b._contact_index = {k: i for i, k in enumerate(s.contacts)}


def declare_variables(b):
    """s = (N, V, M, alpha) of eq. (3); block displacements u; flow multipliers xi."""
    tension = b._structure is not None and bool(np.any(b._structure.ft > 0))  # then the rows bound N
    b.N = Var(b.CONTACTS, bounds=(None, None if tension else 0.0), initialize=0.0,
              doc="normal force, <= 0 in compression")
    b.V = Var(b.CONTACTS, initialize=0.0, doc="shear force along t = (-n_y, n_x)")
    b.M = Var(b.CONTACTS, initialize=0.0, doc="couple about the contact centre, on block a")
    b.alpha = Var(within=NonNegativeReals, initialize=0.0, doc="load multiplier")
    # alpha >= 0: without it the minimum is a collapse under the reversed live load.
    b.ux = Var(b.BLOCKS, within=Reals, initialize=0.0, doc="centroid displacement x")
    b.uy = Var(b.BLOCKS, within=Reals, initialize=0.0, doc="centroid displacement y")
    b.theta = Var(b.BLOCKS, within=Reals, initialize=0.0, doc="rotation about the centroid")

    def xi_bounds_rule(b, k, r):
        # an expression of the mutable xi_factor: changing it moves the bounds
        return 0.0, b.xi_factor * float(b._xi_base[(b.ROWS.ord(r) - 1) * len(b.CONTACTS) + b._contact_index[k]])

    b.xi = Var(b.CONTACTS, b.ROWS, bounds=xi_bounds_rule, initialize=0.0, doc="flow multipliers of eq. (5)")


def _forces(b):
    """The entries of s_f = (N, V, M) in the order of eq. (3) (listed once per block b)."""
    if "_s" not in b.__dict__:
        b._s = [b.N[k] for k in b.CONTACTS] + [b.V[k] for k in b.CONTACTS] + [b.M[k] for k in b.CONTACTS]
    return b._s


def _displacements(b):
    """The entries of u = (ux, uy, theta), block after block (listed once per block b)."""
    if "_u" not in b.__dict__:
        b._u = [v for j in b.BLOCKS for v in (b.ux[j], b.uy[j], b.theta[j])]
    return b._u


def _row(matrix, i, variables):
    """Row i of a sparse (CSR) matrix times the variables: a linear expression (built in
    one piece: summing term by term costs several times more on large models)."""
    lo, hi = matrix.indptr[i], matrix.indptr[i + 1]
    return LinearExpression([MonomialTermExpression((a, variables[c]))
                             for a, c in zip(matrix.data[lo:hi].tolist(), matrix.indices[lo:hi].tolist())])


def declare_equilibrium(b):
    """Eq. (1)-(2): ``A s_f + f0 + alpha fbar = 0`` for every block (forces, moment).

    ``extra_x``/``extra_y`` are further constant forces at the centroids, zero until a
    user's study sets them (``m.wall.extra_x['b33'] = -m.T`` for a tie whose force T is a
    decision): they belong to f0, so they enter both the equilibrium and alpha_K of eq. (5).
    """
    b.extra_x = Expression(b.BLOCKS, initialize=0.0, doc="user's constant force at the centroid, x (part of f0)")
    b.extra_y = Expression(b.BLOCKS, initialize=0.0, doc="user's constant force at the centroid, y (part of f0)")

    def rule(dof):
        def equilibrium(b, j):
            F, i = b._formulation, 3 * b.BLOCKS.ord(j) - 3 + dof
            lhs = _row(F.A, i, _forces(b)) + float(F.f0[i]) + b.alpha * float(F.fbar[i])
            return (lhs + (b.extra_x, b.extra_y)[dof][j] if dof < 2 else lhs) == 0
        return equilibrium

    b.equilibrium_x = Constraint(b.BLOCKS, rule=rule(0))
    b.equilibrium_y = Constraint(b.BLOCKS, rule=rule(1))
    b.equilibrium_moment = Constraint(b.BLOCKS, rule=rule(2))


def yield_row(b, k, r):
    """Value of yield row r of eq. (4) at contact k (row of ``Y s_f``); its negative is the
    slack (with the joints' strengths: ``b`` minus it, :func:`row_bound`)."""
    return _row(b._formulation.Y, _row_index(b, k, r), _forces(b))


def _row_index(b, k, r):
    return (b.ROWS.ord(r) - 1) * len(b.CONTACTS) + b._contact_index[k]


def row_bound(b, k, r) -> float:
    """The right-hand side of yield row r at contact k: 0 in eq. (4), the cohesion or the
    facet's with the joints' strengths (:func:`~.matrices.strength_rows`)."""
    F = b._formulation
    return 0.0 if F.b is None else float(F.b[_row_index(b, k, r)])


def declare_yield(b):
    """Eq. (4): mu N +- V <= 0 (Coulomb), d N -+ M <= 0 (no tension, eccentricity <= d);
    with the joints' strengths ``Y s_f <= b`` (cohesion, the N-M facets)."""
    b.yield_condition = Constraint(b.CONTACTS, b.ROWS, rule=lambda b, k, r: yield_row(b, k, r) <= row_bound(b, k, r))


def relative_displacement(b, k, parts=(0, 1, 2)):
    """Opening, slip and relative rotation (``parts`` 0, 1, 2) of block b with respect to
    block a at contact k: the contact strains ``q = -A^T u``."""
    if "_At" not in b.__dict__:
        b._At = (-b._formulation.A.T).tocsr()
    i, nc = b._contact_index[k], len(b.CONTACTS)
    return tuple(_row(b._At, i + part * nc, _displacements(b)) for part in parts)


def declare_kinematics(b):
    """(u, xi) in K: the flow rule of the fictitious cohesive system ``-A^T u = G^T xi``,
    and ``fbar^T u = 1``.

    The cohesive sliding rows have gradient (0, +-1, 0): slip without opening (the real
    non-associative Coulomb flow); the hinge rows (d, 0, -+1): rotation about an edge,
    opening d times the rotation. xi >= 0 keeps every opening non-negative.
    """
    def rule(part):
        def flow(b, k):
            if "_Gt" not in b.__dict__:
                b._Gt = b._formulation.G.T.tocsr()
                b._xi_list = [b.xi[c, r] for r in b.ROWS for c in b.CONTACTS]
            i = b._contact_index[k] + part * len(b.CONTACTS)
            return relative_displacement(b, k, (part,))[0] == _row(b._Gt, i, b._xi_list)
        return flow

    b.flow_opening = Constraint(b.CONTACTS, rule=rule(0))
    b.flow_slip = Constraint(b.CONTACTS, rule=rule(1))
    b.flow_rotation = Constraint(b.CONTACTS, rule=rule(2))

    def normalisation(b):
        fbar, u = b._formulation.fbar, _displacements(b)
        return sum(float(fbar[i]) * u[i] for i in np.flatnonzero(fbar)) == 1

    b.normalisation = Constraint(rule=normalisation)


def kinematic_multiplier(b):
    """alpha_K = -u^T f0 - xi^T N_mu s_N (eq. 5): the work of the dead loads (with the
    user's extra forces) plus the dissipation on the fictitious cohesion -mu N."""
    f0, u = b._formulation.f0, _displacements(b)
    dead_work = sum(float(f0[i]) * u[i] for i in np.flatnonzero(f0))
    dead_work += sum(b.extra_x[j] * b.ux[j] + b.extra_y[j] * b.uy[j] for j in b.BLOCKS)
    dissipation = sum(b.mu[k] * b.N[k] * (b.xi[k, "slide+"] + b.xi[k, "slide-"]) for k in b.CONTACTS)
    if b._formulation.b is not None:  # the joints' strengths dissipate xi b (cohesion, facets)
        dissipation -= sum(row_bound(b, k, r) * b.xi[k, r] for k in b.CONTACTS for r in b.ROWS
                           if row_bound(b, k, r) != 0)
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
    """The model of a Structure, ready to solve (its joints' strengths included)."""
    return declare_limit_analysis(ConcreteModel(name=structure.name), _structure(structure), objective, xi_factor)


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
LimitAnalysisBlock.__doc__ = LimitAnalysisBlockData.__doc__  # noqa: F821  its help() and API reference


# ------------------------------------------------------------- values in and out of a model
def set_state(b, structure: Structure, N, V, M, alpha, u, xi):
    """Load forces, multiplier, mechanism and flow (lamodel's array layout) into the model."""
    nc = structure.n_contacts
    for k, c in enumerate(structure.contacts):
        b.N[c].set_value(float(N[k]), skip_validation=True)
        b.V[c].set_value(float(V[k]), skip_validation=True)
        b.M[c].set_value(float(M[k]), skip_validation=True)
        for r, row in enumerate(b.ROWS):
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
    xi = np.array([val(b.xi[c, row]) for row in b.ROWS for c in cs])
    u = np.array([val(v) for blk in bs for v in (b.ux[blk], b.uy[blk], b.theta[blk])])
    return N, V, M, val(b.alpha), u, xi
