"""Results: the four CSV tables of a result folder, their round trip, errors and atomicity."""
import os

import numpy as np
import pandas as pd
import pytest

import lamodel.output.folder as files_mod
from lamodel.errors import InputError
from lamodel.output.results import (BLOCK_COLUMNS, CONTACT_COLUMNS, MODES, RUN_COLUMNS, SUMMARY_COLUMNS,
                             Results)


def two_blocks(**summary_changes) -> Results:
    """Two blocks on the ground, one over the other side by side; awkward floats on purpose."""
    summary = dict(instance="pair", alpha=0.1 + 0.2, certified=True, alpha_associative=2.0 / 3.0,
                   n_blocks=2, n_contacts=3, n_starts=2, n_certified=1, wall_time_s=1.25e-3,
                   seed=7, status="ok")
    summary.update(summary_changes)
    blocks = pd.DataFrame(dict(
        block=["b1", "b2"], x=[1.0, 3.0], y=[0.875, 0.875], dead_x=[0.0, 0.0], dead_y=[-1.0, -1.0],
        live_x=[1.0, 1.0], live_y=[0.0, 0.0], ux=[0.5, 1.0 / 3.0], uy=[-0.0, 1e-300],
        theta=[np.pi, -np.e / 7.0]))
    contacts = pd.DataFrame(dict(
        contact=["c1", "c2", "c3"], block_a=["ground", "ground", "b1"], block_b=["b1", "b2", "b2"],
        cx=[1.0, 3.0, 2.0], cy=[0.0, 0.0, 0.875], nx=[0.0, 0.0, 1.0], ny=[1.0, 1.0, 0.0],
        d=[1.0, 1.0, 0.875], mu=[0.65, 0.65, 0.65], N=[-1.0 / 3.0, -1.7, 0.0],
        V=[0.1, -0.2, 0.0], M=[1.0 / 3.0, 0.0, -0.0], mode=["hinging", "closed", "open"]))
    runs = pd.DataFrame(dict(
        start=[0, 1], source=["lp", "random"], alpha_ipopt=[0.1 + 0.2, np.nan], status=["optimal", 'failed: ValueError: "x", y\nsecond line'],
        alpha_certified=[0.1 + 0.2, np.nan], iterations=[17, None], seconds=[0.01, 0.02]))
    return Results.from_frames(summary, blocks, contacts, runs)


def assert_bit_identical(r1: Results, r2: Results):
    for table in ("summary", "blocks", "contacts", "runs"):
        a, b = getattr(r1, table), getattr(r2, table)
        pd.testing.assert_frame_equal(a, b, check_exact=True)
        for c in a.columns:
            if a[c].dtype == np.float64:
                assert np.array_equal(a[c].to_numpy().view(np.int64), b[c].to_numpy().view(np.int64)) or (
                    np.array_equal(np.isnan(a[c]), np.isnan(b[c]))
                    and np.array_equal(a[c][~np.isnan(a[c])].to_numpy().view(np.int64),
                                       b[c][~np.isnan(b[c])].to_numpy().view(np.int64))), (table, c)


# ------------------------------------------------------------------------------ round trip
def test_round_trip_is_bit_identical(tmp_path):
    r = two_blocks()
    folder = r.write(tmp_path / "res")
    assert sorted(os.listdir(folder)) == ["blocks.csv", "contacts.csv", "runs.csv", "summary.csv"]
    back = Results.read(folder)
    assert_bit_identical(r, back)
    # the path of summary.csv names the same folder
    assert_bit_identical(r, Results.read(os.path.join(folder, "summary.csv")))
    # -0.0 keeps its sign, 1e-300 its value
    assert np.signbit(back.blocks["uy"].iloc[0]) and back.blocks["uy"].iloc[1] == 1e-300
    # writing again what was read gives the same bytes
    again = back.write(tmp_path / "again")
    for name in os.listdir(folder):
        with open(os.path.join(folder, name), "rb") as f1, open(os.path.join(again, name), "rb") as f2:
            assert f1.read() == f2.read(), name


