"""3D inputs (COMPAS, meshes, lamodel.io.read), generators, pictures, the HTML view, CSV tables."""
import json
import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from lamodel.errors import InputError
from lamodel.geometry import generators3d as G
from lamodel.io import read
from lamodel.io.json3d import structure3d_from_spec
from lamodel.output.plot3d import plot_structure3d
from lamodel.output.results3d import write_results3d
from lamodel.output.tables3d import build_summary3d
from lamodel.output.view3d import write_view3d

from test_contacts3d import stack_spec


def compas_json(spec, with_support=True):
    """Our own geometry written in COMPAS's assembly layout (convex hulls as faces)."""
    from lamodel.geometry.polyhedra import polyhedron
    nodes = {}
    for k, b in enumerate(spec["blocks"]):
        p = polyhedron(b["id"], b["vertices"])
        nodes[str(k)] = {"block": {"dtype": "compas_assembly.datastructures/Block", "data": {
            "vertex": {str(i): dict(zip("xyz", map(float, v))) for i, v in enumerate(p.vertices)},
            "face": {str(i): f for i, f in enumerate(p.faces)}}},
            "is_support": bool(b.get("support")) and with_support}
    return {"dtype": "compas_assembly.datastructures/Assembly",
            "data": {"attributes": {"name": "Assembly"}, "graph": {"dtype": "compas.datastructures/Graph",
                                                                  "data": {"node": nodes, "edge": {}}}}}


def test_compas_assembly_reads_with_defaults(tmp_path):
    path = tmp_path / "stack.json"
    path.write_text(json.dumps(compas_json(stack_spec())))
    s = read(path)
    assert s.dimension == 3 and s.n_interfaces == 16 and s.supports == ["0"]
    assert s.meta["defaults"] == ["mu", "unit_weight", "live_load"] and s.meta["mu"] == 0.6
    assert s.meta["source"] == "COMPAS assembly" and s.meta["live_load"] == [1.0, 0.0, 0.0]
    assert np.allclose(s.live, s.dead[:, [2, 1, 0]] * [-1, 0, 0])     # +x, equal to the weight
    path.write_text(json.dumps(compas_json(stack_spec(), with_support=False)))
    with pytest.raises(InputError, match="no block is a support"):
        read(path)
    assert read(path, supports_below=-0.25, mu=0.4).n_interfaces == 16


def test_mesh_file_one_block_per_geometry_or_component(tmp_path):
    import trimesh
    spec = stack_spec()
    meshes = [trimesh.convex.convex_hull(np.asarray(b["vertices"])) for b in spec["blocks"]]
    path = tmp_path / "stack.glb"
    trimesh.Scene(meshes).export(path)                     # one geometry per block
    s = read(path, supports_below=-0.25)
    assert s.n_blocks == 8 and len(s.supports) == 1 and s.n_interfaces == 16
    assert "GLB" in s.meta["source"]
    apart = tmp_path / "apart.stl"                          # one geometry: its connected components
    trimesh.util.concatenate([meshes[0], meshes[1].apply_translation([0, 0, 0.0])]).export(apart)
    assert read(apart, supports_below=-0.25).n_blocks == 1
    assert "16 interfaces" in build_summary3d(path, supports_below=-0.25)


def test_2d_inputs_unchanged():
    from lamodel.structure import Structure
    root = Path(__file__).resolve().parents[2]
    assert isinstance(read(root / "instances" / "wall33.json"), Structure)
    assert build_summary3d(root / "instances" / "wall33.json") is None


GENERATORS = {"wall_panel": lambda: G.wall_panel(), "wall_panel_2_leaves": lambda: G.wall_panel(leaves=2),
              "facade_L": lambda: G.facade(plan="L"), "facade_U": lambda: G.facade(),
              "box_building": lambda: G.box_building(), "barrel_vault": lambda: G.barrel_vault(),
              "dome": lambda: G.dome()}


@pytest.mark.parametrize("name", list(GENERATORS) + ["extruded"])
def test_each_generator_validates_and_draws(name, tmp_path):
    specs = G.extruded_seed_instances() if name == "extruded" else {name: GENERATORS[name]()}
    for key, spec in specs.items():
        s = structure3d_from_spec(spec)
        assert s.n_blocks > 0 and s.n_interfaces >= s.n_blocks
        png = plot_structure3d(s, tmp_path / f"{key}.png")
        img = __import__("matplotlib.image").image.imread(png)
        assert img.std() > 0.05


def test_extruded_wall_keeps_the_planar_contacts():
    from lamodel.geometry.generators import seed_wall
    from lamodel.io.jsonspec import structure_from_json
    s2 = structure_from_json(seed_wall(6))
    s3 = structure3d_from_spec(G.extrude(seed_wall(6), depth=2.0))
    assert s3.n_interfaces == s2.n_contacts and s3.n_blocks == s2.n_blocks
    assert np.allclose(s3.live[:, [0, 2]], 2.0 * s2.live)     # weights per unit depth, times the depth


