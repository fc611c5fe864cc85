"""simulate, align, gait_library."""

import warnings

import numpy as np
import pytest

import limbfuse
from limbfuse import LimbfuseError, Trial


def test_simulate_is_seeded_and_matches_the_cli(cli, tmp_path):
    a = limbfuse.simulate("walking", duration=2.0, seed=9)
    b = limbfuse.simulate("walking", duration=2.0, seed=9)
    assert len(a) == 200 and "walking" in a.meta["source"]
    for k in a.channels:
        assert np.array_equal(a.channels[k], b.channels[k])
    p, q = tmp_path / "cli.csv", tmp_path / "py.csv"
    cli("simulate", "walking", "--duration", "2", "--seed", "9", "-o", p)
    a.write(q)
    assert p.read_bytes() == q.read_bytes()


def test_simulate_gait_reference_matches_the_cli(cli, tmp_path):
    """`gait_reference=True` writes the CLI's `--gait-reference` file, and
    `gait-events` is scored against it: every contact found."""
    a = limbfuse.simulate("walking", duration=8.0, seed=5, gait_reference=True)
    p, q = tmp_path / "cli.csv", tmp_path / "py.csv"
    cli("simulate", "walking", "--duration", "8", "--seed", "5", "--gait-reference", "-o", p)
    a.write(q)
    assert p.read_bytes() == q.read_bytes()
    ev = limbfuse.evaluate(a, limbfuse.estimate(a, "gait-events"))
    ic = ev["initial_contact"]
    assert ic["n_matched"] == ic["n_reference"] > 0 and ic["missed"] == 0 and ic["extra"] == 0, ic


@pytest.mark.parametrize("kind", ["walking", "knee", "knee-fes", "fixed-hip"])
def test_every_kind_simulates(kind):
    tr = limbfuse.simulate(kind, duration=2.0, seed=1)
    assert len(tr) > 0 and tr.channels


def test_simulate_bad_input():
    with pytest.raises(LimbfuseError, match="unknown kind `running`"):
        limbfuse.simulate("running")
    with pytest.raises(LimbfuseError, match="`duration`: expected a positive number"):
        limbfuse.simulate("walking", duration=-5)
    with pytest.raises(LimbfuseError, match="unknown option `durations`"):
        limbfuse.simulate("walking", durations=5)
    with pytest.raises(LimbfuseError, match="`duration`: expected a finite number"):
        limbfuse.simulate("walking", duration=float("nan"))
    with pytest.raises(LimbfuseError, match="`seed`: expected a non-negative integer"):
        limbfuse.simulate("walking", seed=1.5)
    with pytest.raises(LimbfuseError, match="unknown leg `P9`"):
        limbfuse.simulate("knee-fes", subject="P9")
    with pytest.raises(LimbfuseError, match="cap"):
        limbfuse.simulate("walking", duration=1e9)


def test_align_recovers_the_segment_frames(tmp_path, cli):
    raw = limbfuse.simulate("walking", duration=30.0, seed=2, mounting="random")
    aligned = limbfuse.align(raw)
    assert any(k.endswith("_align_quat") for k in aligned.meta)
    assert set(aligned.channels) == set(raw.channels)
    # Same as the CLI's `align`.
    p, q = tmp_path / "raw.csv", tmp_path / "al.csv"
    raw.write(p)
    cli("align", p, "-o", q)
    ref = limbfuse.read_trial(q)
    for k in ref.channels:
        assert np.array_equal(np.ma.filled(aligned.channels[k], 0.0), np.ma.filled(ref.channels[k], 0.0)), k
    with pytest.raises(LimbfuseError, match="no gyroscope channels"):
        limbfuse.align(limbfuse.Trial(raw.t, {"knee_enc": raw.channels["knee_enc"]}))
    with pytest.raises(LimbfuseError, match="unknown segment `knee`"):
        limbfuse.align(raw, mean_angle={"knee": 3})


