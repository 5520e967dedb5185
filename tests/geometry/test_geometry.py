"""Geometry -> Structure: contacts, loads, conventions and input errors (lamodel.geometry)."""
from __future__ import annotations

import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import assert_same_structure
from lamodel.errors import InputError
from lamodel.formulation.matrices import equilibrium_matrix, load_vectors, yield_matrix
from lamodel.geometry import arch, portal, running_bond_wall, seed_instances, seed_wall
from lamodel.io.jsonspec import structure_from_json, structure_to_json

ROOT = Path(__file__).resolve().parents[2]
INSTANCES = ROOT / "instances"


def rect(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


def ground(x0=-10, x1=10, top=0.0):
    return {"id": "ground", "support": True, "vertices": rect(x0, top - 1, x1, top)}


def spec_of(*blocks, mu=0.6, **top):
    return {"name": "t", "mu": mu, **top, "blocks": list(blocks)}


def pairs(s):
    return {frozenset(p) for p in zip(s.block_a, s.block_b)}


# ------------------------------------------------------------------ an independent count
def wall_contacts_by_intervals(courses, full=4.0):
    """Contacts of a running-bond wall counted by brute force on the block intervals:
    ground under the bottom course, touching ends within a course, and overlapping
    intervals of consecutive courses. Independent of the polygon machinery."""
    rows = []
    for lengths in courses:
        x, row = 0.0, []
        for length in lengths:
            if length > 0:
                row.append((x, x + length * full))
            x += abs(length) * full
        rows.append(row)
    count = len(rows[0])
    for row in rows:
        count += sum(1 for (_, e), (s, _) in zip(row, row[1:]) if abs(e - s) < 1e-12)
    for below, above in zip(rows, rows[1:]):
        count += sum(1 for a in below for b in above if min(a[1], b[1]) - max(a[0], b[0]) > 1e-12)
    return count


# ========================================================================== walls
@pytest.mark.parametrize("name, n_courses, n_blocks, n_contacts",
                         [("wall33", 6, 33, 83), ("wall55", 10, 55, 141)])
def test_seed_walls_from_json_files(name, n_courses, n_blocks, n_contacts):
    """The seed's panels (Table 1): block counts from the paper, contact counts as
    specified for this project (support contacts included)."""
    s = structure_from_json(INSTANCES / f"{name}.json")
    assert s.name == name
    assert s.n_blocks == n_blocks
    assert s.n_contacts == n_contacts
    assert s.supports == ["ground"]
    courses = [[0.5, 1, 1, 1, 1, 0.5] if r % 2 == 0 else [1] * 5 for r in range(n_courses)]
    assert s.n_contacts == wall_contacts_by_intervals(courses)
    s.validate()


@pytest.mark.parametrize("name", ["wall33", "wall55", "arch", "portal", "portal_columns"])
def test_instance_files_match_their_generators(name):
    """instances/*.json are exactly what lamodel.geometry.seed_instances() generates."""
    on_disk = json.loads((INSTANCES / f"{name}.json").read_text())
    assert on_disk == json.loads(json.dumps(seed_instances()[name]))


@pytest.mark.parametrize("n_courses", [6, 10])
def test_seed_wall_loads(n_courses):
    """A full 4 x 1.75 block weighs 1 and carries a unit horizontal live load; a half
    block half of that. Loads act at the centroid."""
    s = structure_from_json(seed_wall(n_courses))
    n_half = 2 * ((n_courses + 1) // 2)
    n_full = s.n_blocks - n_half
    total = n_full + 0.5 * n_half
    assert np.isclose(-s.dead[:, 1].sum(), total)
    assert np.allclose(s.dead[:, 0], 0)
    assert np.isclose(s.live[:, 0].sum(), total)
    assert np.allclose(s.live[:, 1], 0)
    widths = np.array([np.ptp(s.polygons[b][:, 0]) for b in s.blocks])
    assert np.allclose(-s.dead[:, 1], widths / 4.0)
    for j, b in enumerate(s.blocks):
        assert np.allclose(s.centroid[j], s.polygons[b].mean(axis=0))


def test_wall_conventions():
    """Support contacts have the support as block a; bed joints point up from the block
    below, head joints point right from the block on the left; ids are c1..cN."""
    s = structure_from_json(seed_wall(6))
    assert s.contacts == [f"c{k + 1}" for k in range(s.n_contacts)]
    idx = s.block_index()
    for k in range(s.n_contacts):
        a, b, n = s.block_a[k], s.block_b[k], s.normal[k]
        if "ground" in (a, b):
            assert a == "ground"
            assert np.allclose(n, [0, 1])
            continue
        ga, gb = s.centroid[idx[a]], s.centroid[idx[b]]
        if np.allclose(n, [0, 1]):
            assert ga[1] < gb[1]
        else:
            assert np.allclose(n, [1, 0])
            assert ga[0] < gb[0] and np.isclose(ga[1], gb[1])
        # the centre lies on both polygons' boundaries, d is half the shared length
        for body in (a, b):
            poly = s.polygons[body]
            assert poly[:, 0].min() - 1e-9 <= s.centre[k, 0] <= poly[:, 0].max() + 1e-9
            assert poly[:, 1].min() - 1e-9 <= s.centre[k, 1] <= poly[:, 1].max() + 1e-9
    assert np.all(s.d > 0)


def test_wall_with_an_opening():
    """A gap (negative length) leaves no contact across it; a lintel bridges it."""
    courses = [[1, 1, 1, 1], [1, -2, 1], [1, -2, 1], [0.5, 3, 0.5]]
    s = structure_from_json(running_bond_wall(courses))
    assert s.n_blocks == 4 + 2 + 2 + 3
    assert s.n_contacts == wall_contacts_by_intervals(courses)
    # the jambs of the opening do not touch each other
    assert frozenset(("b5", "b6")) not in pairs(s)
    assert frozenset(("b7", "b8")) not in pairs(s)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.lists(st.sampled_from([0.25, 0.5, 0.75, 1.0, 1.5]), min_size=1, max_size=6),
                min_size=1, max_size=6))