def test_contract_columns_come_first_in_order(tmp_path):
    r = two_blocks()
    folder = r.write(tmp_path)
    for name, cols in (("summary.csv", SUMMARY_COLUMNS), ("blocks.csv", BLOCK_COLUMNS),
                       ("contacts.csv", CONTACT_COLUMNS), ("runs.csv", RUN_COLUMNS)):
        with open(os.path.join(folder, name)) as fh:
            header = fh.readline().strip().split(",")
        assert header[:len(cols)] == list(cols), name
    with open(os.path.join(folder, "summary.csv")) as fh:
        assert fh.readline().strip().endswith("wall_time_s,seed,status")
        assert fh.readline().startswith("pair,0.30000000000000004,True,")


def test_from_frames_orders_columns_and_types():
    r = two_blocks()
    shuffled = Results.from_frames(r.summary.iloc[0].to_dict(), r.blocks[r.blocks.columns[::-1]],
                                   r.contacts[r.contacts.columns[::-1]], r.runs)
    assert_bit_identical(r, shuffled)
    assert r.summary["certified"].dtype == bool
    assert r.summary["n_blocks"].dtype == np.int64
    assert r.runs["start"].tolist() == [0, 1] and r.runs["start"].dtype == np.int64
    assert r.runs["iterations"].isna().tolist() == [False, True]


def test_from_frames_missing_column():
    r = two_blocks()
    with pytest.raises(InputError, match="contacts table: column 'mode' is missing"):
        Results.from_frames(r.summary.iloc[0].to_dict(), r.blocks, r.contacts.drop(columns="mode"), r.runs)


def test_accessors():
    r = two_blocks()
    assert r.instance == "pair"
    assert r.alpha == 0.1 + 0.2
    assert r.certified is True
    assert r.alpha_associative == 2.0 / 3.0
    u = r.mechanism()
    assert u.shape == (2, 3) and u[0, 2] == np.pi
    assert r.modes() == ["hinging", "closed", "open"]
    counts = r.mode_counts()
    # every mode listed, but "unknown" (no certified state) and the crushing modes (joints
    # with strengths) only when a contact is
    rare = ("unknown", "crushing", "crushing+sliding")
    assert list(counts.index) == [m for m in MODES if m not in rare] and counts["open"] == 1
    assert counts["sliding"] == 0


def test_text_has_summary_runs_and_modes():
    text = str(two_blocks())
    assert "alpha" in text and "certified" in text and "0.3" in text
    assert "random" in text and "failed" in text
    assert "hinging" in text and "Contact modes (3 contacts)" in text


def test_text_aligns_numbers_right_and_words_left_so_a_long_message_widens_only_its_line():
    message = "no collapse state certified " + "x" * 150
    lines = str(two_blocks(message=message, status="not_certified")).splitlines()
    summary = lines[2:lines.index("Solver starts (2):") - 1]
    assert [line.split()[0] for line in summary if len(line) > 40] == ["message"]
    assert " ".join(next(line for line in summary if line.startswith("message")).split()[1:]) == message
    assert len({line.index(line.split()[1]) for line in summary if len(line.split()) == 2}) == 1  # one column
    runs = lines[lines.index("Solver starts (2):") + 1:][:3]
    status = runs[0].index("status")
    # the words start under their name, the numbers end under theirs; a line break in a status stays on its row
    assert runs[1][status:].startswith("optimal ") and runs[2][status:].startswith('failed: ValueError: "x", y second')
    end = runs[0].index("alpha_ipopt") + len("alpha_ipopt")
    assert runs[1][:end].endswith(" 0.3") and runs[2][:end].endswith(" NaN")


# ------------------------------------------------------------------------------ errors
@pytest.fixture
def folder(tmp_path):
    return two_blocks().write(tmp_path / "res")


def rewrite(path, edit):
    with open(path) as fh:
        text = fh.read()
    with open(path, "w") as fh:
        fh.write(edit(text))


def test_missing_file(folder):
    os.remove(os.path.join(folder, "runs.csv"))
    with pytest.raises(InputError, match=r"runs\.csv: no such file") as exc:
        Results.read(folder)
    assert "\n" not in str(exc.value)


def test_missing_folder(tmp_path):
    with pytest.raises(InputError, match="no such folder or file"):
        Results.read(tmp_path / "nowhere")


def test_missing_column(folder):
    rewrite(os.path.join(folder, "contacts.csv"), lambda t: t.replace(",mu,", ",friction,", 1))
    with pytest.raises(InputError, match=r"contacts\.csv: column 'mu' is missing; expected columns contact"):
        Results.read(folder)