def test_csv_tables_rebuild_block_equilibrium(tmp_path):
    """A hand-made equilibrium state written to the CSVs; equilibrium rebuilt with plain loops."""
    s = structure3d_from_spec(stack_spec())
    alpha = 0.25
    # statics found here by least squares on an equilibrium matrix written for this test
    idx = s.block_index()
    A = np.zeros((6 * s.n_blocks, 3 * s.n_points))
    ia, ib = s.point_blocks()
    for p in range(s.n_points):
        for c, axis in enumerate((s.normal[p], s.tangent1[p], s.tangent2[p])):
            for j, sign in ((ia[p], 1.0), (ib[p], -1.0)):
                if j >= 0:
                    A[6 * j:6 * j + 3, 3 * p + c] += sign * axis
                    A[6 * j + 3:6 * j + 6, 3 * p + c] += sign * np.cross(s.point[p] - s.centroid[j], axis)
    f = np.c_[s.dead + alpha * s.live, s.dead_m + alpha * s.live_m].reshape(-1)
    x = np.linalg.lstsq(A, -f, rcond=None)[0]
    forces = x.reshape(-1, 3)
    motions = np.zeros((s.n_blocks, 6))
    motions[0, 3] = -0.0                   # a block at rest, as a solver may leave it
    state = SimpleNamespace(N=forces[:, 0], T1=forces[:, 1], T2=forces[:, 2], modes=["stuck"] * s.n_points)
    write_results3d(tmp_path, s, SimpleNamespace(state=state, motions=motions), {"instance": s.name, "alpha": alpha},
                    pd.DataFrame())
    assert ",-0," not in (tmp_path / "blocks.csv").read_text().replace("\n", ",")
    blocks, contacts = pd.read_csv(tmp_path / "blocks.csv"), pd.read_csv(tmp_path / "contacts.csv")
    res = {}
    for r in blocks.itertuples():
        res[r.block] = [r.dead_x + alpha * r.live_x, r.dead_y + alpha * r.live_y, r.dead_z + alpha * r.live_z,
                        r.dead_mx + alpha * r.live_mx, r.dead_my + alpha * r.live_my, r.dead_mz + alpha * r.live_mz]
    cen = {r.block: (r.x, r.y, r.z) for r in blocks.itertuples()}
    for c in contacts.itertuples():
        F = [c.N * n + c.T1 * t + c.T2 * u for n, t, u in ((c.nx, c.t1x, c.t2x), (c.ny, c.t1y, c.t2y), (c.nz, c.t1z, c.t2z))]
        for body, sign in ((c.block_a, 1.0), (c.block_b, -1.0)):
            if body in res:
                rx, ry, rz = c.x - cen[body][0], c.y - cen[body][1], c.z - cen[body][2]
                m = [ry * F[2] - rz * F[1], rz * F[0] - rx * F[2], rx * F[1] - ry * F[0]]
                for k in range(3):
                    res[body][k] += sign * F[k]
                    res[body][3 + k] += sign * m[k]
    assert max(abs(v) for r in res.values() for v in r) < 1e-9
    assert len(contacts) == s.n_points and set(contacts["interface"]) == set(s.interfaces)


def test_a_folder_without_a_certified_state_writes_nan_not_zeros(tmp_path):
    """Nothing certified: the forces, the motions and alpha are empty, the modes unknown
    (the independent oracle reads them so), never zeros that read as a state."""
    import sys
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from oracle3d import uncertified, violations
    s = structure3d_from_spec(stack_spec())
    write_results3d(tmp_path, s, SimpleNamespace(state=None, motions=None),
                    {"instance": s.name, "alpha": np.nan, "certified": False, "live_load": "1 0 0"}, pd.DataFrame())
    contacts, blocks = pd.read_csv(tmp_path / "contacts.csv"), pd.read_csv(tmp_path / "blocks.csv")
    assert contacts[["N", "T1", "T2"]].isna().all().all() and set(contacts["mode"]) == {"unknown"}
    assert blocks[["ux", "uy", "uz", "rx", "ry", "rz"]].isna().all().all()
    assert uncertified(tmp_path) == [] and violations(tmp_path) == []
    # the oracle sees a zero written where nothing is known
    contacts.loc[3, "N"] = 0.0
    contacts.to_csv(tmp_path / "contacts.csv", index=False)
    assert uncertified(tmp_path) == ["contacts.csv: 1 values of N, T1, T2 written without a certified state"]


