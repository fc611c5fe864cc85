"""`limbfuse.repair_time`: the CLI's `repair-time` from Python. A trial file
whose time does not increase is refused by `read_trial` with the line and
column and a pointer to the repair; the repaired copy holds rows of the clean
file only, in order, the same file the CLI writes."""

import pytest

import limbfuse


def _rows(path):
    """The data rows (after the comment lines and the header)."""
    lines = [ln for ln in open(path).read().splitlines() if not ln.startswith("#")]
    return lines[1:]


def _head(path):
    return [ln for ln in open(path).read().splitlines() if ln.startswith("#")] + [
        next(ln for ln in open(path).read().splitlines() if ln.startswith("t,"))
    ]


@pytest.fixture()
def glitched(walking_file, tmp_path):
    """The walking file with data row 50 written twice, rows 200 and 201 in
    the wrong order and row 400's stamp 0.5 s late."""
    rows = _rows(walking_file)
    t, rest = rows[400].split(",", 1)
    rows[400] = f"{float(t) + 0.5},{rest}"
    rows[200], rows[201] = rows[201], rows[200]
    rows.insert(51, rows[50])
    p = tmp_path / "glitched.csv"
    p.write_text("\n".join(_head(walking_file) + rows) + "\n")
    return p


def test_read_trial_names_the_row_and_the_repair(glitched):
    with pytest.raises(limbfuse.LimbfuseError) as e:
        limbfuse.read_trial(glitched)
    m = str(e.value)
    assert "glitched.csv:" in m and "column 1 (`t`): time must increase strictly" in m
    assert "limbfuse.repair_time" in m


def test_inspect_says_what_the_repair_would_drop(glitched):
    with pytest.raises(limbfuse.LimbfuseError) as e:
        limbfuse.inspect(glitched)
    m = str(e.value)
    assert "`limbfuse.repair_time(path, output)` would drop 3 of its 1001 rows: 1 exact duplicate of" in m, m
    assert "2 time stamps out of order" in m and "time must increase strictly" in m, m


def test_repair_time_keeps_rows_of_the_clean_file_and_matches_the_cli(walking_file, glitched, tmp_path, cli):
    out = tmp_path / "repaired.csv"
    r = limbfuse.repair_time(glitched, out)
    assert (r["rows_read"], r["rows_kept"]) == (1001, 998)
    assert [d["reason"] for d in r["dropped"]] == ["duplicate", "out_of_order", "out_of_order"]
    assert r["dropped"][0]["kept_line"] == r["dropped"][0]["line"] - 1
    assert r["largest_step_back_s"] == pytest.approx(0.49)
    clean = _rows(walking_file)
    it = iter(clean)
    for row in _rows(out):
        assert any(c == row for c in it), row
    trial = limbfuse.read_trial(out)
    assert len(trial) == 998
    assert len(limbfuse.estimate(trial, "mjls")) == 998
    cli("repair-time", glitched, "-o", tmp_path / "cli.csv")
    assert open(out).read() == open(tmp_path / "cli.csv").read()


def test_repair_time_sorts_rows_in_the_wrong_order(walking_file, tmp_path):
    rows = _rows(walking_file)
    rows[200], rows[201] = rows[201], rows[200]
    p = tmp_path / "swapped.csv"
    p.write_text("\n".join(_head(walking_file) + rows) + "\n")
    r = limbfuse.repair_time(p, tmp_path / "sorted.csv", out_of_order="sort")
    assert (r["rows_kept"], r["moved"], r["dropped"]) == (1000, 1, [])
    assert _rows(tmp_path / "sorted.csv") == _rows(walking_file)


@pytest.mark.parametrize(
    "kwargs, needle",
    [
        ({"out_of_order": "shuffle"}, 'out_of_order: expected "drop" or "sort", found "shuffle"'),
        ({"output": "x.arrow"}, "writes a CSV trial file"),
        ({"output": "same"}, "is the input"),
    ],
)
def test_repair_time_refuses_bad_options(walking_file, tmp_path, kwargs, needle):
    output = tmp_path / kwargs.pop("output", "o.csv")
    if output.name == "same":
        output = walking_file
    with pytest.raises(limbfuse.LimbfuseError, match=needle.replace("(", r"\(")):
        limbfuse.repair_time(walking_file, output, **kwargs)


def test_repair_time_names_a_missing_file(tmp_path):
    with pytest.raises(limbfuse.LimbfuseError, match="nope.csv"):
        limbfuse.repair_time(tmp_path / "nope.csv", tmp_path / "o.csv")
    with pytest.raises(TypeError, match="out_of_order"):
        limbfuse.repair_time(tmp_path / "nope.csv", tmp_path / "o.csv", out_of_order=1)
