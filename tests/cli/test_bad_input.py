"""Bad input and failures (issue 6): clear errors, nothing lost, reproducible runs.

Every bad-input case goes through ``scripts/solve.py`` as a user would run it and must end
with exit status 2 and one line on stderr naming the file, the field or line, what is
wrong and what is expected — never a traceback (unless ``--debug``), never a result
folder. To keep the suite quick, most cases execute the file scripts/solve.py inside this
process (:func:`solve_py`, by runpy: the same code path without the 2 s of imports of a
new interpreter); a representative few (:data:`FRESH`) run as real processes, started
together by the module fixture :func:`fresh`. Physical edge cases, failures during a run
(time limit, write failures, a dying Ipopt worker, Ctrl-C) and reproducibility follow.
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

import lamodel.search.driver as driver_mod
import lamodel.search.ipopt as ipopt_mod
import lamodel.output.folder as files_mod
import lamodel.output.results as results_mod
from lamodel.search.driver import SolveOptions, solve
from lamodel.io.jsonspec import structure_from_json
from lamodel.search.lp import LimitLPs, LPResult
from lamodel.output.report import outcome_results
from lamodel.output.results import Results

from conftest import INSTANCES, ROOT, rect, run_script, stack_spec

# ----------------------------------------------------------------------------- inputs
#: Two unit blocks stacked on the ground (alpha = 1/2), as a Pyomo .dat file; the cases
#: below are small edits of it. Line numbers: b2's row is line 7, c2's row line 11.
BASE_DAT = """\
set BLOCKS := b1 b2 ;
set SUPPORTS := ground ;
set CONTACTS := c1 c2 ;
param: x y dead_x dead_y live_x live_y :=
  b1 0.0 0.5 0.0 -1.0 1.0 0.0
# the upper block
  b2 0.0 1.5 0.0 -1.0 1.0 0.0
;
param: block_a block_b cx cy nx ny d mu :=
  c1 ground b1 0.0 0.0 0.0 1.0 0.5 0.6
  c2 b1 b2 0.0 1.0 0.0 1.0 0.5 0.6
;
param: VERTICES: vx vy :=
  b1 1 -0.5 0.0
  b1 2 0.5 0.0
  b1 3 0.5 1.0
  b1 4 -0.5 1.0
