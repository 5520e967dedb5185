"""Generators of block assemblies as JSON specs: running-bond walls (with openings),
arches, portals, and the seed's examples. Build a Structure with
:func:`lamodel.io.jsonspec.structure_from_json`.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import InputError

# ===================================================================== generators
def _rectangle(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


def _clean_number(x: float, scale: float) -> float:
    """Round-off below 1e-12 of the model's scale snapped to zero (tidier JSON files)."""
    x = float(x)
    return 0.0 if abs(x) < 1e-12 * scale else x


def _finish(name, description, mu, unit_weight, live_load, blocks):
    spec = {"name": name}
    if description:
        spec["description"] = description
    spec.update({"mu": mu, "unit_weight": unit_weight, "live_load": [float(v) for v in live_load], "blocks": blocks})
    return spec


def running_bond_wall(courses, full: float = 4.0, height=1.75, mu: float = 0.65,
                      unit_weight: float | None = None, live_load=(1.0, 0.0), name: str = "wall",
                      x0: float = 0.0, ground_margin: float | None = None,
                      ground_thickness: float | None = None, description: str | None = None) -> dict:
    """JSON spec of a dry-stone wall of rectangular blocks on a rigid ground.

    ``courses`` lists the rows, bottom row first; each row lists block lengths in units of
    the full block length ``full``, placed left to right from ``x0``; a negative entry is
    a gap (an opening) of that length. ``height`` is the course height (one number, or
    one per course). Blocks are named ``b1, b2, ...`` row by row, left to right; the
    support ``ground`` spans the whole wall plus ``ground_margin`` on each side.

    ``unit_weight`` defaults to ``1 / (full * height[0])``, so that a full block weighs
    1 (and, with the default ``live_load``, carries a unit horizontal live load, left to
    right), as in the seed's wall examples.
    """
    courses = [list(c) for c in courses]
    if not courses:
        raise InputError("running_bond_wall: no courses given; expected a list of rows of block lengths")
    heights = [float(height)] * len(courses) if np.isscalar(height) else [float(h) for h in height]
    if len(heights) != len(courses) or min(heights) <= 0:
        raise InputError(f"running_bond_wall: {len(heights)} course heights for {len(courses)} courses; "
                         "expected one positive height, or one per course")
    if unit_weight is None:
        unit_weight = 1.0 / (full * heights[0])
    blocks, y, xmin, xmax = [], 0.0, x0, x0
    for row, lengths in enumerate(courses):
        x = x0
        for length in lengths:
            if length == 0:
                raise InputError(f"running_bond_wall: course {row + 1} has a zero length; "
                                 "expected block lengths > 0 or gaps < 0")
            step = abs(length) * full
            if length > 0:
                blocks.append({"id": f"b{len(blocks) + 1}", "vertices": _rectangle(x, y, x + step, y + heights[row])})
            x += step
        xmax = max(xmax, x)
        y += heights[row]
    margin = full / 4 if ground_margin is None else ground_margin
    thick = full / 4 if ground_thickness is None else ground_thickness
    blocks.append({"id": "ground", "support": True,
                   "vertices": _rectangle(xmin - margin, -thick, xmax + margin, 0.0)})
    return _finish(name, description, mu, unit_weight, live_load, blocks)


def _course_with_holes(offset, width, holes):
    """Block lengths of one course (units of a full block) from 0 to ``width``.

    Joints at ``offset + k``; ``holes`` are (x0, x1, kind): 'gap' leaves [x0, x1] empty,
    'lintel' puts one block over [x0, x1]. Negative lengths are gaps (running_bond_wall).
    """
    cuts = {0.0, float(width)} | {offset + k for k in range(int(width) + 1) if 0 < offset + k < width}
    for x0, x1, _ in holes:
        cuts = {c for c in cuts if not x0 < c < x1} | {max(0.0, x0), min(float(width), x1)}
    cuts = sorted(cuts)
    out = []
    for a, b in zip(cuts[:-1], cuts[1:]):
        gap = any(kind == "gap" and x0 <= a and b <= x1 for x0, x1, kind in holes)
        out.append(-(b - a) if gap else (b - a))
    return out


