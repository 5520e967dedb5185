"""Mechanism pictures (lamodel.output.plot): kinematics of the contacts, and what is drawn."""
from __future__ import annotations

import dataclasses

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from matplotlib.quiver import Quiver  # noqa: E402

from lamodel.errors import InputError  # noqa: E402
from lamodel.geometry import seed_wall  # noqa: E402
from lamodel.io.jsonspec import structure_from_json  # noqa: E402
from lamodel.output.plot import contact_kinematics, contact_modes, pivots, plot_mechanism  # noqa: E402
from lamodel.structure import Structure  # noqa: E402
from lamodel.formulation.matrices import equilibrium_matrix  # noqa: E402



def _polygons(ax):
    """The axes' polygon collections: supports, blocks at rest, displaced blocks (the load
    arrows are quivers, polygon collections too)."""
    return [c for c in ax.collections if isinstance(c, PolyCollection) and not isinstance(c, Quiver)]

def rect(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


@pytest.fixture
def block_on_ground():
    """One 2 x 1 block (centroid (1, 0.5)) on the ground: a single contact, a = ground."""
    return structure_from_json({"name": "one", "mu": 0.5, "blocks": [
        {"id": "a", "vertices": rect(0, 0, 2, 1)},
        {"id": "ground", "support": True, "vertices": rect(-1, -1, 3, 0)}]})


@pytest.fixture
def wall():
    return structure_from_json(seed_wall(6))


def rotation_about(structure, j, point, theta):
    """u of block j for a small rotation theta about a point."""
    g = structure.centroid[j]
    u = np.zeros((structure.n_blocks, 3))
    u[j] = [-theta * (g[1] - point[1]), theta * (g[0] - point[0]), theta]
    return u


# ====================================================================== kinematics
def test_contact_kinematics_are_the_contact_strains(wall):
    """opening, slip and relative rotation are q = -A^T u of lamodel.structure."""
    rng = np.random.default_rng(0)
    u = rng.normal(size=(wall.n_blocks, 3))
    opening, slip, rotation, _ = contact_kinematics(wall, u)
    q = -(equilibrium_matrix(wall).T @ u.ravel())
    nc = wall.n_contacts
    assert np.allclose(opening, q[:nc])
    assert np.allclose(slip, q[nc:2 * nc])
    assert np.allclose(rotation, q[2 * nc:])


@pytest.mark.parametrize("corner, theta", [((2, 0), -1e-2), ((0, 0), 1e-2)])
def test_toppling_block_hinges_at_the_corner_it_rotates_about(block_on_ground, corner, theta):
    """Clockwise rotation about the right corner, counter-clockwise about the left one:
    the pivot is that corner — centre + d t for a positive relative rotation of b."""
    s = block_on_ground
    u = rotation_about(s, 0, corner, theta)
    assert contact_modes(s, u) == ["hinging"]
    assert np.allclose(pivots(s, u)[0], corner)
    t = s.tangent[0]
    expected = s.centre[0] + (1 if theta > 0 else -1) * s.d[0] * t
    assert np.allclose(pivots(s, u)[0], expected)


@pytest.mark.parametrize("motion, mode", [
    ("slide", "sliding"), ("lift", "open"), ("rest", "closed"), ("rock and slide", "sliding+hinging")])
def test_modes_of_simple_motions(block_on_ground, motion, mode):
    s = block_on_ground
    u = {"slide": np.array([[1.0, 0.0, 0.0]]), "lift": np.array([[0.0, 1.0, 0.0]]),
         "rest": np.zeros((1, 3))}.get(motion)
    if motion == "rock and slide":  # rotate about the left corner while slipping along the ground
        u = rotation_about(s, 0, (0, 0), 0.5)
        u[0, 0] += 0.3
    assert contact_modes(s, u) == [mode]


# ====================================================================== the picture
def pixels(structure, u, path, **kw):
    plot_mechanism(structure, u, path=str(path), **kw)
    return mpimg.imread(str(path))


@pytest.mark.slow
def test_picture_changes_with_the_mechanism(wall, tmp_path):
    rng = np.random.default_rng(1)
    still = pixels(wall, np.zeros((wall.n_blocks, 3)), tmp_path / "still.png")
    u1 = np.zeros((wall.n_blocks, 3))
    u1[:, 0] = np.linspace(0, 1, wall.n_blocks)
    u2 = rng.normal(size=(wall.n_blocks, 3))
    p1 = pixels(wall, u1, tmp_path / "u1.png")
    p2 = pixels(wall, u2, tmp_path / "u2.png")
    again = pixels(wall, u1, tmp_path / "u1again.png")
    for a, b in ((still, p1), (p1, p2), (still, p2)):
        assert a.shape != b.shape or np.abs(a - b).max() > 0.1
    assert p1.shape == again.shape and np.array_equal(p1, again)  # deterministic


def test_displaced_blocks_are_drawn_where_the_mechanism_puts_them(wall):
    """The displaced polygons are the rest polygons moved rigidly by scale * u, and the
    default scale makes the largest vertex displacement 10 % of the structure's size."""
    u = rotation_about(wall, wall.n_blocks - 1, (20, 0), -1e-3)
    u[:, 0] += 1e-3
    fig, ax = plt.subplots()
    plot_mechanism(wall, u, ax=ax, path=None)
    polys = _polygons(ax)
    rest, moved = polys[-2], polys[-1]  # supports, blocks at rest, displaced blocks
    biggest = 0.0
    for j, (p0, p1) in enumerate(zip(rest.get_paths(), moved.get_paths())):
        v0, v1 = p0.vertices[:4], p1.vertices[:4]
        assert np.allclose(v0, wall.polygons[wall.blocks[j]])
        g = wall.centroid[j]
        delta = v1 - v0
        # rigid: delta = scale * (ux - th (y - yG), uy + th (x - xG)) with one scale for all
        expect = np.column_stack([u[j, 0] - u[j, 2] * (v0[:, 1] - g[1]), u[j, 1] + u[j, 2] * (v0[:, 0] - g[0])])
        scale = np.linalg.norm(delta) / np.linalg.norm(expect)
        assert np.allclose(delta, scale * expect)
        biggest = max(biggest, np.hypot(delta[:, 0], delta[:, 1]).max())
    assert np.isclose(biggest, 0.1 * wall.size())
    plt.close(fig)


def test_scale_override(block_on_ground):
    s = block_on_ground
    u = np.array([[0.1, 0.0, 0.0]])
    fig, ax = plt.subplots()
    plot_mechanism(s, u, ax=ax, path=None, scale=2.0)
    moved = _polygons(ax)[-1]
    assert np.allclose(moved.get_paths()[0].vertices[:4], np.array(rect(0, 0, 2, 1)) + [0.2, 0.0])
    plt.close(fig)


def test_markers_for_hinges_and_sliding(block_on_ground):
    s = block_on_ground
    fig, ax = plt.subplots()
    u = rotation_about(s, 0, (2, 0), -1e-2)
    plot_mechanism(s, u, ax=ax, path=None)
    dots = [line for line in ax.lines if line.get_marker() == "o"]
    assert len(dots) == 1 and np.allclose(dots[0].get_xydata(), [[2, 0]])  # a = ground: not displaced
    assert not any(isinstance(c, LineCollection) for c in ax.collections)
    plt.close(fig)
    fig, ax = plt.subplots()
    plot_mechanism(s, np.array([[1.0, 0, 0]]), ax=ax, path=None)
    slides = [c for c in ax.collections if isinstance(c, LineCollection)]
    assert len(slides) == 1 and np.allclose(slides[0].get_segments()[0], [[2, 0], [0, 0]])
    assert not [line for line in ax.lines if line.get_marker() == "o"]
    plt.close(fig)


def test_explicit_modes_are_drawn(wall):
    modes = ["closed"] * wall.n_contacts
    modes[0], modes[1] = "hinging", "sliding+hinging"
    fig, ax = plt.subplots()
    plot_mechanism(wall, np.zeros((wall.n_blocks, 3)), modes=modes, ax=ax, path=None)
    dots = [line for line in ax.lines if line.get_marker() == "o"]
    assert len(dots) == 1 and len(dots[0].get_xdata()) == 2
    assert len([c for c in ax.collections if isinstance(c, LineCollection)]) == 1
    plt.close(fig)


@pytest.mark.parametrize("certified, text", [(True, "α = 0.63898 (certified)"), (False, "α = 0.63898 (NOT certified)"),
                                             (None, "α = 0.63898")])
def test_title(wall, certified, text):
    fig, ax = plt.subplots()
    plot_mechanism(wall, np.zeros((wall.n_blocks, 3)), alpha=0.63898, certified=certified, ax=ax, path=None)
    assert ax.get_title().endswith(text)
    plt.close(fig)


@pytest.mark.slow
@pytest.mark.parametrize("ext, magic", [("png", b"\x89PNG"), ("svg", b"<?xml"), ("pdf", b"%PDF")])
def test_format_follows_the_extension(wall, tmp_path, ext, magic):
    path = tmp_path / f"m.{ext}"
    u = np.zeros((wall.n_blocks, 3))
    u[:, 2] = 1e-3
    assert plot_mechanism(wall, u, path=str(path)) == str(path)
    assert path.read_bytes().startswith(magic)


@pytest.mark.slow
def test_blocks_without_polygons_are_drawn_as_centroids(tmp_path):
    """A structure read from a .dat file may carry no polygons: only centroid markers."""
    s = structure_from_json(seed_wall(6))
    bare = Structure(**{**s.__dict__, "polygons": {}})
    u = np.zeros((bare.n_blocks, 3))
    u[:, 0] = 1.0
    fig, ax = plt.subplots()
    plot_mechanism(bare, u, ax=ax, path=None)
    crosses = [line for line in ax.lines if line.get_marker() == "+"]
    assert len(crosses) == 2 and len(crosses[0].get_xdata()) == bare.n_blocks
    assert not _polygons(ax)
    plt.close(fig)
    a = pixels(bare, u, tmp_path / "a.png")
    b = pixels(bare, np.zeros_like(u), tmp_path / "b.png")
    assert a.shape != b.shape or not np.array_equal(a, b)


def test_bad_arguments(wall, tmp_path):
    with pytest.raises(InputError, match=r"expected finite \(n_blocks, 3\)"):
        plot_mechanism(wall, np.zeros((3, 3)), path=str(tmp_path / "x.png"))
    with pytest.raises(InputError, match="'twisting'"):
        plot_mechanism(wall, np.zeros((wall.n_blocks, 3)), modes=["twisting"] * wall.n_contacts,
                       path=str(tmp_path / "x.png"))
    with pytest.raises(InputError, match="unsupported picture format '.xyz'"):
        plot_mechanism(wall, np.zeros((wall.n_blocks, 3)), path=str(tmp_path / "x.xyz"))


def test_crushed_joints_are_marked_apart_from_hinges_with_a_legend(wall):
    modes = ["closed"] * wall.n_contacts
    modes[0], modes[1], modes[2] = "hinging", "crushing", "crushing+sliding"
    # on dry joints (no f_c) a closing joint cannot crush: every turning joint is a hinge
    fig, ax = plt.subplots()
    plot_mechanism(wall, np.zeros((wall.n_blocks, 3)), modes=modes, ax=ax, path=None)
    assert not [line for line in ax.lines if line.get_marker() == "D"]
    assert sum(len(line.get_xdata()) for line in ax.lines if line.get_marker() == "o") == 3
    plt.close(fig)
    wall = dataclasses.replace(wall, fc=np.full(wall.n_contacts, 10.0))
    fig, ax = plt.subplots()
    plot_mechanism(wall, np.zeros((wall.n_blocks, 3)), modes=modes, ax=ax, path=None)
    dots = [line for line in ax.lines if line.get_marker() == "o"]
    diamonds = [line for line in ax.lines if line.get_marker() == "D"]
    assert len(dots) == 1 and len(dots[0].get_xdata()) == 1
    assert len(diamonds) == 1 and len(diamonds[0].get_xdata()) == 2
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "hinge" in labels and "crushing (joint at its crushing cap)" in labels
    assert len([c for c in ax.collections if isinstance(c, LineCollection)]) == 1  # the one that slides
    plt.close(fig)
