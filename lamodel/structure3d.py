"""A block assembly in space as data: polyhedral blocks, supports, interfaces, contact points.

The 3D counterpart of :class:`lamodel.structure.Structure`; the matrices of eq. (1)-(5) in
3D built from these data live in :mod:`lamodel.formulation` (point-contact model).

Conventions (used everywhere in lamodel's 3D code, and in the 3D output CSVs):

* z is up; gravity acts along -z.
* An **interface** joins body ``a`` and body ``b`` (either may be a support, not both) over a
  planar polygon (the intersection of two opposite faces). A block pair may share several
  interfaces (non-convex blocks).
* Each interface carries **contact points** (by default its polygon's vertices). At point i
  the unit normal ``n`` points from a to b; ``t1``, ``t2`` are unit tangents with
  ``(n, t1, t2)`` right-handed and orthonormal.
* The force ``N n + T1 t1 + T2 t2`` acts on body a at the point, its opposite on body b.
  ``N <= 0`` is compression (as in 2D); the Coulomb cone reads ``hypot(T1, T2) <= -mu N``.
* Block motions ``u = (ux, uy, uz, rx, ry, rz)`` are taken at the block centroid; block
  forces are ordered ``(fx, fy, fz, mx, my, mz)`` block after block, moments about the
  centroid.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .assembly import Assembly
from .errors import InputError
from .validation import (check_ends, check_finite, check_friction, check_ids, check_live, check_strengths, check_touched,
                         first)


@dataclass
class Structure3D(Assembly):
    """An assembly of rigid polyhedral blocks with Coulomb point contacts (seed eq. 1-4 in 3D)."""

    # name, blocks, centroid (nb, 3), dead, live, supports: Assembly's
    interfaces: list             # ids of the interfaces
    iface_a: list                # per interface: id of body a (a block or a support)
    iface_b: list                # per interface: id of body b
    iface_polygon: list          # per interface: (k, 3) polygon vertices in the face plane
    point_interface: np.ndarray  # (np,) index into interfaces of each contact point
    point: np.ndarray            # (np, 3) position of each contact point
    normal: np.ndarray           # (np, 3) unit normal from a to b
    tangent1: np.ndarray         # (np, 3)
    tangent2: np.ndarray         # (np, 3)
    mu: np.ndarray               # (np,) friction coefficient
    dead_m: np.ndarray | None = None   # (nb, 3) moment of dead loads about the centroid
    live_m: np.ndarray | None = None   # (nb, 3) moment of live loads about the centroid
    volume: np.ndarray | None = None   # (nb,) block volumes (information, pictures)
    polyhedra: dict = field(default_factory=dict)  # id -> (vertices (k, 3), faces [[i, j, k, ...]])
    units: dict = field(default_factory=dict)      # {"length": "m", "force": "kN"}; empty: dimensionless
    meta: dict = field(default_factory=dict)       # defaults applied, source format, ...
    # the joints' strengths per contact point (stresses; the defaults are the dry joint,
    # infinitely strong in compression) and its tributary area (lamodel.geometry.tributary)
    fc: np.ndarray | None = None         # (np,) compressive strength, inf: no crushing
    ft: np.ndarray | None = None         # (np,) tensile strength
    cohesion: np.ndarray | None = None   # (np,) cohesion c0
    area: np.ndarray | None = None       # (np,) tributary area A_i; None: from iface_polygon
    iface_holes: list = field(default_factory=list)  # per interface: [(m, 3) hole rings]; empty: none

    dimension = 3

    def __post_init__(self):
        self._as_text("blocks", "supports", "interfaces", "iface_a", "iface_b")
        f, nb, npt = self._floats, len(self.blocks), len(np.asarray(self.point_interface).reshape(-1))
        self.centroid = f(self.centroid, (nb, 3))
        self.dead = f(self.dead, (nb, 3))
        self.live = f(self.live, (nb, 3))
        self.iface_polygon = [np.asarray(p, dtype=float).reshape(-1, 3) for p in self.iface_polygon]
        self.point_interface = np.asarray(self.point_interface, dtype=int).reshape(npt)
        self.point = f(self.point, (npt, 3))
        self.normal = f(self.normal, (npt, 3))
        self.tangent1 = f(self.tangent1, (npt, 3))
        self.tangent2 = f(self.tangent2, (npt, 3))
        self.mu = f(self.mu, (npt,))
        self.dead_m = np.zeros((nb, 3)) if self.dead_m is None else f(self.dead_m, (nb, 3))
        self.live_m = np.zeros((nb, 3)) if self.live_m is None else f(self.live_m, (nb, 3))
        self.volume = np.zeros(nb) if self.volume is None else f(self.volume, (nb,))
        for name, default in (("fc", np.inf), ("ft", 0.0), ("cohesion", 0.0)):
            value = getattr(self, name)
            setattr(self, name, np.full(npt, default) if value is None else f(value, (npt,)))
        if self.area is not None:
            self.area = f(self.area, (npt,))

    # ----------------------------------------------------------------- sizes and lookups
    @property
    def n_interfaces(self) -> int:
        return len(self.interfaces)

    @property
    def n_points(self) -> int:
        return len(self.point_interface)

    @property
    def has_materials(self) -> bool:
        """Whether some point crushes, takes tension or has cohesion (else the dry cone)."""
        return bool(np.isfinite(self.fc).any() or (self.ft > 0).any() or (self.cohesion > 0).any())

    def areas(self) -> np.ndarray:
        """The tributary area A_i of every contact point (computed once from the
        interfaces' polygons when the reader gave none)."""
        if self.area is None:
            from .geometry.tributary import point_areas
            self.area = point_areas(self.iface_polygon, self.point_interface, self.point, self.iface_holes)
        return self.area

    def caps(self):
        """Per point ``(N_c, N_t, k)``: the crushing force ``-f_c A_i`` (-inf: none), the
        tensile force and the cohesion force ``k = c0 A_i``; the real domain is
        ``N_c <= N <= N_t``, ``||T|| <= k - mu N``. The cone ends at its apex ``N = k / mu``,
        so the tensile force is ``min(f_t A_i, k / mu)``: the tension a point can carry
        (none without cohesion), and where an associative point opens."""
        A = self.areas()
        finite = np.isfinite(self.fc)
        crush = np.where(finite, -np.where(finite, self.fc, 0.0) * A, -np.inf)
        k = self.cohesion * A
        apex = np.divide(k, self.mu, out=np.full(self.n_points, np.inf), where=self.mu > 0)
        return crush, np.minimum(self.ft * A, apex), k

    def interface_blocks(self):
        """Indices of blocks a and b per interface, -1 for a support."""
        return self._ends(self.iface_a, self.iface_b)

    def point_blocks(self):
        """Indices of blocks a and b per contact point, -1 for a support."""
        ia, ib = self.interface_blocks()
        return ia[self.point_interface], ib[self.point_interface]

    def size(self) -> float:
        """A length that measures the whole structure (diagonal of its bounding box)."""
        pts = [self.centroid, self.point] + [np.asarray(v[0]) for v in self.polyhedra.values()]
        p = np.vstack([x for x in pts if len(x)])
        return float(np.linalg.norm(p.max(axis=0) - p.min(axis=0))) or 1.0

    # ----------------------------------------------------------------------- checking
    def validate(self) -> "Structure3D":
        """Raise InputError on anything that cannot describe a block assembly in space."""
        where = f"structure '{self.name}'"
        check_ids(where, self.blocks, self.supports, ("interface", self.interfaces),
                  self.n_interfaces > 0 and self.n_points > 0)
        block = lambda j: f"block '{self.blocks[j]}'"  # noqa: E731
        check_finite(where, [(name, arr, block) for name, arr in (
            ("centroid", self.centroid), ("dead", self.dead), ("live", self.live),
            ("dead_m", self.dead_m), ("live_m", self.live_m))])
        at_point = lambda i: f"a contact point of interface '{self.interfaces[self.point_interface[i]]}'"  # noqa: E731
        check_finite(where, [(name, arr, at_point) for name, arr in (
            ("point", self.point), ("normal", self.normal), ("tangent1", self.tangent1),
            ("tangent2", self.tangent2), ("mu", self.mu))])
        if self.point_interface.min() < 0 or self.point_interface.max() >= self.n_interfaces:
            raise InputError(f"{where}: a contact point names an interface that does not exist")
        check_ends(where, "interface", self.interfaces, self.iface_a, self.iface_b, self.blocks, self.supports,
                   ends=("body a", "body b"))
        frame = np.stack([self.normal, self.tangent1, self.tangent2], axis=1)  # (np, 3, 3)
        err = np.abs(np.einsum("pij,pkj->pik", frame, frame) - np.eye(3)).max(axis=(1, 2))
        i = first((err > 1e-6) | (np.linalg.det(frame) < 0))
        if i is not None:
            raise InputError(f"{where}: the frame (n, t1, t2) of {at_point(i)} is not "
                             "orthonormal and right-handed; expected unit normal and tangents")
        at_iface = lambda i: f"interface '{self.interfaces[self.point_interface[i]]}'"  # noqa: E731
        check_friction(where, self.mu, at_iface)
        check_strengths(where, self.fc, self.ft, self.cohesion, np.ones(self.n_points), at_iface)
        if self.area is not None:
            check_finite(where, [("area", self.area, at_point)])
        check_touched(where, self.blocks, *self.interface_blocks())
        check_live(where, bool(np.any(self.live) or np.any(self.live_m)))
        return self


def tangent_frame(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit tangents t1, t2 for unit normals (n, 3) with (n, t1, t2) right-handed.

    t1 is the horizontal direction n x z where n is not vertical (so that t1 follows a
    wall's course), else x; the choice is a convention only: the cone is round.
    """
    n = np.asarray(normal, dtype=float).reshape(-1, 3)
    ref = np.tile([0.0, 0.0, 1.0], (len(n), 1))
    vertical = np.abs(n[:, 2]) > 1 - 1e-9
    t1 = np.cross(n, ref)
    t1[vertical] = [1.0, 0.0, 0.0]
    t1 -= (t1 * n).sum(axis=1, keepdims=True) * n
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    t2 = np.cross(n, t1)
    return t1, t2
