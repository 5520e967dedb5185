"""lamodel compare on two bridge runs: their adequacy tables matched by load position,
the governing factor of each, exit 0 (agree), 1 (differ) and 2 (bad input, one line)."""
import pandas as pd
import pytest

from lamodel.bridges import read_bridge
from lamodel.bridges.adequacy import adequacy_study, write_adequacy
from lamodel.bridges.compare import compare_adequacy, read_adequacy
from lamodel.cli import command
from lamodel.search.driver import SolveOptions

BRIDGE = {"name": "b", "span": 5.0, "rise": 1.25, "width": 1.0,
          "ring": {"thickness": 0.3, "voussoirs": 12, "unit_weight": 20.0, "mu": 0.6},
          "fill": {"depth": 0.3, "unit_weight": 18.0, "phi": 35.0, "passive": 0.33},
          "load": {"force": 50.0, "patch": 0.2, "positions": [-1.5, -0.75]}}


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Two runs of one bridge, with and without the passive restraint, and the first again."""
    b = read_bridge(BRIDGE)
    options = SolveOptions(starts=0, progress=False)
    out = {}
    for name, passive in (("with", True), ("again", True), ("without", False)):
        folder = tmp_path_factory.mktemp(name)
        write_adequacy(b, adequacy_study(b, options, passive=passive), folder)
        out[name] = folder
    return out


def compare(capsys, a, b):
    code = command("compare", [str(a), str(b)], prog="lamodel compare")
    return code, capsys.readouterr()


def test_the_same_bridge_run_twice_agrees(runs, capsys):
    code, (out, _) = compare(capsys, runs["with"], runs["again"] / "adequacy.csv")
    assert code == 0 and "A and B agree" in out
    assert "x=-1.5" in out and "governing" in out


def test_without_the_passive_restraint_each_position_carries_less(runs, capsys):
    code, (out, _) = compare(capsys, runs["with"], runs["without"])
    assert code == 1 and "A and B differ" in out
    a = pd.read_csv(runs["with"] / "adequacy.csv")
    b = pd.read_csv(runs["without"] / "adequacy.csv")
    assert (b["adequacy"] <= a["adequacy"] * (1 + 1e-9)).all() and (b["adequacy"] < a["adequacy"]).any()
    table, differ = compare_adequacy(read_adequacy(runs["with"] / "adequacy.csv"),
                                     read_adequacy(runs["without"] / "adequacy.csv"), 1e-5)
    assert differ
    assert table.loc["governing", "A"] == pytest.approx(a["adequacy"].min(), rel=1e-12)
    assert table.loc["governing", "B"] == pytest.approx(b["adequacy"].min(), rel=1e-12)


def test_other_positions_and_bad_tables_are_said(runs, capsys, tmp_path):
    other = pd.read_csv(runs["with"] / "adequacy.csv")
    other["position"] += 0.25
    (tmp_path / "moved").mkdir()
    other.to_csv(tmp_path / "moved" / "adequacy.csv", index=False)
    code, (out, _) = compare(capsys, runs["with"], tmp_path / "moved")
    assert code == 1 and "only in A" in out
    (tmp_path / "bad").mkdir()
    other.drop(columns="adequacy").to_csv(tmp_path / "bad" / "adequacy.csv", index=False)
    code, (_, err) = compare(capsys, runs["with"], tmp_path / "bad")
    assert code == 2 and "no column 'adequacy'" in err and len(err.strip().splitlines()) == 1


def test_the_governing_mechanism_is_drawn_with_the_fill(tmp_path):
    """With the outcomes, the adequacy folder gets mechanism.png: the governing position's
    certified mechanism over the fill, the restraints at their capacity marked."""
    from matplotlib.image import imread

    from lamodel.bridges.adequacy import adequacy_run
    b = read_bridge(BRIDGE)
    table, outcomes = adequacy_run(b, SolveOptions(starts=0, progress=False))
    assert sorted(outcomes) == sorted(table["position"])
    files = write_adequacy(b, table, tmp_path / "a", outcomes)
    assert files[-1] == str(tmp_path / "a" / "mechanism.png")
    picture = imread(files[-1])
    assert picture.shape[0] > 300 and picture.shape[1] > 600
    governing = table.loc[table["governing"], "position"].iloc[0]
    assert outcomes[governing].best.alpha == pytest.approx(table["adequacy"].min(), rel=1e-12)
    # the fill's colour is in the picture (it is drawn), and without outcomes no picture is made
    assert (abs(picture[..., :3] - [0xf3 / 255, 0xe5 / 255, 0xc0 / 255]).max(axis=-1) < 0.02).mean() > 0.02
    assert not any(f.endswith("mechanism.png") for f in write_adequacy(b, table, tmp_path / "b"))


def test_the_report_page_holds_the_result_the_pictures_and_the_description(tmp_path):
    """report.html: one self-contained page — the governing position and factor, the bridge
    as built, the factor against the position (plot and table, the governing row marked),
    the governing mechanism with the fill and in words, the description as written."""
    import json

    from lamodel.bridges.adequacy import adequacy_run
    from lamodel.bridges.report import write_bridge_report
    b = read_bridge(BRIDGE)
    table, outcomes = adequacy_run(b, SolveOptions(starts=0, progress=False))
    text = json.dumps(BRIDGE, indent=1)
    path = write_bridge_report(tmp_path / "report.html", b, table, outcomes, text, "lamodel bridge b.json")
    page = (tmp_path / "report.html").read_text()
    assert path == str(tmp_path / "report.html")
    worst = table.loc[table["governing"], "adequacy"].iloc[0]
    assert f"{worst:.6f}" in page and table["adequacy"].min() == worst
    for heading in ("Result", "The bridge as built", "Adequacy factor against the load position",
                    "Governing mechanism", "Description"):
        assert f"<h2>{heading}</h2>" in page, heading
    assert page.count("<svg") == 3 and 'class="governing"' in page
    assert f"<td>{len(table)} of {len(table)} ({len(table)} certified)</td>" in page
    assert "hinge at the" in page and '&quot;voussoirs&quot;: 12' in page
    assert "http" not in page.split("<svg", 1)[0]  # nothing fetched from elsewhere


def test_a_position_without_a_factor_says_why_on_the_line_and_in_the_report(tmp_path, capsys):
    """An axle patch wider than the bridge (a load the ring carries at any multiple): the
    position has no factor (exit 3), and the command and report.html say why, as solve does."""
    import json
    spec = dict(BRIDGE, load=dict(BRIDGE["load"], patch=100.0))
    (tmp_path / "b.json").write_text(json.dumps(spec))
    code = command("bridge", [str(tmp_path / "b.json"), str(tmp_path / "o.json"), "--adequacy", str(tmp_path / "a"),
                              "--positions=-1.5", "--workers", "1"], prog="lamodel bridge")
    out = capsys.readouterr().out
    assert code == 3 and "x = -1.5: no collapse state certified: the associative LP is unbounded" in out
    assert "x = -1.5: no collapse state certified: the associative LP is unbounded" in (tmp_path / "a" /
                                                                                     "report.html").read_text()
