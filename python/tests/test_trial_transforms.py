"""resample and mirror: the CLI's `limbfuse resample` / `limbfuse mirror` as
functions (session 44), file for file equal to the CLI's outputs."""

import warnings

import numpy as np
import pytest

import limbfuse
from limbfuse import LimbfuseError, LimbfuseWarning, Trial


@pytest.fixture(scope="module")
def raw_file(tmp_path_factory, cli):
    p = tmp_path_factory.mktemp("raw") / "raw.csv"
    cli("simulate", "walking", "--duration", "8", "--seed", "4", "--mounting", "random", "-o", p)
    return p


@pytest.mark.parametrize("rate,anti_alias", [(50, "sinc"), (40, "boxcar"), (200, "none")])
def test_resample_writes_the_clis_file(cli, tmp_path, raw_file, rate, anti_alias, monkeypatch):
    # (a trial read from a file is named by its file name: the CLI is given the same)
    monkeypatch.chdir(raw_file.parent)
    out = tmp_path / "cli.csv"
    cli("resample", raw_file.name, "--rate", rate, "--anti-alias", anti_alias, "-o", out)
    got = limbfuse.resample(limbfuse.read_trial(raw_file), rate, anti_alias=anti_alias)
    assert isinstance(got, Trial) and got.meta["sample_rate_hz"] == str(rate)
    mine = tmp_path / "py.csv"
    got.write(mine)
    assert mine.read_bytes() == out.read_bytes()


@pytest.mark.parametrize("seed", [None, 5])
def test_mirror_writes_the_clis_file(cli, tmp_path, raw_file, seed, monkeypatch):
    monkeypatch.chdir(raw_file.parent)
    out = tmp_path / "cli.csv"
    flags = [] if seed is None else ["--remount-seed", seed]
    cli("mirror", raw_file.name, *flags, "-o", out)
    got = limbfuse.mirror(limbfuse.read_trial(raw_file), remount_seed=seed)
    assert got.meta["leg"] == "left"
    mine = tmp_path / "py.csv"
    got.write(mine)
    assert mine.read_bytes() == out.read_bytes()


def test_mirroring_twice_gives_the_readings_back():
    t = limbfuse.simulate("walking", duration=3.0, seed=2)
    back = limbfuse.mirror(limbfuse.mirror(t))
    assert back.meta["leg"] == "right"
    for k, v in t.channels.items():
        assert np.array_equal(np.ma.filled(back.channels[k], np.nan), np.ma.filled(v, np.nan), equal_nan=True), k


def test_resample_says_which_readings_it_left_out():
    t = limbfuse.simulate("walking", duration=4.0, seed=1)
    ch = dict(t.channels)
    gyr = np.ma.filled(ch["thigh_gyr_z"], np.nan).copy()
    gyr[100] = 1e308  # no gyroscope reads this
    ch["thigh_gyr_z"] = gyr
    bad = Trial(t.t, ch, meta=t.meta)
    with pytest.warns(LimbfuseWarning, match=r"1 gyroscope, 0 accelerometer and 0 encoder readings out of the sensors' range \(first at t = 1 s\)"):
        out = limbfuse.resample(bad, 50)
    assert len(out) == 200 and np.all(np.isfinite(np.ma.filled(out.channels["thigh_gyr_z"], 0.0)))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        limbfuse.resample(t, 50)  # a clean trial: no warning


def test_resample_and_mirror_bad_input():
    t = limbfuse.simulate("walking", duration=2.0, seed=1)
    for rate in (0, -5, float("nan"), 1e9):
        with pytest.raises(LimbfuseError, match=r"rate: expected a rate in Hz above 0 and at most 100000"):
            limbfuse.resample(t, rate)
    with pytest.raises(TypeError, match=r"resample: rate_hz: expected a number, found '50'"):
        limbfuse.resample(t, "50")
    with pytest.raises(LimbfuseError, match=r'anti_alias: expected "sinc", "boxcar" or "none", found "lanczos"'):
        limbfuse.resample(t, 50, anti_alias="lanczos")
    with pytest.raises(TypeError, match="resample: expected a limbfuse.Trial, found str"):
        limbfuse.resample("walk.csv", 50)
    with pytest.raises(TypeError, match="remount_seed: expected a non-negative integer or None, found -1"):
        limbfuse.mirror(t, remount_seed=-1)
    with pytest.raises(TypeError, match="remount_seed: expected a non-negative integer or None, found True"):
        limbfuse.mirror(t, remount_seed=True)
    with pytest.raises(LimbfuseError, match=r"remount_seed: expected at most 2\^64 - 1"):
        limbfuse.mirror(t, remount_seed=2**70)
    no_imu = Trial(t.t, {"knee_enc": t.channels["knee_enc"]}, meta={"leg": "right"})
    with pytest.raises(LimbfuseError, match="no IMU channel to mirror"):
        limbfuse.mirror(no_imu)


