"""The strength of a planar joint: crushing, tension and cohesion (eq. 4 extended).

A joint of half-length d and thickness b (out of the plane) carries normal stresses
between ``-f_c`` (crushing) and ``f_t`` (tension) under a rigid-plastic rectangular stress
block. Its (N, M) domain is bounded by the parabola

    |M| <= b (f_c + f_t) / 2 (d^2 - a^2),  a = (N / b - (f_t - f_c) d) / (f_t + f_c),

for ``-2 d b f_c <= N <= 2 d b f_t`` (a is where the stress changes sign; with f_t = 0 it
is ``|M| <= |N| (d - |N| / (2 f_c b))``). With f_c infinite it is the cone of eq. (4) with
its apex moved to ``N_t = 2 d b f_t``: ``d (N - N_t) +/- M <= 0``. The shear obeys
Coulomb's law with cohesion, ``mu N +/- V <= c0 (2 d b)`` (N <= 0 compression, so
``-mu N = mu |N|``).

The parabola is replaced by the **inscribed** polygon whose vertices lie on it at the
fractions ``x = (N_t - N) / (N_t - N_c)`` (N_c = -2 d b f_c): ``x = sin^2(theta)``, theta
uniform in [0, pi/2] (m facets a half; vertices crowd at both ends, where the moment
capacity is small), and below the first of them ``x_1 / r^k`` down to a floor (K more
facets near the tension end, r the fan's ratio). At every N the polygon's moment capacity
is at least ``1 - eps`` times the parabola's, ``eps <= sin^2(pi / (2 m))`` everywhere
(attained mid-chord) and ``eps <= max((r - 1)^2 / (4 r) x / (1 - x), x_1)`` near the tension end
(x_1, the smallest vertex fraction, is below r times the floor): as f_c grows the polygon
tends to within that of the cone of eq. (4)
(:func:`relative_error_bound`; m and the floor:
:data:`~lamodel.search.tuning.CRUSHING_FACETS`, ``CRUSHING_FLOOR``, ``CRUSHING_FAN_RATIO``). The polygon lies
inside the parabola: every statics admissible for it is admissible for the stress block
(no stress beyond f_c or f_t; static side), its dissipation for any joint motion is at most
the stress block's (kinematic side: every alpha_K at most the parabola's), and with
associative joints its alpha is at most the parabola's (static theorem) and at least that
of the domain shrunk by ``1 - eps``; with non-associative friction no alpha is monotone in
the domain, and the polygonal joint's alpha is what is reported. Every reported alpha is
exact for the polygonal joint.

Rows of a joint, each ``a N + v V + s M <= beta`` with ``|s| = 1`` for the N-M facets
(their slacks are moments, their flows rotations, like the hinge rows of eq. 4): slide+,
slide-, then its facets, lower half (``s = -1``, M >= ..., the hinge+ row of eq. 4 when
f_c is infinite) from the tension end to the crushing end, then the upper half.
"""
from __future__ import annotations

import numpy as np


def moment_capacity(N, d, b, fc, ft=0.0):
    """The stress block's largest |M| at normal force N (the parabola; -inf outside
    ``[-2 d b f_c, 2 d b f_t]``)."""
    N = np.asarray(N, float)
    if np.isinf(fc):
        out = d * (2 * d * b * ft - N)
        return np.where(N <= 2 * d * b * ft, out, -np.inf)
    a = (N / b - (ft - fc) * d) / (ft + fc)
    out = b * (fc + ft) / 2 * (d * d - a * a)
    return np.where(np.abs(a) <= d, out, -np.inf)


def fractions(m: int, floor: float, ratio: float = 4.0) -> np.ndarray:
    """The vertices' fractions x of the way from the tension end to the crushing end
    (module doc): 0, x_1 / r^K .. x_1 / r (r = ``ratio``), then sin^2(theta_i), i = 1..m."""
    grid = np.sin(np.linspace(0.0, np.pi / 2, m + 1)) ** 2
    below = grid[1] / ratio ** np.arange(1, 64)
    below = below[below >= floor][::-1]
    x = np.concatenate([[0.0], below, grid[1:]])
    x[-1] = 1.0
    return x


def polygon(d, b, fc, ft, m, floor, ratio=4.0):
    """The inscribed polygon's upper vertices ``(N_i, M_i)`` from the tension end
    ``N_t = 2 d b f_t`` to the crushing end ``N_c = -2 d b f_c`` (module doc)."""
    Nt, Nc = 2 * d * b * ft, -2 * d * b * fc
    x = fractions(m, floor, ratio)
    N = Nt + (Nc - Nt) * x
    N[0], N[-1] = Nt, Nc
    M = np.maximum(moment_capacity(N, d, b, fc, ft), 0.0)
    M[0] = M[-1] = 0.0
    return N, M


def facets(d, b, fc, ft, m, floor, ratio=4.0):
    """(a, beta) of the upper facets ``a N + M <= beta`` of one joint (the lower ones are
    ``a N - M <= beta``): one for an infinite f_c (the shifted hinge row of eq. 4), else
    the chords of :func:`polygon`."""
    if np.isinf(fc):
        return np.array([d]), np.array([d * 2 * d * b * ft])
    N, M = polygon(d, b, fc, ft, m, floor, ratio)
    a = -(M[1:] - M[:-1]) / (N[1:] - N[:-1])
    return a, M[:-1] + a * N[:-1]


def relative_error_bound(m: int, floor: float = 0.0, x=1.0, ratio: float = 4.0):
    """The inscribed polygon's moment capacity is at least ``1 - this`` times the
    parabola's at fraction x of the way from the tension end to the crushing end (module
    doc; x = 1: anywhere). A chord [y, r y] of the parabola x (1 - x) loses at most
    ``(r - 1)^2 / (4 r) x / (1 - x)`` at x (the most of (x - y)(r y - x) / x^2), the first chord
    [0, x_1] at most its end x_1, the smallest vertex fraction (below ``ratio`` times the
    floor), every chord at most sin^2(pi / (2 m))."""
    first = fractions(m, floor, ratio)[1]
    fan = (ratio - 1) ** 2 / (4 * ratio)
    x = np.asarray(x, float)
    return np.minimum(np.sin(np.pi / (2 * m)) ** 2, np.maximum(fan * x / np.maximum(1 - x, 1e-300), first))
