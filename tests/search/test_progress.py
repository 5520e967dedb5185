"""The progress line (lamodel.search.progress): on a terminal only; the associative bound,
the best certified alpha and the share of the run's budget spent."""
import io
import re
import sys
import threading
import time

from lamodel.search.driver import SolveOptions, solve
from lamodel.search.progress import Progress


class Terminal(io.StringIO):
    """stderr as a terminal would be (tqdm draws only on one)."""

    def isatty(self):
        return True


def _lines(text):
    return [line for line in text.split("\r") if line.strip()]


def _shares(lines):
    return [int(m.group(1)) for line in lines for m in [re.search(r"(\d+)% of the", line)] if m]


def test_default_run_shows_bound_best_and_work_share(monkeypatch, wall33):
    term = Terminal()
    monkeypatch.setattr(sys, "stderr", term)
    o = solve(wall33, SolveOptions(starts=0, progress=True))
    lines = _lines(term.getvalue())
    assert any(f"associative bound {o.alpha_associative:.6f}" in line for line in lines)
    assert f"best certified alpha {o.best.alpha:.6f}" in lines[-1]  # the last line drawn
    assert any("none certified yet" in line for line in lines)
    assert all("of the work bound" in line for line in lines)
    shares = _shares(lines)
    assert 0 <= min(shares) and max(shares) <= 100
    assert max(shares) > 0  # the budget is spent as the search goes
    assert not term.getvalue().rstrip("\r").split("\r")[-1].strip()  # then cleared (leave=False)
    assert not any(t.name == "lamodel-progress" for t in threading.enumerate())


def test_time_limit_is_the_budget(monkeypatch, wall33):
    term = Terminal()
    monkeypatch.setattr(sys, "stderr", term)
    solve(wall33, SolveOptions(starts=0, progress=True, time_limit=30.0))
    lines = _lines(term.getvalue())
    assert lines and all("of the time limit" in line for line in lines)


def test_nothing_drawn_off_a_terminal(monkeypatch, wall33):
    plain = io.StringIO()
    monkeypatch.setattr(sys, "stderr", plain)
    p = Progress(True)
    assert p._thread is None
    p.bound(0.5)
    p.best(0.4)
    p.close()
    assert plain.getvalue() == ""


def test_line_redrawn_during_a_long_step(monkeypatch):
    """Between two events (a long LP) the line is redrawn with the share read anew."""
    term = Terminal()
    monkeypatch.setattr(sys, "stderr", term)
    share = {"v": 0.1}
    p = Progress(True)
    p.follow(lambda: share["v"])
    p.phase("first certificate")
    share["v"] = 0.57
    for _ in range(100):  # at most 5 s; REFRESH is 0.5 s
        if "57% of the work bound" in term.getvalue():
            break
        time.sleep(0.05)
    p.close()
    assert "57% of the work bound" in term.getvalue()