def test_non_numeric_alpha(folder):
    rewrite(os.path.join(folder, "summary.csv"), lambda t: t.replace("0.30000000000000004", "zero.three"))
    with pytest.raises(InputError, match=r"summary\.csv: column 'alpha', row 1, is 'zero.three'; expected a number"):
        Results.read(folder)


def test_bad_value_names_the_row(folder):
    rewrite(os.path.join(folder, "contacts.csv"), lambda t: t.replace(",closed", ",wobbling"))
    with pytest.raises(InputError, match=r"contacts\.csv: column 'mode', row 2 \(contact 'c2'\), is 'wobbling'"):
        Results.read(folder)
    rewrite(os.path.join(folder, "contacts.csv"), lambda t: t.replace(",wobbling", ",closed"))
    rewrite(os.path.join(folder, "summary.csv"), lambda t: t.replace(",True,", ",maybe,"))
    with pytest.raises(InputError, match="column 'certified', row 1, is 'maybe'; expected True or False"):
        Results.read(folder)


def test_empty_summary(folder):
    rewrite(os.path.join(folder, "summary.csv"), lambda t: t.splitlines()[0] + "\n")
    with pytest.raises(InputError, match=r"summary\.csv: has 0 data rows; expected exactly one row"):
        Results.read(folder)
    rewrite(os.path.join(folder, "summary.csv"), lambda t: "")
    with pytest.raises(InputError, match=r"summary\.csv: the file is empty"):
        Results.read(folder)


def test_duplicate_contact(folder):
    rewrite(os.path.join(folder, "contacts.csv"), lambda t: t.replace("c3,", "c1,"))
    with pytest.raises(InputError, match="contact 'c1' appears twice"):
        Results.read(folder)


def test_garbage_file(folder):
    with open(os.path.join(folder, "blocks.csv"), "wb") as fh:
        fh.write(b"\xff\xfe\x00garbage\n1,2,3,4\n")
    with pytest.raises(InputError, match=r"blocks\.csv: "):
        Results.read(folder)


# ------------------------------------------------------------------------------ atomicity
def test_write_is_atomic_when_rename_fails(tmp_path, monkeypatch):
    old = two_blocks()
    folder = old.write(tmp_path / "res")
    before = {n: open(os.path.join(folder, n), "rb").read() for n in os.listdir(folder)}

    def broken_swap(src, dst):
        raise OSError(5, "disk full")

    monkeypatch.setattr(files_mod, "_exchange", broken_swap)  # the folder is swapped in as a whole
    with pytest.raises(OSError, match="disk full"):
        two_blocks(alpha=0.9).write(folder)
    after = {n: open(os.path.join(folder, n), "rb").read() for n in os.listdir(folder)}
    assert after == before  # same files, same bytes
    assert os.listdir(tmp_path) == ["res"]  # no staging folder left behind
    monkeypatch.undo()
    assert Results.read(folder).alpha == old.alpha


def test_write_is_atomic_when_writing_fails_midway(tmp_path, monkeypatch):
    folder = two_blocks().write(tmp_path / "res")
    before = {n: open(os.path.join(folder, n), "rb").read() for n in os.listdir(folder)}
    real_to_csv = pd.DataFrame.to_csv
    calls = []

    def to_csv_that_dies(self, fh, *args, **kwargs):
        calls.append(1)
        if len(calls) == 3:  # summary and blocks done, contacts half written
            fh.write("contact,block_a,blo")
            raise RuntimeError("killed while writing")
        return real_to_csv(self, fh, *args, **kwargs)

    monkeypatch.setattr(pd.DataFrame, "to_csv", to_csv_that_dies)
    with pytest.raises(RuntimeError, match="killed"):
        two_blocks(alpha=0.9).write(folder)
    after = {n: open(os.path.join(folder, n), "rb").read() for n in os.listdir(folder)}
    assert after == before


def test_write_creates_folder_and_overwrites(tmp_path):
    folder = tmp_path / "a" / "b"
    two_blocks().write(folder)
    two_blocks(alpha=0.5, certified=False).write(folder)
    back = Results.read(folder)
    assert back.alpha == 0.5 and back.certified is False
    assert sorted(os.listdir(folder)) == ["blocks.csv", "contacts.csv", "runs.csv", "summary.csv"]
