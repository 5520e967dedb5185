"""Generators of block assemblies in space, as 3D JSON specs (build a Structure3D with
:func:`lamodel.io.json3d.structure3d_from_spec`): out-of-plane wall panels, a façade with
returns and openings, a one-room box building, a barrel vault on two walls, a dome of
voussoir rings, a circular tower of voussoir courses, and any 2D spec
(:mod:`lamodel.geometry.generators`) extruded to a depth.

Conventions: z up, ground slab ``ground`` (a support) under z = 0; lengths in metres in
the defaults (blocks 0.4 x 0.2 x 0.2, unit weight 1); every block is the convex hull of its
corners. Walls are bonded by alternating the joints of successive courses by half a block;
at corners the walls own the corner square in alternate courses (interlocking).
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from .generators import _ring


def _box(x0, y0, z0, x1, y1, z1):
    return [[x, y, z] for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]


def _spec(name, blocks, mu, unit_weight, live_load, description=None):
    spec = {"name": name, "dimension": 3}
    if description:
        spec["description"] = description
    spec.update({"mu": mu, "unit_weight": unit_weight, "live_load": [float(v) for v in live_load],
                 "blocks": blocks})
    return spec


def _ground(blocks, lo, hi, margin, thickness=None):
    t = margin if thickness is None else thickness
    blocks.append({"id": "ground", "support": True,
                   "vertices": _box(lo[0] - margin, lo[1] - margin, -t, hi[0] + margin, hi[1] + margin, 0.0)})


def _course(s0, s1, length, offset, holes):
    """Pieces (a, b) of one course over [s0, s1]: joints at ``offset + k * length``, gaps
    ``holes`` [(h0, h1, 'gap' | 'lintel')] left empty or spanned by one piece; joints closer
    than a quarter block to a fixed cut are dropped (no slivers)."""
    fixed = {s0, s1}
    for h0, h1, _ in holes:
        fixed |= {max(s0, h0), min(s1, h1)}
    cuts = set(fixed)
    k0 = math.floor((s0 - offset) / length)
    for k in range(k0, k0 + int((s1 - s0) / length) + 3):
        c = offset + k * length
        if s0 < c < s1 and all(abs(c - f) > length / 4 for f in fixed):
            cuts.add(c)
    for h0, h1, _ in holes:
        cuts = {c for c in cuts if not h0 < c < h1}
    cuts = sorted(cuts)
    out = []
    for a, b in zip(cuts[:-1], cuts[1:]):
        if b - a > 1e-12 and not any(kind == "gap" and h0 <= a and b <= h1 for h0, h1, kind in holes):
            out.append((a, b))
    return out


def _course_holes(openings, r, length):
    holes = []
    for s0, s1, c0, c1 in openings:
        if c0 <= r < c1:
            holes.append((s0, s1, "gap"))
        elif r == c1:
            holes.append((s0 - length / 2, s1 + length / 2, "lintel"))
    return holes


def _walls(walls, courses, block, name):
    """Blocks of straight walls: each wall {'axis': 'x'|'y', 'across': (c0, c1), 'spans':
    (even-course span, odd-course span), 'openings': [(s0, s1, c0, c1)], 'tag'}."""
    length, _, height = block
    blocks = []
    for r in range(courses):
        z0, z1 = r * height, (r + 1) * height
        for w in walls:
            s0, s1 = w["spans"][r % 2]
            offset = s0 + (length / 2 if r % 2 else 0.0)
            for k, (a, b) in enumerate(_course(s0, s1, length, offset, _course_holes(w.get("openings", ()), r, length))):
                c0, c1 = w["across"]
                box = _box(a, c0, z0, b, c1, z1) if w["axis"] == "x" else _box(c0, a, z0, c1, b, z1)
                blocks.append({"id": f"{w['tag']}{r + 1}_{k + 1}", "vertices": box})
    if not blocks:
        raise InputError(f"{name}: no blocks; expected at least one course of positive length")
    return blocks


def _check_positive(name, **values):
    for key, v in values.items():
        if not (isinstance(v, (int, float)) and v > 0):
            raise InputError(f"{name}: {key}={v!r}; expected a positive number")


def wall_panel(length: float = 2.4, courses: int = 8, block=(0.4, 0.2, 0.2), bond: str = "running",
               leaves: int = 1, header_every: int = 3, mu: float = 0.6, unit_weight: float = 1.0,
               live_load=(0.0, 1.0, 0.0), name: str = "wall_panel") -> dict:
    """A free-standing wall along x loaded out of its plane (live load along +y).

    ``bond``: "running" (joints shifted half a block course to course) or "stack".
    ``leaves`` = 2 builds two leaves of stretchers side by side, tied every
    ``header_every``-th course by a course of headers (half a block long, crossing the
    whole thickness). ``block`` = (length, width, height) of a stretcher.
    """
    l, w, h = block
    _check_positive(name, length=length, courses=courses, block_length=l, block_width=w, block_height=h)
    if bond not in ("running", "stack") or leaves not in (1, 2):
        raise InputError(f"{name}: bond={bond!r}, leaves={leaves!r}; expected bond 'running' or 'stack' and 1 or 2 leaves")
    blocks = []
    for r in range(int(courses)):
        z0, z1 = r * h, (r + 1) * h
        shift = l / 2 if (bond == "running" and r % 2) else 0.0
        if leaves == 2 and header_every and r % header_every == header_every - 1:
            rows = [("h", 0.0, 2 * w, l / 2, (l / 4 if shift else 0.0))]
        else:
            rows = [("s" if leaves == 1 else f"s{k + 1}_", k * w, (k + 1) * w, l, shift) for k in range(leaves)]
        for tag, y0, y1, piece, off in rows:
            for k, (a, b) in enumerate(_course(0.0, length, piece, off, [])):
                blocks.append({"id": f"{tag}{r + 1}_{k + 1}", "vertices": _box(a, y0, z0, b, y1, z1)})
    _ground(blocks, (0.0, 0.0), (length, leaves * w), max(l, w))
    return _spec(name, blocks, mu, unit_weight, live_load,
                 f"Wall panel {length} long, {courses} courses, {bond} bond, {leaves} leaf/leaves; out-of-plane live load.")


def facade(plan: str = "U", length: float = 4.0, depth: float = 2.0, courses: int = 10, block=(0.4, 0.2, 0.2),
           openings=((1.2, 2.0, 3, 7), (2.6, 3.0, 0, 6)), mu: float = 0.6, unit_weight: float = 1.0,
           live_load=(0.0, -1.0, 0.0), name: str = "facade") -> dict:
    """A façade along x (outer face y = 0) with returns along +y: one at x = 0 (plan "L")
    or one at each end (plan "U"), ``depth`` long; corners interlock course by course.

    ``openings`` (s0, s1, c0, c1): the façade is empty over s0 <= x <= s1 in courses
    c0 .. c1 - 1 (a door when c0 = 0) and a lintel half a block longer each side spans it
    in course c1. The live load points outward (-y): the façade's overturning out of plane.
    """
    l, t, h = block
    _check_positive(name, length=length, depth=depth, courses=courses)
    if plan not in ("L", "U"):
        raise InputError(f"{name}: plan={plan!r}; expected 'L' or 'U'")
    for s0, s1, c0, c1 in openings:
        if not (t + l / 2 <= s0 - l / 2 and s1 + l / 2 <= length - t - (l / 2 if plan == "U" else 0) and s0 < s1
                and 0 <= c0 < c1):
            raise InputError(f"{name}: opening {(s0, s1, c0, c1)} does not fit the façade; expected room for "
                             "its lintel between the returns")
    right_end = length - t if plan == "U" else length
    walls = [{"axis": "x", "across": (0.0, t), "spans": ((0.0, length), (t, right_end)), "openings": openings,
              "tag": "f"},
             {"axis": "y", "across": (0.0, t), "spans": ((t, depth), (0.0, depth)), "tag": "l"}]
    if plan == "U":
        walls.append({"axis": "y", "across": (length - t, length), "spans": ((t, depth), (0.0, depth)), "tag": "r"})
    blocks = _walls(walls, int(courses), block, name)
    _ground(blocks, (0.0, 0.0), (length, depth), l)
    return _spec(name, blocks, mu, unit_weight, live_load,
                 f"Façade {length} x {courses} courses with {plan}-plan returns {depth} deep and {len(openings)} openings.")


def box_building(length: float = 4.0, width: float = 3.0, courses: int = 12, block=(0.4, 0.2, 0.2),
                 door=(1.6, 2.4, 9), windows=(("back", 1.2, 2.0, 4, 9), ("left", 1.0, 1.8, 4, 9),
                                              ("right", 1.0, 1.8, 4, 9)),
                 mu: float = 0.6, unit_weight: float = 1.0, live_load=(1.0, 0.0, 0.0),
                 name: str = "box_building") -> dict:
    """A one-room building: four walls (outer plan ``length`` x ``width``) with interlocking
    corners, a door in the front wall (y = 0) over x in [door[0], door[1]] up to course
    door[2], and windows (wall, s0, s1, c0, c1) with s measured along the wall from its
    outer corner at x = 0 or y = 0; lintels over each opening."""
    l, t, h = block
    _check_positive(name, length=length, width=width, courses=courses)
    ops = {"front": [], "back": [], "left": [], "right": []}
    if door:
        ops["front"].append((door[0], door[1], 0, door[2]))
    for wall, s0, s1, c0, c1 in windows:
        if wall not in ops:
            raise InputError(f"{name}: window on wall {wall!r}; expected front, back, left or right")
        ops[wall].append((s0, s1, c0, c1))
    walls = [{"axis": "x", "across": (0.0, t), "spans": ((0.0, length), (t, length - t)), "tag": "f"},
             {"axis": "x", "across": (width - t, width), "spans": ((0.0, length), (t, length - t)), "tag": "b"},
             {"axis": "y", "across": (0.0, t), "spans": ((t, width - t), (0.0, width)), "tag": "l"},
             {"axis": "y", "across": (length - t, length), "spans": ((t, width - t), (0.0, width)), "tag": "r"}]
    for w, key in zip(walls, ("front", "back", "left", "right")):
        w["openings"] = ops[key]
    blocks = _walls(walls, int(courses), block, name)
    _ground(blocks, (0.0, 0.0), (length, width), l)
    return _spec(name, blocks, mu, unit_weight, live_load,
                 f"One-room building {length} x {width}, {courses} courses, a door and {len(windows)} windows.")


def _prism(quad_xz, y0, y1):
    return [[x, y, z] for x, z in quad_xz for y in (y0, y1)]


def barrel_vault(n_voussoirs: int = 9, inner_radius: float = 1.5, thickness: float = 0.25, length: float = 2.4,
                 segments: int = 4, stagger: bool = True, wall_height: float = 1.2, wall_courses: int = 4,
                 wall_block: float = 0.6, wall_thickness: float = 0.6, mu: float = 0.6, unit_weight: float = 1.0,
                 live_load=(1.0, 0.0, 0.0), name: str = "barrel_vault") -> dict:
    """A semicircular barrel vault along y on two walls, each a running-bond wall of
    ``wall_courses`` courses, ``wall_thickness`` thick from the intrados outwards (the vault
    springs from its inner part); the vault's ``n_voussoirs`` rows are cut into ``segments``
    along y, alternate rows shifted by half a segment when ``stagger``.

    The walls carry the vault's thrust: walls only as thick as the vault (0.25 under a
    vault of radius 1.5, 1.2 high) overturn under its self-weight, and no statics carries
    it; the default 0.6 (0.4 times the radius) stands, with an associative multiplier of
    0.148 under the default horizontal live load."""
    _check_positive(name, inner_radius=inner_radius, thickness=thickness, length=length, wall_height=wall_height,
                    wall_thickness=wall_thickness)
    ring, left, right = _ring(int(n_voussoirs), inner_radius, thickness, 180.0)
    seg = length / segments
    blocks = []
    for k, v in enumerate(ring):
        quad = [(x, z + wall_height) for x, z in v["vertices"]]
        cuts = _course(0.0, length, seg, seg / 2 if (stagger and k % 2) else 0.0, [])
        for j, (a, b) in enumerate(cuts):
            blocks.append({"id": f"v{k + 1}_{j + 1}", "vertices": _prism(quad, a, b)})
    r0 = inner_radius
    r1 = r0 + wall_thickness
    walls = [{"axis": "y", "across": (-r1, -r0), "spans": ((0.0, length), (0.0, length)), "tag": "wl"},
             {"axis": "y", "across": (r0, r1), "spans": ((0.0, length), (0.0, length)), "tag": "wr"}]
    blocks += _walls(walls, int(wall_courses), (wall_block, r1 - r0, wall_height / wall_courses), name)
    _ground(blocks, (-r1, 0.0), (r1, length), thickness)
    return _spec(name, blocks, mu, unit_weight, live_load,
                 f"Barrel vault of {n_voussoirs} voussoir rows, radius {inner_radius}, on two walls {wall_height} high.")


def dome(n_rings: int = 6, n_per_ring: int = 12, radius: float = 2.0, thickness: float = 0.25,
         oculus: float = 15.0, mu: float = 0.6, unit_weight: float = 1.0, live_load=(1.0, 0.0, 0.0),
         name: str = "dome") -> dict:
    """A hemispherical dome of ``n_rings`` voussoir rings (equal angles from the springing
    at z = 0 up to an oculus of half-angle ``oculus`` degrees; 0: closed by wedges),
    ``n_per_ring`` voussoirs each, intrados ``radius``, on a ground slab. Joints lie on
    cones and meridian planes through the centre, so every face is planar."""
    _check_positive(name, radius=radius, thickness=thickness, n_rings=n_rings, n_per_ring=n_per_ring)
    if not 0 <= oculus < 90 or n_per_ring < 3:
        raise InputError(f"{name}: oculus={oculus}, n_per_ring={n_per_ring}; expected 0 <= oculus < 90 degrees "
                         "and at least 3 voussoirs per ring")
    theta = np.radians(90.0 - np.arange(n_rings + 1) * (90.0 - oculus) / n_rings)  # polar angle from +z
    phi = np.arange(n_per_ring + 1) * 2 * np.pi / n_per_ring
    blocks = []

    def point(r, th, ph):
        return [r * math.sin(th) * math.cos(ph), r * math.sin(th) * math.sin(ph), r * math.cos(th)]

    for k in range(n_rings):
        for j in range(n_per_ring):
            pts = [point(r, th, ph) for r in (radius, radius + thickness) for th in theta[k:k + 2]
                   for ph in phi[j:j + 2]]
            uniq = np.unique(np.round(pts, 12), axis=0).tolist()
            blocks.append({"id": f"d{k + 1}_{j + 1}", "vertices": uniq})
    ro = radius + thickness
    _ground(blocks, (-ro, -ro), (ro, ro), thickness)
    return _spec(name, blocks, mu, unit_weight, live_load,
                 f"Dome of {n_rings} rings x {n_per_ring} voussoirs, radius {radius}, oculus {oculus} degrees.")


def tower(courses: int = 16, per_course: int = 12, radius: float = 2.0, thickness: float = 0.4,
          course_height: float = 0.4, stagger: bool = True, mu: float = 0.7, unit_weight: float = 1.0,
          live_load=(1.0, 0.0, 0.0), name: str = "tower") -> dict:
    """A circular tower of ``courses`` ring courses of ``per_course`` voussoirs (inner radius
    ``radius``, wall ``thickness``, each course ``course_height`` high) on a ground slab;
    alternate courses turned by half a voussoir when ``stagger``, so that no vertical joint
    runs through two courses. Each voussoir is the prism on the chords of its annular
    sector, so bed joints are the overlaps of plane quadrilaterals and head joints lie on
    meridian planes."""
    _check_positive(name, radius=radius, thickness=thickness, course_height=course_height, courses=courses)
    if per_course < 3:
        raise InputError(f"{name}: per_course={per_course}; expected at least 3 voussoirs a course")
    step = 2 * math.pi / per_course
    blocks = []
    for k in range(int(courses)):
        z0, z1 = k * course_height, (k + 1) * course_height
        turn = step / 2 if (stagger and k % 2) else 0.0
        for j in range(int(per_course)):
            a, b = turn + j * step, turn + (j + 1) * step
            pts = [[r * math.cos(ph), r * math.sin(ph), z] for r in (radius, radius + thickness)
                   for ph in (a, b) for z in (z0, z1)]
            blocks.append({"id": f"t{k + 1}_{j + 1}", "vertices": pts})
    ro = radius + thickness
    _ground(blocks, (-ro, -ro), (ro, ro), thickness)
    return _spec(name, blocks, mu, unit_weight, live_load,
                 f"Circular tower of {courses} courses x {per_course} voussoirs, radius {radius}, "
                 f"{'staggered' if stagger else 'stack-bonded'}.")


def extrude(spec2d: dict, depth: float = 1.0, name: str | None = None) -> dict:
    """A 2D spec (polygons in x, y) as a 3D spec: the plane becomes x-z (z up), each block a
    prism ``depth`` deep along y. Loads map (fx, fy) -> (fx, 0, fy), couples m -> (0, -m, 0),
    points (x, y) -> (x, depth / 2, y); the unit weight becomes a weight per volume."""
    _check_positive("extrude", depth=depth)
    if "rolling_load" in spec2d:
        raise InputError(f"extrude: '{spec2d.get('name')}' has a rolling load; expected a spec without one")
    vec = lambda f: [float(f[0]), 0.0, float(f[1])]  # noqa: E731
    out = {k: v for k, v in spec2d.items() if k in ("description", "mu", "unit_weight", "units", "tolerance")}
    out.update(name=name or f"{spec2d.get('name', 'structure')}_3d", dimension=3)
    if "live_load" in spec2d:
        out["live_load"] = vec(spec2d["live_load"])
    elif "loads" not in spec2d:
        out["live_load"] = [1.0, 0.0, 0.0]
    blocks = []
    for b in spec2d["blocks"]:
        nb = {k: v for k, v in b.items() if k in ("id", "support", "mu", "description")}
        nb["vertices"] = _prism(b["vertices"], 0.0, depth)
        for key in ("dead", "live"):
            if key in b:
                nb[key] = vec(b[key])
        for key in ("dead_m", "live_m"):
            if key in b:
                nb[key] = [0.0, -float(b[key]), 0.0]
        blocks.append(nb)
    out["blocks"] = blocks
    if spec2d.get("loads"):
        out["loads"] = [dict(ld, at=[ld["at"][0], depth / 2, ld["at"][1]], force=vec(ld["force"]))
                        for ld in spec2d["loads"]]
    return out


def extruded_seed_instances(depth: float = 1.0) -> dict:
    """The seed's walls, arch and portals (:func:`lamodel.geometry.generators.seed_instances`)
    extruded to ``depth``, by name (``wall33_3d``, ...)."""
    from .generators import seed_instances
    return {f"{k}_3d": extrude(v, depth) for k, v in seed_instances().items()}