@pytest.mark.slow
def test_random_walls_match_interval_count(rows):
    """Any stack of courses of equal length: contacts = brute-force interval count."""
    length = 4.0
    courses = []
    for row in rows:
        out, total = [], 0.0
        for x in row * 8:
            step = min(x, length - total)
            if step <= 0:
                break
            out.append(step)
            total += step
        courses.append(out)
    s = structure_from_json(running_bond_wall(courses))
    assert s.n_blocks == sum(len(c) for c in courses)
    assert s.n_contacts == wall_contacts_by_intervals(courses)


def test_large_wall_builds():
    """Thousands of blocks: the contact search is a sweep, not a double loop (no timing
    asserted, but a quadratic search would make this test crawl)."""
    courses = [[0.5] + [1] * 39 + [0.5] if r % 2 == 0 else [1] * 40 for r in range(40)]
    s = structure_from_json(running_bond_wall(courses))
    assert s.n_blocks == 20 * 41 + 20 * 40
    assert s.n_contacts == wall_contacts_by_intervals(courses)


# ==================================================================== arches, portals
@pytest.mark.parametrize("n", [11, 13])
def test_arch_radial_joints_are_found(n):
    """n voussoirs on two imposts: n - 1 radial joints, 2 springing joints and 2 impost
    bases. Radial joints are inclined, and their line passes through the circle's centre
    (their normal is perpendicular to the radius through the contact centre)."""
    s = structure_from_json(arch(n_voussoirs=n, inner_radius=5.0, thickness=1.5, impost_height=2.0))
    assert s.n_blocks == n + 2
    assert s.n_contacts == (n - 1) + 2 + 2
    ring = [k for k in range(s.n_contacts) if s.block_a[k].startswith("v") and s.block_b[k].startswith("v")]
    assert len(ring) == n - 1
    n_ring, c_ring = s.normal[ring], s.centre[ring]
    assert np.all(np.abs(n_ring).min(axis=1) > 0.05)  # not axis-aligned
    radial = c_ring / np.hypot(c_ring[:, 0], c_ring[:, 1])[:, None]
    assert np.allclose((n_ring * radial).sum(axis=1), 0, atol=1e-12)
    assert np.allclose(s.d[ring], 0.75)  # half the thickness
    assert np.allclose(np.hypot(*c_ring.T), 5.75)  # mid-thickness


