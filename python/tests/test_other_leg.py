"""Issue 17 (equivalence): a `Trial` holds every column the CLI's trial
reader reads: the other leg's IMUs (`S_<other leg>_acc_A`, named after the
trial's `leg` metadata), `contact_left_ref` / `contact_right_ref`,
`speed_ref`, and IMU vectors with a missing axis cell (the present axes
kept, issue 18 item 2). Python `estimate` / `evaluate` then equal the CLI's
on a two-foot walk."""

import json
from pathlib import Path

import numpy as np
import pytest

import limbfuse
from limbfuse import LimbfuseError, Trial

REPO = Path(__file__).resolve().parents[2]
SHARED = REPO.parent / "shared" / "data"
WALK = SHARED / "gaitmap-foot-walk" / "trial.csv"


@pytest.fixture(scope="module")
def two_foot_walk():
    """The shared two-foot walk (right foot, left foot, contacts, speed)."""
    if not WALK.is_file():
        pytest.skip(f"the shared recording {WALK} is absent (../shared/data next to the repository)")
    return WALK


def bits(a):
    return np.ascontiguousarray(np.ma.filled(a, np.nan), dtype=np.float64).view(np.uint64)


def without_command(data: bytes) -> bytes:
    """An estimate file's bytes without `# command:` (how the CLI was run)."""
    return b"".join(l for l in data.splitlines(keepends=True) if not l.startswith(b"# command:"))


def same_estimate_file(cli, tmp_path, trial_file, method):
    """The CLI's estimate file of `method` on `trial_file` and the package's,
    byte for byte (without `# command:`); returns the package's estimate."""
    out = tmp_path / f"{method}-cli.csv"
    cli("estimate", "--method", method, trial_file, "-o", out)
    est = limbfuse.estimate(limbfuse.read_trial(trial_file), method)
    mine = tmp_path / f"{method}-py.csv"
    est.write(mine)
    assert without_command(mine.read_bytes()) == without_command(out.read_bytes())
    return est


def test_issue_17_read_trial_keeps_other_leg_contacts_and_speed(two_foot_walk, tmp_path):
    tr = limbfuse.read_trial(two_foot_walk)
    for name in ("foot_left_acc_x", "foot_left_gyr_z", "contact_left_ref", "contact_right_ref", "speed_ref"):
        assert name in tr.channels, name
    for side in ("left", "right"):
        c = np.ma.compressed(tr.channels[f"contact_{side}_ref"])
        assert set(np.unique(c)) == {0.0, 1.0}, side
    assert np.ma.count(tr.channels["speed_ref"]) > 0
    # File, DataFrame and arrays round-trip every column bit for bit.
    p = tmp_path / "back.csv"
    tr.write(p)
    back = limbfuse.read_trial(p)
    df_back = Trial.from_pandas(tr.to_pandas())
    for other in (back, df_back):
        assert list(other.channels) == list(tr.channels)
        for name, a in tr.channels.items():
            assert np.array_equal(bits(other.channels[name]), bits(a)), name
    p2 = tmp_path / "back2.csv"
    back.write(p2)
    assert p2.read_bytes() == p.read_bytes()


def test_issue_17_gait_events_on_two_foot_walk_equal_the_cli_file(cli, two_foot_walk, tmp_path):
    est = same_estimate_file(cli, tmp_path, two_foot_walk, "gait-events")
    # Both feet: the left foot's contacts come from the other leg's IMU.
    for side in ("left", "right"):
        assert np.ma.count(est.channels[f"contact_{side}"]) > 0, side


def test_issue_17_evaluate_reports_the_cli_contact_and_speed_metrics(cli, two_foot_walk, tmp_path):
    out = tmp_path / "ge.csv"
    cli("estimate", "--method", "gait-events", two_foot_walk, "-o", out)
    want = json.loads(cli("evaluate", "--json", two_foot_walk, out).stdout)
    got = limbfuse.evaluate(limbfuse.read_trial(two_foot_walk), limbfuse.read_estimate(out))
    assert got == want
    text = json.dumps(got)
    assert "contact" in text and "speed" in text


def blank_cell(src: Path, dst: Path, column: str, rows) -> None:
    """Copies a trial file with the cells of `column` on data `rows` emptied."""
    lines = src.read_text().splitlines(keepends=True)
    header = next(i for i, l in enumerate(lines) if not l.startswith("#"))
    k = lines[header].rstrip("\n").split(",").index(column)
    for r in rows:
        cells = lines[header + 1 + r].rstrip("\n").split(",")
        cells[k] = ""
        lines[header + 1 + r] = ",".join(cells) + "\n"
    dst.write_text("".join(lines))