def test_gait_library_feeds_imm_bslip(gait_library):
    import json

    gait_library_file, (g,) = gait_library[0], gait_library[1]
    assert abs(g["speed"] - 0.7) < 1e-12 and g["step_time"] > 0 and g["periodicity_residual"] < 1e-6
    assert len(json.loads(gait_library_file.read_text())["gaits"]) == 1
    # imm-bslip reads it (test_equivalence runs it against the CLI).
    trial = limbfuse.Trial(np.arange(3) * 0.01, {"com_meas_x": np.zeros(3), "com_meas_y": np.ones(3), "com_meas_z": np.zeros(3)})
    est = limbfuse.estimate(trial, "imm-bslip", library=str(gait_library_file))
    assert "speed" in est.channels


def test_issue_19_a_trial_outside_the_library_speeds_warns(gait_library, cli, tmp_path):
    """The CLI's stderr note (imm-bslip walking outside the library's
    speeds, the library extension off) is a LimbfuseWarning in Python, with
    the same text."""
    lib = str(gait_library[0])
    path = tmp_path / "fast.csv"
    cli("simulate", "bslip", "--speed", "1.0", "--duration", "3", "-o", path)
    trial = limbfuse.read_trial(path)
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"above the gait library's range \(0\.70-0\.70 m/s") as w:
        limbfuse.estimate(trial, "imm-bslip", library=lib, imm_config="continuous", imm_extend_library="off")
    r = cli("estimate", "--method", "imm-bslip", "--library", lib, "--imm-config", "continuous",
            "--imm-extend-library", "off", path, "-o", tmp_path / "e.csv")
    note = str(w[0].message).split(": ", 1)[1]
    assert note in r.stderr, (note, r.stderr)
    # Inside the range: no warning.
    inside = tmp_path / "at.csv"
    cli("simulate", "bslip", "--speed", "0.7", "--duration", "3", "-o", inside)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        limbfuse.estimate(limbfuse.read_trial(inside), "imm-bslip", library=lib, imm_config="continuous")


def test_issue_19_the_library_extension_says_what_the_cli_says(gait_library, cli, tmp_path):
    """imm-bslip (continuous) on a trial outside the library's speeds: the
    package searches the missing gaits and estimates again, as the CLI does,
    and says so in a LimbfuseWarning with the CLI's stderr text (the search's
    duration aside); the estimate is the CLI's."""
    import re

    lib = str(gait_library[0])
    path = tmp_path / "fast.csv"
    cli("simulate", "bslip", "--speed", "1.0", "--duration", "3", "-o", path)
    with pytest.warns(limbfuse.LimbfuseWarning, match="added 0.800, 0.900, 1.000 m/s") as w:
        est = limbfuse.estimate(limbfuse.read_trial(path), "imm-bslip", library=lib, imm_config="continuous")
    r = cli("estimate", "--method", "imm-bslip", "--library", lib, "--imm-config", "continuous", path, "-o", tmp_path / "e.csv")
    said = str(w[0].message).split(": ", 1)[1]
    line = next(l for l in r.stderr.splitlines() if "gait search" in l).split(": ", 1)[1]
    duration = re.compile(r" in \d+\.\d s")
    assert duration.sub(" in T s", said) == duration.sub(" in T s", line), (said, line)
    cli_est = limbfuse.read_estimate(tmp_path / "e.csv")
    np.testing.assert_array_equal(est.channels["speed"], cli_est.channels["speed"])


def test_gait_library_bad_input(tmp_path):
    with pytest.raises(LimbfuseError, match="speeds"):
        limbfuse.gait_library(tmp_path / "x.json", [-1.0])
    with pytest.raises(LimbfuseError, match="mass"):
        limbfuse.gait_library(tmp_path / "x.json", [0.7], mass=0)
    # a human's: a leg of 1 cm failed with "no periodic gait at 1 m/s"
    with pytest.raises(LimbfuseError, match="leg_length 0.01: expected a human"):
        limbfuse.gait_library(tmp_path / "x.json", [0.7], leg_length=0.01)


