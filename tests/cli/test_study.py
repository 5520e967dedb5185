"""lamodel study: a spec to a table and a plot; the same table for any number of workers
and on a Dask cluster; bad input in one line; lamodel solve --scheduler."""
import json
import os
import re
import socket
import subprocess
import sys

import pandas as pd
import pytest

from conftest import INSTANCES, ROOT

pytestmark = pytest.mark.slow  # every test starts processes or a cluster

#: columns that are the science of a variant (not where or how long it ran)
SCIENCE = ["mu", "alpha", "certified", "alpha_associative", "n_sliding", "n_hinging", "n_open", "status", "ga_seed"]


def lamodel(*args, timeout=600):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "lamodel.cli", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, cwd=ROOT, env=env)


def spec_file(tmp_path, **spec):
    path = tmp_path / "spec.json"
    path.write_text(json.dumps({"structure": str(INSTANCES / "wall33.json"), "options": {"starts": 0}, **spec}))
    return path


def test_a_small_study_is_the_same_serial_local_and_on_dask(tmp_path, dask_cluster):
    spec = spec_file(tmp_path, name="w33", seed=2, vary={"mu": [0.4, 0.9]})
    tables = {}
    for where, args in {"serial": ("--workers", 1), "local": ("--workers", 2),
                        "dask": ("--scheduler", dask_cluster.scheduler_address)}.items():
        out = tmp_path / where
        res = lamodel("study", spec, "--out", out, *args)
        assert res.returncode == 0, res.stdout + res.stderr
        assert "study w33: 2 of 2 variants certified; least alpha 0.400000" in res.stdout
        tables[where] = pd.read_csv(out / "study.csv")
        assert (out / "study.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert not [p for p in out.iterdir() if p.name.endswith(".tmp")]
    serial = tables["serial"]
    assert serial["mu"].tolist() == [0.4, 0.9]
    assert serial["alpha"].tolist() == pytest.approx([0.4, 0.617364], abs=1e-6)
    assert (serial["attempts"] == 1).all()
    for where in ("local", "dask"):
        pd.testing.assert_frame_equal(tables[where][SCIENCE], serial[SCIENCE])
    assert tables["dask"]["worker"].str.startswith("tcp://127.0.0.1:").all()
    assert tables["local"]["worker"].str.startswith("local pid ").all()


def test_random_perturbations_give_a_distribution(tmp_path):
    spec = spec_file(tmp_path, name="w33mc", random={"count": 3, "seed": 4, "mu": {"sd": 0.05, "per": "structure"},
                                                     "size": {"sd": 0.02}})
    res = lamodel("study", spec, "--out", tmp_path / "mc", "--workers", 2, "--quiet")
    assert res.returncode == 0, res.stdout + res.stderr
    df = pd.read_csv(tmp_path / "mc" / "study.csv")
    assert df["sample"].tolist() == [0, 1, 2]
    assert df["certified"].all() and df["ga_seed"].nunique() == 3
    assert df["mu_mean"].nunique() == 3  # one mu for the whole structure per variant:
    assert df["mu_mean"].to_numpy() == pytest.approx(df["mu_min"].to_numpy(), abs=1e-12)
    assert (df["size_min"] < 1).all() and (df["size_max"] > 1).all()
    # the study's variants are reproducible: the first one again, alone in this process
    from lamodel.parametric import read_study, solve_variant
    from lamodel.search.executor import task_seeds
    study = read_study(spec)
    first = solve_variant(study, study.variants()[0], task_seeds(4, 3)[0])
    assert first["alpha"] == df.loc[0, "alpha"] and first["mu_mean"] == df.loc[0, "mu_mean"]
    assert (tmp_path / "mc" / "study.png").exists()


def test_the_friction_study_ships_as_a_spec():
    from lamodel.parametric import read_study
    study = read_study(ROOT / "examples" / "friction_study.json")
    assert [v["mu"] for v in study.variants()] == [0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]
    assert study.structure.n_blocks == 33 and study.options == {"starts": 0}


def _closed_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.parametrize("spec, args, text", [
    ({}, ("--scheduler", f"tcp://127.0.0.1:{_closed_port()}"), "cannot connect"),
    ({}, ("--scheduler", "somewhere"), "expected an address tcp://HOST:PORT"),
    ({}, ("--workers", 2, "--scheduler", "tcp://127.0.0.1:1"), "not allowed with argument"),
    ({"vary": {"friction": [0.5]}}, (), "unknown key 'friction'"),
    ({"vary": {"mu": {"from": 0.3, "to": 0.9}}}, (), "expected a range"),
    ({"vary": {"dead_force": {"block": "nope", "fx": 1}}}, (), "'nope' is not a movable block"),
    ({"random": {"count": 0, "mu": {"sd": 0.1}}}, (), "random.count is 0"),
    ({"options": {"starts": -1}}, (), "option starts is -1"),
])
def test_bad_study_input_is_one_line_exit_2(tmp_path, spec, args, text):
    res = lamodel("study", spec_file(tmp_path, **spec), "--out", tmp_path / "out", *args, timeout=60)
    lines = res.stderr.strip().splitlines()
    assert res.returncode == 2 and len(lines) == 1, res.stderr
    assert lines[0].startswith("lamodel study: error: ") and text in lines[0], lines[0]
    assert not (tmp_path / "out").exists()


def test_solve_on_a_dask_scheduler_gives_the_local_alpha(tmp_path, dask_cluster):
    """The GA's evaluations and the Ipopt starts of lamodel solve on the cluster: the tables
    are those of local workers (pure evaluations: the same LPs too)."""
    common = ("--starts", 1, "--no-plot", "--quiet")
    local = lamodel("solve", INSTANCES / "wall33.json", "--out", tmp_path / "local", *common, "--workers", 2)
    remote = lamodel("solve", INSTANCES / "wall33.json", "--out", tmp_path / "dask", *common,
                     "--scheduler", dask_cluster.scheduler_address)
    assert local.returncode == 0 and remote.returncode == 0, local.stderr + remote.stderr
    a, b = (pd.read_csv(tmp_path / w / "runs.csv") for w in ("local", "dask"))
    # the Ipopt start ran, on the cluster (its status is Ipopt's word; its point is certified)
    assert b.loc[1, "source"].startswith("ipopt from") and b.loc[1, "iterations"] > 0, b.to_string()
    pd.testing.assert_frame_equal(a.drop(columns="seconds"), b.drop(columns="seconds"))
    sa, sb = (pd.read_csv(tmp_path / w / "summary.csv") for w in ("local", "dask"))
    assert sa.loc[0, "alpha"] == sb.loc[0, "alpha"] == pytest.approx(0.638982, abs=1e-6)


def test_a_structure_of_load_cases_is_refused_by_a_study_and_by_solve(tmp_path):
    """A study (and the library's solve) takes one live load: a file of load cases or a
    rolling load is refused in one line naming the way to solve it, not solved as if it had
    no live load."""
    from lamodel import SolveOptions, read, solve
    from lamodel.errors import InputError
    cases = {"name": "cases", "mu": 0.6,
             "blocks": [{"id": "ground", "vertices": [[-2, -1], [2, -1], [2, 0], [-2, 0]], "support": True},
                        {"id": "b1", "vertices": [[-0.5, 0], [0.5, 0], [0.5, 1], [-0.5, 1]]}],
             "loads": [{"block": "b1", "at": [0, 1], "force": [1, 0], "case": "top"},
                       {"block": "b1", "at": [0, 0.5], "force": [1, 0], "case": "mid"}]}
    rolling = {**{k: v for k, v in cases.items() if k != "loads"}, "rolling_load": {"force": [0, -1]}}
    for spec, words in ((cases, "has load cases (top, mid)"), (rolling, "has a rolling load")):
        path = tmp_path / "s.json"
        path.write_text(json.dumps(spec))
        study = tmp_path / "study.json"
        study.write_text(json.dumps({"structure": str(path), "vary": {"mu": [0.3, 0.6]}}))
        res = lamodel("study", study, "--out", tmp_path / "out", timeout=60)
        lines = res.stderr.strip().splitlines()
        assert res.returncode == 2 and len(lines) == 1 and words in lines[0], res.stderr
        assert not (tmp_path / "out").exists()
        with pytest.raises(InputError, match=re.escape(words)):
            solve(read(path), SolveOptions(starts=0))


def test_a_compressive_strength_below_the_tensile_one_is_bad_input_not_a_worker_failure(tmp_path):
    structure = tmp_path / "s.json"
    structure.write_text(json.dumps({"name": "s", "mu": 0.6, "ft": 2.0, "fc": 20.0, "blocks": [
        {"id": "ground", "vertices": [[-2, -1], [2, -1], [2, 0], [-2, 0]], "support": True},
        {"id": "b1", "vertices": [[-0.5, 0], [0.5, 0], [0.5, 1], [-0.5, 1]]}]}))
    study = tmp_path / "study.json"
    study.write_text(json.dumps({"structure": str(structure), "vary": {"fc": [5, 1]}}))
    res = lamodel("study", study, "--out", tmp_path / "out", timeout=60)
    lines = res.stderr.strip().splitlines()
    assert res.returncode == 2 and len(lines) == 1 and "vary.fc has 1, below the tensile strength 2" in lines[0]
    assert not (tmp_path / "out").exists()