@pytest.mark.slow
@pytest.mark.skipif(not Path("/usr/bin/chromium").exists() and not os.environ.get("CI"), reason="Debian chromium not installed (make test installs it; CI must have it)")
def test_view_is_self_contained_and_renders_in_headless_chromium(tmp_path):
    s = structure3d_from_spec(G.facade(plan="L"))
    u = np.zeros((s.n_blocks, 6))
    front = [j for j, b in enumerate(s.blocks) if b.startswith("f")]
    u[front, 3] = 0.05
    u[front, :3] = np.cross(u[front, 3:], s.centroid[front])
    html = write_view3d(s, tmp_path / "view.html", motions=u, modes=np.where(s.point[:, 2] == 0, "open", ""))
    text = Path(html).read_text()
    assert not re.search(r"<(script|link|img|iframe)[^>]+(src|href)\s*=\s*[\"']?(https?:)?//", text)
    assert "Plotly.newPlot" in text and len(text) > 1_000_000       # plotly.js embedded, not linked
    shot = tmp_path / "shot.png"
    subprocess.run(["/usr/bin/chromium", "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                    "--no-first-run", "--disable-background-networking", "--disable-component-update",
                    "--disable-sync", f"--user-data-dir={tempfile.mkdtemp()}", f"--screenshot={shot}",
                    "--window-size=1200,800", f"file://{html}"], check=True, capture_output=True, timeout=120)
    import matplotlib.image
    img = matplotlib.image.imread(shot)[..., :3]
    assert img.std() > 0.05                                   # not blank
    blue = (img[..., 2] > 0.6) & (img[..., 0] < 0.3)          # the macro-block's colour drawn by WebGL
    assert blue.sum() > 200


def test_lamodel_build_prints_the_contacts_summary_of_a_3d_input(tmp_path):
    import os
    import sys
    root = Path(__file__).resolve().parents[2]
    env = dict(os.environ, PYTHONPATH=str(root))
    good, bad = tmp_path / "stack.json", tmp_path / "bad.json"
    good.write_text(json.dumps(stack_spec()))
    spec = stack_spec()
    spec["blocks"][3]["vertices"] = (np.asarray(spec["blocks"][3]["vertices"]) + [0.5, 0, 0]).tolist()
    bad.write_text(json.dumps(spec))
    run = [sys.executable, "-m", "lamodel.cli", "build"]
    out = subprocess.run(run + [str(good)], capture_output=True, text=True, env=env, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "8 blocks, 1 supports, 16 interfaces, 64 contact points, total interface area 16" in out.stdout
    assert not (tmp_path / "stack.dat").exists()
    out = subprocess.run(run + [str(bad)], capture_output=True, text=True, env=env, timeout=120)
    assert out.returncode == 2 and "overlap" in out.stderr and "Traceback" not in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1


def test_lamodel_build_reads_a_mesh_with_its_options(tmp_path):
    import os
    import sys
    import trimesh
    root = Path(__file__).resolve().parents[2]
    env = dict(os.environ, PYTHONPATH=str(root))
    meshes = [trimesh.convex.convex_hull(np.asarray(b["vertices"])) for b in stack_spec()["blocks"]]
    path = tmp_path / "stack.glb"
    trimesh.Scene(meshes).export(path)
    run = [sys.executable, "-m", "lamodel.cli", "build", str(path)]
    out = subprocess.run(run + ["--supports-below", "-0.25", "--mu", "0.5", "--contact-points", "grid:2"],
                         capture_output=True, text=True, env=env, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "8 blocks, 1 supports, 16 interfaces, 128 contact points" in out.stdout   # 4 corners + 4 grid points
    out = subprocess.run(run, capture_output=True, text=True, env=env, timeout=120)
    assert out.returncode == 2 and "no block is a support" in out.stderr


def test_an_obj_of_objects_that_share_corners_gives_a_block_each(tmp_path):
    """Three boxes stacked, one OBJ object ("o") each: corners shared by the boxes above and
    below were welded into one component (the file was refused as misoriented); each object
    is now a block of its own."""
    faces = ["1 4 3 2", "5 6 7 8", "1 2 6 5", "2 3 7 6", "3 4 8 7", "4 1 5 8"]
    lines = []
    for k, (name, z0, z1) in enumerate((("ground", -1, 0), ("a", 0, 1), ("b", 1, 2))):
        lines.append(f"o {name}")
        lines += [f"v {x} {y} {z}" for z in (z0, z1) for x, y in ((0, 0), (1, 0), (1, 1), (0, 1))]
        lines += ["f " + " ".join(str(int(i) + 8 * k) for i in f.split()) for f in faces]
    path = tmp_path / "stack.obj"
    path.write_text("\n".join(lines) + "\n")
    s = read(path, supports_below=-0.5)
    assert s.n_blocks == 2 and len(s.supports) == 1
    assert sorted(np.round(s.centroid[:, 2], 9).tolist()) == [0.5, 1.5]


def test_a_unit_option_against_the_files_own_unit_is_said(tmp_path):
    path = tmp_path / "s.json"
    path.write_text(json.dumps(dict(stack_spec(), units={"length": "mm", "force": "kN"})))
    with pytest.warns(UserWarning, match="--length-unit m replaces the file's length unit mm"):
        s = read(path, units={"length": "m"})
    assert s.units == {"length": "m", "force": "kN"}