def test_issue_17_missing_gyro_axis_cell_gives_the_cli_estimate(cli, tmp_path):
    # A simulated walk with thigh_gyr_x empty on some rows: the sagittal
    # rate (z) of those samples is still there (mjls's chain reads it).
    walk = tmp_path / "walk.csv"
    cli("simulate", "walking", "--duration", "6", "--seed", "5", "-o", walk)
    holed = tmp_path / "walk-holed.csv"
    blank_cell(walk, holed, "thigh_gyr_x", range(100, 400, 3))
    same_estimate_file(cli, tmp_path, holed, "mjls")
    tr = limbfuse.read_trial(holed)
    gx, gz = tr.channels["thigh_gyr_x"], tr.channels["thigh_gyr_z"]
    assert np.ma.count_masked(gx) == 100 and np.ma.count_masked(gz) == 0


def test_issue_17_missing_foot_gyro_axis_cell_gait_events_equal_the_cli(cli, two_foot_walk, tmp_path):
    holed = tmp_path / "walk-holed.csv"
    blank_cell(two_foot_walk, holed, "foot_left_gyr_y", range(2000, 2600, 7))
    same_estimate_file(cli, tmp_path, holed, "gait-events")


def test_issue_17_bad_contact_value_names_the_column_and_sample():
    t = np.arange(4) * 0.01
    ok = Trial(t, {"contact_right_ref": np.ma.MaskedArray([0.0, 1.0, 1.0, 0.0], mask=[1, 0, 0, 0])})
    assert np.ma.count_masked(ok.channels["contact_right_ref"]) == 1
    with pytest.raises(LimbfuseError, match=r"channel `contact_left_ref`, sample 2: expected a foot contact"):
        Trial(t, {"contact_left_ref": [0.0, 1.0, 0.5, 1.0]})


def test_issue_17_other_leg_columns_follow_the_leg_metadata(tmp_path):
    t = np.arange(5) * 0.01
    gyr = {f"foot_right_gyr_{a}": np.full(5, 0.1 * k) for k, a in enumerate("xyz")}
    # A left-leg trial's other leg is the right one.
    tr = Trial(t, {**gyr, "speed_ref": np.full(5, 1.2)}, {"leg": "left"})
    p = tmp_path / "left.csv"
    tr.write(p)
    back = limbfuse.read_trial(p)
    assert back.meta["leg"] == "left"
    for name in gyr:
        assert np.array_equal(back.channels[name], gyr[name]), name
    # Of a right-leg trial (the default) `foot_right_*` is no column.
    with pytest.raises(LimbfuseError, match="unknown channel `foot_right_gyr_x`.*foot_left_gyr_x"):
        Trial(t, gyr)
    with pytest.raises(LimbfuseError, match="incomplete channel group: channel `foot_left_acc_z`"):
        Trial(t, {"foot_left_acc_x": np.zeros(5), "foot_left_acc_y": np.zeros(5)})


def test_issue_17_left_leg_trial_and_filter_equal_the_cli(cli, two_foot_walk, tmp_path):
    # The walk as a left-leg trial: the single-leg columns are the left
    # foot, the other leg's the right foot (`foot_right_...`).
    tr = limbfuse.read_trial(two_foot_walk)
    ch = {}
    for name, a in tr.channels.items():
        if name.startswith("foot_left_"):
            ch["foot_" + name[len("foot_left_"):]] = a
        elif name.startswith("foot_"):
            ch["foot_right_" + name[len("foot_"):]] = a
        else:
            ch[name] = a
    left = Trial(tr.t, ch, {**tr.meta, "leg": "left"})
    p = tmp_path / "left.csv"
    left.write(p)
    est = same_estimate_file(cli, tmp_path, p, "gait-events")
    for side in ("left", "right"):
        assert np.ma.count(est.channels[f"contact_{side}"]) > 0, side
    # Filter.run and Filter.step read the same channels (the filter's `leg`).
    f = limbfuse.Filter.for_trial(left, "gait-events")
    run = f.run({"t": left.t, **left.channels})
    assert list(run.channels) == list(est.channels)
    for name in est.channels:
        assert np.array_equal(bits(run.channels[name]), bits(est.channels[name])), name
    f.reset()
    names = list(left.channels)
    stepped = []
    for i in range(len(left)):
        sample = {n: (None if left.channels[n][i] is np.ma.masked else float(left.channels[n][i])) for n in names}
        stepped.append(f.step({"t": float(left.t[i]), **sample})["contact_left"])
    want = [None if c is np.ma.masked else bool(c) for c in est.channels["contact_left"]]
    assert [None if c is None else bool(c) for c in stepped] == want