def test_calibrate_matches_the_cli(cli, tmp_path):
    """`simulate("calibration")` writes the CLI's pose recording and
    `calibrate` the CLI's calibration file (with the recording read from a
    file, its name is the `source`, as the CLI writes it)."""
    p, cal_cli = tmp_path / "poses.csv", tmp_path / "cli.toml"
    cli("simulate", "calibration", "--seed", "7", "-o", p)
    cli("calibrate", p, "-o", cal_cli)
    poses = limbfuse.simulate("calibration", seed=7)
    q = tmp_path / "py.csv"
    poses.write(q)
    assert p.read_bytes() == q.read_bytes()
    cal = limbfuse.calibrate(limbfuse.read_trial(p))
    # (the CLI's file records its command line too; both record the
    # version, the fit's settings and the recording's hash)
    cli_text = "".join(
        line for line in cal_cli.read_text().splitlines(keepends=True) if not line.startswith("# command: ")
    )
    assert cal.toml == cli_text
    assert "\n# fit_settings: model=full gravity=9.81 " in cal.toml and "\n# source_hash: xxh3:" in cal.toml
    assert [s["segment"] for s in cal.sensors] == ["trunk", "thigh", "shank", "foot"]
    assert all(s["poses"] == 14 and s["residual_mg"] < 1.0 for s in cal.sensors)
    cal.write(tmp_path / "py.toml")
    assert (tmp_path / "py.toml").read_text() == cal.toml
    # These sensors have cross-axis errors: a scale-only model does not fit
    # them, and says so (as `limbfuse calibrate --model scale`).
    with pytest.raises(LimbfuseError, match="do not fit one calibration"):
        limbfuse.calibrate(poses, model="scale")


def test_calibrate_bad_input():
    poses = limbfuse.simulate("calibration", seed=3, poses=6)
    with pytest.raises(LimbfuseError, match="option `model`"):
        limbfuse.calibrate(poses, model="nope")
    with pytest.raises(LimbfuseError, match="calibrating from"):
        limbfuse.calibrate(limbfuse.simulate("walking", duration=3.0))
    with pytest.raises(TypeError):
        limbfuse.calibrate("poses.csv")
    with pytest.raises(LimbfuseError, match="option `imu_rate`"):
        limbfuse.simulate("calibration", imu_rate=0)
    with pytest.raises(LimbfuseError, match="unknown option `lever_arms`"):
        limbfuse.simulate("calibration", lever_arms=0.1)


def test_estimate_with_a_calibration_equals_the_cli(cli, tmp_path):
    """`estimate(..., calibration=...)` (a file or a `Calibration`) equals
    `limbfuse estimate --calibration` bit for bit; a trial with an IMU the
    calibration does not cover is refused."""
    poses, cal_file = tmp_path / "poses.csv", tmp_path / "cal.toml"
    walk, est_file = tmp_path / "walk.csv", tmp_path / "est.csv"
    cli("simulate", "calibration", "--seed", "7", "-o", poses)
    cli("calibrate", poses, "-o", cal_file)
    cli("simulate", "walking", "--seed", "7", "--duration", "6", "-o", walk)
    cli("estimate", "--method", "mjls", "--calibration", cal_file, walk, "-o", est_file)
    ref = limbfuse.read_estimate(est_file)
    trial = limbfuse.read_trial(walk)
    plain = limbfuse.estimate(trial, "mjls")
    for cal in (cal_file, str(cal_file), limbfuse.calibrate(limbfuse.read_trial(poses))):
        est = limbfuse.estimate(trial, "mjls", calibration=cal)
        for name in ref.channels:
            a = np.ma.filled(est.channels[name], np.nan).view(np.uint64)
            b = np.ma.filled(ref.channels[name], np.nan).view(np.uint64)
            assert np.array_equal(a, b), name
    assert not np.array_equal(np.ma.filled(plain.channels["thigh"], 0), np.ma.filled(est.channels["thigh"], 0))
    bad = tmp_path / "bad.toml"
    bad.write_text(cal_file.read_text().split("[sensors.thigh]")[0])
    with pytest.raises(LimbfuseError, match="thigh"):
        limbfuse.estimate(trial, "mjls", calibration=bad)


