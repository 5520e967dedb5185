"""The documented columns of a result folder are the columns written, in their order, in
the plane and in space: docs/guide/results.md (the output contract), the 3D table of
docs/guide/cli.md and the writers' docstrings, each parsed and compared with the header of
a folder that a solve wrote."""
import csv
import json
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "geometry3d"))
from test_contacts3d import cube  # noqa: E402

FILES = ("summary.csv", "blocks.csv", "contacts.csv", "runs.csv")


def header(path):
    with open(path, newline="", encoding="utf-8") as fh:
        return next(csv.reader(fh))


def names(text):
    """The names in backticks (one or two), in order."""
    return re.findall(r"``?([^`\s]+?)``?", text)


def results_md(section):
    """results.md: file -> the first cells of the rows of its table in ``section``."""
    text = (ROOT / "docs" / "guide" / "results.md").read_text(encoding="utf-8")
    part = text.split(f"\n## {section}\n", 1)[1].split("\n## ", 1)[0]
    out = {}
    for block in part.split("\n### ")[1:]:
        title, body = block.split("\n", 1)
        cells = [line.split("|")[1] for line in body.splitlines() if line.startswith("| `")]
        out[names(title)[0]] = [n for c in cells for n in names(c)]
    return out


def listed(text):
    """A list written as ``name: `a`, `b` (a remark), `c`. More ...``: the names of its
    first sentence after the colon, remarks in parentheses left out."""
    text = " ".join(text.split())
    return names(re.sub(r"\([^()]*\)", "", re.split(r"\. ", text.split(": ", 1)[1], maxsplit=1)[0]))


def cli_md():
    """cli.md's table of the result folder in space: file -> its columns."""
    text = (ROOT / "docs" / "guide" / "cli.md").read_text(encoding="utf-8")
    table = text.split("The result folder in space", 1)[1].split("\n| file |", 1)[1].split("\n\n", 1)[0]
    rows = [line.split("|") for line in table.splitlines() if line.startswith("| `")]
    return {names(r[1])[0]: listed(r[2]) for r in rows if names(r[1])[0] in FILES}


def docstring(module):
    """A writer's docstring: file -> its columns (its bullets ``* ``file`` ...: columns.``)."""
    text = module.__doc__
    return {names(b)[0]: listed(b) for b in re.split(r"\n\* ", text)[1:] if names(b)[0] in FILES
            and ": ``" in " ".join(b.split())}


@pytest.fixture(scope="module")
def planar(tmp_path_factory):
    import lamodel
    out = tmp_path_factory.mktemp("plane") / "portal"
    lamodel.analyse(ROOT / "instances" / "portal.json", lamodel.SolveOptions(), out, picture=False)
    return {f: header(out / f) for f in FILES}


@pytest.fixture(scope="module")
def spatial(tmp_path_factory):
    import lamodel
    folder = tmp_path_factory.mktemp("space")
    spec = {"name": "block", "mu": 0.6, "live_load": [0.0, 1.0, 0.0],
            "blocks": [{"id": "ground", "support": True, "vertices": cube(-2, -2, -0.5, 4, 4, 0.5)},
                       {"id": "B", "vertices": cube(-0.5, -0.25, 0, 1.0, 0.5, 2.0)}]}
    (folder / "block.json").write_text(json.dumps(spec))
    lamodel.analyse(folder / "block.json", lamodel.SolveOptions(), folder / "r", picture=False)
    return {f: header(folder / "r" / f) for f in FILES}


def test_the_output_contract_lists_the_planar_columns_as_written(planar):
    assert results_md("In the plane") == planar


def test_the_output_contract_lists_the_3d_columns_as_written(spatial):
    assert results_md("In space") == spatial


def test_the_command_line_guide_lists_the_3d_columns_as_written(spatial):
    assert cli_md() == spatial


def test_the_3d_writers_docstrings_list_the_columns_as_written(spatial):
    from lamodel.output import results3d, tables3d
    documented = docstring(results3d) | docstring(tables3d)
    assert documented == spatial
    assert list(results3d.SUMMARY_COLUMNS3D) == spatial["summary.csv"]
    assert list(results3d.RUN_COLUMNS3D) == spatial["runs.csv"]


def test_the_parser_sees_a_column_out_of_place():
    text = "one row: `a`, `c` (a remark on `e`), `b`. Then `d` is said."
    assert listed(text) == ["a", "c", "b"]
