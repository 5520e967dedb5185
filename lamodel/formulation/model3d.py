"""The seed's eq. (5) in space as a Pyomo model: the Coulomb cone as a quadratic constraint::

    alpha_c = min alpha
        s in S            : equilibrium (6 rows a block) and ``T1^2 + T2^2 <= mu^2 N^2``, N <= 0
        u in K            : openings ``q_n(u) >= 0``, ``fbar^T u = 1``; sigma_p >= ||slip_p(u)||
                            (``s1^2 + s2^2 <= sigma^2``)
        alpha = alpha_K   : ``alpha_K = -u^T f0 - sum_p mu N_p sigma_p``, as
                            ``0 <= alpha_K - alpha <= epsilon``

``alpha_K - alpha`` is the sum over the points of ``-N q_n`` and ``-mu N sigma - T.slip``,
each >= 0 on S, so a point with zero gap is a collapse state: opening only where N = 0,
slip only on the cone along T, sigma the slip's length (the seed's second theorem).

With the joints' strengths (:meth:`lamodel.structure3d.Structure3D.caps`: per point
``N_c = -f_c A <= N <= N_t = min(f_t A, k / mu)`` and ``||T|| <= k - mu N``, k = c0 A) the cone is
``T1^2 + T2^2 <= (k - mu N)^2`` with ``k - mu N >= 0``, the opening ``q_n = open - close``
(``close``, the point crushing, only where it has a cap), and
``alpha_K = -u^T f0 + sum (k - mu N) sigma + N_t open - N_c close``: the fictitious
system's cohesion ``k - mu N`` and its caps associative, as the search's programs
(:mod:`lamodel.search.gap.capped3d`).
Coefficients come from :mod:`lamodel.formulation.space`. Built on a ``ConcreteModel``
(:func:`create_model3d`) or as ``m.room = LimitAnalysisBlock3D(structure=s)`` inside anyone's
model; solved by Ipopt through ``SolverFactory('lamodel_ipopt')``.
"""
from __future__ import annotations

import numpy as np
from pyomo.common.config import Bool, ConfigBlock, ConfigValue
from pyomo.core.base.block import BlockData, declare_custom_block
from pyomo.environ import (ConcreteModel, Constraint, NonNegativeReals, Objective, Param, RangeSet, Set, Var,
                           inequality, minimize)

from ..structure3d import Structure3D
from .model import _row  # noqa: F401  (also registers SolverFactory('lamodel_ipopt'))
from .space import Formulation3D

DOFS = ("ux", "uy", "uz", "rx", "ry", "rz")


def declare_limit_analysis3d(b, structure: Structure3D, objective: bool = True):
    """All components of eq. (5) in space on block b, with the joints' strengths where the
    structure has them (module doc)."""
    s = structure
    F = b._formulation = Formulation3D.of(s)
    n = s.n_points
    crush, tension, k = s.caps() if s.has_materials else (np.full(n, -np.inf), np.zeros(n), np.zeros(n))
    capped = np.isfinite(crush)
    b.BLOCKS = Set(ordered=True, initialize=s.blocks, doc="movable blocks")
    b.DOFS = Set(ordered=True, initialize=DOFS, doc="block motions at the centroid")
    b.POINTS = RangeSet(0, n - 1, doc="contact points")
    b.mu = Param(b.POINTS, initialize=dict(enumerate(map(float, s.mu))), doc="friction coefficient")
    b.epsilon = Param(initialize=0.0, mutable=True, doc="allowed complementarity gap alpha_K - alpha")
    b.N = Var(b.POINTS, bounds=lambda b, p: (float(crush[p]) if capped[p] else None, float(tension[p])),
              initialize=0.0, doc="normal force, < 0 in compression, within the point's crushing and tensile forces")
    b.k = Param(b.POINTS, initialize=dict(enumerate(map(float, k))), doc="cohesion force c0 A")
    b.T1 = Var(b.POINTS, initialize=0.0, doc="tangential force along t1")
    b.T2 = Var(b.POINTS, initialize=0.0, doc="tangential force along t2")
    b.alpha = Var(within=NonNegativeReals, initialize=0.0, doc="load multiplier")
    b.u = Var(b.BLOCKS, b.DOFS, initialize=0.0, doc="block motion at the centroid")
    b.sigma = Var(b.POINTS, within=NonNegativeReals, initialize=0.0, doc="bound on the slip's length")
    b.CAPPED = Set(ordered=True, initialize=[int(p) for p in np.flatnonzero(capped)], doc="points with a crushing cap")
    b.close = Var(b.CAPPED, within=NonNegativeReals, initialize=0.0, doc="closing (crushing) of a capped point")
    closing = lambda b, p: b.close[p] if capped[p] else 0.0  # noqa: E731
    forces = [b.N[p] for p in b.POINTS] + [b.T1[p] for p in b.POINTS] + [b.T2[p] for p in b.POINTS]
    motions = [b.u[j, k] for j in s.blocks for k in DOFS]
    A, f0, fbar = F.A, F.f0, F.fbar
    Qt = (-A.T).tocsr()  # strains q = -A^T u

    def equilibrium(b, j, k):
        i = 6 * b.BLOCKS.ord(j) - 6 + DOFS.index(k)
        return _row(A, i, forces) + float(f0[i]) + b.alpha * float(fbar[i]) == 0
    b.equilibrium = Constraint(b.BLOCKS, b.DOFS, rule=equilibrium)
    # the cone's radius at N (-mu N on a dry point: N <= 0 keeps it >= 0; a point that can
    # take tension keeps N under the apex, N <= k / mu)
    radius = lambda b, p: b.k[p] - b.mu[p] * b.N[p] if k[p] else -b.mu[p] * b.N[p]  # noqa: E731
    b.cone = Constraint(b.POINTS, rule=lambda b, p: b.T1[p] ** 2 + b.T2[p] ** 2 <= radius(b, p) ** 2)
    b.apex = Constraint(b.POINTS, rule=lambda b, p: radius(b, p) >= 0 if tension[p] > 0 else Constraint.Skip)
    b.opening = Constraint(b.POINTS, rule=lambda b, p: _row(Qt, p, motions) + closing(b, p) >= 0)
    b.slip = Constraint(b.POINTS, rule=lambda b, p: _row(Qt, n + p, motions) ** 2 + _row(Qt, 2 * n + p, motions) ** 2
                        <= b.sigma[p] ** 2)
    b.normalisation = Constraint(expr=sum(float(fbar[i]) * motions[i] for i in np.flatnonzero(fbar)) == 1)

    def alpha_K(b):
        work = sum(float(f0[i]) * motions[i] for i in np.flatnonzero(f0))
        caps = sum(float(tension[p]) * (_row(Qt, p, motions) + closing(b, p)) for p in np.flatnonzero(tension))
        caps -= sum(float(crush[p]) * b.close[p] for p in b.CAPPED)
        return -work + sum(radius(b, p) * b.sigma[p] for p in b.POINTS) + caps
    b.complementarity = Constraint(rule=lambda b: inequality(0, alpha_K(b) - b.alpha, b.epsilon))
    if objective:
        b.min_alpha = Objective(expr=b.alpha, sense=minimize)
    b._structure = s
    return b


