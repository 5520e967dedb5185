"""Mirror symmetry of a planar assembly, and the mirror image of a collapse state.

An assembly is mirror-symmetric when reflecting it about a vertical line ``x = x0`` maps
its blocks onto its blocks (polygons and dead loads reflected) and its contacts onto its
contacts (same half-length, friction and strengths; a support onto a support).
Gravity is vertical, so the vertical line is the only mirror dead loads can have. Two
variants of it (load cases, positions of a rolling load) are mirror images when the live
loads of one are those of the other reflected.

The mirror image of a collapse state of one variant is then a collapse state of the other
at the same alpha: statics, mechanism and flows reflected. In the conventions of
:mod:`lamodel.structure` (``t = (-n_y, n_x)``, ``N n + V t`` and ``M`` acting on block a)
a contact k maps to k' either with its ends in the same order (a' the image of a) or
swapped. Either way N is kept and V changes sign (a reflection reverses the tangent), so
the two slides trade places; the couple changes sign when the ends keep their order
(a hinge at one edge becomes a hinge at the other: the two halves of the N-M rows trade
places) and keeps it when they swap. Block motions ``(u_x, u_y, theta)`` at the centroid
reflect to ``(-u_x, u_y, -theta)``. The image is re-checked on the mirror variant by the
residual test every reported state passes (:func:`image_on`), or given to its search as a
mechanism to certify (:func:`lamodel.search.driver.solve`'s ``mechanisms``).
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .formulation.matrices import Formulation
from .search.certify import residuals
from .search.state import CollapseState
from .search.tuning import CANONICAL_TOLERANCE, RESIDUAL_TOLERANCE
from .structure import Structure

#: per-contact values that must agree between a contact and its image
_SAME = ("d", "mu", "fc", "ft", "cohesion", "thickness")


@dataclass(frozen=True)
class Mirror:
    """The reflection of an assembly onto itself: ``blocks[i]`` is the image of block i,
    ``contacts[k]`` that of contact k, ``swapped[k]`` whether its ends swap, ``x0`` the line."""

    blocks: np.ndarray
    contacts: np.ndarray
    swapped: np.ndarray
    x0: float


def mirror_of(s: Structure) -> Mirror | None:
    """The reflection of ``s`` onto itself about a vertical line, or None if it has none
    (geometry, supports, joints and dead loads compared within CANONICAL_TOLERANCE of the
    structure's size and of its largest dead load)."""
    if s.n_blocks < 1 or s.n_contacts < 1:
        return None
    tol = CANONICAL_TOLERANCE * s.size()
    x0 = 0.5 * (s.centroid[:, 0].min() + s.centroid[:, 0].max())
    image = _reflect(s.centroid, x0)
    blocks = _match(image, s.centroid, tol)
    if blocks is None or not _polygons_agree(s, blocks, x0, tol):
        return None
    scale = CANONICAL_TOLERANCE * max(np.abs(s.dead).max(), np.abs(s.dead_m).max() / s.size(), 1e-300)
    if not _loads_agree(s.dead, s.dead_m, s.dead, s.dead_m, blocks, scale, s.size()):
        return None
    contacts = _match(_reflect(s.centre, x0), s.centre, tol, many=True)
    if contacts is None:
        return None
    ends = _ends(s)
    chosen, swapped = np.full(s.n_contacts, -1), np.zeros(s.n_contacts, bool)
    for k in range(s.n_contacts):
        for j in contacts[k]:
            if not all(getattr(s, f)[k] == getattr(s, f)[j] or np.isclose(getattr(s, f)[k], getattr(s, f)[j],
                                                                          rtol=1e-9, atol=0) for f in _SAME):
                continue
            normal = _reflect_vector(s.normal[k])
            for swap in (False, True):
                ak, bk = ends[k][::-1] if swap else ends[k]
                if (np.allclose(s.normal[j], -normal if swap else normal, atol=1e-6)
                        and _end_maps(ak, ends[j][0], blocks) and _end_maps(bk, ends[j][1], blocks)):
                    chosen[k], swapped[k] = j, swap
                    break
            if chosen[k] >= 0:
                break
        if chosen[k] < 0:
            return None
    if len(set(chosen.tolist())) != s.n_contacts:
        return None
    return Mirror(blocks, chosen, swapped, float(x0))


def mirror_loads(s: Structure, other: Structure, m: Mirror) -> bool:
    """Whether the live loads of ``other`` (the same blocks) are those of ``s`` reflected by ``m``."""
    size = s.size()
    big = max(np.abs(s.live).max(), np.abs(other.live).max(),
              np.abs(s.live_m).max() / size, np.abs(other.live_m).max() / size)
    if not big > 0:
        return False
    return _loads_agree(s.live, s.live_m, other.live, other.live_m, m.blocks, CANONICAL_TOLERANCE * big, size)


def mirror_state(st: CollapseState, m: Mirror) -> CollapseState:
    """The image under ``m`` of a collapse state of one variant (the user's order and
    units): a collapse state of the mirror variant at the same alpha (module doc)."""
    nc = len(m.contacts)
    N, V, M = (np.empty(nc) for _ in range(3))
    N[m.contacts], V[m.contacts] = st.N, -st.V
    M[m.contacts] = np.where(m.swapped, st.M, -st.M)
    nb = len(m.blocks)
    u0 = np.asarray(st.u, float).reshape(nb, 3)
    u = np.empty_like(u0)
    u[m.blocks] = u0 * np.array([-1.0, 1.0, -1.0])
    kinds = len(st.xi) // nc
    half = (kinds - 2) // 2
    xi0 = np.asarray(st.xi, float).reshape(kinds, nc)
    flow0 = np.asarray(st.flow, bool).reshape(kinds, nc)
    xi, flow = np.empty_like(xi0), np.empty_like(flow0)
    for kind in range(kinds):
        if kind < 2:
            other = 1 - kind  # the slides trade places
            target = np.full(nc, other)
        else:
            j = kind - 2
            flipped = 2 + (j + half) % (2 * half)  # the other half, the same facet
            target = np.where(m.swapped, kind, flipped)
        xi[target, m.contacts] = xi0[kind]
        flow[target, m.contacts] = flow0[kind]
    return replace(st, N=N, V=V, M=M, u=u.reshape(-1), xi=xi.reshape(-1), flow=flow.reshape(-1),
                   source=f"mirror of {st.source}" if st.source else "mirror", residual={})


def image_on(other: Structure, st: CollapseState, m: Mirror) -> CollapseState | None:
    """The image of ``st`` under ``m`` as a collapse state of ``other`` (the mirror variant,
    user's units), with its residuals there (:func:`lamodel.search.certify.residuals`, the
    check of every reported state); None if it fails that check."""
    image = mirror_state(st, m)
    image.residual = residuals(Formulation.of(other), image.N, image.V, image.M, image.alpha, image.u, image.xi)
    return image if max(image.residual.values()) <= RESIDUAL_TOLERANCE else None


# ----------------------------------------------------------------------------- helpers
def _reflect(points, x0):
    out = np.array(points, float, copy=True)
    out[:, 0] = 2 * x0 - out[:, 0]
    return out


def _reflect_vector(v):
    return np.array([-v[0], v[1]], float)


def _match(image, points, tol, many=False):
    """For each image point the index (``many``: the candidate indices) of the points
    within ``tol`` of it; None if one has none (or, not ``many``, if the map is not one-to-one)."""
    order = np.argsort(points[:, 0], kind="stable")
    xs = points[order, 0]
    out = []
    for p in image:
        lo, hi = np.searchsorted(xs, p[0] - tol), np.searchsorted(xs, p[0] + tol, side="right")
        near = [int(order[i]) for i in range(lo, hi) if abs(points[order[i], 1] - p[1]) <= tol]
        if not near:
            return None
        out.append(near if many else near[0])
    if many:
        return out
    out = np.array(out, int)
    return out if len(set(out.tolist())) == len(out) else None


def _polygons_agree(s, blocks, x0, tol):
    """Every block's polygon reflected is its image's (as sets of vertices)."""
    if not s.polygons:
        return True
    for i, j in enumerate(blocks):
        p, q = s.polygons.get(s.blocks[i]), s.polygons.get(s.blocks[j])
        if p is None or q is None:
            if (p is None) != (q is None):
                return False
            continue
        if len(p) != len(q) or _match(_reflect(p, x0), q, tol) is None:
            return False
    return True


def _loads_agree(f, fm, g, gm, blocks, tol, size):
    """The loads (f, fm) reflected onto the images are (g, gm)."""
    return (np.allclose(g[blocks, 0], -f[:, 0], atol=tol, rtol=0) and np.allclose(g[blocks, 1], f[:, 1], atol=tol, rtol=0)
            and np.allclose(gm[blocks], -fm, atol=tol * size, rtol=0))


def _ends(s):
    """Per contact its ends (a, b), each ("block", index) or ("support", id)."""
    a, b = s.contact_blocks()
    def end(i, name):
        return ("block", int(i)) if i >= 0 else ("support", name)
    return [(end(a[k], s.block_a[k]), end(b[k], s.block_b[k])) for k in range(s.n_contacts)]


def _end_maps(mine, theirs, blocks):
    """Whether end ``theirs`` is the image of end ``mine``: a block's image by ``blocks``; a
    support, any support (supports do not move: which one holds a contact does not enter
    the statics or the mechanism)."""
    if mine[0] == "block":
        return theirs == ("block", int(blocks[mine[1]]))
    return theirs[0] == "support"
