"""The families in space of ``benchmarks/families.py``: what users build in 3D, each a JSON
spec of the generators (:mod:`lamodel.geometry.generators3d`), solved like the planar ones.

* ``dome``: hemispherical domes of R rings of S voussoirs (3 x 12 and 4 x 6 among them);
* ``vault``: barrel vaults on their walls, loaded across and along the barrel;
* ``tower``: circular towers, joints staggered or not, the load turned in plan;
* ``building``: one-room box buildings with a door and windows, and a U-plan façade;
* ``pyramid``: stepped pyramids of boxes pushed along x, at 30 and 45 degrees, whose
  collapse is the top box sliding (alpha = mu);
* ``extruded``: the seed's 33-block wall extruded, loaded out of its plane and at 45 degrees;
* ``compas``: the COMPAS sample assemblies of the folder given with ``--compas`` (joints at
  tolerance 1e-4, the one that finds them), a horizontal load along +x equal to the weight.

In space ``--method all`` is the associative program's mechanism and successive cone
programming (Portioli et al.), each certified, each within the default search's counted
work bound.
"""
from __future__ import annotations

import math
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _box(x, y, z, a=1.0, b=1.0, c=1.0):
    return [[x + i * a, y + j * b, z + k * c] for i in (0, 1) for j in (0, 1) for k in (0, 1)]


def pyramid(levels: int, mu: float, degrees: float, name: str) -> dict:
    """A stepped pyramid of unit boxes: level k holds (levels - k)^2 boxes, offset by half a
    box; a horizontal live load equal to the weight, ``degrees`` from x."""
    blocks = [{"id": "ground", "support": True, "vertices": _box(-1, -1, -0.5, levels + 2, levels + 2, 0.5)}]
    for k in range(levels):
        m = levels - k
        blocks += [{"id": f"b{k}_{i}_{j}", "vertices": _box(i + k / 2, j + k / 2, k)}
                   for i in range(m) for j in range(m)]
    a = math.radians(degrees)
    return {"name": name, "dimension": 3, "mu": mu, "live_load": [math.cos(a), math.sin(a), 0.0], "blocks": blocks}


def _named(spec: dict, name: str, **changes) -> dict:
    return {**spec, **changes, "name": name}


def _extruded(load: str, name: str) -> dict:
    from lamodel.geometry import seed_wall
    from lamodel.geometry.generators3d import extrude
    spec = extrude(seed_wall(6), depth=1.0)
    spec.pop("live_loads", None)
    w = 1.0 / math.sqrt(2.0)
    # the live load as a multiple of each block's weight: out of plane (+y), or 45 degrees
    return _named(spec, name, live_load=[0.0, 1.0, 0.0] if load == "oop" else [w, w, 0.0])


def _compas(path: Path) -> dict:
    """A COMPAS sample as the runner reads it (a file, its reader's options)."""
    return {"_read": str(path), "_options": {"tolerance": 1e-4, "live_load": (1.0, 0.0, 0.0)}, "name": path.stem}


def cases3d(quick: bool, compas: str | None = None):
    """(family, case name, JSON-spec builder) for every case in space."""
    from lamodel.geometry import generators3d as G
    out = []
    domes = [(3, 12), (4, 6)] if quick else [(3, 12), (4, 6), (6, 12)]
    for rings, per in domes:
        name = f"dome{rings}x{per}"
        out.append(("dome", name, lambda r=rings, p=per, name=name: G.dome(r, p, name=name)))
    for word, load in (("across", (1.0, 0.0, 0.0)), ("along", (0.0, 1.0, 0.0))):
        name = f"vault_{word}"
        out.append(("vault", name, lambda load=load, name=name: G.barrel_vault(live_load=load, name=name)))
    towers = [(4, 8, True, 0.0), (4, 8, True, 45.0), (4, 8, False, 0.0)]
    if not quick:
        towers += [(6, 12, True, 0.0), (8, 12, True, 15.0), (16, 12, True, 0.0)]
    for courses, per, stagger, turn in towers:
        name = f"tower{courses}x{per}{'' if stagger else '-stack'}{f'-d{turn:g}' if turn else ''}"
        a = math.radians(turn)
        out.append(("tower", name, lambda c=courses, p=per, st=stagger, a=a, name=name: G.tower(
            c, p, stagger=st, live_load=(math.cos(a), math.sin(a), 0.0), name=name)))
    out.append(("building", "box_small", lambda: G.box_building(
        length=2.0, width=1.6, courses=6, door=(0.8, 1.2, 4), windows=(("back", 0.8, 1.2, 2, 4),), name="box_small")))
    out.append(("building", "facade", lambda: _named(__import__("json").loads(
        (ROOT / "instances" / "facade.json").read_text()), "facade")))
    if not quick:
        out.append(("building", "box1000", lambda: G.box_building(length=7.6, width=5.6, courses=16, name="box1000")))
    for levels, degrees in ((4, 0.0), (4, 30.0), (4, 45.0)) + (() if quick else ((8, 45.0),)):
        name = f"pyramid{levels}_d{degrees:g}"
        out.append(("pyramid", name, lambda lv=levels, d=degrees, name=name: pyramid(lv, 0.5, d, name)))
    for load in ("oop", "diag"):
        name = f"wall33_{load}"
        out.append(("extruded", name, lambda load=load, name=name: _extruded(load, name)))
    if compas:
        for path in sorted(Path(compas).glob("*.json")):
            out.append(("compas", path.stem, lambda path=path: _compas(path)))
    return out


def read_case(spec: dict):
    """The Structure3D of a case's spec (a generator's JSON, or a COMPAS file to read)."""
    if "_read" in spec:
        from lamodel.io import read
        return read(spec["_read"], **spec["_options"])
    from lamodel.io.json3d import structure3d_from_spec
    return structure3d_from_spec(spec)


def published3d(s):
    """{method: certified alpha (nan: none)} of --method all's published methods in space."""
    from lamodel.search.search3d import solve3d
    return {m: solve3d(s, method=which, explore=False).alpha
            for m, which in (("associative", "associative"), ("successive-cone", "successive"))}
