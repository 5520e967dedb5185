"""The picture drawn in a helper process (lamodel.output.painter): the same file as drawn
in-process, errors raised in the caller, and a fallback when the helper is not there."""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from lamodel.errors import InputError
from lamodel.geometry import seed_wall
from lamodel.io.jsonspec import structure_from_json
from lamodel.output import painter as painter_mod
from lamodel.output.painter import Painter
from lamodel.output.plot import plot_mechanism


@pytest.fixture(scope="module")
def wall():
    return structure_from_json(seed_wall(6))


def rocking(s):
    """Every block turns a little about its centroid and moves right: a picture with
    hinges and slips to draw."""
    u = np.zeros((s.n_blocks, 3))
    u[:, 0] = np.linspace(0.0, 1.0, s.n_blocks)
    u[:, 2] = 0.1
    return dict(u=u, alpha=0.5, certified=True)


@pytest.mark.slow
def test_helper_draws_the_same_file_as_in_process(wall, tmp_path):
    here, there = tmp_path / "here.png", tmp_path / "there.png"
    plot_mechanism(wall, path=str(here), **rocking(wall))
    with Painter() as p:
        assert p._proc is not None and p._proc.poll() is None, "the helper should be running"
        p.start(wall, there, rocking(wall))
        p.draw(wall, there, rocking(wall))
        assert p._proc is None  # done with it
    assert there.read_bytes() == here.read_bytes()


@pytest.mark.slow
def test_error_in_the_helper_is_raised_here(wall, tmp_path):
    with Painter() as p:
        with pytest.raises(InputError, match="contact modes"):
            p.draw(wall, tmp_path / "x.png", dict(rocking(wall), modes=["closed"]))
    assert not (tmp_path / "x.png").exists()


@pytest.mark.slow
def test_without_a_helper_the_picture_is_drawn_here(wall, tmp_path, monkeypatch):
    def no_python(*args, **kwargs):
        raise OSError("no such interpreter")
    monkeypatch.setattr(painter_mod.subprocess, "Popen", no_python)
    with Painter() as p:
        assert p._proc is None
        p.draw(wall, tmp_path / "a.png", rocking(wall))
    assert (tmp_path / "a.png").stat().st_size > 1000


@pytest.mark.slow
def test_a_helper_that_dies_is_replaced_by_drawing_here(wall, tmp_path):
    with Painter() as p:
        p._proc.kill()
        p._proc.wait()
        p.draw(wall, tmp_path / "b.png", rocking(wall))
    assert (tmp_path / "b.png").stat().st_size > 1000


@pytest.mark.slow
def test_helper_with_nothing_to_draw_exits(tmp_path):
    """A run that ends before its picture (bad input, Ctrl-C) closes the helper's input:
    it exits without a traceback."""
    proc = subprocess.run([sys.executable, "-m", "lamodel.output.painter"], input=b"", capture_output=True,
                          timeout=60)
    assert proc.returncode == 0 and proc.stderr == b"", proc.stderr
