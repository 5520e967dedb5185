"""Eq. (1)-(5) as sparse matrices: the one place where the mechanics is written.

Everything that solves or checks eq. (5) — the Pyomo model (:mod:`.model`), the LPs of the
search (:mod:`lamodel.search.gap.problem`, :mod:`lamodel.search.lp`), the certification
and the tests — takes its coefficients from here. Conventions are those of :mod:`lamodel.structure`:

* statics ``s = (N, V, M, alpha)`` (eq. 3); equilibrium ``A s_f + f0 + alpha fbar = 0``
  (eq. 1-2), A of size 3 nb x 3 nc, block rows ``(f_x, f_y, m)``;
* yield ``Y s_f <= 0`` (eq. 4), rows stacked by kind slide+, slide-, hinge+, hinge-;
* kinematics of the fictitious cohesive system ``-A^T u = G^T xi``, ``xi >= 0``,
  ``fbar^T u = 1``;
* ``alpha_K = -u^T f0 - xi^T N_mu s_N`` (eq. 5);
* with the joint's strengths (:mod:`.joints`: crushing, tension, cohesion) eq. (4)
  becomes ``Y s_f <= b`` (:func:`strength_rows`) and the fictitious cohesion
  ``c0 (2 d b) - mu N``; a dry joint (the default) keeps eq. (4) and every matrix above
  as it is; the programs take tensile and cohesion forces beyond CAP_FAR times the loads
  as infinite (:func:`far_bounds`);
* the same statics in friction-cone generator form ``s_f = T lambda``, ``lambda >= 0``
  (:func:`generator_matrix`), and the columns of the fictitious cohesive LP
  (:func:`cohesive_matrix`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..search.tuning import CAP_FAR, CRUSHING_FAN_RATIO, CRUSHING_FACETS, CRUSHING_FAR, CRUSHING_FLOOR
from ..structure import YIELD_ROWS, Structure
from .joints import facets, fractions


def equilibrium_matrix(s: Structure) -> sp.csr_matrix:
    """A of eq. (2): block resultants (3 nb) produced by the contact forces (3 nc).

    Column k (N_k), nc+k (V_k), 2nc+k (M_k). ``N n + V t`` at the contact centre and the
    couple M act on block a and, reversed, on block b; moments are about the centroids
    (eq. 1's ``(x_ck - x_G) ^ (V t + N n) +- M k``).
    """
    nb, nc = s.n_blocks, s.n_contacts
    ia, ib = s.contact_blocks()
    n, t, c = s.normal, s.tangent, s.centre
    rows, cols, vals = [], [], []

    def put(blk, sign):
        on = blk >= 0
        k = np.flatnonzero(on)
        j = blk[on]
        r = c[k] - s.centroid[j]  # lever arm from the centroid to the contact centre
        for col0, vec in ((0, n), (nc, t)):
            f = vec[k]
            rows.extend([3 * j, 3 * j + 1, 3 * j + 2])
            cols.extend([col0 + k] * 3)
            vals.extend([sign * f[:, 0], sign * f[:, 1], sign * (r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0])])
        rows.append(3 * j + 2)
        cols.append(2 * nc + k)
        vals.append(sign * np.ones(k.size))

    put(ia, 1.0)
    put(ib, -1.0)
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(3 * nb, 3 * nc))


def load_vectors(s: Structure):
    """(f0, fbar) of eq. (2), each of length 3 nb: the resultants at the centroids and, in
    the m rows, their moments about the centroids (eq. 1's x ^ f of loads applied
    elsewhere, e.g. point loads: ``Structure.dead_m``, ``live_m``)."""
    nb = s.n_blocks
    f0 = np.zeros(3 * nb)
    fb = np.zeros(3 * nb)
    f0[0::3], f0[1::3], f0[2::3] = s.dead[:, 0], s.dead[:, 1], s.dead_m
    fb[0::3], fb[1::3], fb[2::3] = s.live[:, 0], s.live[:, 1], s.live_m
    return f0, fb


def yield_matrix(s: Structure) -> sp.csr_matrix:
    """Rows of eq. (4), ``Y s_f <= 0``, stacked by kind (4 nc x 3 nc).

    slide+: mu N + V, slide-: mu N - V, hinge+: d N - M, hinge-: d N + M.
    """
    nc = s.n_contacts
    I = sp.identity(nc, format="csr")
    Mu, D, Z = sp.diags(s.mu), sp.diags(s.d), sp.csr_matrix((nc, nc))
    return sp.bmat([[Mu, I, Z], [Mu, -I, Z], [D, Z, -I], [D, Z, I]], format="csr")


def flow_matrix(s: Structure) -> sp.csr_matrix:
    """Gradients of the fictitious cohesive yield rows (eq. 5's system), 4 nc x 3 nc.

    The cohesive law replaces mu N by the cohesion -mu N of the real forces, so sliding
    rows carry no normal component (no dilatancy); hinge rows are those of eq. (4).
    Contact strains (opening, slip, rotation) follow the flow rule ``q = G^T xi``.
    """
    nc = s.n_contacts
    I = sp.identity(nc, format="csr")
    D, Z = sp.diags(s.d), sp.csr_matrix((nc, nc))
    return sp.bmat([[Z, I, Z], [Z, -I, Z], [D, Z, -I], [D, Z, I]], format="csr")


def _loads(s: Structure) -> float:
    """The dead and live forces' sum: what the joints' far strengths are measured against."""
    return float(np.abs(s.dead).sum() + np.abs(s.live).sum())


def crushing_strengths(s: Structure) -> np.ndarray:
    """(nc,) each joint's f_c as its rows take it: infinite (eq. 4's hinge rows, shifted by
    the tension) where its crushing force 2 d b f_c passes CRUSHING_FAR times the loads
    (the dead and live forces' sum): the stress block is the cone there to round-off, and
    its polygon's facets, of the size of that force, would pass what an LP can hold."""
    far = 2 * s.d * s.thickness * s.fc > CRUSHING_FAR * _loads(s)
    return np.where(far, np.inf, s.fc)


def far_strengths(s: Structure):
    """(tension, cohesion), each (nc,) bool: the joints whose tensile force 2 d b f_t, or
    cohesion force c0 2 d b, passes CAP_FAR times the loads. A state of forces of the
    loads' size never reaches them: the programs take them as infinite (:func:`far_bounds`)."""
    far = CAP_FAR * _loads(s)
    area = joint_area(s)
    tension, cohesion = area * s.ft > far, area * s.cohesion > far
    if np.any(tension & (s.fc < s.ft)):  # the input's checks keep f_t <= f_c
        raise ValueError("a joint's tensile strength ft passes its compressive strength fc")
    return tension, cohesion


def far_bounds(s: Structure, b: np.ndarray) -> np.ndarray:
    """The right-hand sides ``b`` of :func:`strength_rows` as the programs take them: +inf
    (the row is left out) on the slides of a joint of far cohesion (it never slides: V
    free) and on every facet of a joint of far tension (it never opens, turns or crushes:
    N and M free). Sound as f_c >= f_t: with N_t = 2 d b f_t and N_c <= -N_t the stress
    block carries any |M| <= d N_t / 8 at |N| <= N_t / 2 (moment_capacity = d (N_t - N)
    (N - N_c) / (N_t - N_c)), beyond CAP_FAR / 8 times the loads. The residual test keeps
    ``b`` itself (:meth:`Formulation.slack`)."""
    tension, cohesion = far_strengths(s)
    kinds = len(b) // s.n_contacts
    out = b.copy().reshape(kinds, -1)
    out[:2, cohesion] = np.inf
    out[2:, tension] = np.inf
    return out.ravel()


def facets_per_half(s: Structure) -> int:
    """N-M facets a half of every joint's domain: one (the hinge rows of eq. 4, shifted by
    the tension) unless some joint crushes, then those of :func:`.joints.fractions`."""
    if not np.isfinite(crushing_strengths(s)).any():
        return 1
    return len(fractions(CRUSHING_FACETS, CRUSHING_FLOOR, CRUSHING_FAN_RATIO)) - 1


def joint_facets(s: Structure):
    """(a, beta), each (2 m, nc): the N-M facets ``a N -/+ M <= beta`` of every joint, the
    m lower ones (``-M``) then the m upper ones (``+M``), m = :func:`facets_per_half`. A
    joint of infinite f_c repeats its one facet (its rows are copies: the layout stays a
    block of nc rows a kind)."""
    m = facets_per_half(s)
    fc = crushing_strengths(s)
    a, beta = np.empty((m, s.n_contacts)), np.empty((m, s.n_contacts))
    for k in range(s.n_contacts):
        ak, bk = facets(s.d[k], s.thickness[k], fc[k], s.ft[k], CRUSHING_FACETS, CRUSHING_FLOOR,
                        CRUSHING_FAN_RATIO)
        a[:, k], beta[:, k] = np.resize(ak, m), np.resize(bk, m)
    return np.vstack([a, a]), np.vstack([beta, beta])


def row_origins(s: Structure) -> np.ndarray:
    """(nr,) for each yield row of :func:`strength_rows` the row it copies, itself if none: a
    joint of infinite f_c repeats its one facet a half (:func:`joint_facets`), and its
    copies are the first facet of their half again. The LPs keep one row of each."""
    nc, m = s.n_contacts, facets_per_half(s)
    origin = np.arange((2 + 2 * m) * nc)
    rigid = np.flatnonzero(~np.isfinite(crushing_strengths(s)))
    for first in (2, 2 + m):  # the lower half's facets, then the upper's
        for j in range(1, m):
            origin[(first + j) * nc + rigid] = first * nc + rigid
    return origin


def row_names(s: Structure) -> tuple:
    """The kinds of yield rows, a block of nc rows each: eq. (4)'s ``YIELD_ROWS``, or with
    the joints' strengths slide+, slide-, then the facets of :func:`joint_facets`, lower
    (``crush-1`` at the tension end .. ``crush-m``) and upper (``crush+1`` ..)."""
    if not s.has_materials:
        return YIELD_ROWS
    m = facets_per_half(s)
    return ("slide+", "slide-", *(f"crush-{j + 1}" for j in range(m)), *(f"crush+{j + 1}" for j in range(m)))


def joint_area(s: Structure) -> np.ndarray:
    """2 d b a contact: the area the cohesion acts on."""
    return 2.0 * s.d * s.thickness


def strength_rows(s: Structure):
    """(Y, G, b) of a structure with the joint's strengths (:mod:`.joints`), rows
    ``Y s_f <= b`` a block of nc a kind: slide+ ``mu N + V <= c0 A``, slide-, then the
    facets of :func:`joint_facets` (their M coefficient -1 for the lower half, +1 for the
    upper). G: the fictitious system's flow rows, whose slides carry no N (its cohesion is
    ``c0 A - mu N`` of the real forces), facets as in Y (associative: a crushed joint
    overlaps). With m = 1 and no strengths these are :func:`yield_matrix` and
    :func:`flow_matrix` with b = 0."""
    nc = s.n_contacts
    a, beta = joint_facets(s)
    m = a.shape[0] // 2
    I, Z = sp.identity(nc, format="csr"), sp.csr_matrix((nc, nc))
    sides = [-1.0] * m + [1.0] * m
    facet_rows = [[sp.diags(a[j]), Z, side * I] for j, side in enumerate(sides)]
    Mu = sp.diags(s.mu)
    Y = sp.bmat([[Mu, I, Z], [Mu, -I, Z]] + facet_rows, format="csr")
    G = sp.bmat([[Z, I, Z], [Z, -I, Z]] + facet_rows, format="csr")
    cA = s.cohesion * joint_area(s)
    return Y, G, np.concatenate([cA, cA, beta.ravel()])


def generator_matrix(structure: Structure, friction=None) -> sp.csr_matrix:
    """T (3 nc x 4 nc): the four friction-cone generators of a contact as (N, V, M).

    Generator ``(j, +/-)`` is the unit-compression force ``-n +/- mu t`` at end point j of
    the contact (j = 1: centre + d t; j = 2: centre - d t). Moved to the contact centre
    it is ``N = -1``, ``V = +/- mu`` and the couple ``(+/- d t) x (-n) = +/- d``. Columns
    are ordered 1+, 1-, 2+, 2- contact after contact. With it, the admissible set of
    eq. (1)-(4) is ``A T lambda + alpha fbar = -f0`` with lambda >= 0 (every (N, V, M) of
    the cone is such a combination and vice versa). ``friction`` (one a contact) replaces
    mu: the cone of another friction coefficient (:func:`dilatant_flows`).
    """
    nc = structure.n_contacts
    mu = structure.mu if friction is None else np.broadcast_to(np.asarray(friction, float), (nc,))
    d = structure.d
    k = np.arange(nc)
    rows, cols, vals = [], [], []
    for g, (sv, sm) in enumerate(((1, 1), (-1, 1), (1, -1), (-1, -1))):
        col = 4 * k + g
        rows += [k, nc + k, 2 * nc + k]
        cols += [col, col, col]
        vals += [-np.ones(nc), sv * mu, sm * d]
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(3 * nc, 4 * nc))


def cohesive_matrix(structure: Structure) -> sp.csr_matrix:
    """Tc (3 nc x 3 nc): columns (n1, n2, V) per contact for the fictitious cohesive LP.

    n1, n2 >= 0 are the compressions at the two end points (``N = -(n1 + n2)``,
    ``M = d (n1 - n2)``: the hinge rows of eq. (4) as signs), V the shear, bounded by the
    cohesion. Columns ordered n1, n2, V contact after contact.
    """
    nc = structure.n_contacts
    d = structure.d
    k = np.arange(nc)
    rows = [k, 2 * nc + k, k, 2 * nc + k, nc + k]
    cols = [3 * k, 3 * k, 3 * k + 1, 3 * k + 1, 3 * k + 2]
    vals = [-np.ones(nc), d, -np.ones(nc), -d, np.ones(nc)]
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(3 * nc, 3 * nc))