def test_filter_with_a_calibration_equals_estimate(tmp_path):
    """`Filter(..., calibration=cal)`, stepped or run, equals
    `estimate(..., calibration=cal)` bit for bit."""
    cal = limbfuse.calibrate(limbfuse.simulate("calibration", seed=7))
    trial = limbfuse.simulate("walking", seed=7, duration=4.0)
    ref = limbfuse.estimate(trial, "mjls", calibration=cal)
    run = limbfuse.Filter.for_trial(trial, "mjls", calibration=cal).run({"t": trial.t, **trial.channels})
    f = limbfuse.Filter.for_trial(trial, "mjls", calibration=cal)
    names = list(trial.channels)
    stepped = []
    for k in range(len(trial)):
        s = {"t": float(trial.t[k])}
        for n in names:
            v = trial.channels[n][k]
            s[n] = None if np.ma.is_masked(v) else float(v)
        stepped.append(f.step(s)["thigh"])
    for name in ref.channels:
        a = np.ma.filled(run.channels[name], np.nan).view(np.uint64)
        b = np.ma.filled(ref.channels[name], np.nan).view(np.uint64)
        assert np.array_equal(a, b), name
    # (the thigh has no estimate until it starts: NaN on those rows in both)
    assert np.array_equal(np.array(stepped, dtype=float), np.ma.filled(ref.channels["thigh"], np.nan), equal_nan=True)
    assert not np.isnan(np.array(stepped, dtype=float)).all()


def test_report_protects_its_inputs_and_names_files_safely(tmp_path):
    """An audit: `report` wrote its HTML over the trial or an estimate given
    as the output; an in-memory estimate's method named a file outside the
    temporary folder (`method="../x"`); the same object twice gave two
    identical columns. The CLI refuses the first and the last."""
    tr = limbfuse.simulate("walking", duration=3, seed=4)
    trial = tmp_path / "w.csv"
    tr.write(trial)
    est = limbfuse.estimate(tr, "mjls")
    est_path = tmp_path / "e.csv"
    est.write(est_path)
    before = trial.read_bytes()
    for out in (trial, est_path):
        with pytest.raises(LimbfuseError, match="that is the input file"):
            limbfuse.report(trial, [est_path], out)
    assert trial.read_bytes() == before
    with pytest.raises(LimbfuseError, match="give each estimate once"):
        limbfuse.report(trial, [est, est], tmp_path / "r.html")
    odd = limbfuse.Estimate(est.t, {"knee": est.channels["knee"]}, method="../../escaped")
    n = limbfuse.report(trial, [odd], tmp_path / "r.html", allow_trial_mismatch=True)
    assert n > 0
    assert not list(tmp_path.parent.glob("escaped*"))
    assert "escaped.csv" in (tmp_path / "r.html").read_text()


def test_simulate_defaults_are_the_clis(cli, tmp_path):
    """Without a seed, `simulate` gives the CLI's trial (seed 1; an audit
    found walking, knee and calibration at seed 0)."""
    cli("simulate", "walking", "--duration", "2", "-o", tmp_path / "c.csv")
    a = limbfuse.read_trial(tmp_path / "c.csv")
    b = limbfuse.simulate("walking", duration=2)
    for k, v in a.channels.items():
        np.testing.assert_array_equal(v, b.channels[k], err_msg=k)


def test_gait_library_refuses_a_repeated_speed(tmp_path):
    with pytest.raises(LimbfuseError, match="0.7 m/s given twice"):
        limbfuse.gait_library(tmp_path / "x.json", [0.7, 0.7])
    assert not (tmp_path / "x.json").exists()


def test_simulate_names_the_option_in_its_unit():
    """An audit: `simulate("walking", speed=10)` said `speed_mps`, and the
    FES and calibration errors said "simulate calibration: simulate
    calibration: hold_s = 0"."""
    with pytest.raises(LimbfuseError, match=r"option `speed` = 10: outside the allowed range \[0.4, 1.8\] m/s"):
        limbfuse.simulate("walking", speed=10)
    with pytest.raises(LimbfuseError) as e:
        limbfuse.simulate("calibration", hold=700)
    msg = str(e.value)
    assert "option `hold` = 700" in msg and msg.count("simulate calibration") == 1, msg