def test_segmental_arch_on_skewbacks():
    s = structure_from_json(arch(n_voussoirs=9, inner_radius=4.0, thickness=1.0, angle=120.0, impost_height=0))
    assert sorted(s.supports) == ["support_left", "support_right"]
    assert s.n_blocks == 9 and s.n_contacts == 10
    springing = [k for k in range(s.n_contacts) if s.block_a[k].startswith("support")]
    assert len(springing) == 2
    # springing joints are radial at 30 degrees from the horizontal
    assert np.allclose(np.abs(s.normal[springing, 0]), math.cos(math.radians(60)), atol=1e-12)


def test_portal_counts_and_piers():
    n, pier_blocks = 11, 3
    s = structure_from_json(portal(n_voussoirs=n, inner_radius=3.0, thickness=1.5, pier_height=4.5,
                                   pier_blocks=pier_blocks))
    assert s.n_blocks == n + 2 * pier_blocks
    assert s.n_contacts == (n + 1) + 2 * (pier_blocks - 1) + 2
    assert np.allclose([np.ptp(s.polygons[f"pl{k}"][:, 0]) for k in (1, 2, 3)], 1.5)


@pytest.mark.parametrize("name", ["arch", "portal", "portal_columns"])
def test_draft_instances_are_valid(name):
    """The seed's Figs 2-4 drafts: unit weight 1, mu 0.5, live load = horizontal weight."""
    s = structure_from_json(INSTANCES / f"{name}.json")
    s.validate()
    assert np.allclose(s.mu, 0.5)
    assert np.allclose(s.live[:, 0], s.dead[:, 1])  # fbar = (-W, 0), f0 = (0, -W)
    assert np.allclose(s.live[:, 1], 0)
    areas = []
    for b in s.blocks:
        x, y = s.polygons[b].T
        areas.append(0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))
    assert np.allclose(-s.dead[:, 1], areas)
    assert "description" in json.loads((INSTANCES / f"{name}.json").read_text())


# ============================================================ contacts in general
def test_blocks_that_do_not_touch_get_no_contact():
    g = ground()
    a = {"id": "a", "vertices": rect(0, 0, 1, 1)}
    gap = {"id": "b", "vertices": rect(1.001, 0, 2, 1)}           # 1 mm apart
    corner = {"id": "c", "vertices": rect(1, 1, 2, 2)}          # touches a at a corner only
    s = structure_from_json(spec_of(a, gap, g, {"id": "d", "vertices": rect(1.001, 1, 3, 2)}))
    assert frozenset(("a", "b")) not in pairs(s)
    s = structure_from_json(spec_of(a, corner, {"id": "e", "vertices": rect(1.5, 0, 2.5, 1)}, g))
    assert frozenset(("a", "c")) not in pairs(s)
    assert frozenset(("c", "e")) in pairs(s)


def test_partial_overlap_gives_centre_and_half_length():
    s = structure_from_json(spec_of({"id": "low", "vertices": rect(0, 0, 4, 1)},
                                    {"id": "top", "vertices": rect(3, 1, 7, 2)}, ground()))
    k = s.contacts.index(next(c for c, a, b in zip(s.contacts, s.block_a, s.block_b) if {a, b} == {"low", "top"}))
    assert (s.block_a[k], s.block_b[k]) == ("low", "top")
    assert np.allclose(s.centre[k], [3.5, 1.0])
    assert np.isclose(s.d[k], 0.5)
    assert np.allclose(s.normal[k], [0, 1])


