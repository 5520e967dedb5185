"""The kind of a structure file known without reading it (lamodel.io.dimension): planar or in
space, as lamodel.io.read would read it, with no numpy loaded."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

from lamodel.io import dimension, read

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("name, text, expected", [
    ("wall.json", None, 2),
    ("facade.json", None, 3),
    ("w.dat", "", 2),
    ("box.obj", "", 3),
    ("flat.json", json.dumps({"blocks": [{"id": "b", "vertices": [[0, 0], [1, 0], [0, 1]]}]}), 2),
    ("said.json", json.dumps({"dimension": 3, "blocks": []}), 3),
    ("compas.json", json.dumps({"dtype": "compas_assembly.datastructures/Assembly", "data": {}}), 3),
    ("broken.json", "{", None),
    ("missing.json", False, None),
    ("notes.txt", "x", None),
])
def test_the_dimension_of_a_file(tmp_path, name, text, expected):
    if text is None:
        path = ROOT / "instances" / {"wall.json": "wall33.json", "facade.json": "facade.json"}[name]
        assert read(path).__class__.__name__ == ("Structure" if expected == 2 else "Structure3D")
    else:
        path = tmp_path / name
        if text is not False:
            path.write_text(text)
    assert dimension(path) == expected


def test_it_loads_no_numpy():
    code = (f"import sys, lamodel.io as io; io.dimension({str(ROOT / 'instances' / 'facade.json')!r}); "
            "print(sorted(m for m in ('numpy', 'scipy', 'shapely', 'trimesh') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=60,
                         env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert out.stdout.strip() == "[]", out.stderr