;
"""
B2 = "  b2 0.0 1.5 0.0 -1.0 1.0 0.0\n"
C2 = "  c2 b1 b2 0.0 1.0 0.0 1.0 0.5 0.6\n"


def edit(old, new, text=BASE_DAT):
    assert text.count(old) == 1, old
    return text.replace(old, new)


#: name -> (file text, fragments the one-line message must contain besides the file name)
DAT_CASES = {
    # a block without dead_y ('.' is Pyomo's "no value")
    "missing_dead_y": (edit(B2, "  b2 0.0 1.5 0.0 . 1.0 0.0\n"), ["dead_y", "'b2'", "missing", "expected a value"]),
    "missing_block_row": (edit(B2, ""), ["'b2'", "missing", "expected a value for every block"]),
    "short_row": (edit(B2, "  b2 0.0 1.5 0.0 1.0 0.0\n"), ["line 7", "'b2'", "6 entries", "expected 7"]),
    "long_row": (edit(B2, "  b2 0.0 1.5 0.0 -1.0 1.0 0.0 7\n"), ["line 7", "'b2'", "8 entries", "expected 7"]),
    "duplicated_block_row": (edit(B2, B2 + "  b2 0.0 1.5 0.0 -2.0 1.0 0.0\n"),
                             ["line 8", "'b2' is given twice", "first on line 7", "expected one row per key"]),
    "duplicated_contact_row": (edit(C2, C2 + C2), ["line 12", "'c2' is given twice", "expected one row per key"]),
    "duplicated_set_member": (edit("b1 b2 ;", "b1 b2 b1 ;"), ["line 1", "BLOCKS", "'b1' twice", "expected unique"]),
    "unknown_block": (edit("c2 b1 b2", "c2 b1 b9"), ["contact 'c2'", "unknown block_b 'b9'", "expected a declared"]),
    "contact_itself": (edit("c2 b1 b2", "c2 b1 b1"), ["contact 'c2'", "itself", "expected two different"]),
    "contact_not_in_table": (edit("c1 c2 ;", "c1 c2 c3 ;"), ["'c3'", "missing", "expected a value for every contact"]),
    "row_not_in_set": (edit(B2, B2 + "  b7 0.0 1.5 0.0 -1.0 1.0 0.0\n"), ["'b7'", "not in the set of blocks"]),
    "unknown_parameter": (edit("param: x y dead_x", "param: x y weight dead_x")
                          .replace(" 0.5 0.0 -1.0", " 0.5 7 0.0 -1.0")
                          .replace(" 1.5 0.0 -1.0", " 1.5 7 0.0 -1.0"),
                          ["line 4", "unknown parameter 'weight'", "expected only the parameters"]),
    "zero_normal": (edit(C2, "  c2 b1 b2 0.0 1.0 0.0 0.0 0.5 0.6\n"), ["normal of contact 'c2'", "length 0",
                                                                       "expected a unit vector"]),
    "non_unit_normal": (edit(C2, "  c2 b1 b2 0.0 1.0 0.6 0.6 0.5 0.6\n"), ["normal of contact 'c2'", "length 0.848",
                                                                           "expected a unit vector"]),
    "d_zero": (edit(C2, "  c2 b1 b2 0.0 1.0 0.0 1.0 0.0 0.6\n"),
               ["d of contact 'c2'", "is 0", "expected a half-length > 0"]),
    "d_negative": (edit(C2, "  c2 b1 b2 0.0 1.0 0.0 1.0 -0.5 0.6\n"), ["d of contact 'c2'", "-0.5", "> 0"]),
    "mu_negative": (edit(C2, "  c2 b1 b2 0.0 1.0 0.0 1.0 0.5 -0.1\n"), ["mu of contact 'c2'", "-0.1", "expected",
                                                                         ">= 0"]),
    "nan": (edit(B2, "  b2 0.0 1.5 0.0 nan 1.0 0.0\n"), ["dead_y", "'b2'", "nan", "expected a finite number"]),
    "NaN": (edit(B2, "  b2 0.0 1.5 0.0 -1.0 NaN 0.0\n"), ["live_x", "'b2'", "nan", "expected a finite number"]),
    "inf": (edit(C2, "  c2 b1 b2 0.0 1.0 0.0 1.0 inf 0.6\n"), ["parameter d of contact 'c2'", "inf", "finite"]),
    "minus_inf": (edit(B2, "  b2 -inf 1.5 0.0 -1.0 1.0 0.0\n"), ["parameter x of block 'b2'", "-inf", "finite"]),
    "vertex_nan": (edit("b1 4 -0.5 1.0", "b1 4 -0.5 nan"), ["vertex 4 of 'b1'", "nan", "expected finite"]),
    "text_value": (edit(B2, "  b2 0.0 1.5 0.0 heavy 1.0 0.0\n"), ["dead_y", "'b2'", "'heavy'", "expected a number"]),
    "empty_blocks": (edit("set BLOCKS := b1 b2 ;", "set BLOCKS := ;"), ["BLOCKS is empty", "expected at least one"]),
    "no_blocks_set": (edit("set BLOCKS := b1 b2 ;\n", ""), ["BLOCKS is missing", "expected 'set BLOCKS"]),
    "no_contacts": (edit("c1 c2 ;", ";").split("param: block_a")[0], ["no contacts", "expected blocks resting"]),
    "all_live_zero": (edit(" 1.0 0.0\n# the", " 0.0 0.0\n# the").replace(" -1.0 1.0 0.0\n;", " -1.0 0.0 0.0\n;"),
                      ["every live load is zero", "expected a live load"]),
    "syntax_error": (edit("param: x y dead_x dead_y live_x live_y :=", "param x y dead_x :=: live_x live_y"),
                     ["not a valid Pyomo .dat instance", "line 4"]),
    "missing_semicolon": (BASE_DAT.rstrip().rstrip(";"), ["not a valid Pyomo .dat instance", "end of file"]),
    "garbage": ("this is { not a dat file\n", ["not a valid Pyomo .dat instance", "line 1"]),
    "empty_file": ("", ["BLOCKS is missing", "expected"]),
    # a block that touches nothing: declared with its loads, named by no contact
    "free_body": (edit("b1 b2 ;", "b1 b2 b3 ;").replace(B2, B2 + "  b3 5.0 0.5 0.0 -1.0 1.0 0.0\n"),
                  ["block 'b3'", "touches nothing", "free body", "expected every block to have a contact"]),
}


def json_spec(**changes):
    """stack_spec(2) (ground, b1, b2) with top-level changes; blocks edited by the caller."""
    spec = stack_spec(2)
    spec.update(changes)
    return spec


def with_block(i, **fields):
    spec = json_spec()
    spec["blocks"][i] = dict(spec["blocks"][i], **fields)
    return spec


def without(i, key):
    spec = json_spec()
    del spec["blocks"][i][key]
    return spec


JSON_CASES = {
    "malformed": ('{"name": "x", "blocks": [ {"id": "a", }',
                  ["malformed JSON", "line 1, column 39", "expected a JSON"]),
    "not_an_object": ("[1, 2]", ["a JSON list", "expected a JSON object"]),
    "missing_vertices": (without(1, "vertices"), ["block 'b1'", "no 'vertices'", "expected a list"]),
    "two_vertices": (with_block(1, vertices=[[-0.5, 0], [0.5, 0]]),
                     ["block 'b1'", "2 vertices", "expected at least 3"]),
    "non_convex": (with_block(2, vertices=[[-0.5, 1], [0.5, 1], [0.5, 2], [0, 1.5], [-0.5, 2]]),
                   ["block 'b2'", "not convex", "vertex (0, 1.5)", "expected the corners of a convex polygon"]),
    "self_intersecting": (with_block(2, vertices=[[-0.5, 1], [0.5, 2], [0.5, 1], [-0.5, 2]]),
                          ["block 'b2'", "crosses itself", "expected the corners of a convex polygon"]),
    "zero_area": (with_block(2, vertices=[[-0.5, 1], [0, 1], [0.5, 1]]), ["block 'b2'", "zero area", "positive area"]),
    "interpenetrating": (with_block(2, vertices=rect(-0.5, 0.8, 0.5, 1.8)),
                         ["'b1'", "'b2'", "interpenetrate", "overlap by 0.2", "expected bodies that touch"]),
    "no_support": (without(0, "support"), ["no block is a support", 'expected at least one body with "support": true']),
    "all_supports": (json_spec(blocks=[dict(b, support=True) for b in json_spec()["blocks"]]),
                     ["every body is a support", "expected at least one movable block"]),
    "no_blocks": (json_spec(blocks=[]), ["'blocks' is missing or empty", "expected a list"]),
    "nan_vertex": ('{"mu": 0.6, "blocks": [{"id": "g", "support": true, "vertices": [[-2,-1],[2,-1],[2,0],[-2,0]]},'
                   '{"id": "b", "vertices": [[-0.5,0],[0.5,0],[0.5,NaN],[-0.5,1]]}]}',
                   ["block 'b'", "NaN", "expected a finite number"]),
    "string_vertex": (with_block(1, vertices=[[-0.5, 0], [0.5, 0], [0.5, "1"], [-0.5, 1]]),
                      ["block 'b1'", '"1"', "expected a finite number"]),
    "mu_negative": (json_spec(mu=-0.2), ["'mu' is -0.2", "expected a number >= 0"]),
    "no_mu": ({k: v for k, v in json_spec().items() if k != "mu"}, ["no friction coefficient", "expected a top-level"]),
    "live_load_zero": (json_spec(live_load=[0, 0]), ["every live load is zero", "expected a live load"]),
    "duplicate_id": (with_block(2, id="b1"), ["block 'b1'", "declared twice", "expected unique ids"]),
    # a block that touches nothing: beside the stack, in the air
    "free_body": (json_spec(blocks=json_spec()["blocks"] + [{"id": "b3", "vertices": rect(5, 0.5, 6, 1.5)}]),
                  ["block 'b3'", "touches no other body", "free body", "expected every block to share an edge"]),
    "corner_only": (with_block(2, vertices=rect(0.5, 1, 1.5, 2)), ["block 'b2'", "free body"]),
}

# Bodies for the physical edge cases (section 2)
OVERHANG = {"name": "overhang", "mu": 0.6, "blocks": [
    {"id": "ground", "support": True, "vertices": rect(-2, -1, 2, 0)},
    {"id": "b1", "vertices": rect(-0.5, 0, 0.5, 1)},
    {"id": "b2", "vertices": rect(0.2, 1, 1.2, 2)}]}   # centroid x = 0.7 beyond b1's edge x = 0.5
HELD = {"name": "held", "mu": 0.6, "blocks": [
    {"id": "ground", "support": True, "vertices": rect(-3, -1, 3, 0)},
    {"id": "left", "support": True, "vertices": rect(-3, 0, -1, 2)},
    {"id": "right", "support": True, "vertices": rect(1, 0, 3, 2)},
    {"id": "b", "vertices": rect(-1, 0, 1, 1)}]}       # a block between two walls, full height of it


def _one_line_error(p, path=None):
    """Exit 2, and exactly one stderr line 'solve.py: error: <file>: ...' without a traceback."""
    assert p.returncode == 2, (p.returncode, p.stdout[-500:], p.stderr[-2000:])
    assert "Traceback" not in p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    line = lines[0]
    assert line.startswith("solve.py: error: "), line
    if path is not None:
        assert str(path) in line, line
    return line


# ------------------------------------------------------------------- running solve.py
def solve_py(capfd, *args):
    """Run scripts/solve.py in this process, as ``python scripts/solve.py ARGS`` would:
    returns (exit status, stdout, stderr). The file itself is executed (runpy), so its
    whole path, from argument parsing to the exit status, is the one a user takes; only
    the interpreter start-up is saved (the imports take about 2 s per process)."""
    import runpy
    argv, path = sys.argv, list(sys.path)
    sys.argv = [str(ROOT / "scripts" / "solve.py"), *map(str, args)]
    capfd.readouterr()
    try:
        runpy.run_path(sys.argv[0], run_name="__main__")
        code = 0
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else 1
    finally:
        sys.argv, sys.path[:] = argv, path
    out, err = capfd.readouterr()
    return subprocess.CompletedProcess(args, code, out, err)


#: cases also run in a fresh process (exit status and stderr of a real process)
FRESH = {"dat:missing_dead_y": [], "json:interpenetrating": [], "unknown_fields": ["--no-plot"],
         "repro_a": ["--seed", "7", "--no-plot"], "repro_b": ["--seed", "7", "--no-plot"]}


@pytest.fixture(scope="module")
def fresh(tmp_path_factory):
    """Run the FRESH cases as separate processes, os.cpu_count() at a time;
    name -> (CompletedProcess, result folder)."""
    root = tmp_path_factory.mktemp("fresh")
    inputs = {}
    for key in FRESH:
        kind, _, name = key.partition(":")
        if kind == "dat":
            inputs[key] = root / f"{name}.dat"
            inputs[key].write_text(DAT_CASES[name][0])
        elif kind == "json":
            inputs[key] = root / f"{name}.json"
            inputs[key].write_text(json.dumps(JSON_CASES[name][0]))
    extra = json_spec(colour="red")
    extra["blocks"][1]["weight"] = 3
    inputs["unknown_fields"] = root / "unknown_fields.json"
    inputs["unknown_fields"].write_text(json.dumps(extra))
    inputs["repro_a"] = inputs["repro_b"] = INSTANCES / "wall33.dat"
    env = dict(os.environ, PYTHONPATH=str(ROOT))

    def run(key):
        folder = root / "out" / key.replace(":", "_")
        argv = [str(inputs[key]), "--out", str(folder), "--starts", "0", *FRESH[key]]
        p = subprocess.run([sys.executable, str(ROOT / "scripts" / "solve.py"), *argv], capture_output=True,
                           text=True, cwd=root, env=env, timeout=600)
        return key, (p, folder)

    with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
        return dict(pool.map(run, FRESH))


# ------------------------------------------------------------------ 1. bad input files
@pytest.mark.parametrize("kind, name", [("dat", k) for k in sorted(DAT_CASES)] + [("json", k) for k in sorted(JSON_CASES)],
                         ids=lambda v: v)
def test_bad_input_file(tmp_path, capfd, kind, name):
    text, fragments = (DAT_CASES if kind == "dat" else JSON_CASES)[name]
    path = tmp_path / f"{name}.{kind}"
    path.write_text(text if isinstance(text, str) else json.dumps(text))
    p = solve_py(capfd, path, "--out", tmp_path / "out", "--starts", "0")
    line = _one_line_error(p, path=path)
    for fragment in fragments:
        assert fragment in line, (fragment, line)
    assert "expected" in line, line
    assert not (tmp_path / "out").exists(), "bad input must not leave a result folder"


@pytest.mark.slow
@pytest.mark.parametrize("key", [k for k in FRESH if ":" in k])
def test_bad_input_in_a_fresh_process(fresh, key):
    p, folder = fresh[key]
    kind, _, name = key.partition(":")
    line = _one_line_error(p, path=f"{name}.{kind}")
    for fragment in (DAT_CASES if kind == "dat" else JSON_CASES)[name][1]:
        assert fragment in line, (fragment, line)
    assert not folder.exists()


def test_unknown_json_fields_warn_and_the_run_proceeds(fresh):
    p, folder = fresh["unknown_fields"]
    assert p.returncode in (0, 3), p.stderr
    assert "Traceback" not in p.stderr and "error" not in p.stderr.lower()
    assert re.search(r"unknown_fields.json: unknown top-level field\(s\) 'colour' ignored", p.stderr), p.stderr
    assert re.search(r"unknown_fields.json: unknown block field\(s\) 'weight' ignored", p.stderr), p.stderr
    assert Results.read(folder).alpha == pytest.approx(0.5, abs=1e-9)


def test_missing_file(tmp_path, capfd):
    p = solve_py(capfd, tmp_path / "nowhere.dat", "--out", tmp_path / "out")
    line = _one_line_error(p, path="nowhere.dat")
    assert "no such file" in line and "expected" in line
    assert not (tmp_path / "out").exists()


def test_unknown_extension(tmp_path, capfd):
    path = tmp_path / "stack.txt"
    path.write_text(BASE_DAT)
    line = _one_line_error(solve_py(capfd, path, "--out", tmp_path / "out"), path=path)
    assert "unknown file type '.txt'" in line and "expected .dat" in line and ".json" in line


def test_upper_case_extension_is_read(tmp_path, capfd):
    path = tmp_path / "STACK.DAT"
    path.write_text(BASE_DAT)
    p = solve_py(capfd, path, "--out", tmp_path / "out", "--starts", "0", "--no-plot", "--quiet")
    assert p.returncode == 0, p.stderr
    assert Results.read(tmp_path / "out").alpha == pytest.approx(0.5, abs=1e-9)


def test_debug_shows_the_traceback(tmp_path, capfd):
    path = tmp_path / "d_negative.dat"
    path.write_text(DAT_CASES["d_negative"][0])
    p = solve_py(capfd, path, "--debug", "--out", tmp_path / "out")
    assert p.returncode == 2
    assert "Traceback (most recent call last)" in p.stderr and "InputError" in p.stderr
    last = p.stderr.strip().splitlines()[-1]
    assert last.startswith("solve.py: error: ") and "d of contact 'c2' is -0.5" in last


@pytest.mark.parametrize("option, value", [("--starts", "-1"), ("--time-limit", "0"), ("--time-limit", "-2"),
                                           ("--workers", "-3"), ("--seed", "1.5")])
def test_bad_option(tmp_path, capfd, option, value):
    p = solve_py(capfd, INSTANCES / "wall33.dat", option, value, "--out", tmp_path / "out")
    line = _one_line_error(p)
    assert option in line and value in line, line
    if option != "--seed":  # argparse's own "invalid int value: '1.5'" for a plain int
        assert "expected" in line, line
    assert not (tmp_path / "out").exists()


def test_option_not_a_number(tmp_path, capfd):
    line = _one_line_error(solve_py(capfd, INSTANCES / "wall33.dat", "--starts", "x", "--out", tmp_path / "out"))
    assert "--starts" in line and "x" in line
    assert "_positive_int" not in line and "expected a whole number" in line


def test_out_is_an_existing_file(tmp_path, capfd):
    path = tmp_path / "stack.dat"
    path.write_text(BASE_DAT)
    taken = tmp_path / "notes.txt"
    taken.write_text("not a folder")
    line = _one_line_error(solve_py(capfd, path, "--out", taken, "--starts", "0", "--no-plot"))
    assert "notes.txt" in line and "expected" in line


# ------------------------------------------------------------ 2. physical edge cases
@pytest.mark.slow
def test_unstable_under_dead_load(tmp_path, capfd):
    path, folder = tmp_path / "overhang.json", tmp_path / "out"
    path.write_text(json.dumps(OVERHANG))
    p = solve_py(capfd, path, "--out", folder, "--starts", "1")
    assert p.returncode == 3, p.stderr
    assert "Traceback" not in p.stderr
    assert "unstable under dead load" in p.stdout
    r = Results.read(folder)
    assert r.summary.status[0] == "unstable" and not r.certified and np.isnan(r.alpha)
    assert "unstable under dead load" in r.summary.message[0]
    assert len(r.blocks) == 2 and r.blocks[["ux", "uy", "theta"]].isna().all().all()
    assert (folder / "mechanism.png").stat().st_size > 0  # a picture of the structure at rest


def test_no_collapse_for_this_live_load(tmp_path, capfd):
    path, folder = tmp_path / "held.json", tmp_path / "out"
    path.write_text(json.dumps(HELD))
    p = solve_py(capfd, path, "--out", folder, "--starts", "0", "--no-plot")
    assert p.returncode == 3, p.stderr
    assert "no collapse for this live load" in p.stdout
    r = Results.read(folder)
    assert r.summary.status[0] == "no_collapse" and not r.certified and np.isnan(r.alpha)
    # no mechanism: the contacts' modes are unknown and their forces empty, never "closed" with numbers
    assert (r.contacts["mode"] == "unknown").all() and r.contacts[["N", "V", "M"]].isna().all().all()


def test_held_block_has_no_mechanism_at_all():
    """The 'no collapse' verdict above is right: no mechanism follows the live load."""
    lps = LimitLPs(structure_from_json(HELD))
    res, _, _ = lps.mechanism(np.ones(4 * lps.nc, dtype=bool), np.zeros(lps.nc))
    assert res.status == "infeasible"


def test_structure_that_needs_the_live_load_to_stand_is_unstable():
    s = structure_from_json(dict(OVERHANG, live_load=[-1.0, 0.0]))  # pushing b2 back over b1
    o = solve(s, SolveOptions(starts=0, pop_size=4, generations=2))
    assert o.status == "unstable" and not o.certified


def test_unbounded_associative_lp_can_still_collapse():
    s = structure_from_json(dict(HELD, live_load=[0.0, 1.0]))  # lift the held block
    lps = LimitLPs(s)
    assert lps.associative().status == "unbounded"
    o = solve(s, SolveOptions(starts=0, pop_size=4, generations=2))
    assert o.certified and o.best.alpha == pytest.approx(1.0, abs=1e-9)


def test_ambiguous_lp_status_of_an_unstable_structure(monkeypatch):
    s = structure_from_json(OVERHANG)
    assert LimitLPs(s).associative().status == "infeasible"
    monkeypatch.setattr(LimitLPs, "associative", lambda self: LPResult(status="unbounded_or_infeasible"))
    o = solve(s, SolveOptions(starts=0, pop_size=4, generations=2))
    assert o.status == "unstable"


# ------------------------------------------------------------ 3. failures during a run
@pytest.fixture(scope="module")
def time_limited(tmp_path_factory):
    out = tmp_path_factory.mktemp("time_limit") / "res"
    t = time.perf_counter()
    p = run_script("solve.py", INSTANCES / "wall55.dat", "--time-limit", "1", "--out", out, "--no-plot")
    return p, out, time.perf_counter() - t


@pytest.mark.slow
def test_time_limit_writes_a_complete_result_folder(time_limited):
    p, out, elapsed = time_limited
    assert p.returncode in (0, 3), p.stderr
    assert "Traceback" not in p.stderr
    r = Results.read(out)  # all four tables, each complete and of the contract's types
    assert sorted(f.name for f in out.iterdir()) == ["blocks.csv", "contacts.csv", "runs.csv", "summary.csv"]
    assert len(r.blocks) == 55 and len(r.contacts) == 141 and len(r.runs) >= 1
    assert r.summary.wall_time_s[0] < 1.0 + 5.0, "the search ran far past its time limit"
    if r.certified:
        assert 0.5574 < r.alpha <= r.alpha_associative + 1e-9
        assert r.runs.alpha_certified.min() == pytest.approx(r.alpha, abs=1e-12)
    assert elapsed < 60


@pytest.mark.slow
def test_time_limit_is_recorded_in_runs(time_limited):
    _, out, _ = time_limited
    r = Results.read(out)
    assert r.runs.status.str.contains("time limit").any(), r.runs.to_string()


def _results(tag):
    """The tables of a small solve, marked by tag in every table so that two writes differ."""
    s = structure_from_json(stack_spec(2))
    o = solve(s, SolveOptions(starts=0, pop_size=4, generations=2))
    r = outcome_results(o)
    r.summary.loc[0, "alpha"] = tag
    r.blocks["ux"] += tag
    r.contacts["N"] -= tag
    r.runs["seconds"] = tag
    return r


def _snapshot(folder):
    return {f.name: f.read_bytes() for f in sorted(Path(folder).iterdir())}


@pytest.mark.parametrize("error", [OSError(28, "No space left on device"), KeyboardInterrupt()])
def test_failed_write_leaves_the_old_result_folder(tmp_path, monkeypatch, error):
    folder = tmp_path / "res"
    _results(0.5).write(folder)
    before = _snapshot(folder)
    real = results_mod._write_table
    calls = []

    def failing(path, df):
        calls.append(path)
        if len(calls) == 3:  # summary and blocks already written to the staging folder
            raise error
        return real(path, df)

    monkeypatch.setattr(results_mod, "_write_table", failing)
    with pytest.raises(type(error)):
        _results(0.25).write(folder)
    assert _snapshot(folder) == before  # the old files, byte for byte, and no temporary file left
    assert os.listdir(tmp_path) == ["res"]  # nor a staging folder
    assert Results.read(folder).alpha == 0.5


def test_failed_rename_leaves_the_old_result_folder(tmp_path, monkeypatch):
    folder = tmp_path / "res"
    _results(0.5).write(folder)
    before = _snapshot(folder)

    def failing(src, dst):
        raise OSError(5, "Input/output error")

    monkeypatch.setattr(files_mod, "_exchange", failing)  # the swap of the whole folder fails
    with pytest.raises(OSError):
        _results(0.25).write(folder)
    assert _snapshot(folder) == before
    assert os.listdir(tmp_path) == ["res"]  # no staging folder left behind


def _die(*args, **kwargs):
    os._exit(1)  # runs in the forked Ipopt worker: the process vanishes


def _raise(*args, **kwargs):
    raise RuntimeError("Ipopt exploded")


@pytest.mark.slow
@pytest.mark.parametrize("task, status", [(_die, "worker died"), (_raise, "failed: RuntimeError: Ipopt exploded")])
def test_failing_ipopt_worker(monkeypatch, wall33, task, status):
    options = dict(seed=0, pop_size=4, generations=2)
    lp_only = solve(wall33, SolveOptions(starts=0, **options))
    monkeypatch.setattr(ipopt_mod, "_ipopt_task", task)
    t = time.perf_counter()
    o = solve(wall33, SolveOptions(starts=1, workers=1, **options))
    assert time.perf_counter() - t < 60
    assert o.status == "certified" and o.certified
    assert o.best.alpha == lp_only.best.alpha  # the certified LP result survives
    assert [r.start for r in o.runs] == [0, 1]
    assert o.runs[1].status == status and np.isnan(o.runs[1].alpha_certified)
    r = outcome_results(o)
    assert r.runs.status[1] == status and r.summary.n_starts[0] == 2 and r.summary.n_certified[0] == 1


def _children(pid):
    try:
        return Path(f"/proc/{pid}/task/{pid}/children").read_text().split()
    except OSError:
        return None


def _sigint_as_a_terminal_sends_it():
    """Child processes start with Ctrl-C at its default: a shell (or CI runner) that started
    pytest as a background job left SIGINT ignored, which the children would inherit."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.fixture(scope="module")
