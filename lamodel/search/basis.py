"""Exact solves with an LP's final basis (:class:`lamodel.search.highs.HighsLP`'s exact
primal values and duals): HiGHS's own are exact only to its tolerances."""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu


def solve(A, cols, rows, rhs, transpose=False):
    """Solve B v = rhs (B^T v = rhs) with B = [A_cols | unit columns of rows]; None if B
    is singular. A basic row's unit column makes B block-triangular, so only the rows
    at a bound (as many as basic columns) are factorised: with joints' strengths most
    of the yield rows are basic and B shrinks to a tenth. B is gathered from A's CSC
    arrays directly (scipy's slicing and stacking cost more than the factorisation on
    small models)."""
    m = A.shape[0]
    at_bound = np.ones(m, bool)
    at_bound[rows] = False
    tight = np.flatnonzero(at_bound)  # the rows of the reduced system, ascending
    if tight.size != cols.size:
        return None
    new_row = np.full(m, -1, np.int64)
    new_row[tight] = np.arange(tight.size)
    start, count = A.indptr[cols], np.diff(A.indptr)[cols]
    # positions in A.indices of every entry of the chosen columns, column by column
    pos = np.repeat(start - np.r_[0, np.cumsum(count)[:-1]], count) + np.arange(count.sum())
    col_of = np.repeat(np.arange(cols.size), count)
    row_of, val = A.indices[pos], A.data[pos]
    keep = at_bound[row_of]
    Bt = sp.csc_matrix((val[keep], (new_row[row_of[keep]], col_of[keep])),
                       shape=(cols.size, cols.size))
    v = np.zeros(m)
    lu = None
    try:
        if cols.size:
            lu = splu(Bt)
        if transpose:
            # a basic row's unit column fixes its dual; the tight rows' follow from the
            # basic columns' equations
            v[rows] = rhs[cols.size:]
            r = rhs[:cols.size] - np.bincount(col_of, val * v[row_of], minlength=cols.size)
            if lu is not None:
                v[tight] = lu.solve(r, trans="T")
            return v
        if lu is not None:
            v[:cols.size] = lu.solve(rhs[tight])
    except RuntimeError:
        return None
    # the basic rows' unit columns take what the basic columns leave of rhs
    v[cols.size:] = rhs[rows] - np.bincount(row_of, val * v[col_of], minlength=m)[rows]
    return v

