"""Runs keep their work whatever stops them: SIGTERM, SIGHUP and SIGINT to real processes
at several moments, with and without Ipopt workers; the state written is checked by the
independent oracle, and no child process outlives the run or holds the caller's pipes."""
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

from conftest import INSTANCES, ROOT
from oracle import check_folder

pytestmark = pytest.mark.slow


def _as_a_terminal_starts_it():
    """Children start with the stop signals at their defaults (a CI runner may start the
    tests with SIGINT ignored, which the children would inherit)."""
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(sig, signal.SIG_DFL)


def start(*args, cwd=ROOT):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.Popen([sys.executable, "-m", "lamodel.cli", *map(str, args)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env, cwd=cwd, preexec_fn=_as_a_terminal_starts_it)


def descendants(pid) -> set:
    """Every process below ``pid`` (psutil when installed, else /proc)."""
    try:
        import psutil
        return {p.pid for p in psutil.Process(pid).children(recursive=True)}
    except ImportError:
        pass
    except Exception:  # the process is gone
        return set()
    found, todo = set(), [pid]
    while todo:
        p = todo.pop()
        try:
            kids = [int(k) for t in os.listdir(f"/proc/{p}/task")
                    for k in Path(f"/proc/{p}/task/{t}/children").read_text().split()]
        except OSError:
            continue
        found.update(kids)
        todo.extend(kids)
    return found


def alive(pids) -> list:
    out = []
    for p in pids:
        try:
            state = Path(f"/proc/{p}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except OSError:
            continue
        if state != "Z":
            out.append(p)
    return out


def no_child_survives(kids, within=5.0):
    t = time.monotonic()
    while alive(kids) and time.monotonic() - t < within:
        time.sleep(0.1)
    assert alive(kids) == [], "child processes outlived the run"


@pytest.fixture(scope="module")
def wall(tmp_path_factory):
    """A running-bond wall of 192 blocks: a search of several seconds."""
    from lamodel.geometry import running_bond_wall
    rows = [[1] * 12 if i % 2 == 0 else [0.5] + [1] * 11 + [0.5] for i in range(16)]
    path = tmp_path_factory.mktemp("wall") / "bond.json"
    path.write_text(json.dumps(running_bond_wall(rows, name="bond")))
    return path


CASES = {  # signal, seconds into the solve, options
    "term-lp": (signal.SIGTERM, 1.0, ()),
    "hup-ipopt": (signal.SIGHUP, 1.5, ("--starts", "2")),
    "int-ipopt-workers": (signal.SIGINT, 2.5, ("--starts", "2", "--workers", "2")),
    "term-ipopt-workers-late": (signal.SIGTERM, 5.0, ("--starts", "2", "--workers", "2")),
    "term-with-picture": (signal.SIGTERM, 2.0, ("--starts", "2", "--plot", "m.png")),
}


def wait_for_the_solve(p, out, timeout=120):
    """Until the result folder's staging folder exists: the input is read, the places
    checked, the search about to start."""
    t = time.monotonic()
    while time.monotonic() - t < timeout and p.poll() is None:
        if any(f.name.startswith(f".{out.name}.lamodel-new-") for f in out.parent.iterdir()):
            return
        time.sleep(0.05)
    pytest.fail("the solve never started")


@pytest.mark.parametrize("case", CASES)
def test_a_stop_signal_writes_the_best_certified_state(tmp_path, wall, case):
    sig, after, options = CASES[case]
    out = tmp_path / "o"
    options = tuple(str(tmp_path / o) if o.endswith(".png") else o for o in options)
    p = start("solve", wall, "--out", out, "--generations", "40", *options, *(() if "--plot" in options else
                                                                              ("--no-plot",)))
    wait_for_the_solve(p, out)
    time.sleep(after)
    kids = descendants(p.pid)
    p.send_signal(sig)
    # the caller's pipes close when the run ends: no child holds them
    stdout, stderr = p.communicate(timeout=120)
    assert "Traceback" not in stderr, stderr[-2000:]
    assert p.returncode in (128 + sig, 0), (p.returncode, stderr[-2000:])
    no_child_survives(kids | descendants(p.pid))
    assert not [f for f in tmp_path.iterdir() if f.name.startswith(".")], "staging folders left behind"
    summary = pd.read_csv(out / "summary.csv")
    if p.returncode == 0:
        pytest.skip("the solve ended before the signal (a fast machine)")
    assert summary.status[0] == "interrupted"
    if summary.certified[0]:  # the best certified state so far, a collapse state for the oracle
        assert check_folder(out) == pytest.approx(summary.alpha[0], abs=1e-9)
        assert f"alpha = {summary.alpha[0]:.6f}" in stdout


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP, signal.SIGINT])
def test_a_stop_signal_before_the_search_ends_the_run_at_once(tmp_path, sig):
    p = start("solve", INSTANCES / "wall55.dat", "--out", tmp_path / "o", "--starts", "2")
    time.sleep(0.4)  # reading the modules and the input
    kids = descendants(p.pid)
    p.send_signal(sig)
    _, stderr = p.communicate(timeout=120)
    assert p.returncode in (128 + sig, 0), (p.returncode, stderr[-2000:])
    assert "Traceback" not in stderr, stderr[-2000:]
    no_child_survives(kids | descendants(p.pid))
    assert not [f for f in tmp_path.iterdir() if f.name.startswith(".")], "staging folders left behind"