def interrupted(tmp_path_factory):
    """solve.py on wall55 with 2 Ipopt starts, sent SIGINT about a second into the search.

    The search has begun when the worker pool exists (the process has children, Linux);
    elsewhere a fixed 4 s wait stands in for it.
    """
    out = tmp_path_factory.mktemp("ctrl_c") / "res"
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    p = subprocess.Popen([sys.executable, str(ROOT / "scripts" / "solve.py"), str(INSTANCES / "wall55.dat"),
                          "--starts", "2", "--out", str(out), "--no-plot"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                         preexec_fn=_sigint_as_a_terminal_sends_it)
    kids = []
    if _children(p.pid) is None:
        time.sleep(4.0)
    else:
        t = time.perf_counter()
        while p.poll() is None and not kids and time.perf_counter() - t < 60:
            kids = _children(p.pid) or []
            time.sleep(0.05)
        time.sleep(1.0)
    p.send_signal(signal.SIGINT)
    t = time.perf_counter()
    stdout, stderr = p.communicate(timeout=120)
    return p.returncode, stdout, stderr, out, time.perf_counter() - t, kids


@pytest.mark.slow
def test_ctrl_c_writes_complete_results(interrupted):
    code, stdout, stderr, out, latency, kids = interrupted
    assert code in (130, 0), (code, stderr[-2000:])
    assert "Traceback" not in stderr
    assert latency < 30, "Ctrl-C must stop the run promptly"
    r = Results.read(out)  # complete, readable tables
    assert len(r.blocks) == 55 and len(r.contacts) == 141
    assert not [f for f in out.iterdir() if f.name.startswith(".")], "temporary files left behind"
    if code == 130:
        assert r.summary.status[0] == "interrupted"
    if r.certified:  # what was certified so far is a complete collapse state
        assert 0.5574 < r.alpha <= r.alpha_associative + 1e-9
        u = r.mechanism()
        assert np.isfinite(u).all()
        assert (r.blocks.live_x * r.blocks.ux + r.blocks.live_y * r.blocks.uy).sum() == pytest.approx(1.0, abs=1e-9)
        assert f"alpha = {r.alpha:.6f}" in stdout
    time.sleep(0.5)
    assert not [k for k in kids if Path(f"/proc/{k}").exists()], "Ipopt workers outlived the run"


@pytest.mark.slow
def test_ctrl_c_is_recorded_in_runs(interrupted):
    code, _, _, out, _, _ = interrupted
    r = Results.read(out)
    if code == 0:
        pytest.skip("the run finished before the interrupt")
    assert r.runs.status.str.contains("interrupted").any(), r.runs.to_string()
    assert r.summary.n_certified[0] >= int(r.certified)


def _solve_wall33(out, preexec_fn, *python_options):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.Popen([sys.executable, *python_options, str(ROOT / "scripts" / "solve.py"), str(INSTANCES / "wall33.dat"),
                             "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=env, preexec_fn=preexec_fn)


@pytest.mark.slow
@pytest.mark.parametrize("after", [0.0, 0.05, 0.15, 0.3, 0.5])
def test_ctrl_c_during_start_up(tmp_path, after):
    """Ctrl-C while the modules load (the command-line parser imports the search's
    choices, numpy with them) is an interrupt like any other: exit 130, no traceback.

    Timed from the moment lamodel's command line is loaded (``-X importtime`` reports
    it): earlier, the interpreter is still starting up (site, the editable install's
    finder) and what Ctrl-C does there is Python's business, not ours."""
    p = _solve_wall33(tmp_path / "o", _sigint_as_a_terminal_sends_it, "-X", "importtime")
    seen = []
    for line in p.stderr:
        seen.append(line)
        if line.rstrip().endswith("lamodel.cli"):
            break
    else:
        pytest.fail("lamodel.cli was never imported: " + "".join(seen[-5:]))
    time.sleep(after)
    p.send_signal(signal.SIGINT)
    _, stderr = p.communicate(timeout=60)
    stderr = "".join(l for l in stderr.splitlines(keepends=True) if not l.startswith("import time:"))
    assert p.returncode == 130 and "Traceback" not in stderr, (p.returncode, stderr[-500:])
    assert not (tmp_path / "o").exists() or Results.read(tmp_path / "o") is not None  # whole, if written


def test_ctrl_c_inside_an_extension_import(monkeypatch, capsys):
    """numpy's C core turns a KeyboardInterrupt during its own import into an ImportError
    ("PyCapsule_Import could not import module 'datetime'"): still an interrupt, 130."""
    import lamodel.cli as cli

    def parser_whose_import_is_interrupted(*args, **kwargs):
        try:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(5)  # the signal arrives during this
        except KeyboardInterrupt:
            raise ImportError('PyCapsule_Import could not import module "datetime"') from None
        raise AssertionError("SIGINT did not arrive")

    monkeypatch.setattr(cli, "_parser", parser_whose_import_is_interrupted)
    # as in a terminal (a CI runner may start the tests with SIGINT ignored)
    outer = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        assert cli.command("solve", ["instances/wall33.dat"], prog="solve.py") == 130
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # put back
    finally:
        signal.signal(signal.SIGINT, outer)
    err = capsys.readouterr().err
    assert err.strip() == "solve.py: interrupted", err


def test_an_import_error_without_ctrl_c_is_not_an_interrupt(monkeypatch):
    import lamodel.cli as cli

    def broken(*args, **kwargs):
        raise ImportError("no module named nowhere")

    monkeypatch.setattr(cli, "_parser", broken)
    with pytest.raises(ImportError):
        cli.command("solve", ["instances/wall33.dat"], prog="solve.py")


@pytest.mark.slow
def test_ignored_sigint_stays_ignored(tmp_path):
    """A run started with SIGINT ignored (`lamodel solve ... &` from a script) is not
    stopped by it: the search does not put its own Ctrl-C handler over the ignore."""
    def ignore():
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    p = _solve_wall33(tmp_path / "o", ignore)
    time.sleep(0.5)
    for _ in range(10):
        if p.poll() is not None:
            break
        p.send_signal(signal.SIGINT)
        time.sleep(0.2)
    _, stderr = p.communicate(timeout=120)
    assert p.returncode == 0, (p.returncode, stderr[-500:])
    assert Results.read(tmp_path / "o").certified


# ---------------------------------------------------------------- 4. reproducibility
def test_same_seed_same_files(fresh):
    (pa, a), (pb, b) = fresh["repro_a"], fresh["repro_b"]
    assert pa.returncode == 0 and pb.returncode == 0, (pa.stderr, pb.stderr)
    ra, rb = Results.read(a), Results.read(b)
    assert ra.alpha == rb.alpha and ra.certified
    for name in ("blocks.csv", "contacts.csv"):
        assert (a / name).read_bytes() == (b / name).read_bytes(), name

    def without_time(path, column):
        df = pd.read_csv(path, dtype=str, keep_default_na=False)
        return df.drop(columns=[column, "alpha_lower_seconds"], errors="ignore").to_csv(index=False)

    assert without_time(a / "summary.csv", "wall_time_s") == without_time(b / "summary.csv", "wall_time_s")
    assert without_time(a / "runs.csv", "seconds") == without_time(b / "runs.csv", "seconds")
    assert f"alpha = {ra.alpha:.6f}" in pa.stdout and f"alpha = {ra.alpha:.6f}" in pb.stdout


def test_same_seed_same_state_with_ipopt():
    s = structure_from_json(stack_spec(n=3, width=1.0, height=1.0))
    a = solve(s, SolveOptions(seed=4, starts=1, workers=1, pop_size=4, generations=2))
    b = solve(s, SolveOptions(seed=4, starts=1, workers=1, pop_size=4, generations=2))
    ra, rb = outcome_results(a), outcome_results(b)
    assert a.best.alpha == b.best.alpha
    pd.testing.assert_frame_equal(ra.blocks, rb.blocks)
    pd.testing.assert_frame_equal(ra.contacts, rb.contacts)
    pd.testing.assert_frame_equal(ra.runs.drop(columns="seconds"), rb.runs.drop(columns="seconds"))
