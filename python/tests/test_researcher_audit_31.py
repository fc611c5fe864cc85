"""Session 31's researcher audit: a gait researcher's first afternoon with
the package on the shared recordings (gaitmap foot walk, mobgap lower
back, the independent simulator's B-SLIP and FES trials). Each test is one
stumble that was fixed; each failed before its fix (what it saw is in its
docstring). The trials are simulated, so the tests need no shared data."""

import math
import warnings

import numpy as np
import pytest

import limbfuse

pd = pytest.importorskip("pandas")


@pytest.fixture(scope="module")
def gait_walk():
    """10 s of walking with the simulator's contact and speed references."""
    return limbfuse.simulate("walking", duration=10.0, seed=3, gait_reference=True)


def side(trial, prefix, meta=None):
    """The trial's `prefix*` channels only, as a new in-memory trial."""
    return limbfuse.Trial(trial.t, {k: v for k, v in trial.channels.items() if k.startswith(prefix)}, meta=meta)


def test_no_gait_error_carries_the_unit_warnings_of_peers_units(gait_walk):
    """Foot IMUs in the units peers' tools use (gaitmap: deg/s and g):
    `limbfuse estimate` prints "these look like deg/s (multiply them by
    pi/180 ...)" and "these look like g (multiply them by 9.81)" before its
    "no gait found" error. Python raised the error with the rejected-readings
    line only: the warnings that say what is wrong were lost."""
    ch = {k: (np.degrees(v) if "_gyr_" in k else v / 9.81) for k, v in gait_walk.channels.items() if k.startswith("foot_")}
    with pytest.raises(limbfuse.LimbfuseError) as e:
        limbfuse.estimate(limbfuse.Trial(gait_walk.t, ch), "gait-events")
    text = str(e.value)
    assert "no gait found" in text
    assert "these look like deg/s" in text, text
    assert "these look like g (multiply them by 9.81)" in text, text


def test_no_gait_error_carries_the_time_unit_warning(gait_walk):
    """`t` in milliseconds (a common logger unit): the error said "no gait
    found" and nothing about the time column the CLI warns about."""
    trial = side(gait_walk, "foot_")
    ms = limbfuse.Trial(trial.t * 1000.0, dict(trial.channels))
    with pytest.raises(limbfuse.LimbfuseError) as e:
        limbfuse.estimate(ms, "gait-events")
    assert "milliseconds" in str(e.value), str(e.value)


def test_missing_gait_library_names_the_python_call(gait_walk):
    """`estimate(trial, "imm-bslip")` without a library said "needs library
    LIB.json (build one with `limbfuse gait-library build`)": a CLI
    subcommand, where Python has `limbfuse.gait_library`."""
    bslip = limbfuse.Trial(
        gait_walk.t, {"com_meas_x": gait_walk.t * 0.8, "com_meas_y": np.full(len(gait_walk.t), 0.9), "com_meas_z": np.zeros(len(gait_walk.t))}
    )
    with pytest.raises(limbfuse.LimbfuseError) as e:
        limbfuse.estimate(bslip, "imm-bslip")
    text = str(e.value)
    assert "limbfuse.gait_library(" in text, text
    assert "gait-library build" not in text, text


def test_lowback_speed_does_not_read_the_imu_mounts_it_does_not_use(gait_walk):
    """The independent simulator's FES trials state `# imu_mounts_m:` in
    words (`thigh: static; shank: ...`). `cohort.run(..., "lowback-speed",
    on_error="record")` over that folder said, for them, "metadata `#
    imu_mounts_m: ...`: expected `segment (x, y[, z])`" (lowback-speed reads
    no IMU position) where `inspect` says the trunk accelerometer is
    missing; and a lower-back trial with such a line did not run at all."""
    words = {"imu_mounts_m": "thigh: static; shank: on the shank axis 0.25 m below the knee"}
    with pytest.raises(limbfuse.LimbfuseError, match="no trunk_acc_x/y/z"):
        limbfuse.estimate(side(gait_walk, "shank_", words), "lowback-speed")
    plain = limbfuse.estimate(side(gait_walk, "trunk_"), "lowback-speed")
    worded = limbfuse.estimate(side(gait_walk, "trunk_", words), "lowback-speed")
    for name in plain.channels:
        assert np.array_equal(np.ma.filled(plain.channels[name], np.nan), np.ma.filled(worded.channels[name], np.nan), equal_nan=True)


def test_filter_steps_a_pandas_row_with_nan_as_missing(gait_walk):
    """docs/python.md: "in a pandas DataFrame or Series NaN is missing".
    `Filter.step(df.iloc[i])` (a row of the trial's own `to_pandas()`) raised
    "sample `contact_left_ref`: NaN is not a value": the row of a trial whose
    reference is unknown at that time could not be stepped."""
    trial = side(gait_walk, "foot_")
    trial = limbfuse.Trial(
        trial.t, {**trial.channels, "contact_left_ref": np.ma.masked_all(len(trial.t))}, meta=gait_walk.meta
    )
    df = trial.to_pandas()
    assert math.isnan(df["contact_left_ref"].iloc[0])
    by_row = limbfuse.Filter.for_trial(trial, "gait-events")
    outs = [by_row.step(df.iloc[i]) for i in range(300)]
    by_dict = limbfuse.Filter.for_trial(trial, "gait-events")
    for i in range(300):
        sample = {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in df.iloc[i].to_dict().items()}
        assert by_dict.step(sample) == outs[i]
    # a dict keeps its rule: NaN is refused, not taken for missing
    with pytest.raises(limbfuse.LimbfuseError, match="NaN is not a value"):
        by_dict.step(df.iloc[300].to_dict())