@pytest.mark.parametrize("angle", [0.0, 17.0, 45.0, 90.0, 133.0, 200.0])
def test_contacts_do_not_depend_on_the_orientation_of_the_model(angle):
    """Rotating the whole geometry rotates the contacts: same pairs, same d, rotated centres."""
    base = structure_from_json(seed_wall(6))
    spec = seed_wall(6)
    c, s_ = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    R = np.array([[c, -s_], [s_, c]])
    for body in spec["blocks"]:
        body["vertices"] = (np.array(body["vertices"]) @ R.T).tolist()
    rot = structure_from_json(spec)
    assert rot.n_contacts == base.n_contacts
    key = lambda st: {frozenset((a, b)): k for k, (a, b) in enumerate(zip(st.block_a, st.block_b))}  # noqa: E731
    kb, kr = key(base), key(rot)
    assert kb.keys() == kr.keys()
    for p, k in kb.items():
        j = kr[p]
        assert np.isclose(rot.d[j], base.d[k])
        assert np.allclose(rot.centre[j], R @ base.centre[k], atol=1e-9)
        sign = 1 if base.block_a[k] == rot.block_a[j] else -1
        assert np.allclose(rot.normal[j], sign * (R @ base.normal[k]), atol=1e-12)


def test_clockwise_polygons_and_extra_collinear_vertices_change_nothing():
    ccw = structure_from_json(seed_wall(6))
    spec = seed_wall(6)
    for body in spec["blocks"]:
        v = body["vertices"]
        mid = [(v[0][0] + v[1][0]) / 2, (v[0][1] + v[1][1]) / 2]  # a vertex in the middle of an edge
        body["vertices"] = [v[0], mid] + v[1:]
        body["vertices"] = body["vertices"][::-1]                  # clockwise
    cw = structure_from_json(spec)
    assert cw.block_a == ccw.block_a and cw.block_b == ccw.block_b
    assert np.allclose(cw.centre, ccw.centre) and np.allclose(cw.d, ccw.d)
    assert np.allclose(cw.centroid, ccw.centroid) and np.allclose(cw.dead, ccw.dead)
    for b, v in cw.polygons.items():
        assert len(v) == 4


def test_contact_ids_do_not_depend_on_how_contacts_are_found():
    """Ids follow the file order of the bodies: reversing the list reverses nothing but
    that order; the set of (a, b, centre) is the same."""
    spec = seed_wall(6)
    s1 = structure_from_json(spec)
    s2 = structure_from_json(dict(spec, blocks=spec["blocks"][::-1]))
    t1 = sorted(zip(s1.block_a, s1.block_b, map(tuple, np.round(s1.centre, 9))))
    t2 = sorted(zip(s2.block_a, s2.block_b, map(tuple, np.round(s2.centre, 9))))
    assert t1 == t2
    s3 = structure_from_json(spec)
    assert s3.block_a == s1.block_a and s3.block_b == s1.block_b


def test_nearly_collinear_edges_within_tolerance():
    """Round-off (1e-12 on a model of size ~10) does not lose a contact; the tolerance field
    lets hand-typed coordinates (rounded to 1e-4) find theirs."""
    s = structure_from_json(spec_of({"id": "a", "vertices": rect(0, 1e-12, 1, 1)}, ground()))
    assert s.n_contacts == 1
    rough = spec_of({"id": "a", "vertices": rect(0, 0, 1, 1)},
                    {"id": "b", "vertices": [[0, 1.00004], [1, 0.99996], [1, 2], [0, 2]]}, ground())
    with pytest.raises(InputError, match="'a' and block 'b' interpenetrate"):  # by 4e-5 > 1e-9 * size
        structure_from_json(rough)
    assert structure_from_json(dict(rough, tolerance=1e-5)).n_contacts == 2


def test_friction_is_the_smaller_of_the_two_bodies():
    s = structure_from_json(spec_of({"id": "a", "vertices": rect(0, 0, 1, 1), "mu": 0.3},
                                    {"id": "b", "vertices": rect(0, 1, 1, 2)}, ground(), mu=0.7))
    by_pair = {frozenset((a, b)): m for a, b, m in zip(s.block_a, s.block_b, s.mu)}
    assert by_pair[frozenset(("a", "b"))] == 0.3
    assert by_pair[frozenset(("ground", "a"))] == 0.3


