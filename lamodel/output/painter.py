"""The picture of a solve drawn in a second process, started before the search.

Loading matplotlib takes about as long as solving a seed wall (0.6 s on the reference
machine). A helper process (``python -m lamodel.output.painter``) started with the command
loads it on another core while the search runs; the parent then sends it what to draw
(pickled, through a pipe) and waits for the file. It is a plain subprocess, not a
multiprocessing one, which would run the caller's main script again in the child. If it
cannot start or dies, the picture is drawn in this process: the same file either way.
"""
from __future__ import annotations

import os
import pickle
import subprocess
import sys
from pathlib import Path


def _draw(structure, path, picture):
    from .plot import plot_mechanism
    plot_mechanism(structure, path=path, **picture)


class Painter:
    """``draw(structure, path, picture)`` = ``plot_mechanism(structure, path=path, **picture)``,
    in the helper process when it is there."""

    def __init__(self):
        env = dict(os.environ)
        root = str(Path(__file__).resolve().parents[2])  # lamodel importable as in this process
        env["PYTHONPATH"] = root + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
        try:
            # its own session: Ctrl-C at the terminal is the parent's to handle
            self._proc = subprocess.Popen([sys.executable, "-m", "lamodel.output.painter"], stdin=subprocess.PIPE,
                                          stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, env=env,
                                          start_new_session=True)
        except OSError:
            self._proc = None
        self._sent = False

    def start(self, structure, path, picture):
        """Send the picture to the helper and return at once (:meth:`draw` waits for it)."""
        self._sent = True
        if self._proc is not None:
            try:
                pickle.dump((structure, str(path), picture), self._proc.stdin)
                self._proc.stdin.close()
            except (OSError, pickle.PickleError):
                self.close()

    def draw(self, structure, path, picture):
        """The picture (the one :meth:`start` sent, if it was called), drawn; raises what
        drawing it raised."""
        if not self._sent:
            self.start(structure, path, picture)
        proc = self._proc
        if proc is not None:
            try:
                error = pickle.load(proc.stdout)
            except (OSError, EOFError, pickle.PickleError):
                error = _GONE
            self.close()
            if error is None:
                return
            if error is not _GONE:
                raise error
        _draw(structure, str(path), picture)  # no helper: here

    def close(self):
        """Stop the helper (one still loading matplotlib is killed, not waited for)."""
        proc, self._proc = self._proc, None
        if proc is not None:
            if proc.poll() is None:
                proc.kill()
            proc.wait()
            for f in (proc.stdin, proc.stdout):
                try:
                    f.close()
                except OSError:
                    pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


_GONE = object()


def _serve():
    """The helper: load matplotlib, then draw the one picture it is sent; answers None or
    the exception raised (pickled)."""
    from ..process import end_with_parent
    end_with_parent()  # whatever ends the solve ends this helper too
    from . import plot  # noqa: F401  (the point of this process: loaded while the parent searches)
    try:
        job = pickle.load(sys.stdin.buffer)
    except (EOFError, pickle.PickleError):
        return  # the parent needed no picture after all
    try:
        _draw(*job)
        answer = None
    except Exception as exc:  # sent back to be raised there as it would be in-process
        answer = exc
    try:
        pickle.dump(answer, sys.stdout.buffer)
    except (pickle.PickleError, TypeError, AttributeError):
        pickle.dump(RuntimeError(f"the picture failed: {answer}"), sys.stdout.buffer)
    sys.stdout.buffer.flush()


if __name__ == "__main__":
    _serve()
