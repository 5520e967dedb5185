"""Contacts of 3D block assemblies: counts, areas, invariance, hostile inputs."""
import json

import numpy as np
import pytest

from lamodel.errors import InputError
from lamodel.io.json3d import structure3d_from_spec
from lamodel.output.tables3d import contacts_summary, interface_areas


def cube(x, y, z, a=1.0, b=1.0, c=1.0):
    return [[x + i * a, y + j * b, z + k * c] for i in (0, 1) for j in (0, 1) for k in (0, 1)]


def stack_spec():
    blocks = [{"id": "ground", "support": True, "vertices": cube(-1, -1, -0.5, 4, 4, 0.5)}]
    for i in range(2):
        for j in range(2):
            for k in range(2):
                blocks.append({"id": f"b{i}{j}{k}", "vertices": cube(i, j, k)})
    return {"name": "stack", "mu": 0.6, "blocks": blocks}


def transformed(spec, rot=np.eye(3), shift=np.zeros(3), scale=1.0, order=None):
    out = json.loads(json.dumps(spec))
    for b in out["blocks"]:
        b["vertices"] = (scale * np.asarray(b["vertices"]) @ rot.T + shift).tolist()
    if order is not None:
        out["blocks"] = [out["blocks"][k] for k in order]
    return out


def rotation(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def contact_set(s, scale=1.0):
    """Sorted (pair, area in the base units) of the interfaces."""
    areas = interface_areas(s) / scale ** 2
    return sorted((tuple(sorted((a, b))), float(x)) for a, b, x in zip(s.iface_a, s.iface_b, areas))


def test_cube_stack_has_12_block_and_4_ground_interfaces_of_unit_area():
    s = structure3d_from_spec(stack_spec())
    ground = [k for k, a in enumerate(s.iface_a) if a == "ground"]
    assert len(ground) == 4 and s.n_interfaces == 16
    assert np.allclose(interface_areas(s), 1.0)
    assert s.n_points == 64                      # four corners each
    c = contacts_summary(s)
    assert (c["blocks"], c["supports"], c["interfaces"], c["points"]) == (8, 1, 16, 64)
    assert c["area"] == pytest.approx(16.0)
    # normals from a to b: the ground (a) pushes up
    for k in ground:
        assert np.allclose(s.normal[s.point_interface == k], [0, 0, 1])


@pytest.mark.parametrize("rot, shift, scale, mirror", [
    (rotation([1, 2, 3], 0.7), [10.0, -3.0, 5.0], 1.0, False),
    (rotation([0, 0, 1], np.pi / 6), [0.0, 0.0, 0.0], 1000.0, False),   # millimetres
    (rotation([1, 1, 0], 1.1), [1e3, 2e3, 0.0], 0.01, True),
])
def test_contacts_invariant_under_rigid_motion_mirror_units_and_renumbering(rot, shift, scale, mirror):
    base = structure3d_from_spec(stack_spec())
    if mirror:
        rot = rot @ np.diag([-1.0, 1.0, 1.0])
    spec = transformed(stack_spec(), rot, np.asarray(shift), scale, order=list(np.random.default_rng(1).permutation(9)))
    s = structure3d_from_spec(spec)
    got, want = contact_set(s, scale), contact_set(base)
    assert [p for p, _ in got] == [p for p, _ in want]
    # areas agree within the geometric tolerance (1e-6 of the size; overlays snap-rounded finer)
    assert [x for _, x in got] == pytest.approx([x for _, x in want], rel=1e-5)


def test_grid_points_add_interior_points():
    s = structure3d_from_spec(dict(stack_spec(), contact_points="grid:3"))
    assert s.n_points == 16 * (4 + 9)


def test_non_convex_blocks_touch_on_several_faces():
    # an L-shaped block (given by faces) on two cubes; a block in its corner touches it twice
    v = [[0, 0, 1], [3, 0, 1], [3, 0, 2], [1, 0, 2], [1, 0, 3], [0, 0, 3]]
    v = v + [[x, 1, z] for x, _, z in v]
    front = [5, 4, 3, 2, 1, 0]
    back = [6, 7, 8, 9, 10, 11]
    sides = [[0, 1, 7, 6], [1, 2, 8, 7], [2, 3, 9, 8], [3, 4, 10, 9], [4, 5, 11, 10], [5, 0, 6, 11]]
    spec = {"name": "L", "mu": 0.6, "blocks": [
        {"id": "ground", "support": True, "vertices": cube(-1, -1, -1, 6, 3, 1)},
        {"id": "p1", "vertices": cube(0, 0, 0)}, {"id": "p2", "vertices": cube(2, 0, 0)},
        {"id": "L", "vertices": v, "faces": [front[::-1], back[::-1]] + [f[::-1] for f in sides]},
        {"id": "top", "vertices": cube(1, 0, 2, 2, 1, 1)}]}
    s = structure3d_from_spec(spec)
    pairs = list(zip(s.iface_a, s.iface_b))
    assert pairs.count(("L", "top")) == 2 and pairs.count(("p1", "L")) == 1
    areas = sorted(x for p, x in zip(pairs, interface_areas(s)) if p == ("L", "top"))
    assert areas == pytest.approx([1.0, 2.0])


def _bad(spec, words):
    with pytest.raises(InputError) as e:
        structure3d_from_spec(spec)
    msg = str(e.value)
    assert "\n" not in msg
    for w in words:
        assert w in msg, msg


def test_hostile_inputs_give_one_line_errors_naming_the_block():
    spec = stack_spec()
    spec["blocks"][3]["vertices"] = cube(0.5, 0, 0)         # overlaps b000
    _bad(spec, ["overlap", "b0"])
    spec = stack_spec()
    spec["blocks"].append({"id": "b000", "vertices": cube(5, 5, 0)})
    _bad(spec, ["'b000'", "declared twice"])
    spec = stack_spec()
    spec["blocks"].append({"id": "far", "vertices": cube(9, 9, 9)})
    _bad(spec, ["'far'", "touches nothing"])
    spec = stack_spec()
    spec["blocks"][0]["support"] = False
    _bad(spec, ["no block is a support"])
    # open surface, non-planar face, inward faces, self-crossing face
    v = cube(0, 0, 0)
    faces = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    good = {"name": "f", "mu": 0.6, "blocks": [{"id": "ground", "support": True, "vertices": cube(-1, -1, -1, 3, 3, 1)},
                                               {"id": "box", "vertices": v, "faces": faces}]}
    structure3d_from_spec(good)
    bad = json.loads(json.dumps(good))
    bad["blocks"][1]["faces"] = faces[:-1]
    _bad(bad, ["'box'", "open"])
    bad = json.loads(json.dumps(good))
    bad["blocks"][1]["vertices"][7] = [1, 1, 1.3]
    _bad(bad, ["'box'", "not planar"])
    bad = json.loads(json.dumps(good))
    bad["blocks"][1]["faces"] = [f[::-1] for f in faces]
    _bad(bad, ["'box'", "inward"])
    bad = json.loads(json.dumps(good))
    bad["blocks"][1]["faces"][0] = [0, 3, 1, 2]
    _bad(bad, ["'box'"])


def test_a_surface_crossing_itself_is_refused():
    from lamodel.geometry.polyhedra import polyhedron
    faces = polyhedron("c", cube(0, 0, 0)).faces          # outward loops of the hull, same corners
    v = cube(0, 0, 0) + cube(0.5, 0.3, 0.4)             # two cubes' surfaces crossing, as one block
    both = faces + [[i + 8 for i in f] for f in faces]
    spec = {"name": "x", "mu": 0.6, "blocks": [{"id": "ground", "support": True, "vertices": cube(-1, -1, -1, 3, 3, 1)},
                                               {"id": "one", "vertices": cube(0, 0, 0), "faces": faces}]}
    structure3d_from_spec(spec)                            # the faces are right: one cube reads
    spec["blocks"][1] = {"id": "twin", "vertices": v, "faces": both}
    _bad(spec, ["'twin'", "crosses itself"])


def test_an_open_mesh_is_refused(tmp_path):
    import trimesh
    from lamodel.io import read
    ground = trimesh.creation.box(extents=[4, 4, 1]).apply_translation([0, 0, -0.5])
    box = trimesh.creation.box(extents=[1, 1, 1]).apply_translation([0, 0, 0.5])
    box = trimesh.Trimesh(box.vertices, box.faces[:-1], process=False)     # one triangle missing
    path = tmp_path / "open.glb"
    trimesh.Scene([ground, box]).export(path)
    with pytest.raises(InputError, match=r"block 'b\d'.*open"):
        read(path, supports_below=-0.5)


@pytest.mark.parametrize("make", ["dome", "barrel_vault"])
def test_curved_generators_keep_their_contacts_when_turned(make):
    from lamodel.geometry import generators3d as G
    spec = getattr(G, make)()
    base = structure3d_from_spec(spec)
    turned = structure3d_from_spec(transformed(spec, rotation([0.3, -1, 0.2], 2.0), np.array([5.0, 7.0, -3.0]),
                                               order=list(np.random.default_rng(2).permutation(len(spec["blocks"])))))
    got, want = contact_set(turned), contact_set(base)
    assert [p for p, _ in got] == [p for p, _ in want]
    assert [x for _, x in got] == pytest.approx([x for _, x in want], rel=1e-5)


def test_faces_tilted_within_the_tolerance_touch_wherever_their_origins_are():
    # a block on a cube, its bottom tilted about the joint's diagonal: 1.6e-3 below and
    # above the cube's top at two opposite corners, 0 at the centre; tolerance 2.45e-3 (1e-3
    # of the size). Opposite corners are 3.2e-3 apart across the planes; where the faces
    # overlap (the centre) they are 0 apart: they touch over the whole square
    t = 0.8e-3

    def z(x, y):
        return 1.0 + t * ((2 * x - 1) + (2 * y - 1))

    q = [(0, 0), (1, 0), (1, 1), (0, 1)]
    cube = [[x, y, 0.0] for x, y in q] + [[x, y, 1.0] for x, y in q]
    cube_faces = [[3, 2, 1, 0], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    top = [[x, y, z(x, y)] for x, y in q] + [[x, y, 2.0] for x, y in q]
    top_faces = [[2, 1, 0, 3], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]   # from (1, 1)
    spec = {"name": "tilted", "dimension": 3, "mu": 0.6, "tolerance": 1e-3, "live_load": [1, 0, 0],
            "blocks": [{"id": "ground", "support": True, "vertices": [[x, y, zz] for x in (-1, 2) for y in (-1, 2)
                                                                      for zz in (-1, 0)]},
                       {"id": "cube", "vertices": cube, "faces": cube_faces},
                       {"id": "top", "vertices": top, "faces": top_faces}]}
    s = structure3d_from_spec(spec)
    pairs = [tuple(sorted(p)) for p in zip(s.iface_a, s.iface_b)]
    assert ("cube", "top") in pairs
    assert interface_areas(s)[pairs.index(("cube", "top"))] == pytest.approx(1.0, rel=1e-4)


@pytest.mark.parametrize("mode", ["grid:0", "grid:65", "grid:100000", "grid:x"])
def test_a_contact_grid_beyond_its_bound_is_refused_in_a_line(mode):
    """grid:100000 asked 149 GiB; n from 1 to GRID_MAX is a choice, past it an input error."""
    with pytest.raises(InputError, match="with a whole n from 1 to 64"):
        structure3d_from_spec(dict(stack_spec(), contact_points=mode))
