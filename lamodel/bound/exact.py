"""The certificates of the bound, checked in exact rational arithmetic on the user's data.

Every float of the structure's matrices (:mod:`lamodel.formulation.matrices`, user units)
is taken as the exact rational it represents; HiGHS's points are turned into rationals and
checked with :class:`fractions.Fraction`, so a bound that passes holds for those data
without any rounding error.

* :meth:`ExactData.dual_bound` — a lower bound on ``min -N_k`` (or a proof that a region of
  statics is empty) from any multipliers y of the equilibrium rows, by weak duality. The
  yield rows' multipliers are chosen exactly from y; where ``-N_j`` has no upper bound
  and the reduced cost comes out positive (HiGHS's tolerance), y is moved along an
  exactly checked opening motion (a dual correction) until it is exactly dual feasible.
* :meth:`ExactData.cohesive_bound` — a lower bound on ``alpha_coh(c)``: the cohesive
  LP's statics rebuilt from its basis by exact elimination (equilibrium exactly zero),
  then every row of the cohesive system checked against the true cohesions and
  half-lengths. Its alpha is the bound.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..formulation.matrices import equilibrium_matrix, load_vectors
from ..structure import Structure


def weights(k) -> dict:
    """An objective on the ``-N``: None (zero), a contact (weight 1) or {contact: weight}."""
    if k is None:
        return {}
    if isinstance(k, dict):
        return {int(j): float(w) for j, w in k.items()}
    return {int(k): 1.0}


def _q(x) -> Fraction:
    return Fraction(float(x))


def floor_float(q: Fraction) -> float:
    """The largest float <= q (a bound rounded in the safe direction)."""
    f = float(q)
    if Fraction(f) > q:
        f = math.nextafter(f, -math.inf)
    return f


class ExactData:
    """The user's eq. (1)-(4) data as exact rationals, and the checks that use them."""

    #: the dual correction's step is taken this much longer (1: the reduced costs are
    #: exactly convex in y; in space their norms are rounded up, so a little more)
    step_slack = Fraction(1)

    def __init__(self, structure: Structure):
        s = structure
        self.nb, self.nc = s.n_blocks, s.n_contacts
        self._load(equilibrium_matrix(s), *load_vectors(s), s.mu)
        self.d = [_q(v) for v in s.d]

    def _load(self, A, f0, fb, mu):
        """The equilibrium matrix A, loads f0, fbar and friction coefficients, exactly."""
        A = sp.csc_matrix(A)
        A.sum_duplicates()
        self.cols = [[(int(i), _q(v)) for i, v in zip(A.indices[A.indptr[j]:A.indptr[j + 1]],
                                                       A.data[A.indptr[j]:A.indptr[j + 1]])]
                     for j in range(A.shape[1])]
        # the same entries as dyadic integers (value = int * 2**exponent) for fast dot products
        Ai, self._eA = _dyadic(A.data)
        self._icols = [(A.indices[A.indptr[j]:A.indptr[j + 1]].tolist(), Ai[A.indptr[j]:A.indptr[j + 1]])
                       for j in range(A.shape[1])]
        self._f0i, self._fbi = _dyadic(f0), _dyadic(fb)
        self.f0 = [_q(v) for v in f0]
        self.fbar = [_q(v) for v in fb]
        self.mu = [_q(v) for v in mu]
        self.y0 = None      # exact opening motion (list of Fractions), set by use_opening_motion
        self.r0 = None      # its reduced costs of -N (each < 0)
        self._opening = None  # where to find y0 when first needed (see opening_from)

    # ------------------------------------------------------------------ dual side
    def _products(self, y):
        """(A^T y, y^T f0, y^T fbar), exact, for floats y: integer sums of dyadic numbers."""
        Y, ey = _dyadic(y)
        scale = _pow2(self._eA + ey)
        t = [scale * sum(a * Y[i] for i, a in zip(rows, vals)) for rows, vals in self._icols]
        return t, _dot(Y, ey, self._f0i), _dot(Y, ey, self._fbi)

    def _reduced(self, t, k):
        """Reduced costs of -N's objective row: the yield multipliers chosen for the shear
        and moment terms to vanish exactly, ``r_N = c_N + t_N + mu |t_V| + d |t_M|``."""
        nc = self.nc
        r = [t[j] + self.mu[j] * abs(t[nc + j]) + self.d[j] * abs(t[2 * nc + j]) for j in range(nc)]
        for j, w in weights(k).items():
            r[j] -= _q(w)
        return r

    def use_opening_motion(self, y0) -> bool:
        """Keep y0 as the correction direction if every contact's reduced cost of N under
        it is exactly negative."""
        if y0 is None:
            return False
        products = self._products(np.asarray(y0, float))
        r0 = self._reduced(products[0], None)
        if all(v < 0 for v in r0):
            self.y0, self.r0 = products, r0
            return True
        return False

    def opening_from(self, find):
        """Find the opening motion with ``find()`` (an LP: seconds on thousands of contact
        points) only when a certificate first needs the correction."""
        self._opening = find

    def dual_bound(self, y, k, a, b, lo, hi):
        """Exact lower bound on ``min -N_k`` over the admissible statics with alpha in
        [a, b] and ``lo <= -N <= hi`` (hi may hold inf), from multipliers y (floats).

        ``k`` a dict {contact: weight}: on the weighted sum of the ``-N``. ``k=None``: the
        zero objective; a result > 0 proves the region empty. Returns a
        Fraction, or None when y cannot be made exactly dual feasible."""
        t, yf0, yfb = self._products(np.asarray(y, float))
        r = self._reduced(t, k)
        bad = [j for j in range(self.nc) if r[j] > 0 and not math.isfinite(hi[j])]
        if bad:
            if self.y0 is None and self._opening is not None:
                find, self._opening = self._opening, None
                self.use_opening_motion(find())
            if self.y0 is None:
                return None
            # reduced costs are convex in y: r(y + s y0) <= r(y) + s r0, exactly
            step = max(r[j] / -self.r0[j] for j in bad) * self.step_slack
            t0, f0, fb = self.y0
            t = [ti + step * si for ti, si in zip(t, t0)]
            yf0, yfb = yf0 + step * f0, yfb + step * fb
            r = self._reduced(t, k)
            if any(r[j] > 0 and not math.isfinite(hi[j]) for j in range(self.nc)):
                return None
        bound = yf0
        for j in range(self.nc):
            if r[j] > 0:
                bound -= r[j] * _q(hi[j])   # N_j = -hi_j
            elif r[j] < 0:
                bound -= r[j] * _q(lo[j])   # N_j = -lo_j
        bound += min(yfb * _q(a), yfb * _q(b))
        return bound

    def empty(self, ray, a, b, lo, hi) -> bool:
        """Whether a Farkas ray (either sign) proves the region of statics empty."""
        if ray is None:
            return False
        for sign in (1.0, -1.0):
            q = self.dual_bound(sign * np.asarray(ray), None, a, b, lo, hi)
            if q is not None and q > 0:
                return True
        return False

    # ------------------------------------------------------------------ primal side
    def cohesive_bound(self, answer, limits, c, d_shrunk):
        """Exact lower bound on ``alpha_coh(c)`` from the cohesive LP's ``answer``
        (:class:`lamodel.bound.lps.LPAnswer`), or None when its statics cannot be rebuilt
        exactly inside the rows.

        ``c``: the true cohesions (Fractions); ``limits``: the LP's column bounds (user
        units) where its nonbasic columns sit; ``d_shrunk``: the half-lengths of its
        columns. The statics is rebuilt with the LP's basic columns solved exactly."""
        if answer.basic is None:
            return None
        nc = self.nc
        ncol = 3 * nc + 1
        dq = [_q(v) for v in d_shrunk]
        # columns (n1, n2, V) per contact then alpha, as sparse rational columns
        colN = {k: dict(self.cols[k]) for k in range(nc)}

        def column(j):
            k, kind = divmod(j, 3)
            if j == ncol - 1:
                return {i: v for i, v in enumerate(self.fbar) if v}
            if kind == 2:
                return dict(self.cols[nc + k])
            sign = 1 if kind == 0 else -1
            out = {i: -v for i, v in colN[k].items()}
            for i, v in self.cols[2 * nc + k]:
                out[i] = out.get(i, Fraction(0)) + sign * dq[k] * v
            return out

        x = rebuild(column, ncol, answer, limits, [-v for v in self.f0])
        if x is None:
            return None
        alpha = x[-1]
        N = [-(x[3 * k] + x[3 * k + 1]) for k in range(nc)]
        V = [x[3 * k + 2] for k in range(nc)]
        M = [dq[k] * (x[3 * k] - x[3 * k + 1]) for k in range(nc)]
        if self.check_cohesive(N, V, M, alpha, c):
            return alpha
        return None

    def check_cohesive(self, N, V, M, alpha, c) -> bool:
        """Exactly: ``A s_f + f0 + alpha fbar = 0``, ``|V| <= c``, ``d N -/+ M <= 0``."""
        nc = self.nc
        res = [self.f0[i] + alpha * self.fbar[i] for i in range(3 * self.nb)]
        for j, col in enumerate(self.cols):
            v = (N, V, M)[j // nc][j % nc]
            if v:
                for i, a in col:
                    res[i] += a * v
        if any(res):
            return False
        for k in range(nc):
            if abs(V[k]) > c[k] or self.d[k] * N[k] - M[k] > 0 or self.d[k] * N[k] + M[k] > 0:
                return False
        return True


def rebuild(column, ncol, answer, limits, rhs, room=None):
    """An LP's point rebuilt exactly from its basis (a list of Fractions), or None.

    ``column(j)``: column j of the equality rows ``B x = rhs`` as {row: Fraction};
    ``answer.basic``/``answer.at_upper``: HiGHS's basis; ``limits``: (lo, hi) where the
    nonbasic columns sit (a free nonbasic column at 0). The basic columns are solved
    exactly, so the rows hold exactly. Where HiGHS left a row's slack basic (a row held
    to its tolerance only), ``room`` (bool per column: its bound was shrunk inside the
    true one, so it may move a little) names the nonbasic columns that may complete the
    basis (chosen by a float QR with pivoting)."""
    if answer.basic is None:
        return None
    lo, hi = limits
    # a fixed column (a zero cohesion) sits at its value even where HiGHS calls it basic
    fixed = np.asarray(lo) == np.asarray(hi)
    basic = np.flatnonzero(answer.basic & ~fixed)
    if basic.size > len(rhs):
        return None
    if basic.size < len(rhs) and room is not None:
        basic = _completed(column, basic, np.flatnonzero(np.asarray(room) & ~answer.basic & ~fixed), len(rhs))
    x = [None] * ncol
    rhs = list(rhs)
    set_basic = set(basic.tolist())
    for j in range(ncol):
        if j in set_basic:
            continue
        bound = hi[j] if answer.at_upper[j] else lo[j]
        if not math.isfinite(bound):
            bound = 0.0  # a free column nonbasic at zero
        x[j] = _q(bound)
        if x[j]:
            for i, v in column(j).items():
                rhs[i] -= v * x[j]
    rows = [dict() for _ in range(len(rhs))]
    for p, j in enumerate(basic):
        for i, v in column(j).items():
            if v:
                rows[i][p] = v
    sol = solve_exact(rows, rhs, _column_order(rows, basic.size))
    if sol is None:
        return None
    for p, j in enumerate(basic):
        x[j] = sol[p]
    return x


def _completed(column, basic, candidates, m):
    """``basic`` and as many of ``candidates`` as make m independent columns (floats)."""

    def dense(cols):
        M = np.zeros((m, len(cols)))
        for q, j in enumerate(cols):
            for i, v in column(int(j)).items():
                M[i, q] = float(v)
        return M
    B, C = dense(basic), dense(candidates)
    if not candidates.size:
        return basic
    Q = la.qr(B, mode="economic")[0] if basic.size else np.zeros((m, 0))
    C = C - Q @ (Q.T @ C)
    _, R, piv = la.qr(C, mode="economic", pivoting=True)
    d = np.abs(np.diag(R))
    need = m - basic.size
    take = [candidates[piv[q]] for q in range(min(need, d.size)) if d[q] > 1e-9 * max(1.0, d[0])]
    return np.sort(np.concatenate([basic, np.asarray(take, int)]))


def _dyadic(values):
    """Floats as integers times one power of two: (ints, exponent), exactly."""
    values = np.asarray(values, float)
    m, e = np.frexp(values)
    e = e.astype(np.int64) - 53
    ints = [int(x) for x in np.ldexp(m, 53)]  # exact: 53-bit mantissas
    low = int(e[values != 0].min()) if np.any(values != 0) else 0
    return [v << int(x - low) if v else 0 for v, x in zip(ints, e)], low


def _pow2(e) -> Fraction:
    return Fraction(2 ** e) if e >= 0 else Fraction(1, 2 ** -e)


def _dot(Y, ey, vec) -> Fraction:
    """y^T vec exactly, y and vec as dyadic integers."""
    V, ev = vec
    return _pow2(ey + ev) * sum(a * b for a, b in zip(Y, V))


def _column_order(rows, n):
    """A fill-reducing order of the unknowns (scipy's COLAMD through SuperLU)."""
    r, c, v = [], [], []
    for i, row in enumerate(rows):
        for j, a in row.items():
            r.append(i)
            c.append(j)
            v.append(float(a))
    B = sp.csc_matrix((v, (r, c)), shape=(len(rows), n))
    try:
        return list(splu(B, permc_spec="COLAMD").perm_c.argsort())
    except (RuntimeError, ValueError):  # singular or not square: the exact solve decides
        return list(range(n))


def solve_exact(rows, rhs, order):
    """Solve ``B x = rhs`` exactly (rows: dicts column -> Fraction), eliminating the
    columns in ``order`` with the sparsest exactly nonzero pivot row. None if singular."""
    rows = [dict(r) for r in rows]
    b = list(rhs)
    where = {}
    for i, row in enumerate(rows):
        for j in row:
            where.setdefault(j, set()).add(i)
    used, pivots = set(), []
    for j in order:
        cand = [i for i in where.get(j, ()) if i not in used and rows[i].get(j)]
        if not cand:
            return None
        p = min(cand, key=lambda i: len(rows[i]))
        used.add(p)
        pivots.append((p, j))
        prow, pv = rows[p], rows[p][j]
        for i in list(where[j]):
            if i in used or not rows[i].get(j):
                continue
            f = rows[i][j] / pv
            for jj, v in prow.items():
                nv = rows[i].get(jj, 0) - f * v
                if nv:
                    rows[i][jj] = nv
                    where.setdefault(jj, set()).add(i)
                else:
                    rows[i].pop(jj, None)
                    where[jj].discard(i)
            b[i] -= f * b[p]
    if any(b[i] for i in range(len(rows)) if i not in used):
        return None  # more rows than unknowns and these do not hold
    x = {}
    for p, j in reversed(pivots):
        acc = b[p] - sum((v * x[jj] for jj, v in rows[p].items() if jj != j), Fraction(0))
        x[j] = acc / rows[p][j]
    return x