@pytest.mark.parametrize(
    "kind, options, flags",
    [
        (
            "walking",
            dict(duration=12, leg="left", turn_every=5, turn_deg=90, turn_s=2, misalignment=False),
            ["--duration", "12", "--leg", "left", "--turn-every", "5", "--turn-deg", "90", "--turn-s", "2", "--no-misalignment"],
        ),
        (
            "knee",
            dict(duration=10, ap_offset_sd_cm=1, remount_at=5, remount_deg=30),
            ["--duration", "10", "--ap-offset-sd-cm", "1", "--remount-at", "5", "--remount-deg", "30"],
        ),
        (
            "knee-fes",
            dict(duration=5, gyro_drift=2, activation_dynamics=False),
            ["--duration", "5", "--gyro-drift", "2", "--no-activation-dynamics"],
        ),
        (
            "fixed-hip",
            dict(duration=5, gyro_drift=1, activation_t_a=0.1),
            ["--duration", "5", "--gyro-drift", "1", "--activation-t-a", "0.1"],
        ),
        (
            "calibration",
            dict(lever_arm=0.1, wobble_pose=3, poses=6),
            ["--lever-arm", "0.1", "--wobble-pose", "3", "--poses", "6"],
        ),
        (
            "bslip",
            dict(speed=0.8, position_only=True, seed=3, duration=3),
            ["--speed", "0.8", "--position-only", "--seed", "3", "--duration", "3"],
        ),
    ],
)
def test_simulate_has_every_cli_option(cli, tmp_path, kind, options, flags):
    """Every `limbfuse simulate` subcommand and flag is a `simulate` kind and
    option giving the CLI's file byte for byte (an audit: Python had no
    `bslip`, no turns, leg, re-mounting, gyro drift or activation options)."""
    p, q = tmp_path / "cli.csv", tmp_path / "py.csv"
    cli("simulate", kind, *flags, "-o", p)
    limbfuse.simulate(kind, **options).write(q)
    assert p.read_bytes() == q.read_bytes()


def test_simulate_bslip_from_a_library_and_bad_options(tmp_path):
    lib = tmp_path / "lib.json"
    limbfuse.gait_library(lib, [0.6, 0.7])
    t = limbfuse.simulate("bslip", speed=0.6, library=lib, duration=2)
    assert float(t.meta["bslip_speed_mps"]) == 0.6 and len(t) == 200
    with pytest.raises(LimbfuseError, match=r"lib.json: no gait at 0.65 m/s"):
        limbfuse.simulate("bslip", speed=0.65, library=lib)
    with pytest.raises(LimbfuseError, match="give one or the other"):
        limbfuse.simulate("bslip", library=lib, mass=70)
    with pytest.raises(LimbfuseError, match=r"option `speed`: expected a walking speed in \(0, 2\] m/s, found 3"):
        limbfuse.simulate("bslip", speed=3)
    with pytest.raises(LimbfuseError, match="option `mass` 1e9: expected a human's body mass"):
        limbfuse.simulate("bslip", mass=1e9)


def test_simulate_new_options_name_themselves():
    cases = [
        ("walking", dict(leg="up"), 'option `leg`: expected "right" or "left"'),
        ("walking", dict(turn_deg=90), "give it too"),
        ("walking", dict(turn_every=5, turn_deg=1e300), r"option `turn_deg` = 1e300: outside the allowed range"),
        ("knee", dict(remount_at=100), "option `remount_at` = 100: expected a time within the trial"),
        ("knee-fes", dict(gyro_drift=100), r"option `gyro_drift` = 100: outside the allowed range \[-57.3, 57.3\] deg/s"),
        ("fixed-hip", dict(activation_t_a=0), "option `activation_t_a` = 0: outside the allowed range > 0 s"),
        ("calibration", dict(wobble_pose=20), r"option `wobble_pose` = 20: expected a pose from 1 to 14"),
    ]
    for kind, options, message in cases:
        with pytest.raises(LimbfuseError, match=message):
            limbfuse.simulate(kind, **options)


def _cli_align(cli, tmp_path, trial, *flags):
    trial.write(tmp_path / "raw.csv")
    cli("align", tmp_path / "raw.csv", *flags, "-o", tmp_path / "cli.csv")
    return (tmp_path / "cli.csv").read_bytes()