def test_load_fields():
    s = structure_from_json(spec_of({"id": "a", "vertices": rect(0, 0, 2, 1)},
                                    {"id": "b", "vertices": rect(0, 1, 2, 2), "dead": [0, -5], "live": [0.5, 0.25]},
                                    ground(), unit_weight=3.0, live_load=[0.2, -0.1]))
    j = s.block_index()
    assert np.allclose(s.dead[j["a"]], [0, -6.0])
    assert np.allclose(s.live[j["a"]], [1.2, -0.6])
    assert np.allclose(s.dead[j["b"]], [0, -5])
    assert np.allclose(s.live[j["b"]], [0.5, 0.25])


def test_overlapping_supports_are_allowed_and_never_in_contact():
    g1 = {"id": "g1", "support": True, "vertices": rect(-5, -1, 1, 0)}
    g2 = {"id": "g2", "support": True, "vertices": rect(0, -2, 5, 0)}
    s = structure_from_json(spec_of({"id": "a", "vertices": rect(-1, 0, 2, 1)}, g1, g2))
    assert pairs(s) == {frozenset(("g1", "a")), frozenset(("g2", "a"))}
    assert all(a in ("g1", "g2") for a in s.block_a)


def test_round_trip_through_json(tmp_path):
    s = structure_from_json(INSTANCES / "portal.json")
    path = tmp_path / "again.json"
    structure_to_json(s, path)
    t = structure_from_json(path)
    assert_same_structure(t, s, exact=False)


# ============================================================== equilibrium sanity
def test_single_block_on_the_ground_carries_its_weight_in_compression():
    s = structure_from_json(spec_of({"id": "a", "vertices": rect(0, 0, 2, 1)}, ground()))
    A = equilibrium_matrix(s).toarray()
    f0, _ = load_vectors(s)
    sol, *_ = np.linalg.lstsq(A, -f0, rcond=None)
    assert np.allclose(A @ sol, -f0)
    N, V, M = sol
    assert N < 0 and np.isclose(N, -2.0)  # compression equal to the weight
    assert np.isclose(V, 0) and np.isclose(M, 0)
    Y = yield_matrix(s).toarray()
    assert np.all(Y @ sol <= 1e-12)


def test_overhanging_block_is_at_the_hinge_limit():
    """A block whose centroid is above the edge of its support: N carries the weight,
    the couple M puts the resultant at the edge (|M| = -d N)."""
    s = structure_from_json(spec_of({"id": "a", "vertices": rect(0, 0, 2, 1)},
                                    {"id": "g", "support": True, "vertices": rect(-1, -1, 1, 0)}))
    A = equilibrium_matrix(s).toarray()
    f0, _ = load_vectors(s)
    N, V, M = np.linalg.solve(A, -f0)
    assert np.isclose(N, -2.0) and np.isclose(V, 0.0)
    assert np.isclose(abs(M), -s.d[0] * N)


@pytest.mark.slow
def test_wall_equilibrium_is_solvable():
    s = structure_from_json(seed_wall(6))
    A = equilibrium_matrix(s).toarray()
    f0, fbar = load_vectors(s)
    for load in (f0, f0 + 0.5 * fbar):
        sol, *_ = np.linalg.lstsq(A, -load, rcond=None)
        assert np.allclose(A @ sol, -load)


# ==================================================================== input errors
SQ = {"id": "a", "vertices": rect(0, 0, 1, 1)}


