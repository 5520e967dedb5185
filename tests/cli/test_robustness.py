"""Issue 11: nothing half-written, nothing outside its folder, every path checked before solving.

Every case runs ``scripts/solve.py`` (or ``scripts/compare.py``, ``scripts/build_instance.py``)
as a separate process, as a user would. The kill test sends a real SIGKILL to a solve at
every file-system step of its writing (a wrapper announces each step on stderr and
pauses, so the kill lands between two steps), and at a few fixed fractions of a run;
after each kill the result folder must hold the complete old set or the complete new set
(summary, blocks, contacts, runs and the picture).
"""
from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from lamodel.output.results import Results

from conftest import INSTANCES, ROOT, rect, stack_spec

QUICK = ["--starts", "0", "--pop-size", "4", "--generations", "2"]
ENV = dict(os.environ, PYTHONPATH=str(ROOT))
RESULT_FILES = {"summary.csv", "blocks.csv", "contacts.csv", "runs.csv", "mechanism.png"}
PNG_END = b"IEND\xaeB`\x82"


def script(name, *args, cwd=None, umask=None, timeout=300):
    return subprocess.run([sys.executable, str(ROOT / "scripts" / name), *map(str, args)], capture_output=True,
                          text=True, cwd=cwd or ROOT, env=ENV, timeout=timeout,
                          preexec_fn=None if umask is None else (lambda: os.umask(umask)))


def solve(*args, **kw):
    return script("solve.py", *args, **kw)