def create_model3d(structure: Structure3D, objective: bool = True) -> ConcreteModel:
    """The Pyomo model of eq. (5) for a Structure3D, ready to solve."""
    return declare_limit_analysis3d(ConcreteModel(name=structure.name), structure.validate(), objective)


def _structure3d(value):
    if not isinstance(value, Structure3D):
        raise TypeError(f"expected a lamodel Structure3D, got {type(value).__name__}")
    return value.validate()


@declare_custom_block(name="LimitAnalysisBlock3D", rule="build")
class LimitAnalysisBlock3DData(BlockData):
    """Eq. (5) in space of one structure as a Block inside a user's model:
    ``m.room = LimitAnalysisBlock3D(structure=s, objective=False)``."""

    CONFIG = ConfigBlock()
    CONFIG.declare("structure", ConfigValue(domain=_structure3d, description="the block assembly (Structure3D)"))
    CONFIG.declare("objective", ConfigValue(default=True, domain=Bool, description="declare min alpha on the block"))

    def build(self, *index):
        self.config = self.CONFIG(getattr(self.parent_component(), "_lamodel_config", {}))
        if self.config.structure is None:
            raise TypeError("LimitAnalysisBlock3D needs structure=<lamodel Structure3D>")
        declare_limit_analysis3d(self, self.config.structure, self.config.objective)


def _init_with_config(init):
    def __init__(self, *args, **kwargs):
        self._lamodel_config = {k: kwargs.pop(k) for k in list(kwargs) if k in LimitAnalysisBlock3DData.CONFIG}
        init(self, *args, **kwargs)
    return __init__


LimitAnalysisBlock3D.__init__ = _init_with_config(LimitAnalysisBlock3D.__init__)  # noqa: F821


def set_state3d(b, state):
    """Load a state (lamodel's arrays: N, T1, T2, alpha, u (6 nb), q) into the model."""
    n = len(state.N)
    slip = np.hypot(state.q[n:2 * n], state.q[2 * n:])
    for p in range(n):
        if p in b.CAPPED:
            b.close[p].set_value(max(-float(state.q[p]), 0.0), skip_validation=True)
        b.N[p].set_value(float(state.N[p]), skip_validation=True)
        b.T1[p].set_value(float(state.T1[p]))
        b.T2[p].set_value(float(state.T2[p]))
        b.sigma[p].set_value(float(slip[p]), skip_validation=True)
    for j, blk in enumerate(b._structure.blocks):
        for k, dof in enumerate(DOFS):
            b.u[blk, dof].set_value(float(state.u[6 * j + k]))
    b.alpha.set_value(float(state.alpha), skip_validation=True)


def get_state3d(b):
    """(N, T1, T2, alpha, u) of the model's current values, in lamodel's array layout."""
    pts = list(b.POINTS)
    val = lambda v: np.array([v[p].value for p in pts], float)  # noqa: E731
    u = np.array([b.u[j, k].value for j in b._structure.blocks for k in DOFS], float)
    return val(b.N), val(b.T1), val(b.T2), float(b.alpha.value), u