def test_align_is_the_clis_with_its_gate_and_leg_detection(cli, tmp_path):
    """An audit: the Python `align` lacked the CLI's reading gate (one
    1e308 gyro cell made it blame the sensor's placement) and its leg
    detection (a left leg declared right kept `leg: right`); both now give
    the CLI's file byte for byte, the CLI's warnings as LimbfuseWarnings."""
    raw = limbfuse.simulate("walking", duration=30, mounting="random", leg="left", seed=4)
    ch = {k: np.ma.array(v, copy=True) for k, v in raw.channels.items()}
    ch["thigh_gyr_x"][700] = 1e308
    meta = dict(raw.meta, leg="right")
    glitchy = Trial(raw.t, ch, meta)
    want = _cli_align(cli, tmp_path, glitchy)
    with pytest.warns(limbfuse.LimbfuseWarning) as said:
        got = limbfuse.align(glitchy)
    text = " | ".join(str(w.message) for w in said)
    assert "1 gyroscope and 0 accelerometer readings" in text and "leg: left (detected" in text, text
    assert got.meta["leg"] == "left" and got.meta["leg_declared"] == "right"
    got.write(tmp_path / "py.csv")
    assert (tmp_path / "py.csv").read_bytes() == want


def test_align_static_rotation_and_imu_calibration_are_the_clis(cli, tmp_path, monkeypatch):
    """`procedure="static-rotation"` with a `calibration` recording
    (`--procedure static-rotation --calibration`) and `imu_calibration=`
    (`--imu-calibration`) give the CLI's files."""
    monkeypatch.chdir(tmp_path)  # (the metadata names the files as given)
    cli("simulate", "knee-fes", "--duration", "10", "--mounting", "random", "--calibration", "rec.csv", "-o", "fes.csv")
    fes, rec = limbfuse.read_trial("fes.csv"), limbfuse.read_trial("rec.csv")
    cli("align", "fes.csv", "--procedure", "static-rotation", "--calibration", "rec.csv", "-o", "cli.csv")
    limbfuse.align(fes, procedure="static-rotation", calibration=rec).write("py.csv")
    assert (tmp_path / "py.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()
    cal = limbfuse.calibrate(limbfuse.simulate("calibration", seed=4))
    cal.write("cal.toml")
    limbfuse.simulate("walking", duration=30, mounting="random", seed=4).write("raw.csv")
    cli("align", "raw.csv", "--imu-calibration", "cal.toml", "-o", "cli.csv")
    raw = limbfuse.read_trial("raw.csv")
    limbfuse.align(raw, imu_calibration=tmp_path / "cal.toml").write("py.csv")
    assert (tmp_path / "py.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()
    by_object = limbfuse.align(raw, imu_calibration=cal)
    assert by_object.meta["imu_calibration"].startswith("<Calibration>")
    np.testing.assert_array_equal(by_object.channels["thigh_gyr_z"], limbfuse.read_trial("py.csv").channels["thigh_gyr_z"])
    with pytest.raises(TypeError, match="an IMU calibration is `imu_calibration=`"):
        limbfuse.align(raw, calibration=cal)
    with pytest.raises(LimbfuseError, match="`calibration` .* is for procedure=\"static-rotation\""):
        limbfuse.align(raw, calibration=rec)


def test_knee_fes_calibration_recording_equals_the_cli(cli, tmp_path):
    """`simulate("knee-fes", calibration=PATH)` writes the CLI's
    `--calibration` recording byte for byte, and `align` takes it as a file
    (an audit: Python could not make it, so docs/python.md's static-rotation
    line could not run)."""
    cli("simulate", "knee-fes", "--duration", "5", "--mounting", "random",
        "--calibration", tmp_path / "cli-cal.csv", "-o", tmp_path / "cli.csv")
    fes = limbfuse.simulate("knee-fes", duration=5, mounting="random", calibration=tmp_path / "py-cal.csv")
    assert (tmp_path / "py-cal.csv").read_bytes() == (tmp_path / "cli-cal.csv").read_bytes()
    by_file = limbfuse.align(fes, procedure="static-rotation", calibration=tmp_path / "py-cal.csv")
    by_trial = limbfuse.align(
        fes, procedure="static-rotation", calibration=limbfuse.read_trial(tmp_path / "py-cal.csv")
    )
    assert by_file.meta == by_trial.meta
    with pytest.raises(LimbfuseError, match="option `calibration`: .*missing"):
        limbfuse.simulate("knee-fes", duration=5, calibration=tmp_path / "missing" / "c.csv")