def shear_matrix(structure: Structure) -> sp.csr_matrix:
    """(3 nc x nc): a cohesive shear V per contact as (N, V, M)."""
    nc = structure.n_contacts
    return sp.csr_matrix((np.ones(nc), (nc + np.arange(nc), np.arange(nc))), shape=(3 * nc, nc))


def dilatant_flows(structure: Structure, q: np.ndarray, dilatancy: float) -> np.ndarray:
    """The flows xi (4 nc) of contact strains ``q = (opening, slip, rotation)`` (3 nc) in the
    fictitious system of dilatancy t = ``dilatancy``.

    That system's yield rows are ``t mu N +/- V <= c`` and the hinge rows of eq. (4), with
    associative flow: a slip s opens the contact by ``t mu |s|``. At t = 1 (c = 0) it is
    the associative system, at t = 0 the seed's cohesive one (:func:`flow_matrix`). With
    ``c = -(1 - t) mu N`` of a statics of S its rows have the slacks of eq. (4), so
    ``alpha_K - alpha = xi^T slack`` holds at every t (the gap of eq. 5). From
    ``q = G_t^T xi``: ``xi_slide+- = max(+-slip, 0)``; what is left of the opening,
    ``r = opening - t mu |slip|``, and the rotation give the hinge flows
    ``xi_hinge+- = (r / d -+ rotation) / 2``.
    """
    nc = structure.n_contacts
    qn, qv, qm = q[:nc], q[nc:2 * nc], q[2 * nc:]
    rest = (qn - dilatancy * structure.mu * np.abs(qv)) / structure.d
    return np.maximum(np.concatenate([qv, -qv, (rest - qm) / 2, (rest + qm) / 2]), 0.0)