def test_filter_steps_a_row_of_a_gait_trial_with_its_phase_reference():
    """A B-SLIP trial's `to_pandas()` has a `phase_ref` column of labels;
    `Filter.run(df)` takes it (a reference, no method reads it) but
    `Filter.step(df.iloc[0])` raised "sample `phase_ref`: expected a number
    or None, found 'SS1'"."""
    trial = limbfuse.simulate("walking", duration=2.0, seed=1)
    labels = np.array(["SS1"] * len(trial.t), dtype=object)
    bslip = limbfuse.Trial(trial.t, {k: v for k, v in trial.channels.items() if k.startswith("thigh_")}, phase_ref=labels)
    df = bslip.to_pandas()
    assert df["phase_ref"].iloc[0] == "SS1"
    f = limbfuse.Filter.for_trial(bslip, "gyro-integration")
    out = f.step(df.iloc[0])
    assert out["t"] == 0.0


def test_cohort_metric_columns_are_numbers_when_a_method_lacks_some(gait_walk):
    """`cohort.run(..., "lowback-speed")`: the final-contact, contact and
    phase columns (which a lower-back method does not estimate) were object
    columns of None, so `df.describe()` left them out and
    `df["fc_missed"].sum()` gave 0 rather than NaN."""
    trials = [gait_walk, limbfuse.simulate("walking", duration=10.0, seed=4, gait_reference=True)]
    df = limbfuse.cohort.run(trials, "lowback-speed")
    for col in limbfuse.cohort.EVENT_METRICS:
        assert df[col].dtype.kind in "fi", (col, df[col].dtype)
    assert df["fc_median_abs_ms"].isna().all()
    assert df["ic_n_reference"].dtype.kind == "i"


def test_inspect_says_why_a_method_that_runs_after_align_cannot(gait_walk):
    """`inspect` of a lower-back recording in raw frames (the mobgap walks):
    `methods["gyro-integration"]` was `("runs after align", "")` while
    `limbfuse align` cannot align a trunk-only trial; the CLI says so on the
    same line. The reason is now the second element."""
    raw = limbfuse.simulate("walking", duration=10.0, seed=3, mounting="random")
    trunk = side(raw, "trunk_", raw.meta)
    info = limbfuse.inspect(trunk)
    assert info["align"]["possible"] is False
    kind, why = info["methods"]["gyro-integration"]
    assert kind == "runs after align"
    assert "cannot align" in why and info["align"]["reason"] in why, why
    whole = limbfuse.inspect(raw)
    kind, why = whole["methods"]["gyro-integration"]
    assert kind == "runs after align"
    assert "limbfuse.align" in why, why


def test_knee_estimate_carries_the_summary_line_of_the_cli(tmp_path, cli):
    """Session 31 audit: `limbfuse estimate` prints a knee-axis method's
    identification line (sign confidence, committed or not: a knee that may
    come out negated); Python dropped it. `Estimate.summary` holds it, the
    CLI's line word for word up to the backfill's spelling."""
    trial = limbfuse.simulate("knee", seed=3, duration=20.0)
    path = tmp_path / "knee.csv"
    limbfuse.write_trial(trial, path)
    est = limbfuse.estimate(trial, "knee-selfalign")
    assert est.summary is not None
    assert est.summary.startswith("knee-selfalign: knee axis identified at t = "), est.summary
    assert "sign confidence" in est.summary
    assert est.summary.endswith("(`backfill=True` fills it offline)"), est.summary
    said = cli("estimate", "--method", "knee-selfalign", path, "-o", tmp_path / "k.csv").stderr
    line = next(x for x in said.splitlines() if x.startswith("knee-selfalign: knee axis identified"))
    assert line.split("; no knee angle")[0] == est.summary.split("; no knee angle")[0]
    back = limbfuse.estimate(trial, "knee-selfalign", backfill=True)
    assert back.summary.endswith("knee backfilled before it (gyro angle)"), back.summary
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (the raw-frames warning: not what is tested)
        assert limbfuse.estimate(trial, "gyro-integration").summary is None
    assert limbfuse.read_estimate(tmp_path / "k.csv").summary is None


def test_methods_with_details_gives_what_the_cli_lists(cli):
    """Session 31 audit: `limbfuse methods` says what each method reads and
    what sets it; Python's `methods()` gave only names and summaries."""
    listed = cli("methods").stdout
    details = limbfuse.methods(details=True)
    assert [d["name"] for d in details] == [n for n, _ in limbfuse.methods()]
    for d in details:
        assert set(d) == {"name", "summary", "reads", "settings"}
        block = f"{d['name']}\n    {d['summary']}\n    reads:    {d['reads']}\n    settings: {d['settings']}\n"
        assert block in listed, block
    with pytest.raises(TypeError, match="details"):
        limbfuse.methods(details="yes")
