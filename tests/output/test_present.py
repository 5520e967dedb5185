"""The library's analyse() is what `lamodel solve` does: the same result folder, the same words."""
import os
import subprocess
import sys

import pandas as pd
import pytest

from conftest import INSTANCES, ROOT

pytestmark = pytest.mark.slow  # a solve in this process and one in a command-line process


def test_analyse_writes_the_folder_lamodel_solve_writes(tmp_path):
    import lamodel
    options = ["--seed", "3", "--starts", "0", "--generations", "2"]
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    cli = subprocess.run([sys.executable, "-m", "lamodel.cli", "solve", str(INSTANCES / "wall33.dat"), "--out",
                          str(tmp_path / "cli"), *options], capture_output=True, text=True, env=env, cwd=ROOT)
    assert cli.returncode == 0, cli.stderr
    a = lamodel.analyse(INSTANCES / "wall33.dat", lamodel.SolveOptions(seed=3, starts=0, generations=2),
                        out=tmp_path / "lib")
    assert a.certified and a.folder == tmp_path / "lib"
    assert sorted(os.listdir(tmp_path / "cli")) == sorted(os.listdir(tmp_path / "lib"))
    for table in ("blocks.csv", "contacts.csv"):
        pd.testing.assert_frame_equal(pd.read_csv(tmp_path / "cli" / table), pd.read_csv(tmp_path / "lib" / table))
    timing = ["wall_time_s"]
    pd.testing.assert_frame_equal(pd.read_csv(tmp_path / "cli" / "summary.csv").drop(columns=timing),
                                  pd.read_csv(tmp_path / "lib" / "summary.csv").drop(columns=timing))
    # the words and the tables the command prints, but for the seconds and the folder's name
    text = a.text()
    for line in a.words:
        assert line in cli.stdout
    assert a.line().split(" in ")[0] == cli.stdout.strip().splitlines()[-1].split(" in ")[0]
    assert text.splitlines()[0] == cli.stdout.splitlines()[0]
