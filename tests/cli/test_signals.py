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

import numpy as np
import pandas as pd
import pytest

from conftest import INSTANCES, ROOT, descendants
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


def handles_stop_signals(pid) -> bool:
    """lamodel's own handler is in place (the kernel shows SIGTERM caught): before it, in the
    interpreter's first tens of milliseconds, a signal has its default action."""
    try:
        line = next(x for x in Path(f"/proc/{pid}/status").read_text().splitlines() if x.startswith("SigCgt:"))
    except (OSError, StopIteration):
        return False
    return bool(int(line.split()[1], 16) >> (signal.SIGTERM - 1) & 1)


def group_members(pgid) -> list:
    """The live processes of a process group (zombies are gone for good)."""
    found = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                fields = (d / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[2]) == pgid and fields[0] != "Z":
                found.append(int(d.name))
    return found


#: 15 moments after lamodel's start-up began, from reading its modules to the search's end
MOMENTS = [round(float(t), 3) for t in np.geomspace(0.05, 3.0, 15)]
#: every (moment, signal) this many times: LAMODEL_SIGNAL_REPEAT=50 for the long check
REPEAT = int(os.environ.get("LAMODEL_SIGNAL_REPEAT", "1"))


def stop_once(structure, out, sig, moment, oracle, extra=()):
    """Start ``lamodel solve`` in its own process group, send ``sig`` ``moment`` seconds after
    its handler is in place; what went wrong (empty: the run ended as it must)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    p = subprocess.Popen([sys.executable, "-m", "lamodel.cli", "solve", str(structure), "--out", str(out),
                          "--no-plot", *extra], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=env, cwd=out.parent, preexec_fn=_as_a_terminal_starts_it, start_new_session=True)
    t = time.monotonic()
    while not handles_stop_signals(p.pid) and p.poll() is None and time.monotonic() - t < 60:
        time.sleep(0.002)
    time.sleep(moment)
    p.send_signal(sig)
    sent = time.monotonic()
    try:
        stdout, stderr = p.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        return [f"{sig.name} at {moment} s: still running 60 s later"]
    took = time.monotonic() - sent
    while group_members(p.pid) and time.monotonic() - sent < 5.0:  # workers see their parent gone
        time.sleep(0.05)
    left = group_members(p.pid)
    if left:
        os.killpg(p.pid, signal.SIGKILL)
    what = f"{sig.name} at {moment} s"
    wrong = []
    if p.returncode != 128 + sig:
        wrong.append(f"{what}: exit {p.returncode}: {stderr[-300:]}")
    if took > 5.0:
        wrong.append(f"{what}: ended {took:.1f} s after the signal")
    if "Traceback" in stderr:
        wrong.append(f"{what}: a traceback: {stderr[-300:]}")
    if left:
        wrong.append(f"{what}: processes left in its group: {left}")
    if [f for f in out.parent.iterdir() if f.name.startswith(".")]:
        wrong.append(f"{what}: a staging folder left behind")
    if (out / "summary.csv").exists() and pd.read_csv(out / "summary.csv").certified[0]:
        wrong += [f"{what}: the state written: {w}" for w in oracle(out)]  # a collapse state, for the oracle
    return wrong


@pytest.fixture(scope="module")
def a_solve_beside(wall, tmp_path_factory):
    """Another solve loading the machine while the runs are stopped (under load, imports take
    longer: the moments a signal can land in one widen)."""
    out = tmp_path_factory.mktemp("load") / "o"
    p = start("solve", wall, "--out", out, "--no-plot", "--generations", "400", "--time-limit", "900")
    yield p
    p.kill()
    p.communicate()


def building(tmp_path):
    sys.path.insert(0, str(ROOT / "tests" / "space"))
    from cases3d import case_specs
    path = tmp_path / "building.json"
    path.write_text(json.dumps(case_specs()["building_mu0.9"]))  # certified at 0.6 s, ends at 10 s
    return path


@pytest.mark.parametrize("space", [False, True], ids=["plane", "space"])
def test_a_stop_signal_at_any_moment_ends_the_run_within_5_s(tmp_path, wall, a_solve_beside, space):
    """SIGINT, SIGTERM and SIGHUP at 15 moments from start-up to the search's end, two runs at
    a time beside another solve: each run exits with 128 + the signal within 5 s, leaves no
    process of its group and no staging folder, and whatever it wrote is a collapse state."""
    from concurrent.futures import ThreadPoolExecutor

    from oracle3d import violations

    def plane(out):
        alpha = pd.read_csv(out / "summary.csv").alpha[0]
        return [] if abs(check_folder(out) - alpha) <= 1e-9 else [f"the oracle's alpha is not {alpha}"]
    structure, oracle = (building(tmp_path), violations) if space else (wall, plane)
    extra = () if space else ("--starts", "2", "--generations", "40")
    cases = [(sig, t, i) for i in range(REPEAT) for t in MOMENTS
             for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)]

    def one(case):
        sig, t, i = case
        place = tmp_path / f"{sig.name}-{t}-{i}"
        place.mkdir()
        return stop_once(structure, place / "o", sig, t, oracle, extra)
    with ThreadPoolExecutor(2) as pool:
        wrong = [w for found in pool.map(one, cases) for w in found]
    assert not wrong, "\n".join(wrong[:10]) + f"\n({len(wrong)} in all, {len(cases)} runs)"


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


THREE_SPANS = {  # searches of 5 to 40 s a position
    "name": "three_spans", "units": {"length": "m", "force": "kN"},
    "spans": [{"span": 8.0, "rise": 2.5}] * 3, "piers": [{"height": 5.0, "width": 1.5, "kind": "block"}] * 2,
    "ring": {"thickness": 0.5, "rings": 2, "voussoirs": 20, "unit_weight": 20.0, "mu": 0.6},
    "abutments": {"height": 1.5, "width": 1.5}, "backing": {"height": 1.0},
    "fill": {"depth": 0.5, "unit_weight": 18.0, "phi": 35.0, "passive": 0.33, "spread": 30.0},
    "load": {"force": 100.0, "patch": 0.3, "positions": [-12, -9, -6, 12]}}


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_stop_signal_ends_positions_solved_side_by_side(tmp_path, sig):
    """A bridge's positions solved two at once (worker processes): a stop signal sent to the
    command alone reaches both solves under way, which end with their best certified state
    (``interrupted``); the positions not begun are ``not run``; the table is written and no
    worker outlives the run."""
    bridge, out = tmp_path / "three.json", tmp_path / "adequacy"
    bridge.write_text(json.dumps(THREE_SPANS))
    p = start("bridge", bridge, tmp_path / "b.json", "--adequacy", out, "--workers", 2)
    lines, t = [], time.monotonic()
    while time.monotonic() - t < 300:  # the first position ended (-9 m): two more are under way
        lines.append(p.stdout.readline())
        if lines[-1].startswith("  x = ") or not lines[-1]:
            break
    assert lines[-1].startswith("  x = "), (lines, p.stderr.read()[-2000:])
    kids = descendants(p.pid)
    assert len(kids) >= 2
    p.send_signal(sig)
    t = time.monotonic()
    stdout, stderr = p.communicate(timeout=120)
    assert time.monotonic() - t < 30  # the searches end at their next check
    assert p.returncode == 128 + sig, (p.returncode, stderr[-2000:])
    assert "Traceback" not in stderr
    no_child_survives(kids | descendants(p.pid))
    df = pd.read_csv(out / "adequacy.csv")
    status = df["status"].tolist()
    # -12 m under way, -9 m done, 12 m not begun; -6 m under way unless the signal came before it was handed out
    assert status[:2] == ["interrupted", "certified"] and status[2] in ("interrupted", "not run"), status
    assert status[3] == "not run", status
    assert not df.loc[df["status"] == "not run", "certified"].any()


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_stop_signal_during_the_proven_bound_keeps_the_certified_state(tmp_path, sig):
    """--prove runs the bound after the search: a signal then ends the bound (what it proved
    is kept: it is anytime), the folder is written with the search's certified state, and
    the run exits with 128 + the signal within seconds (it exited 143 with nothing written)."""
    out = tmp_path / "out"
    p = start("solve", INSTANCES / "wall33.json", "--out", out, "--no-plot", "--prove", "120", "-v")
    line = ""
    deadline = time.monotonic() + 120
    while "certified: alpha" not in line and time.monotonic() < deadline:   # the search's last log line
        line = p.stderr.readline()
    assert "certified: alpha" in line
    time.sleep(1.0)   # the bound runs
    sent = time.monotonic()
    p.send_signal(sig)
    p.communicate(timeout=30)
    assert p.returncode == 128 + sig and time.monotonic() - sent < 10
    summary = pd.read_csv(out / "summary.csv").iloc[0]
    assert summary["certified"] and summary["alpha"] == pytest.approx(0.638982, abs=1e-6)
    assert summary["alpha_lower_seconds"] < 60
    assert check_folder(out) == pytest.approx(summary["alpha"], rel=1e-9)