@pytest.mark.parametrize(
    "fmt,rel,leg",
    [("gaittoolbox", "gaittoolbox-s02-walk", None), ("gaittoolbox", "gaittoolbox-s02-walk", "right"), ("knee-rig", "knee-rig/Trial_02.csv", None)],
)
def test_import_recording_is_the_clis_import(cli, tmp_path, fmt, rel, leg, shared_data):
    src = shared_data(rel)
    out = tmp_path / "cli.csv"
    cli("import", "--format", fmt, *(["--leg", leg] if leg else []), src, "-o", out)
    got = limbfuse.import_recording(src, fmt, leg=leg)
    assert got.source is None and len(got) > 0
    mine = tmp_path / "py.csv"
    got.write(mine)
    assert mine.read_bytes() == out.read_bytes()


def test_import_recording_with_a_calibration_is_the_clis(cli, tmp_path, shared_data):
    src = shared_data("knee-rig/Trial_02.csv")
    rig = limbfuse.import_recording(src, "knee-rig")
    # a calibration of the rig's two IMUs (thigh, shank) from simulated poses
    poses = limbfuse.simulate("calibration", seed=7)
    cal = limbfuse.calibrate(poses)
    cal_file = tmp_path / "cal.toml"
    cal.write(cal_file)
    out = tmp_path / "cli.csv"
    r = cli("import", "--format", "knee-rig", src, "--calibration", cal_file, "-o", out, check=False)
    if r.returncode != 0:
        # the CLI refuses it (e.g. a sensor it does not cover): Python must refuse it too, in its words
        with pytest.raises(LimbfuseError):
            limbfuse.import_recording(src, "knee-rig", calibration=cal_file)
        return
    with pytest.warns(LimbfuseWarning, match="also calibrates trunk, foot"):
        got = limbfuse.import_recording(src, "knee-rig", calibration=cal_file)
    mine = tmp_path / "py.csv"
    got.write(mine)
    assert mine.read_bytes() == out.read_bytes()
    assert not np.array_equal(np.ma.filled(got.channels["thigh_acc_x"], 0), np.ma.filled(rig.channels["thigh_acc_x"], 0))


def test_calibration_notes_are_the_clis_notes_as_warnings(cli, tmp_path, shared_data):
    """A calibration of sensors the trial lacks, or applied to an aligned
    trial: the CLI prints a `note:`, Python gives the same words as a
    `LimbfuseWarning` (session 45; it said nothing before)."""
    cal = limbfuse.calibrate(limbfuse.simulate("calibration", seed=7))
    cal_file = tmp_path / "cal.toml"
    cal.write(cal_file)
    src = shared_data("knee-rig/Trial_02.csv")
    r = cli("import", "--format", "knee-rig", src, "--calibration", cal_file, "-o", tmp_path / "t.csv")
    notes = [line[len("note: "):] for line in r.stderr.splitlines() if line.startswith("note: ")]
    assert any("also calibrates trunk, foot, which" in n for n in notes), r.stderr
    with pytest.warns(LimbfuseWarning) as said:
        limbfuse.import_recording(src, "knee-rig", calibration=cal_file)
    assert set(notes) <= {str(w.message) for w in said}
    walk = tmp_path / "walk.csv"
    cli("simulate", "walking", "--seed", "7", "--duration", "6", "--mounting", "random", "-o", walk)
    aligned = tmp_path / "aligned.csv"
    cli("align", walk, "-o", aligned)
    r = cli("estimate", "--method", "mjls", "--calibration", cal_file, aligned, "-o", tmp_path / "e.csv")
    notes = [line[len("note: "):] for line in r.stderr.splitlines() if line.startswith("note: ")]
    assert any("was aligned (`<segment>_align_quat`)" in n for n in notes), r.stderr
    with pytest.warns(LimbfuseWarning) as said:
        limbfuse.estimate(limbfuse.read_trial(aligned), "mjls", calibration=cal_file)
    texts = {str(w.message) for w in said}
    # (the trial is named by its file name in Python, by the path given in the CLI)
    assert any(t.endswith("the raw-frame calibration is rotated into the aligned frames") and "aligned.csv" in t for t in texts)
    with pytest.warns(LimbfuseWarning, match="the filter's input was aligned"):
        limbfuse.Filter.for_trial(limbfuse.read_trial(aligned), "mjls", calibration=cal)


def test_import_recording_bad_input(tmp_path):
    with pytest.raises(LimbfuseError, match=r'format: expected "gaittoolbox" or "knee-rig", found "vicon"'):
        limbfuse.import_recording(tmp_path, "vicon")
    with pytest.raises(LimbfuseError, match=r'leg applies to format="gaittoolbox" only'):
        limbfuse.import_recording(tmp_path / "Trial_01.csv", "knee-rig", leg="left")
    with pytest.raises(LimbfuseError, match=r'leg: expected "left" or "right", found "both"'):
        limbfuse.import_recording(tmp_path, "gaittoolbox", leg="both")
    with pytest.raises(LimbfuseError, match=r"missing\.csv: cannot read"):
        limbfuse.import_recording(tmp_path / "missing.csv", "knee-rig")
    with pytest.raises(LimbfuseError, match=r"cannot read"):
        limbfuse.import_recording(tmp_path / "no-such-folder", "gaittoolbox")
    with pytest.raises(TypeError, match="calibration: expected a Calibration"):
        limbfuse.import_recording(tmp_path, "gaittoolbox", calibration=3)