@pytest.mark.parametrize("blocks, message", [
    ([{"id": "a"}, ground()], "block 'a' has no 'vertices'"),
    ([{"id": "a", "vertices": [[0, 0], [1, 0]]}, ground()], "block 'a' has 2 vertices; expected at least 3"),
    ([{"id": "a", "vertices": [[0, 0], [2, 0], [1, 0.5], [2, 1], [0, 1]]}, ground()], "block 'a' is not convex"),
    ([{"id": "a", "vertices": [[0, 0], [1, 1], [1, 0], [0, 1]]}, ground()], "block 'a' is not convex or crosses itself"),
    ([{"id": "a", "vertices": [[1, 0], [-0.809, 0.588], [0.309, -0.951], [0.309, 0.951], [-0.809, -0.588]]},
      ground()], "block 'a' is self-intersecting"),
    ([{"id": "a", "vertices": [[0, 0], [1, 0], [2, 0]]}, ground()], "block 'a' has zero area"),
    ([SQ, {"id": "b", "vertices": rect(0.5, 0.5, 1.5, 1.5)}, ground()], "block 'a' and block 'b' interpenetrate"),
    ([{"id": "a", "vertices": rect(0, -0.5, 1, 1)}, ground()], "block 'a' and support 'ground' interpenetrate"),
    ([SQ], "no block is a support"),
    ([SQ, dict(SQ, vertices=rect(1, 0, 2, 1)), ground()], "block 'a' is declared twice"),
    ([SQ, {"id": "b", "vertices": rect(0, 3, 1, 4)}, ground()], "block 'b' touches no other body"),
    ([{"id": "a", "vertices": [[0, 0], [1, "x"], [1, 1]]}, ground()], "vertex coordinate"),
    ([{"vertices": rect(0, 0, 1, 1)}, ground()], r"blocks\[0\] has no valid 'id'"),
    ([dict(SQ, support="yes"), ground()], "'support' is \"yes\""),
    ([ground()], "every body is a support"),
])
def test_bad_geometry_is_reported_with_the_block(blocks, message):
    with pytest.raises(InputError, match=message):
        structure_from_json({"name": "bad", "mu": 0.5, "blocks": blocks})


def test_bad_files_name_the_file(tmp_path):
    path = tmp_path / "broken.json"
    path.write_text('{"mu": 0.5, "blocks": [')
    with pytest.raises(InputError, match=r"broken\.json: malformed JSON at line 1"):
        structure_from_json(path)
    path.write_text("[1, 2]")
    with pytest.raises(InputError, match=r"broken\.json: the file holds a JSON list"):
        structure_from_json(path)
    with pytest.raises(InputError, match="cannot read"):
        structure_from_json(tmp_path / "missing.json")
    path.write_text(json.dumps({"blocks": [SQ, ground()]}))
    with pytest.raises(InputError, match=r"broken\.json: block 'a' has no friction coefficient"):
        structure_from_json(path)
    path.write_text(json.dumps({"mu": -1, "blocks": [SQ, ground()]}))
    with pytest.raises(InputError, match="'mu' is -1; expected a number >= 0"):
        structure_from_json(path)
    path.write_text(json.dumps({"mu": 0.5, "blocks": []}))
    with pytest.raises(InputError, match="'blocks' is missing or empty"):
        structure_from_json(path)


def test_messages_are_one_line():
    for bad in ({"mu": 0.5, "blocks": [SQ]}, {"mu": 0.5, "blocks": [{"id": "a"}, ground()]}):
        with pytest.raises(InputError) as err:
            structure_from_json(bad)
        assert "\n" not in str(err.value)


def test_unknown_fields_only_warn():
    with pytest.warns(UserWarning) as record:
        s = structure_from_json({"mu": 0.5, "colour": "red", "blocks": [dict(SQ, texture=1), ground()]})
    assert s.n_contacts == 1
    messages = [str(w.message) for w in record]
    assert any("unknown top-level field(s) 'colour'" in m for m in messages)
    assert any("unknown block field(s) 'texture'" in m for m in messages)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        structure_from_json({"mu": 0.5, "description": "known", "blocks": [dict(SQ, description="x"), ground()]})


@pytest.mark.parametrize("spec, blocks, supports", [
    (seed_wall(6), 33, ["ground"]),
    (arch(), 13 + 2, ["ground"]),
    (portal(), 11 + 2 * 2, ["ground"]),
    (arch(angle=140, impost_height=0), 13, ["support_left", "support_right"]),
    (portal(angle=150, pier_blocks=1), 11 + 2, ["ground"]),
])
def test_generated_structures_validate(spec, blocks, supports):
    s = structure_from_json(spec).validate()
    assert s.n_blocks == blocks and sorted(s.supports) == supports
    assert (s.dead[:, 1] < 0).all() and (s.d > 0).all()  # every block has weight, every joint a length
    # every block rests, through a chain of joints, on a support
    reached, frontier = set(s.supports), set(s.supports)
    while frontier:
        frontier = {b for a, b in zip(s.block_a, s.block_b) if a in frontier and b not in reached} | \
                   {a for a, b in zip(s.block_a, s.block_b) if b in frontier and a not in reached}
        reached |= frontier
    assert reached >= set(s.blocks)
    if blocks == 33:
        assert s.n_contacts == 83  # the seed's panel, as instances/wall33.dat