def one_line_error(p, *fragments):
    """Exit 2, one line on stderr naming what is wrong, no traceback, nothing solved."""
    assert p.returncode == 2, (p.returncode, p.stdout, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("solve.py: error: "), p.stderr
    assert "Traceback" not in p.stderr and "alpha" not in p.stdout, p.stdout
    for f in fragments:
        assert str(f) in lines[0], (f, lines[0])
    return lines[0]


def write_json(path, spec):
    path.write_text(json.dumps(spec))
    return path


# ------------------------------------------------- 1. kill -9: the old set or the new set
#: Runs the solve command with every file-system step under ROOT_DIR announced on stderr
#: ("@@step <op> <path>") and followed by a pause, so that a SIGKILL sent on reading the
#: k-th announcement lands before that step. With FALLBACK set, the atomic exchange of
#: two folders is made unavailable (as on file systems without renameat2).
WRAPPER = r'''
import os, sys, time
root, pause = os.environ["ROOT_DIR"], float(os.environ["PAUSE"])

def where(name, args, kwargs):
    try:
        if name == "fsync":
            return os.readlink(f"/proc/self/fd/{args[0]}")
        p = os.fsdecode(args[0] if args else kwargs.get("path", kwargs.get("src")))
        fd = kwargs.get("dir_fd") or kwargs.get("src_dir_fd")
        return os.path.join(os.readlink(f"/proc/self/fd/{fd}"), p) if fd is not None else os.path.abspath(p)
    except (OSError, TypeError, ValueError):
        return ""

def announced(name, real):
    def step(*args, **kwargs):
        path = where(name, args, kwargs)
        if path.startswith(root):
            print(f"@@step {name} {path}", file=sys.stderr, flush=True)
            time.sleep(pause)
        return real(*args, **kwargs)
    return step

for name in ("rename", "replace", "link", "unlink", "rmdir", "mkdir", "fsync"):
    setattr(os, name, announced(name, getattr(os, name)))
sys.path.insert(0, os.environ["LAMODEL_ROOT"])
import lamodel.output.folder as files
if os.environ.get("FALLBACK"):
    import errno
    def no_exchange(a, b):
        raise OSError(errno.EINVAL, "no exchange here")
    files._exchange = no_exchange
from lamodel.cli import command
sys.exit(command("solve", sys.argv[1:], prog="solve.py"))
'''


def snapshot(folder):
    return {f.name: f.read_bytes() for f in Path(folder).iterdir()}


def restore(folder, files):
    import shutil
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir()
    for name, data in files.items():
        (folder / name).write_bytes(data)


def which_set(folder, old):
    """'old' or 'new' when the folder holds one complete set; AssertionError otherwise."""
    now = snapshot(folder)
    if now == old:
        return "old"
    assert set(now) == RESULT_FILES, f"{folder}: files {sorted(now)}"
    mixed = sorted(n for n in now if now[n] == old[n])
    assert not mixed, f"{folder}: {mixed} of the old run beside new files"
    r = Results.read(folder)  # every table complete and of the contract's types
    assert r.instance == "stack3" and len(r.blocks) == 3 and len(r.contacts) == 3
    assert now["mechanism.png"].endswith(PNG_END), "a truncated picture"
    return "new"


def leftovers(folder):
    return sorted(p.name for p in folder.parent.iterdir() if p.name.startswith(f".{folder.name}."))


@pytest.fixture(scope="module")
def kill_setup(tmp_path_factory):
    """An old result folder (stack2), the new input (stack3), and a reference run of the
    wrapper: its announced steps and its duration."""
    root = tmp_path_factory.mktemp("kill")
    new_input = write_json(root / "stack3.json", stack_spec(3))
    old = root / "old"
    t = time.monotonic()
    p = solve(write_json(root / "stack2.json", stack_spec(2)), "--out", old, *QUICK, "--quiet")
    seconds = time.monotonic() - t  # a whole run, for the timed kills
    assert p.returncode == 0, p.stderr
    wrapper = root / "wrapper.py"
    wrapper.write_text(WRAPPER)
    ref = root / "ref"
    restore(ref, snapshot(old))
    p = subprocess.run(wrapper_command(wrapper, new_input, ref), capture_output=True, text=True, timeout=300,
                       env=wrapper_env(root, pause=0))
    assert p.returncode == 0, p.stderr
    steps = [line.split(" ", 2)[1:] for line in p.stderr.splitlines() if line.startswith("@@step ")]
    assert steps, p.stderr
    return dict(root=root, old=snapshot(old), new_input=new_input, wrapper=wrapper, steps=steps, seconds=seconds)


def kill_points(steps, first=1):
    """The steps (1-based) to kill at: every step, except that of a run of steps doing the
    same operation in the same folder only the first and the last are kept (the states in
    between are alike, and each kill costs a process start)."""
    key = [(op, os.path.dirname(path)) for op, path in steps]
    keep = [k for k in range(first, len(steps) + 1)
            if k == first or k == len(steps) or key[k - 1] != key[k - 2] or key[k - 1] != key[k]]
    return keep + [len(steps) + 1]  # + 1: killed at the end, or not at all

def wrapper_command(wrapper, instance, out):
    return [sys.executable, str(wrapper), str(instance), "--out", str(out), *QUICK, "--quiet"]


def wrapper_env(root, pause=0.2, fallback=False):
    env = dict(ENV, ROOT_DIR=str(root), PAUSE=str(pause), LAMODEL_ROOT=str(ROOT))
    if fallback:
        env["FALLBACK"] = "1"
    return env


def kill_at_step(setup, folder, k, fallback=False):
    """Run the wrapper into ``folder`` and SIGKILL it on its k-th announced step; returns
    True if it was killed (False: it finished first)."""
    restore(folder, setup["old"])
    p = subprocess.Popen(wrapper_command(setup["wrapper"], setup["new_input"], folder), stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True, env=wrapper_env(setup["root"], fallback=fallback))
    seen, killed = 0, False
    for line in p.stderr:
        if line.startswith("@@step "):
            seen += 1
            if seen == k:
                os.kill(p.pid, signal.SIGKILL)
                killed = True
                break
    p.stderr.close()
    p.wait(timeout=120)
    return killed


def kill_after(setup, folder, seconds):
    """A plain solve into ``folder``, SIGKILLed after ``seconds``."""
    restore(folder, setup["old"])
    p = subprocess.Popen([sys.executable, str(ROOT / "scripts" / "solve.py"), str(setup["new_input"]), "--out",
                          str(folder), *QUICK, "--quiet"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=ENV)
    try:
        p.wait(timeout=seconds)
    except subprocess.TimeoutExpired:
        os.kill(p.pid, signal.SIGKILL)
    p.wait(timeout=120)


@pytest.mark.slow
def test_kill_9_at_every_step_leaves_the_old_or_the_new_set(kill_setup):
    setup, root = kill_setup, kill_setup["root"]

    def trial(k):
        folder = root / f"step{k}"
        killed = kill_at_step(setup, folder, k)
        return k, killed, which_set(folder, setup["old"])

    def timed(fraction):  # kills at fixed fractions of a run: mostly while solving or drawing
        folder = root / f"timed{fraction}"
        kill_after(setup, folder, fraction * setup["seconds"])
        return fraction, which_set(folder, setup["old"])

    with ThreadPoolExecutor(max_workers=2) as pool:
        outcomes = list(pool.map(trial, kill_points(setup["steps"])))
        list(pool.map(timed, (0.6, 0.9)))
    assert {state for _, _, state in outcomes} == {"old", "new"}, outcomes  # both sides of the swap, each whole
    assert all(killed for _, killed, _ in outcomes[:-1]), outcomes

    # the next run cleans up after a killed one and replaces the folder as a whole
    stale = [root / f"step{k}" for k, _, _ in outcomes if leftovers(root / f"step{k}")]
    assert stale, "no kill left a staging folder behind: the clean-up is not exercised"
    p = solve(setup["new_input"], "--out", stale[0], *QUICK, "--quiet")
    assert p.returncode == 0, p.stderr
    assert which_set(stale[0], setup["old"]) == "new"
    assert leftovers(stale[0]) == []


@pytest.mark.slow
def test_kill_9_without_an_atomic_exchange_loses_nothing(kill_setup):
    """Where two folders cannot be exchanged in one step, the old folder is renamed aside
    first: a kill right then leaves it aside, and the next run for the folder puts it back."""
    from lamodel.output.folder import ResultFolder
    from lamodel.output.results import foreign_files
    setup, root = kill_setup, kill_setup["root"]
    # from the flush of the staged folder (the last step on a hidden folder's path before
    # the parent's) on: the two renames and the clean-up
    staged = max(k for k, (op, path) in enumerate(setup["steps"], start=1)
                 if op == "fsync" and Path(path).name.startswith("."))
    states = []
    for k in range(staged, staged + 4):
        folder = root / f"fallback{k}"
        kill_at_step(setup, folder, k, fallback=True)
        if not folder.exists():
            aside = [root / n for n in leftovers(folder) if ".lamodel-old-" in n]
            assert len(aside) == 1 and snapshot(aside[0]) == setup["old"], leftovers(folder)
            ResultFolder(folder, foreign_files).open().discard()  # what the next run does first
            assert leftovers(folder) == []
            states.append("aside")
        states.append(which_set(folder, setup["old"]))
    assert {"old", "new", "aside"} <= set(states), states


# ------------------------------------------------------------ 2. every path checked first
@pytest.fixture
def stack2(tmp_path):
    return write_json(tmp_path / "stack2.json", stack_spec(2))


@pytest.mark.parametrize("case", ["out unwritable", "plot unwritable", "plot in a missing folder",
                                  "unknown picture format"])
@pytest.mark.slow
def test_output_places_are_checked_before_solving(tmp_path, stack2, case):
    out = tmp_path / "out"
    args = {"out unwritable": ["--out", "/proc/lamodel-out"],
            "plot unwritable": ["--out", out, "--plot", "/proc/lamodel.png"],
            "plot in a missing folder": ["--out", out, "--plot", tmp_path / "missing" / "m.png"],
            "unknown picture format": ["--out", out, "--plot", tmp_path / "m.xyz"]}[case]
    line = one_line_error(solve(stack2, *args, *QUICK), "expected")
    assert {"out unwritable": "/proc/lamodel-out", "plot unwritable": "/proc",
            "plot in a missing folder": "missing", "unknown picture format": ".xyz"}[case] in line
    assert not out.exists() and not (tmp_path / "missing").exists(), "nothing may be written"


@pytest.mark.slow
def test_a_users_files_in_the_folder_are_kept_and_a_users_folder_refused(tmp_path, stack2):
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("my notes")
    p = solve(stack2, "--out", out, *QUICK)
    assert p.returncode == 0, p.stderr
    files = snapshot(out)
    assert files["notes.txt"] == b"my notes" and "summary.csv" in files  # the user's file went along
    (out / "mine").mkdir()
    one_line_error(solve(stack2, "--out", out, *QUICK), "mine", "expected")
    assert (out / "notes.txt").read_text() == "my notes" and (out / "mine").is_dir()


# --------------------------------------------------------- 3. the name chooses no path
@pytest.mark.slow
@pytest.mark.parametrize("kind", ["absolute", "parent"])
def test_json_name_never_leaves_results(tmp_path, kind):
    work = tmp_path / "work"
    work.mkdir()
    outside = tmp_path / "outside"
    name = str(outside) if kind == "absolute" else "../outside"
    path = write_json(work / "s.json", dict(stack_spec(2), name=name))
    p = solve(path, *QUICK, "--no-plot", "--quiet", cwd=work)
    assert p.returncode == 0, p.stderr
    assert not outside.exists()
    folders = list((work / "results").iterdir())
    assert len(folders) == 1 and not folders[0].name.startswith(".")
    assert Results.read(folders[0]).instance == name  # the name itself is kept in the table
    assert sorted(p.name for p in work.iterdir()) == ["results", "s.json"]


# ----------------------------------------------------------------------- 4. UTF-8 input
@pytest.mark.slow
def test_invalid_utf8_is_bad_input_naming_the_file(tmp_path):
    spec = json.dumps(dict(stack_spec(2), description="ma\u00e7onnerie"), ensure_ascii=False).encode("utf-8")
    bad_json = tmp_path / "latin1.json"
    bad_json.write_bytes(spec.replace("\u00e7".encode("utf-8"), b"\xe7"))
    dat = tmp_path / "latin1.dat"
    dat.write_bytes(b"# ma\xe7onnerie\n" + (INSTANCES / "wall33.dat").read_bytes())
    for path in (bad_json, dat):
        one_line_error(solve(path, "--out", tmp_path / "out", *QUICK), path.name, "UTF-8", "expected")
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_a_utf8_byte_order_mark_is_accepted(tmp_path):
    bom = b"\xef\xbb\xbf"
    js = tmp_path / "bom.json"
    js.write_bytes(bom + json.dumps(stack_spec(2)).encode())
    dat = tmp_path / "bom.dat"
    built = script("build_instance.py", write_json(tmp_path / "plain.json", stack_spec(2)), "-o", dat)
    assert built.returncode == 0, built.stderr
    dat.write_bytes(bom + dat.read_bytes())
    for path in (js, dat):
        p = solve(path, "--out", tmp_path / path.stem, *QUICK, "--no-plot", "--quiet")
        assert p.returncode == 0, p.stderr
        assert Results.read(tmp_path / path.stem).alpha == pytest.approx(0.5, abs=1e-9)  # overturning: width / (n height)


# ------------------------------------------------------------------------ 5. the umask
@pytest.mark.slow
def test_outputs_follow_the_umask(tmp_path, stack2):
    out, picture, dat = tmp_path / "out", tmp_path / "elsewhere.png", tmp_path / "s.dat"
    p = solve(stack2, "--out", out, *QUICK, "--quiet", umask=0o027)
    assert p.returncode == 0, p.stderr
    p = solve(stack2, "--out", tmp_path / "out2", "--plot", picture, *QUICK, "--quiet", umask=0o027)
    assert p.returncode == 0, p.stderr
    assert script("build_instance.py", stack2, "-o", dat, umask=0o027).returncode == 0
    modes = {f.name: f.stat().st_mode & 0o777 for f in [*out.iterdir(), picture, dat]}
    assert set(modes) == RESULT_FILES | {"elsewhere.png", "s.dat"}
    assert set(modes.values()) == {0o640}, {k: oct(v) for k, v in modes.items()}
    assert out.stat().st_mode & 0o777 == 0o750


# ---------------------------------------------------------- 6. no stale picture
@pytest.mark.slow
def test_no_plot_leaves_no_stale_picture(tmp_path, stack2):
    out = tmp_path / "out"
    assert solve(stack2, "--out", out, *QUICK, "--quiet").returncode == 0
    assert (out / "mechanism.png").exists()
    three = write_json(tmp_path / "stack3.json", stack_spec(3))
    p = solve(three, "--out", out, *QUICK, "--quiet", "--no-plot")
    assert p.returncode == 0, p.stderr
    assert sorted(f.name for f in out.iterdir()) == ["blocks.csv", "contacts.csv", "runs.csv", "summary.csv"]
    assert Results.read(out).instance == "stack3"


@pytest.mark.slow
def test_files_named_inside_the_folder_are_part_of_the_set(tmp_path, stack2):
    """A picture, report or animation written into the result folder belongs to its set:
    the next run replaces them with the rest (none is left stale, none makes it refuse)."""
    out = tmp_path / "out"
    p = solve(stack2, "--out", out, *QUICK, "--quiet", "--plot", out / "fig.svg", "--report", out / "r.html",
              "--animate", out / "m.gif")
    assert p.returncode == 0, p.stderr
    assert sorted(f.name for f in out.iterdir()) == ["blocks.csv", "contacts.csv", "fig.svg", "m.gif", "r.html",
                                                     "runs.csv", "summary.csv"]
    p = solve(stack2, "--out", out, *QUICK, "--quiet", "--report", out / "r.html")
    assert p.returncode == 0, p.stderr
    assert sorted(f.name for f in out.iterdir()) == ["blocks.csv", "contacts.csv", "mechanism.png", "r.html",
                                                     "runs.csv", "summary.csv"]


# ------------------------------------------------------------ 7. -0 and empty ids
@pytest.mark.slow
def test_mu_zero_reports_alpha_zero_not_minus_zero(tmp_path):
    path = write_json(tmp_path / "mu0.json", stack_spec(1, mu=0.0))
    out = tmp_path / "out"
    p = solve(path, "--out", out, *QUICK, "--no-plot")
    assert p.returncode == 0, p.stderr
    minus_zero = re.compile(r"(?<![\w.])-0(?:\.0*)?(?![\w.])")
    assert not minus_zero.search(p.stdout), p.stdout
    assert "alpha = 0.000000" in p.stdout
    for name in ("summary.csv", "runs.csv"):
        text = (out / name).read_text()
        assert not minus_zero.search(text), text
    assert Results.read(out).alpha == 0.0


@pytest.mark.slow
def test_an_empty_block_id_is_rejected_naming_the_file(tmp_path):
    spec = stack_spec(2)
    spec["blocks"][2]["id"] = ""
    path = write_json(tmp_path / "empty_id.json", spec)
    line = one_line_error(solve(path, "--out", tmp_path / "out", *QUICK), "empty_id.json", "id")
    assert "table" not in line, line
    assert not (tmp_path / "out").exists()


# ----------------------------------------------------- 8. warnings reach stderr, always
@pytest.mark.slow
def test_quiet_keeps_warnings_that_change_the_answer(tmp_path):
    spec = stack_spec(2)
    spec["live_laod"] = spec.pop("live_load")
    path = write_json(tmp_path / "typo.json", spec)
    p = solve(path, "--out", tmp_path / "out", *QUICK, "--no-plot", "--quiet")
    assert p.returncode == 0, p.stderr
    assert re.search(r"warning: .*typo.json: unknown top-level field\(s\) 'live_laod' ignored", p.stderr), p.stderr
    assert "GA + LP" not in p.stderr, "--quiet silences the progress"
    assert len(p.stdout.strip().splitlines()) == 1, p.stdout  # and the tables: only the one-line result


# ------------------------------------------------------------------------ 9. --starts
@pytest.mark.slow
def test_starts_help_says_what_it_does():
    p = solve("--help")
    text = " ".join(p.stdout.split())
    assert "K Ipopt solves" in text and "why it was skipped" in text and "fewer" in text, text


@pytest.mark.slow
def test_runs_has_a_row_for_every_requested_start(tmp_path):
    out = tmp_path / "out"
    p = solve(INSTANCES / "wall33.dat", "--out", out, "--starts", "3", "--no-plot", "--quiet", "--workers", "1")
    assert p.returncode == 0, p.stderr
    runs = Results.read(out).runs
    ipopt = runs[runs.start >= 1]
    assert len(ipopt) == 3, runs.to_string()  # each one an Ipopt solve or a row saying why it was skipped
    assert ipopt.source.str.contains("ipopt").all() or ipopt.status.str.contains("skip").any(), runs.to_string()


# -------------------------------------------------------------------------- 10. compare
def row_of_blocks(n, N, modes, name="row"):
    """n blocks side by side, each on the ground (contact ck under block bk); by hand."""
    x = np.arange(n, dtype=float)
    summary = dict(instance=name, alpha=0.5, certified=True, alpha_associative=0.6, n_blocks=n, n_contacts=n,
                   n_starts=1, n_certified=1, wall_time_s=0.1)
    blocks = pd.DataFrame(dict(block=[f"b{k + 1}" for k in range(n)], x=x, y=0.5, dead_x=0.0, dead_y=-1.0,
                               live_x=1.0, live_y=0.0, ux=1.0, uy=0.0, theta=0.0))
    contacts = pd.DataFrame(dict(contact=[f"c{k + 1}" for k in range(n)], block_a="ground",
                                 block_b=[f"b{k + 1}" for k in range(n)], cx=x, cy=0.0, nx=0.0, ny=1.0, d=0.5,
                                 mu=0.6, N=N, V=0.0, M=0.0, mode=modes))
    runs = pd.DataFrame(dict(start=[0], source=["ga+lp"], alpha_ipopt=[np.nan], status=["certified"],
                             alpha_certified=[0.5], iterations=[1], seconds=[0.1]))
    return Results.from_frames(summary, blocks, contacts, runs)


@pytest.mark.slow
def test_compare_shows_the_force_difference_in_short_lines(tmp_path):
    n = 30
    rng = np.random.default_rng(1)
    NA, NB = -rng.uniform(1, 10, n), -rng.uniform(1, 10, n)
    a = row_of_blocks(n, NA, ["closed"] * n).write(tmp_path / "a")
    b = row_of_blocks(n, NB, ["hinging"] * n).write(tmp_path / "b")
    p = script("compare.py", a, b)
    assert p.returncode == 1, p.stderr
    widest = max(len(line) for line in p.stdout.splitlines())
    assert widest < 200, f"lines up to {widest} characters"
    row = next(line for line in p.stdout.splitlines() if line.startswith("max |dN|"))
    k = int(np.argmax(np.abs(NB - NA)))
    numbers = [float(v) for v in re.findall(r"-?\d+\.\d+(?:e-?\d+)?", row)]
    assert numbers[:3] == pytest.approx([NA[k], NB[k], abs(NB[k] - NA[k])], rel=1e-9), row
    assert f"N at contact c{k + 1}" in row, row


@pytest.mark.slow
@pytest.mark.parametrize("change", ["one block less", "other ids"])
def test_compare_says_when_the_structures_differ(tmp_path, change):
    n = 6
    a = row_of_blocks(n, -np.ones(n), ["closed"] * n).write(tmp_path / "a")
    if change == "one block less":
        other = row_of_blocks(n - 1, -np.ones(n - 1), ["closed"] * (n - 1))
    else:
        other = row_of_blocks(n, -np.ones(n), ["closed"] * n)
        other.contacts["contact"] = [f"k{k + 1}" for k in range(n)]
    b = other.write(tmp_path / "b")
    p = script("compare.py", a, b)
    assert p.returncode == 1, p.stderr
    assert "different structures" in p.stdout, p.stdout
    assert "max |dN|" not in p.stdout, "contacts of two structures are not matched by id"
