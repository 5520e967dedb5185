"""The .dat reader's plain path (no Pyomo import) reads exactly what Pyomo's parser reads."""
from pathlib import Path

import numpy as np
import pytest

from lamodel.io import datfile
from lamodel.io.files import read_text

INSTANCES = Path(__file__).resolve().parents[2] / "instances"
FIELDS = ("blocks", "supports", "contacts", "block_a", "block_b")
ARRAYS = ("centroid", "dead", "live", "dead_m", "live_m", "centre", "normal", "d", "mu")


def _same(a, b):
    for k in FIELDS:
        assert list(getattr(a, k)) == list(getattr(b, k)), k
    for k in ARRAYS:
        assert np.array_equal(np.asarray(getattr(a, k)), np.asarray(getattr(b, k))), k
    assert {k: np.asarray(v).tolist() for k, v in a.polygons.items()} == \
        {k: np.asarray(v).tolist() for k, v in b.polygons.items()}


@pytest.mark.parametrize("name", sorted(p.name for p in INSTANCES.glob("*.dat")))
def test_plain_reader_equals_pyomo(name):
    path = str(INSTANCES / name)
    text = read_text(path, "Pyomo .dat instance")
    plain = datfile._plain_data(text)
    assert plain is not None  # lamodel's own files take the fast path
    _same(datfile._structure_from_data(path, plain), datfile._structure_from_data(path, datfile._pyomo_data(path, text)))


def test_hand_written_variants_agree_or_go_to_pyomo(tmp_path):
    """Comments, wrapped rows, '.' (no value) and one-line statements read the
    same both ways; syntax outside the plain subset (a quoted id) is left to Pyomo."""
    text = """# two blocks
set BLOCKS := b1 b2 ;
set SUPPORTS := ground ;
set CONTACTS := c1 c2 ;
param: x y dead_x dead_y live_x live_y :=
  b1 0.0 0.5 0.0 -1.0 1.0 0.0   b2 0.0 1.5
  0.0 -1.0 1.0 0.0 ;   # wrapped row
param: dead_m live_m := b1 0 . b2 0.25 0 ;
param: block_a block_b cx cy nx ny d mu :=
  c1 ground b1 0.0 0.0 0.0 1.0 0.5 0.6
  c2 b1 b2 0.0 1.0 0.0 1.0 0.5 0.6 ;
"""
    path = tmp_path / "hand.dat"
    path.write_text(text)
    plain = datfile._plain_data(text)
    assert plain is not None
    a = datfile._structure_from_data(str(path), plain)
    _same(a, datfile._structure_from_data(str(path), datfile._pyomo_data(str(path), text)))
    assert a.blocks == ["b1", "b2"] and a.live_m.tolist() == [0.0, 0.0] and a.dead_m.tolist() == [0.0, 0.25]
    assert datfile._plain_data(text.replace("b2 0.0 1.5", "'b2' 0.0 1.5")) is None


def test_numeric_ids_are_read_as_ids(tmp_path):
    text = ("set BLOCKS := 1 ;\nset SUPPORTS := 0 ;\nset CONTACTS := 7 ;\n"
            "param: x y dead_x dead_y live_x live_y := 1 0.0 0.5 0.0 -1.0 1.0 0.0 ;\n"
            "param: block_a block_b cx cy nx ny d mu := 7 0 1 0.0 0.0 0.0 1.0 0.5 0.6 ;\n")
    path = tmp_path / "numeric.dat"
    path.write_text(text)
    s = datfile.read_dat(path)
    assert s.blocks == ["1"] and s.block_a == ["0"] and s.block_b == ["1"] and s.contacts == ["7"]