# ============================================================== the build script
@pytest.mark.slow
def test_build_instance_script(tmp_path):
    from conftest import run_script

    from lamodel.cli import command
    from lamodel.io.datfile import read_dat

    out = tmp_path / "wall33.dat"
    assert command("build", [str(INSTANCES / "wall33.json"), "-o", str(out)]) == 0
    assert read_dat(out).n_contacts == structure_from_json(INSTANCES / "wall33.json").n_contacts
    bad = tmp_path / "bad.json"
    bad.write_text("{")
    assert command("build", [str(bad), "-o", str(tmp_path / "bad.dat")]) == 2
    res = run_script("build_instance.py", bad, "-o", tmp_path / "bad.dat")  # the old script path
    assert res.returncode == 2 and res.stderr.startswith("build_instance.py: error: "), res.stderr


def test_wall_with_openings_leaves_the_openings_empty_and_bridges_them_with_lintels():
    from lamodel.geometry import wall_with_openings
    from lamodel.errors import InputError
    spec = wall_with_openings(courses=6, width=8, openings=((3, 5, 0, 4),))
    blocks = [b for b in spec["blocks"] if not b.get("support")]
    area = 0.0
    for b in blocks:
        v = np.asarray(b["vertices"], float)
        x, y = v[:, 0], v[:, 1]
        area += 0.5 * abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1)))
        # no block inside the door: x in (12, 20) (full block 4 long), courses 0..3 (height 1.75)
        cx, cy = x.mean(), y.mean()
        assert not (12 < cx < 20 and cy < 4 * 1.75), b["id"]
    assert area == pytest.approx((8 * 6 - 2 * 4) * 4 * 1.75)
    # the lintel over the door (course 4) is one block spanning [10, 22]
    lintel = [b for b in blocks if min(v[0] for v in b["vertices"]) == 10 and max(v[0] for v in b["vertices"]) == 22]
    assert len(lintel) == 1
    s = structure_from_json(spec)
    assert s.n_blocks == len(blocks)
    with pytest.raises(InputError, match="does not fit"):
        wall_with_openings(courses=6, width=8, openings=((7, 9, 0, 4),))


def test_load_cases_and_a_rolling_load_survive_a_round_trip_through_json(tmp_path):
    """A structure's point loads (dead, live, of every case), its load cases' own and its
    rolling load are written and read back: every case's forces and moments, the point
    loads, the rolling axles and positions the same."""
    from lamodel.loads import case_structure
    blocks = [{"id": "b1", "vertices": rect(0, 0, 1, 1)}, {"id": "b2", "vertices": rect(0, 1, 1, 2)}, ground()]
    cases = {**spec_of(*blocks), "mu": 0.6,
             "loads": [{"block": "b2", "at": [0, 2], "force": [1, 0], "case": "top"},
                       {"block": "b1", "at": [0.2, 0.5], "force": [0.5, -0.1], "case": "low"},
                       {"block": "b2", "at": [1, 1.5], "force": [0.25, 0]},
                       {"block": "b1", "at": [0.9, 1], "force": [0, -2], "kind": "dead"}]}
    rolling = {**spec_of(*blocks), "mu": 0.6,
               "rolling_load": {"force": [0, -1], "axles": [0, 0.4], "positions": [0.1, 0.5]}}
    for spec in (cases, rolling):
        s = structure_from_json(spec)
        path = tmp_path / "again.json"
        structure_to_json(s, path)
        t = structure_from_json(path)
        assert_same_structure(t, s, exact=False)
        assert list(t.cases) == list(s.cases) and t.rolling == s.rolling
        assert t.point_loads == s.point_loads   # drawn where they act, not folded into the blocks' loads
        assert np.allclose(t.dead_m, s.dead_m) and np.allclose(t.live_m, s.live_m)
        for name in s.cases:
            a, b = case_structure(t, name), case_structure(s, name)
            assert np.allclose(a.live, b.live) and np.allclose(a.live_m, b.live_m)
            assert np.allclose(a.dead, b.dead) and np.allclose(a.dead_m, b.dead_m)


