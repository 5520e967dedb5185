"""The tables of a 3D structure and its state (blocks.csv, contacts.csv) and its contacts
summary; :func:`lamodel.output.results3d.write_results3d` writes them.

Columns, in the order written (the conventions of :mod:`lamodel.structure3d`):

* ``blocks.csv`` (:data:`BLOCK_COLUMNS3D`): ``block``, ``x``, ``y``, ``z`` (centroid),
  ``dead_x``, ``dead_y``, ``dead_z``, ``live_x``, ``live_y``, ``live_z``, ``dead_mx``,
  ``dead_my``, ``dead_mz``, ``live_mx``, ``live_my``, ``live_mz`` (moments of the loads
  about the centroid), ``volume``, ``ux``, ``uy``, ``uz``, ``rx``, ``ry``, ``rz`` (motion
  at the centroid).
* ``contacts.csv`` (:data:`CONTACT_COLUMNS3D`): one row per contact point: ``interface``,
  ``block_a``, ``block_b``, ``x``, ``y``, ``z``, ``nx``, ``ny``, ``nz`` (from a to b),
  ``t1x``, ``t1y``, ``t1z``, ``t2x``, ``t2y``, ``t2z``, ``mu``, ``N``, ``T1``, ``T2``,
  ``mode``. The force ``N n + T1 t1 + T2 t2`` acts on block_a at the point, its opposite
  on block_b. A structure whose joints have strengths adds ``fc``, ``ft``, ``cohesion``
  (stresses) and ``area`` (the point's tributary area): its caps ``-fc area <= N <= ft
  area`` and its cone ``hypot(T1, T2) <= cohesion area - mu N``.

Without a certified state the motions and the forces are empty (NaN) and every mode is
``unknown``: nothing uncertified is written as if it were known. A point's mode is
``opening`` when it separates (whatever its tangential motion: an open point carries no
force, so it does not slide on anything), else ``sliding`` when it slips, else ``stuck``
(:func:`lamodel.search.certify3d.point_modes`) — the plane's rule for a contact whose two
ends separate (``open`` before ``sliding``); a point has no second end to hinge about. A
point that closes sits on its crushing cap: ``crushing`` (``crushing+sliding`` if it slips).

With these and alpha every block's equilibrium can be rebuilt from the files alone.
"""
from __future__ import annotations

import numpy as np
import pandas as pd

from ..structure3d import Structure3D

#: blocks.csv's columns, in the order written.
BLOCK_COLUMNS3D = ("block", "x", "y", "z", "dead_x", "dead_y", "dead_z", "live_x", "live_y", "live_z",
                   "dead_mx", "dead_my", "dead_mz", "live_mx", "live_my", "live_mz", "volume",
                   "ux", "uy", "uz", "rx", "ry", "rz")
#: contacts.csv's columns, in the order written.
CONTACT_COLUMNS3D = ("interface", "block_a", "block_b", "x", "y", "z", "nx", "ny", "nz",
                     "t1x", "t1y", "t1z", "t2x", "t2y", "t2z", "mu", "N", "T1", "T2", "mode")
#: The mode of every point without a certified state (as in the plane).
UNKNOWN = "unknown"


def interface_areas(s: Structure3D) -> np.ndarray:
    """Area of each interface polygon (Newell's formula on its vertices)."""
    out = []
    for p in s.iface_polygon:
        out.append(0.5 * np.linalg.norm(np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)) if len(p) >= 3 else 0.0)
    return np.array(out)


def _known(values, shape) -> np.ndarray:
    """``values`` as floats of ``shape``, NaN when None (nothing certified)."""
    if values is None:
        return np.full(shape, np.nan)
    return np.asarray(values, dtype=float).reshape(shape)


def blocks_table(s: Structure3D, motions=None) -> pd.DataFrame:
    """One row per block (see the module docs); ``motions`` (nb, 6) or None (NaN)."""
    u = _known(motions, (s.n_blocks, 6))
    cols = {"block": s.blocks}
    for name, arr in (("", s.centroid), ("dead_", s.dead), ("live_", s.live)):
        for k, c in enumerate("xyz"):
            cols[f"{name}{c}"] = arr[:, k]
    for name, arr in (("dead_m", s.dead_m), ("live_m", s.live_m)):
        for k, c in enumerate("xyz"):
            cols[f"{name}{c}"] = arr[:, k]
    cols["volume"] = s.volume
    for k, c in enumerate(("ux", "uy", "uz", "rx", "ry", "rz")):
        cols[c] = u[:, k]
    return pd.DataFrame(cols, columns=list(BLOCK_COLUMNS3D))


def contacts_table(s: Structure3D, forces=None, modes=None) -> pd.DataFrame:
    """One row per contact point; ``forces`` (np, 3) of (N, T1, T2) or None (NaN),
    ``modes`` (np,) strings or None (``unknown``)."""
    f = _known(forces, (s.n_points, 3))
    cols = {"interface": [s.interfaces[i] for i in s.point_interface],
            "block_a": [s.iface_a[i] for i in s.point_interface],
            "block_b": [s.iface_b[i] for i in s.point_interface]}
    for name, arr in (("", s.point), ("n", s.normal), ("t1", s.tangent1), ("t2", s.tangent2)):
        for k, c in enumerate("xyz"):
            cols[f"{name}{c}"] = arr[:, k]
    cols["mu"] = s.mu
    cols["N"], cols["T1"], cols["T2"] = f[:, 0], f[:, 1], f[:, 2]
    cols["mode"] = [UNKNOWN] * s.n_points if modes is None else list(modes)
    extra = []
    if s.has_materials:  # the joints' strengths and each point's tributary area (caps: fc A, ft A, cohesion A)
        extra = ["fc", "ft", "cohesion", "area"]
        cols.update(fc=s.fc, ft=s.ft, cohesion=s.cohesion, area=s.areas())
    return pd.DataFrame(cols, columns=list(CONTACT_COLUMNS3D) + extra)


def contacts_summary(s: Structure3D) -> dict:
    """Blocks, supports, interfaces, contact points and total interface area of a structure."""
    return {"blocks": s.n_blocks, "supports": len(s.supports), "interfaces": s.n_interfaces,
            "points": s.n_points, "area": float(interface_areas(s).sum())}


def build_summary3d(path, **options) -> str | None:
    """The ``lamodel build`` line for a 3D input (None when ``path`` is a planar input);
    ``options`` as :func:`lamodel.io.read`."""
    from pathlib import Path

    from ..io import read
    from ..io.assemblies import MESH_SUFFIXES, read_3d_json
    p = Path(path)
    if p.suffix.lower() in MESH_SUFFIXES:
        s = read(p, **options)
    elif p.suffix.lower() == ".json" and p.is_file():
        s = read_3d_json(p, **options)
        if s is None:
            return None
    else:
        return None
    c = contacts_summary(s)
    return (f"{path}: {c['blocks']} blocks, {c['supports']} supports, {c['interfaces']} interfaces, "
            f"{c['points']} contact points, total interface area {c['area']:.6g}")
