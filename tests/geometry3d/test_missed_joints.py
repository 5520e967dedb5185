"""Joints the geometric tolerance misses (near-joints, a COMPAS file's own interfaces), the
blocks an unstable verdict names, and the support error: each one line a user can act on."""
import json
import warnings

import pytest

from lamodel.cli import main
from lamodel.errors import InputError
from lamodel.geometry.polyhedra import polyhedron
from lamodel.io import read
from lamodel.io.assemblies import read_compas
from lamodel.io.json3d import structure3d_from_spec
from lamodel.search.unstable import unheld_blocks3d

GAP = 1e-4


def box(x0, y0, z0, x1, y1, z1):
    return [[x, y, z] for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]


def side_by_side(gap=GAP):
    """Two unit cubes on a ground slab, the second ``gap`` apart from the first along x
    (size: the diagonal of 3 x 1 x 1.2, 3.38; the default tolerance 1e-6 of it is 3.4e-6)."""
    return {"name": "pair", "mu": 0.6, "blocks": [
        {"id": "ground", "support": True, "vertices": box(-0.5, 0, -0.2, 2.5, 1, 0)},
        {"id": "b1", "vertices": box(0, 0, 0, 1, 1, 1)},
        {"id": "b2", "vertices": box(1 + gap, 0, 0, 2 + gap, 1, 1)}]}


def pairs(s):
    return {tuple(sorted(p)) for p in zip(s.iface_a, s.iface_b)}


def read_warnings(build):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        s = build()
    return s, [str(w.message) for w in caught]


def test_facets_a_hair_apart_give_one_warning_with_the_tolerance_that_joins_them():
    s, said = read_warnings(lambda: structure3d_from_spec(side_by_side()))
    assert ("b1", "b2") not in pairs(s)
    assert len(said) == 1 and "\n" not in said[0]
    # 1e-4 apart: 3.4e-4 (100 x) finds them, 3.4e-5 (10 x) does not: the least that joins them is 1e-4
    assert "1 pair of blocks (first: blocks 'b1' and 'b2')" in said[0]
    assert "within tolerance 0.0001 but not within 1e-06" in said[0] and said[0].endswith("--tolerance 0.0001 joins them")
    s, said = read_warnings(lambda: structure3d_from_spec(side_by_side(), tolerance=1e-4))
    assert ("b1", "b2") in pairs(s) and said == []


def test_no_warning_where_the_blocks_touch_or_stand_well_apart():
    for gap in (0.0, 0.01):
        s, said = read_warnings(lambda: structure3d_from_spec(side_by_side(gap)))
        assert said == [] and (("b1", "b2") in pairs(s)) == (gap == 0.0)