def test_a_round_trip_keeps_the_order_ids_tolerance_and_description(tmp_path):
    """Written back, a file gives the same contacts under the same ids (the bodies in the
    file's order, ground first here), its tolerance and description; a support in no
    contact beside bodies of other frictions is read back."""
    spec = spec_of(ground(), {"id": "a", "vertices": rect(0, 0, 1, 1), "mu": 0.9},
                   {"id": "b", "vertices": rect(0, 1.0005, 1, 2)},
                   {"id": "far", "vertices": rect(30, 0, 31, 3), "support": True},
                   tolerance=1e-3, description="a stack with a gap")
    s = structure_from_json(spec)
    path = tmp_path / "again.json"
    structure_to_json(s, path)
    t = structure_from_json(path)
    assert_same_structure(t, s, exact=False)
    assert [b["id"] for b in json.loads(path.read_text())["blocks"]] == ["ground", "a", "b", "far"]
    assert t.tolerance == 1e-3 and t.description == "a stack with a gap"


def test_an_empty_case_name_is_refused():
    spec = spec_of({"id": "a", "vertices": rect(0, 0, 1, 1)}, ground(),
                   loads=[{"block": "a", "at": [0, 1], "force": [1, 0], "case": " "}])
    with pytest.raises(InputError, match="'case' is \" \"; expected a case name"):
        structure_from_json(spec)


def test_a_turned_live_load_turns_the_moments_of_its_point_loads():
    """with_load_angle (a study's load_angle) on live point loads off the centroids: the
    same forces and moments as the file written with the turned forces."""
    from lamodel.variants import with_load_angle
    blocks = [{"id": "a", "vertices": rect(0, 0, 1, 2)}, {"id": "b", "vertices": rect(0, 2, 1, 3)}, ground()]
    def file(force):
        return structure_from_json(spec_of(*blocks, loads=[{"block": "b", "at": [0, 3], "force": force},
                                                          {"block": "a", "at": [1, 0.5], "force": [0.5, 0.2]}]))
    for degrees in (30.0, 90.0, -120.0):
        c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
        turned = with_load_angle(file([1.0, 0.0]), degrees)
        want = structure_from_json(spec_of(*blocks, loads=[
            {"block": "b", "at": [0, 3], "force": [c, s]},
            {"block": "a", "at": [1, 0.5], "force": [0.5 * c - 0.2 * s, 0.5 * s + 0.2 * c]}]))
        assert np.allclose(turned.live, want.live) and np.allclose(turned.live_m, want.live_m)
        assert np.allclose([p.force for p in turned.point_loads], [p.force for p in want.point_loads])


def test_a_key_given_twice_in_one_object_is_said(tmp_path):
    path = tmp_path / "twice.json"
    path.write_text('{"name": "t", "mu": 0.6, "mu": 0.01, "blocks": [' + json.dumps(ground()) + ", "
                    + json.dumps({"id": "a", "vertices": rect(0, 0, 1, 1)}) + "]}")
    with pytest.warns(UserWarning, match="'mu' is given twice in one object; the last value is used"):
        s = structure_from_json(path)
    assert np.all(s.mu == 0.01)


def test_a_solve_stopped_before_any_certificate_says_so():
    from lamodel.search.driver import SolveOptions, solve
    o = solve(structure_from_json(INSTANCES / "wall33.json"), SolveOptions(starts=0), stop=lambda: True)
    assert o.status == "interrupted" and o.best is None
    assert o.message == "interrupted before any state was certified"