def held_generators(nc: int) -> np.ndarray:
    """(4 nc, 2): the two generators (columns of :func:`generator_matrix`) whose lambdas a
    yield row's slack is made of, row by row (slide+, slide-, hinge+, hinge-).

    Holding a yield row at equality is fixing those two lambdas at 0: slide+ {1-, 2-},
    slide- {1+, 2+}, hinge+ {1+, 1-}, hinge- {2+, 2-}. From the pattern, not from the
    slacks' nonzeros: with mu = 0 a slide's slack coefficients vanish (and holding it
    constrains nothing more).
    """
    k4 = 4 * np.arange(nc)
    return np.concatenate([np.column_stack([k4 + a, k4 + b]) for a, b in ((1, 3), (0, 2), (0, 1), (2, 3))])


def xi_bounds(s: Structure, factor: float = 100.0) -> np.ndarray:
    """Upper bounds on the 4 nc flow multipliers, from the data.

    A mechanism normalised by ``fbar^T u = 1`` moves a block carrying the smallest live
    load by at most about 1/|fbar_min|; slips are lengths of that size, hinge rotations
    that size over d. ``factor`` leaves ample room. Without such a bound, multipliers of
    order 1e7 on contacts with N ~ 0 turn 1e-8 violations into a fake, low alpha.
    """
    mag = np.hypot(s.live[:, 0], s.live[:, 1])
    if not np.any(mag > 0):  # only live couples: a couple m turning a block by u/L does work m u/L
        mag = np.abs(s.live_m) / s.size()
    U = 1.0 / mag[mag > 0].min()
    slide = np.full(s.n_contacts, factor * U)
    hinge = factor * U / s.d  # the N-M facets of joints with strengths flow rotations too
    return np.concatenate([slide, slide] + [hinge] * (len(row_names(s)) - 2))