def wall_with_openings(courses: int = 12, width: int = 12, openings=((2, 4, 0, 7), (7, 9, 3, 8)),
                       name: str = "wall_openings", mu: float = 0.65, **kwargs) -> dict:
    """A running-bond wall with rectangular openings (doors and windows), in the style of
    Ferris & Tin-Loi's (2001) and Gilbert et al.'s (2006) walls.

    ``width`` full blocks long and ``courses`` high (4 x 1.75 blocks of weight 1 with a unit
    horizontal live load, as the seed's panels; other keywords go to
    :func:`running_bond_wall`). Courses alternate, from the bottom, 1/2 + full + 1/2 and full
    blocks. Each opening ``(x0, x1, c0, c1)`` is empty over [x0, x1] (full-block units)
    in courses c0 .. c1 - 1 (a door when c0 = 0) and carries one lintel block over
    [x0 - 1/2, x1 + 1/2] in course c1. The default (a door and a window) has 129 blocks
    and 324 contacts.
    """
    courses, width = int(courses), int(width)
    if courses < 1 or width < 2:
        raise InputError(f"wall_with_openings: {courses} courses of width {width}; expected >= 1 course, width >= 2")
    for o in openings:
        x0, x1, c0, c1 = o
        if not (0 < x0 - 0.5 and x1 + 0.5 < width and x0 < x1 and 0 <= c0 < c1 < courses):
            raise InputError(f"wall_with_openings: opening {tuple(o)} does not fit a wall of width {width} and "
                             f"{courses} courses; expected 0.5 < x0 < x1 < width - 0.5 and 0 <= c0 < c1 < courses")
    rows = []
    for r in range(courses):
        holes = []
        for x0, x1, c0, c1 in openings:
            if c0 <= r < c1:
                holes.append((float(x0), float(x1), "gap"))
            elif r == c1:
                holes.append((x0 - 0.5, x1 + 0.5, "lintel"))
        rows.append(_course_with_holes(0.5 if r % 2 == 0 else 0.0, width, holes))
    return running_bond_wall(rows, name=name, mu=mu, **kwargs)


def seed_wall(n_courses: int = 6, **kwargs) -> dict:
    """The seed's panels (Table 1): running bond of 4 x 1.75 full blocks, 5 blocks long.

    Courses alternate, from the bottom, [1/2, 1, 1, 1, 1, 1/2] and [1, 1, 1, 1, 1]; a full
    block weighs 1 and carries a unit horizontal live load (left to right); mu = 0.65.
    6 courses give the 33-block panel, 10 courses the 55-block one.
    """
    courses = [[0.5, 1, 1, 1, 1, 0.5] if r % 2 == 0 else [1, 1, 1, 1, 1] for r in range(n_courses)]
    n_blocks = sum(len(c) for c in courses)
    kwargs.setdefault("name", f"wall{n_blocks}")
    kwargs.setdefault("description",
                      f"Seed panel of {n_blocks} blocks in {n_courses} courses of running bond: full blocks "
                      "4 x 1.75 (weight 1, unit horizontal live load left to right), half blocks 2 x 1.75 "
                      "at the ends of the odd courses from the bottom; mu = 0.65; rigid ground.")
    return running_bond_wall(courses, **kwargs)


def _ring(n_voussoirs, inner_radius, thickness, angle, prefix="v"):
    """Voussoirs of a circular ring with radial joints, left to right.

    The ring subtends ``angle`` degrees (180: semicircular; less: segmental), symmetric
    about the vertical through the centre; the circle's centre is placed so that the
    intrados springing points lie on y = 0, at x = -/+ inner_radius * sin(angle / 2).
    Returns (blocks, (inner, outer) springing points of the left and right ends).
    """
    if n_voussoirs < 1 or inner_radius <= 0 or thickness <= 0 or not 0 < angle <= 180:
        raise InputError(f"arch: n_voussoirs={n_voussoirs}, inner_radius={inner_radius}, thickness={thickness}, "
                         f"angle={angle}; expected n >= 1, positive radius and thickness, 0 < angle <= 180 degrees")
    half = math.radians(angle) / 2
    r_in, r_out = inner_radius, inner_radius + thickness
    yc = -r_in * math.cos(half)
    phi = np.pi / 2 + half - np.arange(n_voussoirs + 1) * (2 * half / n_voussoirs)
    scale = r_out

    def point(r, p):
        return [_clean_number(r * math.cos(p), scale), _clean_number(yc + r * math.sin(p), scale)]

    blocks = []
    for k in range(n_voussoirs):
        blocks.append({"id": f"{prefix}{k + 1}",
                       "vertices": [point(r_in, phi[k]), point(r_in, phi[k + 1]),
                                    point(r_out, phi[k + 1]), point(r_out, phi[k])]})
    left = (point(r_in, phi[0]), point(r_out, phi[0]))
    right = (point(r_in, phi[-1]), point(r_out, phi[-1]))
    return blocks, left, right