def test_a_block_that_touches_nothing_is_explained_by_the_warning_before_the_error(tmp_path, capsys):
    spec = side_by_side()
    spec["blocks"][2]["vertices"] = box(0, 0, 1 + GAP, 1, 1, 2 + GAP)   # on b1, a hair above it
    path = tmp_path / "tower.json"
    path.write_text(json.dumps(spec))
    assert main(["build", str(path)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2 and "warning:" in err[0] and "--tolerance 0.0001 joins them" in err[0]
    assert "block 'b2' touches nothing" in err[1]
    assert "b2" in read(path, tolerance=1e-4).blocks


def compas(spec, stored, supports=True):
    """``spec``'s blocks in COMPAS's assembly layout, nodes named 0, 1, ...; ``stored``:
    the node pairs whose edges carry an interface."""
    nodes, edges = {}, {}
    for k, b in enumerate(spec["blocks"]):
        p = polyhedron(b["id"], b["vertices"])
        nodes[str(k)] = {"is_support": bool(b.get("support")) and supports, "block": {"data": {
            "vertex": {str(i): dict(zip("xyz", map(float, v))) for i, v in enumerate(p.vertices)},
            "face": {str(i): f for i, f in enumerate(p.faces)}}}}
    for a, b in stored:
        edges.setdefault(str(a), {})[str(b)] = {"interfaces": [{"data": {"points": [[0, 0, 0]]}}]}
    return {"dtype": "compas_assembly.datastructures/Assembly",
            "data": {"graph": {"data": {"node": nodes, "edge": edges}}}}


def test_a_compas_interface_the_tolerance_misses_is_counted_with_the_tolerance_that_finds_it():
    data = compas(side_by_side(), [(0, 1), (0, 2), (1, 2)])
    s, said = read_warnings(lambda: read_compas(data))
    assert ("1", "2") not in pairs(s) and len(said) == 1
    assert "1 of the 3 block pairs the file's own interfaces join have no joint at tolerance 1e-06" in said[0]
    assert "(first: blocks '1' and '2')" in said[0] and said[0].endswith("--tolerance 0.0001 joins them")
    s, said = read_warnings(lambda: read_compas(data, tolerance=1e-4))
    assert ("1", "2") in pairs(s) and said == []


def test_compas_interfaces_all_found_or_too_far_apart():
    s, said = read_warnings(lambda: read_compas(compas(side_by_side(0.0), [(0, 1), (0, 2), (1, 2)])))
    assert said == []
    # stored, but 0.05 apart: no tolerance up to 100 x the one in force reads them joined
    s, said = read_warnings(lambda: read_compas(compas(side_by_side(0.05), [(0, 1), (0, 2), (1, 2)])))
    assert len(said) == 1 and said[0].endswith("no tolerance up to 0.0001 reads them joined")


def overhang():
    """b2, a slab on b1 reaching 2.5 beyond it (its centroid 1 beyond b1's edge): it tips
    over under its own weight; b1 and b3, beside it, stand."""
    return {"name": "overhang", "mu": 0.6, "blocks": [
        {"id": "ground", "support": True, "vertices": box(-1, -1, -0.2, 6, 2, 0)},
        {"id": "b1", "vertices": box(0, 0, 0, 1, 1, 1)},
        {"id": "b2", "vertices": box(0.5, 0, 1, 3.5, 1, 1.2)},
        {"id": "b3", "vertices": box(4, 0, 0, 5, 1, 1)}]}


def test_the_blocks_no_statics_holds_are_the_overhanging_one():
    s = structure3d_from_spec(overhang())
    assert unheld_blocks3d(s) == (["b2"], True)
    stable = overhang()
    stable["blocks"][2]["vertices"] = box(0, 0, 1, 1, 1, 1.2)
    assert unheld_blocks3d(structure3d_from_spec(stable)) == ([], True)


def test_the_unstable_verdict_names_its_blocks_on_one_line(tmp_path, capsys):
    path = tmp_path / "overhang.json"
    path.write_text(json.dumps(overhang()))
    assert main(["solve", str(path), "--out", str(tmp_path / "out"), "--no-plot", "--quiet"]) == 3
    line = capsys.readouterr().out.strip()
    assert "\n" not in line and "unstable under dead load" in line
    assert line.endswith("the blocks that move under dead load alone: b2 (1 block)")


def test_no_support_names_both_options_and_the_lowest_block():
    spec = overhang()
    spec["blocks"][0]["vertices"] = box(-1, -1, -0.25, 6, 2, 0)
    with pytest.raises(InputError) as err:
        read_compas(compas(spec, [], supports=False), where="bridge.json")
    text = str(err.value)
    assert "\n" not in text and text.startswith("bridge.json: no block is a support")
    assert "--supports-below Z" in text and "--supports ID,ID,..." in text
    assert "the lowest block is '0' (its lowest point at z = -0.25; 1 block(s) reach below z = -0.24" in text
    assert read_compas(compas(spec, []), supports_below=-0.24).supports == ["0"]
    spec["blocks"][0]["support"] = False                 # lamodel's own JSON: its field, not the options
    with pytest.raises(InputError, match=r"expected at least one body with \"support\": true; the lowest block is "
                                         r"'ground' \(its lowest point at z = -0.25;"):
        structure3d_from_spec(spec)