def kinematic_multiplier(f0, mu, u, xi, N, b=None) -> float:
    """alpha_K = -u^T f0 - xi^T N_mu s_N (eq. 5): the work of the dead loads plus the
    dissipation on the fictitious cohesion -mu N (only the sliding rows dissipate). With
    the joint's strengths (``b``: the right-hand sides of :func:`strength_rows`) every row
    also dissipates ``xi b``: the cohesion on the slides, crushing and tension on the
    facets."""
    nc = len(mu)
    alpha = float(-np.dot(f0, u) - np.sum(mu * N * (xi[:nc] + xi[nc:2 * nc])))
    return alpha if b is None else alpha + float(xi @ b)


@dataclass
class Statics:
    """Eq. 1 of one structure (plane or space): its equilibrium matrix and load vectors."""

    structure: object
    A: sp.csr_matrix
    f0: np.ndarray
    fbar: np.ndarray


@dataclass
class Formulation(Statics):
    """The matrices of one structure, built once (every solver of it shares them)."""

    Y: sp.csr_matrix
    G: sp.csr_matrix
    #: right-hand sides of ``Y s_f <= b`` with the joint's strengths (None: eq. 4, b = 0)
    b: np.ndarray | None = None
    #: ... as the programs take them: +inf on the rows of far strengths (:func:`far_bounds`)
    b_far: np.ndarray | None = None

    @classmethod
    def of(cls, s: Structure) -> "Formulation":
        f0, fbar = load_vectors(s)
        if s.has_materials:
            Y, G, b = strength_rows(s)
            return cls(s, equilibrium_matrix(s), f0, fbar, Y, G, b, far_bounds(s, b))
        return cls(s, equilibrium_matrix(s), f0, fbar, yield_matrix(s), flow_matrix(s))

    @property
    def nb(self) -> int:
        return self.structure.n_blocks

    @property
    def nc(self) -> int:
        return self.structure.n_contacts

    def slack(self, s_f) -> np.ndarray:
        """b - Y s_f: the yield slacks (>= 0 when admissible), stacked by row (b = 0 for eq. 4;
        the real b, however far: the residual test checks a state against it)."""
        out = -(self.Y @ s_f[:3 * self.nc])
        return out if self.b is None else out + self.b

    def kinematic_multiplier(self, u, xi, N) -> float:
        return kinematic_multiplier(self.f0, self.structure.mu, u, xi, N, self.b)