def _skewback(inner, outer, width, y_base):
    """Convex block under a springing joint ``inner -> outer`` (inner point on y = 0).

    Vertical inner face under the inner point, vertical outer face ``width`` further out,
    flat base at ``y_base``; its top is the springing joint (cut by the outer face if the
    block is narrower than the joint) followed by a flat shoulder if it is wider.
    """
    (xi, yi), (xo, yo) = inner, outer
    side = -1.0 if xo < xi else 1.0  # -1: left springing, outer point further left
    x_out = xi + side * width
    top = [[xi, yi]]
    if side * (x_out - xo) >= 0:   # wider than the joint: whole joint, then a shoulder
        top.append([xo, yo])
        if abs(x_out - xo) > 1e-12 * max(1.0, abs(xo)):
            top.append([x_out, yo])
    else:                          # narrower: the joint is cut by the outer face
        top.append([x_out, yi + (yo - yi) * (x_out - xi) / (xo - xi)])
    verts = [[xi, y_base]] + top + [[x_out, y_base]]
    return verts if side < 0 else verts[::-1]


def arch(n_voussoirs: int = 13, inner_radius: float = 5.0, thickness: float = 1.5, angle: float = 180.0,
         impost_height: float = 2.0, impost_width: float | None = 2.5, mu: float = 0.5,
         unit_weight: float = 1.0, live_load=(-1.0, 0.0), name: str = "arch",
         description: str | None = None, ground_margin: float | None = None) -> dict:
    """JSON spec of a circular arch of ``n_voussoirs`` with radial joints.

    ``angle`` is the angle the ring subtends (180: semicircular; less: segmental, with
    inclined springing joints). With ``impost_height > 0`` the ring springs from two
    impost blocks (``impost_left``, ``impost_right``) of that height below the intrados
    springing point and ``impost_width`` wide (default: the horizontal extent of the
    springing joint), standing on a rigid ``ground``; with ``impost_height == 0`` it
    springs directly from two fixed skewbacks ``support_left`` and ``support_right``.
    Voussoirs are ``v1 ... vn`` from left to right.

    The default live load is horizontal, pointing left, and proportional to the weight:
    the seed's eq. (6), ``fbar = (-W, 0)``.
    """
    blocks, left, right = _ring(n_voussoirs, inner_radius, thickness, angle)
    r_out = inner_radius + thickness
    joint = abs(left[1][0] - left[0][0])
    width = joint if impost_width is None else float(impost_width)
    if width <= 0:
        raise InputError(f"arch: impost_width={width}; expected a positive width")
    if impost_height > 0:
        y_base = -float(impost_height)
        blocks.append({"id": "impost_left", "vertices": _skewback(*left, width, y_base)})
        blocks.append({"id": "impost_right", "vertices": _skewback(*right, width, y_base)})
        margin = r_out / 4 if ground_margin is None else ground_margin
        x_ext = abs(left[0][0]) + width
        blocks.append({"id": "ground", "support": True,
                       "vertices": _rectangle(-x_ext - margin, y_base - thickness, x_ext + margin, y_base)})
    else:
        blocks.append({"id": "support_left", "support": True, "vertices": _skewback(*left, width, -thickness)})
        blocks.append({"id": "support_right", "support": True, "vertices": _skewback(*right, width, -thickness)})
    return _finish(name, description, mu, unit_weight, live_load, blocks)