def test_kill_9_leaves_no_worker_holding_the_pipes(tmp_path, wall):
    p = start("solve", wall, "--out", tmp_path / "o", "--starts", "2", "--workers", "2", "--generations", "40")
    t = time.monotonic()
    kids = set()
    while len(kids) < 2 and time.monotonic() - t < 60:  # the painter and the Ipopt workers
        kids = descendants(p.pid)
        time.sleep(0.1)
    time.sleep(1.0)
    kids |= descendants(p.pid)
    assert kids, "no child process started"
    p.kill()
    p.communicate(timeout=30)  # returns only when no child holds stdout and stderr
    no_child_survives(kids)


def study_spec(tmp_path, count=60, **extra):
    spec = tmp_path / "spec.json"
    spec.write_text(json.dumps({"name": "many", "structure": str(INSTANCES / "wall33.json"),
                                "options": {"starts": 0}, "vary": {"mu": [0.3 + 0.01 * i for i in range(count)]},
                                **extra}))
    return spec


@pytest.mark.parametrize("sig, workers", [(signal.SIGINT, 1), (signal.SIGTERM, 1), (signal.SIGTERM, 2)])
def test_a_stop_signal_ends_a_study_with_the_rows_done(tmp_path, sig, workers):
    out = tmp_path / "s"
    p = start("study", study_spec(tmp_path), "--out", out, "--workers", workers, "--no-plot")
    first = p.stdout.readline()
    assert first.startswith("study many: 60 variants of 'wall33'"), first  # told before any starts
    partial, t = out / "study.partial.csv", time.monotonic()
    while time.monotonic() - t < 120:  # rows stream to the table as they finish
        if partial.exists() and len(partial.read_text().splitlines()) >= 3:
            break
        time.sleep(0.1)
    else:
        pytest.fail("no row was streamed")
    kids = descendants(p.pid)
    p.send_signal(sig)
    stdout, stderr = p.communicate(timeout=120)
    assert p.returncode == 128 + sig, (p.returncode, stderr[-2000:])
    assert "Traceback" not in stderr
    no_child_survives(kids | descendants(p.pid))
    df = pd.read_csv(out / "study.csv")
    assert len(df) == 60 and df["mu"].tolist() == pytest.approx([0.3 + 0.01 * i for i in range(60)])
    done = df[df["status"] != "not run"]
    assert 2 <= len(done) < 60
    assert (df.loc[df["status"] == "not run", "certified"] == False).all()  # noqa: E712
    assert done["certified"].sum() >= len(done) - 1  # the one the signal stopped may have none
    assert not partial.exists()
    assert "interrupted" in stdout.splitlines()[-1]


def test_a_study_beyond_the_limit_is_refused_before_it_starts(tmp_path):
    spec = tmp_path / "spec.json"
    spec.write_text(json.dumps({"structure": str(INSTANCES / "wall33.json"),
                                "vary": {"mu": {"from": 0.3, "to": 0.9, "num": 1000},
                                         "load_angle": {"from": 0, "to": 10, "num": 1000}}}))
    t = time.monotonic()
    p = start("study", spec, "--out", tmp_path / "s")
    _, stderr = p.communicate(timeout=120)
    assert p.returncode == 2 and "asks for 1000000 variants, more than 10000" in stderr, stderr
    assert "--max-variants" in stderr and time.monotonic() - t < 60
    assert not (tmp_path / "s").exists()
    spec.write_text(json.dumps({"structure": str(INSTANCES / "wall33.json"),
                                "vary": {"mu": {"from": 0, "to": 1, "step": 1e-12}}}))
    p = start("study", spec, "--out", tmp_path / "s", "--max-variants", 10**13)
    _, stderr = p.communicate(timeout=120)
    assert p.returncode == 2 and "the range has" in stderr, stderr


def test_sigterm_during_a_library_solve_still_ends_the_program(tmp_path, wall):
    """In a Python program of the user's, SIGTERM stops the solve (its workers end), then
    ends the program as its default action would: it is never swallowed."""
    code = ("import sys, lamodel\n"
            f"s = lamodel.read({str(wall)!r})\n"
            "print('solving', flush=True)\n"
            "lamodel.solve(s, lamodel.SolveOptions(starts=2, workers=2, generations=40))\n"
            "print('the program went on')\n")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=env, preexec_fn=_as_a_terminal_starts_it)
    assert p.stdout.readline().strip() == "solving"
    time.sleep(3.0)
    kids = descendants(p.pid)
    p.send_signal(signal.SIGTERM)
    stdout, stderr = p.communicate(timeout=120)
    assert p.returncode == -signal.SIGTERM, (p.returncode, stderr[-2000:])
    assert "the program went on" not in stdout
    no_child_survives(kids)
