"""The "lamodel" log: a solve tells its phases, lanes and results at INFO and every step at
DEBUG; the library adds no handler but a NullHandler; ``lamodel solve --verbose`` shows the
log on stderr (and only then)."""
import logging

from conftest import INSTANCES, stack_spec
from lamodel.cli import command
from lamodel.io.jsonspec import structure_from_json
from lamodel.search.driver import SolveOptions, solve


def _messages(caplog, level):
    return [r.getMessage() for r in caplog.records if r.name.startswith("lamodel") and r.levelno == level]


def test_a_solve_logs_its_phases_lanes_and_result_at_info(caplog, wall33):
    caplog.set_level(logging.INFO, logger="lamodel")
    out = solve(wall33, SolveOptions(starts=0, progress=False))
    info = _messages(caplog, logging.INFO)
    for phase in ("first certificate", "continuation", "GA + LP"):
        assert f"phase: {phase}" in info
    assert f"associative bound {out.alpha_associative:.6f} (1 LP solves)" in info
    assert any(m.startswith("continuation: lanes [continuation, ") for m in info)
    assert sum(m.startswith("lane [continuation, ") for m in info) == 2
    assert any(f"certified alpha {out.best.alpha:.6f}" in m for m in info)  # the new best, as it came
    assert info[-1].startswith(f"certified: alpha {out.best.alpha:.6f} (gap alternation) after ")
    assert _messages(caplog, logging.DEBUG) == []


def test_debug_shows_every_step_and_lp_solve(caplog):
    caplog.set_level(logging.DEBUG, logger="lamodel")
    out = solve(structure_from_json(stack_spec(3)), SolveOptions(starts=0, progress=False))
    assert out.certified
    debug = _messages(caplog, logging.DEBUG)
    assert any(" LP statics " in m for m in debug)             # HiGHS, solve by solve
    assert any(" rho " in m and " gap " in m for m in debug)   # the alternation, step by step
    assert any(m.startswith("alternate: ") for m in debug)


def test_the_library_adds_only_a_null_handler():
    import lamodel  # noqa: F401
    handlers = logging.getLogger("lamodel").handlers
    assert handlers and all(isinstance(h, logging.NullHandler) for h in handlers)


def test_solve_verbose_prints_the_log_on_stderr(tmp_path, capsys):
    args = [str(INSTANCES / "wall33.dat"), "--no-plot", "--starts", "0"]
    assert command("solve", [*args, "--out", str(tmp_path / "quiet")]) == 0
    err = capsys.readouterr().err
    assert "phase:" not in err
    assert command("solve", [*args, "--out", str(tmp_path / "verbose"), "--verbose"]) == 0
    out, err = capsys.readouterr()
    assert "phase: first certificate" in err and "lane [continuation, " in err and "certified: alpha 0.638982" in err
    assert "phase:" not in out and "wall33: alpha = 0.638982" in out
    assert " rho " not in err  # the steps only with -vv
    handlers = logging.getLogger("lamodel").handlers  # the command's handler is gone
    assert all(isinstance(h, logging.NullHandler) for h in handlers)
    assert command("solve", [*args, "--out", str(tmp_path / "debug"), "-vv"]) == 0
    assert " rho " in capsys.readouterr().err
