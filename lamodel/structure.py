"""The block assembly as data: blocks, supports, contacts, loads; checked once by validate().

The matrices of eq. (1)-(5) built from these data live in :mod:`lamodel.formulation.matrices`.

Conventions (used everywhere in lamodel, and in the output CSVs):

* Each contact k joins block ``a`` and block ``b`` (either may be a support, not both).
  Its unit normal ``n`` points from a to b, its tangent is ``t = (-n_y, n_x)``.
* The contact force ``N n + V t`` (applied at the contact centre) and the couple ``M`` act on
  block a; their opposites act on block b. ``N <= 0`` is compression.
* Block displacements ``u = (u_x, u_y, theta)`` are taken at the block centroid.
* The relative displacement of b with respect to a at the contact centre gives the contact
  strains ``q = (opening, slip, relative rotation)``.
* The vector of contact forces is ordered as in eq. (3): ``s_f = (N_1..N_nc, V_1..V_nc,
  M_1..M_nc)``; block forces are ordered ``(f_x, f_y, m)`` block after block.

With these conventions (:mod:`lamodel.formulation.matrices`) the equilibrium of eq. (1)-(2) reads ``A s_f + f0 + alpha fbar = 0``
and compatibility reads ``q = -A^T u``, so that virtual work holds:
``alpha fbar^T u + f0^T u = s_f^T q``.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .assembly import Assembly
from .errors import InputError
from .validation import (check_ends, check_finite, check_friction, check_ids, check_live, check_strengths,
                         check_touched, first)

#: Per-block and per-contact data, by the names of the Pyomo model's parameters and of the
#: .dat files (:mod:`lamodel.io.datfile`, :mod:`lamodel.formulation.model`).
BLOCK_PARAMS = ("x", "y", "dead_x", "dead_y", "live_x", "live_y")
#: Optional per-block parameters (default 0, so files without them stay valid): the moments
#: about the centroid of loads that act elsewhere (point loads), eq. (1)'s x ^ f.
BLOCK_MOMENT_PARAMS = ("dead_m", "live_m")
CONTACT_PARAMS = ("block_a", "block_b", "cx", "cy", "nx", "ny", "d", "mu")

#: The joint's strengths (:mod:`lamodel.formulation.joints`) and their defaults: the dry,
#: infinitely strong joint of eq. (4), out-of-plane thickness 1.
JOINT_DEFAULTS = {"fc": np.inf, "ft": 0.0, "cohesion": 0.0, "thickness": 1.0}
#: Their names: optional per-contact parameters of the .dat files and fields of the JSON ones.
STRENGTH_PARAMS = tuple(JOINT_DEFAULTS)

#: Yield rows of eq. (4), in the order used for the flow multipliers xi (4 per contact):
#: sliding forward, sliding backward, hinging on one edge, hinging on the other.
YIELD_ROWS = ("slide+", "slide-", "hinge+", "hinge-")


@dataclass
class Structure(Assembly):
    """A planar assembly of rigid blocks with Coulomb contacts (seed eq. 1-4)."""

    # name, blocks, centroid (nb, 2), dead, live, supports: Assembly's
    contacts: list          # ids of the contacts
    block_a: list           # per contact: id of block a (a block or a support)
    block_b: list           # per contact: id of block b (a block or a support)
    centre: np.ndarray      # (nc, 2)
    normal: np.ndarray      # (nc, 2) unit normal from a to b
    d: np.ndarray           # (nc,) half-length: largest eccentricity of N
    mu: np.ndarray          # (nc,) friction coefficient
    polygons: dict = field(default_factory=dict)  # id -> (k, 2) vertices, for pictures
    dead_m: np.ndarray | None = None  # (nb,) moment of the dead loads about the centroid (point loads)
    live_m: np.ndarray | None = None  # (nb,) moment of the live loads about the centroid
    units: dict = field(default_factory=dict)     # {"length": "m", "force": "kN"}; empty: dimensionless
    point_loads: list = field(default_factory=list)  # PointLoad of this structure's loads (pictures)
    cases: dict = field(default_factory=dict)     # name -> LoadCase: named live-load patterns
    rolling: object = None                        # a RollingLoad study, or None
    # the joint's strengths (lamodel.formulation.joints), per contact; the defaults are the
    # dry joint of eq. (4), infinitely strong in compression
    fc: np.ndarray | None = None         # (nc,) compressive strength (stress), inf: no crushing
    ft: np.ndarray | None = None         # (nc,) tensile strength (stress)
    cohesion: np.ndarray | None = None   # (nc,) cohesion c0 (stress)
    thickness: np.ndarray | None = None  # (nc,) b, the joint's width out of the plane (length)
    # the last this many contacts are restraints a file gave (lamodel.io.restraints): one-way
    # bounded reactions from a support, not found from the polygons
    restraints: int = 0
    # what a JSON file said besides (written back by lamodel.io.jsonspec.structure_to_json)
    description: str = ""
    tolerance: float | None = None       # the geometric tolerance relative to the model's size

    def __post_init__(self):
        self._as_text("blocks", "supports", "contacts", "block_a", "block_b")
        f, nb, nc = self._floats, len(self.blocks), len(self.contacts)
        self.centroid = f(self.centroid, (nb, 2))
        self.dead = f(self.dead, (nb, 2))
        self.live = f(self.live, (nb, 2))
        self.centre = f(self.centre, (nc, 2))
        self.normal = f(self.normal, (nc, 2))
        self.d = f(self.d, (nc,))
        self.mu = f(self.mu, (nc,))
        self.polygons = {str(k): np.asarray(v, dtype=float) for k, v in self.polygons.items()}
        self.dead_m = np.zeros(nb) if self.dead_m is None else f(self.dead_m, (nb,))
        self.live_m = np.zeros(nb) if self.live_m is None else f(self.live_m, (nb,))
        for name, default in JOINT_DEFAULTS.items():
            value = getattr(self, name)
            setattr(self, name, np.full(nc, default) if value is None else f(value, (nc,)))

    # ----------------------------------------------------------------- sizes and lookups
    @property
    def n_contacts(self) -> int:
        return len(self.contacts)

    @property
    def tangent(self) -> np.ndarray:
        return np.column_stack([-self.normal[:, 1], self.normal[:, 0]])

    @property
    def has_materials(self) -> bool:
        """Whether some joint crushes, takes tension or has cohesion (else eq. 4 as it is)."""
        return bool(np.isfinite(self.fc).any() or (self.ft > 0).any() or (self.cohesion > 0).any())

    def contact_blocks(self):
        """Indices of blocks a and b per contact, -1 for a support."""
        return self._ends(self.block_a, self.block_b)

    def size(self) -> float:
        """A length that measures the whole structure (diagonal of its bounding box)."""
        pts = [self.centroid, self.centre]
        pts += [v for v in self.polygons.values()]
        p = np.vstack([x for x in pts if len(x)])
        return float(np.hypot(*(p.max(axis=0) - p.min(axis=0)))) or 1.0

    # ----------------------------------------------------------------------- checking
    def validate(self) -> "Structure":
        """Raise InputError on anything that cannot describe a block assembly."""
        where = f"structure '{self.name}'"
        check_ids(where, self.blocks, self.supports, ("contact", self.contacts), self.n_contacts > 0)
        block = lambda i: f"'{self.blocks[i]}'"  # noqa: E731
        contact = lambda i: f"'{self.contacts[i]}'"  # noqa: E731
        check_finite(where, [("x/y", self.centroid, block), ("dead", self.dead, block), ("live", self.live, block),
                             ("dead_m", self.dead_m, block), ("live_m", self.live_m, block),
                             ("centre", self.centre, contact), ("normal", self.normal, contact),
                             ("d", self.d, contact), ("mu", self.mu, contact)])
        check_ends(where, "contact", self.contacts, self.block_a, self.block_b, self.blocks, self.supports)
        norm = np.hypot(self.normal[:, 0], self.normal[:, 1])
        k = first(np.abs(norm - 1.0) > 1e-6)
        if k is not None:
            raise InputError(f"{where}: normal of contact '{self.contacts[k]}' has length {norm[k]:.6g}; expected a unit vector")
        k = first(self.d <= 0)
        if k is not None:
            raise InputError(f"{where}: d of contact '{self.contacts[k]}' is {self.d[k]:.6g}; expected a half-length > 0")
        check_friction(where, self.mu, lambda i: f"contact '{self.contacts[i]}'")
        check_strengths(where, self.fc, self.ft, self.cohesion, self.thickness,
                        lambda i: f"contact '{self.contacts[i]}'")
        check_touched(where, self.blocks, *self.contact_blocks())
        # a file of load cases or a rolling load is solved per case / position (lamodel.loads)
        check_live(where, bool(np.any(self.live) or np.any(self.live_m) or self.cases or self.rolling))
        return self