def portal(n_voussoirs: int = 11, inner_radius: float = 3.0, thickness: float = 1.5, angle: float = 180.0,
           pier_height: float = 3.0, pier_blocks: int = 2, pier_width: float | None = None,
           mu: float = 0.5, unit_weight: float = 1.0, live_load=(-1.0, 0.0), name: str = "portal",
           description: str | None = None, ground_margin: float | None = None) -> dict:
    """JSON spec of a portal: a circular arch (see :func:`arch`) on two piers.

    Each pier is a column of ``pier_blocks`` equal stacked blocks (1: a single block),
    ``pier_height`` tall in all and ``pier_width`` wide (default: the arch thickness),
    its inner face flush with the intrados springing point; the top block carries the
    springing joint (with a skewback top for a segmental ring). Piers are ``pl1 ...``
    (left) and ``pr1 ...`` (right), numbered from the bottom; they stand on ``ground``.
    """
    if pier_blocks < 1 or pier_height <= 0:
        raise InputError(f"portal: pier_blocks={pier_blocks}, pier_height={pier_height}; "
                         "expected at least one block and a positive height")
    blocks, left, right = _ring(n_voussoirs, inner_radius, thickness, angle)
    width = thickness if pier_width is None else float(pier_width)
    if width <= 0:
        raise InputError(f"portal: pier_width={width}; expected a positive width")
    h = pier_height / pier_blocks
    for prefix, (inner, outer) in (("pl", left), ("pr", right)):
        xi = inner[0]
        x_out = xi - width if prefix == "pl" else xi + width
        x0, x1 = min(xi, x_out), max(xi, x_out)
        for k in range(pier_blocks - 1):
            y0 = -pier_height + k * h
            blocks.append({"id": f"{prefix}{k + 1}", "vertices": _rectangle(x0, y0, x1, y0 + h)})
        blocks.append({"id": f"{prefix}{pier_blocks}", "vertices": _skewback(inner, outer, width, -h)})
    margin = (inner_radius + thickness) / 4 if ground_margin is None else ground_margin
    x_ext = abs(left[0][0]) + width
    blocks.append({"id": "ground", "support": True,
                   "vertices": _rectangle(-x_ext - margin, -pier_height - thickness, x_ext + margin, -pier_height)})
    return _finish(name, description, mu, unit_weight, live_load, blocks)


_SEED_LOADS = ("Live load horizontal, pointing left and equal to the weight (seed eq. 6: fbar = (-W, 0), "
               "f0 = (0, -W)); unit weight 1, mu = 0.5, unit width. Dimensions chosen for this project "
               "(the seed's figure gives none): ")


def seed_instances() -> dict:
    """JSON specs of the seed's examples, by name: the panels of Table 1 (exact) and
    drafts of the arch and portals of Figs 2-4 (the text gives loads and friction but no
    dimensions; these were chosen so that the collapse mechanisms have the character the
    seed describes). ``instances/<name>.json`` are these specs, written by
    :func:`structure_to_json`.
    """
    return {
        "wall33": seed_wall(6),
        "wall55": seed_wall(10),
        "arch": arch(13, 5.0, 1.5, impost_height=2.0, impost_width=2.5, name="arch", description=(
            _SEED_LOADS + "semicircular ring of 13 voussoirs with radial joints, intrados radius 5, thickness 1.5 "
            "(centre at (0, 0)); it springs from two impost blocks 2.5 wide and 2 high (inner faces flush with "
            "the intrados) standing on a rigid ground. Note: with every block loaded and flat frictional bases, "
            "alpha <= mu = 0.5 for any such model, so the seed's 0.63425 cannot be reproduced without its figure.")),
        "portal": portal(11, 3.0, 1.5, pier_height=3.0, pier_blocks=2, name="portal", description=(
            _SEED_LOADS + "portal of constant thickness 1.5: semicircular ring of 11 voussoirs, intrados radius 3, "
            "on two piers each made of 2 stacked 1.5 x 1.5 blocks (pier height 3, inner faces flush with the "
            "intrados), on a rigid ground.")),
        "portal_columns": portal(11, 3.0, 1.5, pier_height=4.5, pier_blocks=1, pier_width=2.25,
                                 name="portal_columns", description=(
            _SEED_LOADS + "semicircular ring of 11 voussoirs, intrados radius 3, thickness 1.5, on two columns "
            "each a single block 2.25 wide and 4.5 high (inner faces flush with the intrados), on a rigid ground.")),
    }
