"""estimate, evaluate, Filter, read/write_estimate; bad input."""

import copy
import json
import pickle
import threading
import warnings

import numpy as np
import pytest

import limbfuse
from limbfuse import Estimate, Filter, LimbfuseError, Trial


def bits(a):
    """An array's exact bits (NaN included)."""
    return np.ascontiguousarray(np.ma.filled(a, np.nan), dtype=np.float64).view(np.uint64)


def test_methods_are_the_registry():
    names = [n for n, _ in limbfuse.methods()]
    assert names == list(limbfuse.METHODS)
    assert {"mjls", "local", "global", "gyro-integration", "sdre", "imm-bslip"} <= set(names)
    assert "method" in limbfuse.default_params("mjls")
    with pytest.raises(LimbfuseError, match="nope"):
        limbfuse.default_params("nope")


def test_estimate_returns_arrays_and_a_dataframe(walking_trial):
    e = limbfuse.estimate(walking_trial, "mjls")
    assert isinstance(e, Estimate) and e.method == "mjls" and len(e) == len(walking_trial)
    assert e.t is not walking_trial.t and np.array_equal(e.t, walking_trial.t)
    assert {"trunk", "thigh", "shank", "foot", "hip", "knee", "ankle"} <= set(e.channels)
    assert any(c.startswith("diag_") for c in e.channels)
    df = e.to_pandas()
    assert list(df.columns) == e.columns and len(df) == len(e)
    rmse = limbfuse.evaluate(walking_trial, e)["rmse_deg"]["thigh"]
    assert 0.0 < rmse < 10.0


def test_estimate_bad_input(walking_trial):
    with pytest.raises(LimbfuseError, match="unknown method `nope`"):
        limbfuse.estimate(walking_trial, "nope")
    no_thigh = Trial(
        walking_trial.t,
        {k: v for k, v in walking_trial.channels.items() if not k.startswith("thigh_")},
        walking_trial.meta,
    )
    with pytest.raises(LimbfuseError, match="thigh"):
        limbfuse.estimate(no_thigh, "mjls")
    with pytest.raises(LimbfuseError, match="no_such_key"):
        limbfuse.estimate(walking_trial, "mjls", {"no_such_key": 1.0})
    with pytest.raises(LimbfuseError, match="^window and order apply"):
        limbfuse.estimate(walking_trial, "mjls", window=100)
    with pytest.raises(LimbfuseError, match="unknown option `bogus`"):
        limbfuse.estimate(walking_trial, "mjls", bogus=1)
    with pytest.raises(TypeError, match="limbfuse.Trial"):
        limbfuse.estimate({"t": [0.0]}, "mjls")
    with pytest.raises(LimbfuseError, match="missing.toml"):
        limbfuse.estimate(walking_trial, "mjls", "missing.toml")


def test_params_dict_equals_params_file(walking_trial, tmp_path):
    p = tmp_path / "m.toml"
    p.write_text(limbfuse.default_params("mjls"))
    a = limbfuse.estimate(walking_trial, "mjls", p)
    b = limbfuse.estimate(walking_trial, "mjls", {"method": "mjls"})
    for k in a.channels:
        assert np.array_equal(bits(a.channels[k]), bits(b.channels[k])), k


def test_evaluate_options_and_errors(walking_trial):
    e = limbfuse.estimate(walking_trial, "local")
    full = limbfuse.evaluate(walking_trial, e)
    w = limbfuse.evaluate(walking_trial, e, window=(2.0, None))
    assert w["n_samples"] < full["n_samples"] and w["window_s"] == [2.0, None]
    assert limbfuse.evaluate(walking_trial, e, window="2:")["rmse_deg"] == w["rmse_deg"]
    off = limbfuse.evaluate(walking_trial, e, offset_free=True)
    assert off["offset_free"] is True
    lag = limbfuse.evaluate(walking_trial, e, max_lag=3)
    assert set(lag["sync_lag_samples"]) == set(lag["rmse_deg"])
    with pytest.raises(LimbfuseError, match="longer than half the trial"):
        limbfuse.evaluate(walking_trial, e, max_lag=10_000)
    with pytest.raises(LimbfuseError, match="window"):
        limbfuse.evaluate(walking_trial, e, window="40:10")
    with pytest.raises(LimbfuseError, match="max_lag"):
        limbfuse.evaluate(walking_trial, e, max_lag=-1)
    short = Trial(walking_trial.t[:50], {k: v[:50] for k, v in walking_trial.channels.items()})
    with pytest.raises(LimbfuseError, match="samples but the trial"):
        limbfuse.evaluate(short, e)
    no_ref = Trial(walking_trial.t, {k: v for k, v in walking_trial.channels.items() if not k.endswith("_ref")})
    with pytest.raises(LimbfuseError, match="no reference angle"):
        limbfuse.evaluate(no_ref, e)


def test_evaluate_refuses_an_estimate_of_another_trial(tmp_path, walking_trial):
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    walking_trial.write(a)
    limbfuse.simulate("walking", duration=10.0, seed=4).write(b)
    ta, tb = limbfuse.read_trial(a), limbfuse.read_trial(b)
    e = limbfuse.estimate(ta, "gyro-integration")
    assert "trial: a.csv" in e.header
    with pytest.raises(LimbfuseError, match="made from `a.csv`.*allow_trial_mismatch"):
        limbfuse.evaluate(tb, e)
    # (an audit: allowed, it said nothing where the CLI warns)
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"made from `a.csv`.*evaluated anyway, as asked"):
        assert limbfuse.evaluate(tb, e, allow_trial_mismatch=True)["n_samples"] == len(tb)


def test_evaluate_refuses_an_estimate_of_another_in_memory_trial(tmp_path):
    """An audit: an estimate of one in-memory trial was scored against
    another of the same length without a word (2.97 deg); it is refused as
    the CLI refuses another trial file. The same trial read back from its
    file, a pickled copy, or references corrected afterwards are the same
    trial."""
    a = limbfuse.simulate("walking", duration=10, seed=7)
    b = limbfuse.simulate("walking", duration=10, seed=8)
    est = limbfuse.estimate(a, "mjls", diagnostics="none")
    with pytest.raises(LimbfuseError, match=r"made from another trial than the one given.*allow_trial_mismatch=True"):
        limbfuse.evaluate(b, est)
    with pytest.warns(limbfuse.LimbfuseWarning, match="evaluated anyway, as asked"):
        limbfuse.evaluate(b, est, allow_trial_mismatch=True)
    a.write(tmp_path / "a.csv")
    same = limbfuse.evaluate(a, est)["mean_rmse_deg"]
    assert limbfuse.evaluate(limbfuse.read_trial(tmp_path / "a.csv"), est)["mean_rmse_deg"] == same
    assert limbfuse.evaluate(pickle.loads(pickle.dumps(a)), copy.deepcopy(est))["mean_rmse_deg"] == same
    fixed = Trial(a.t, {k: (v + 0.01 if k == "knee_ref" else v) for k, v in a.channels.items()}, a.meta)
    limbfuse.evaluate(fixed, est)  # a reference changed: still its trial


def test_trials_and_estimates_pickle_and_copy(tmp_path):
    """An audit: `pickle.dumps(trial)` / `copy.deepcopy` failed ("cannot
    pickle 'mappingproxy' object"); both round-trip every array, mask,
    header and the trial's source."""
    tr = limbfuse.read_trial(_written(tmp_path, limbfuse.simulate("walking", duration=3, seed=2)))
    ch = dict(tr.channels)
    ch["thigh_gyr_z"] = np.ma.array(ch["thigh_gyr_z"], mask=np.arange(len(tr)) % 7 == 0)
    gappy = Trial(tr.t, ch, tr.meta, source=tr.source)
    for obj in (gappy, limbfuse.estimate(gappy, "mjls")):
        for back in (pickle.loads(pickle.dumps(obj)), copy.deepcopy(obj)):
            assert type(back) is type(obj) and np.array_equal(back.t, obj.t)
            assert back.channels.keys() == obj.channels.keys()
            for k in obj.channels:
                np.testing.assert_array_equal(np.ma.getmaskarray(back.channels[k]), np.ma.getmaskarray(obj.channels[k]))
                np.testing.assert_array_equal(np.ma.filled(back.channels[k], 0), np.ma.filled(obj.channels[k], 0))
            if isinstance(obj, Trial):
                assert back.meta == obj.meta and back.source == obj.source
            else:
                assert back.header == obj.header and back.columns == obj.columns


def _written(tmp_path, trial):
    p = tmp_path / "w.csv"
    trial.write(p)
    return p


def test_pandas_nan_is_a_missing_sample_everywhere():
    """An audit: NaN in a pandas column was missing for `from_pandas` but
    refused by `Trial(...)` given the Series and by `Filter.run(df)`; and a
    bool contact column or a `t` index was refused."""
    pd = pytest.importorskip("pandas")
    tr = limbfuse.simulate("walking", duration=4, seed=3, gait_reference=True)
    df = tr.to_pandas()
    df.loc[10:19, "thigh_gyr_z"] = np.nan
    a = Trial(df["t"], {c: df[c] for c in df.columns if c != "t"}, tr.meta)
    assert np.ma.getmaskarray(a.channels["thigh_gyr_z"]).sum() == 10
    b = Trial.from_pandas(df)
    est = limbfuse.estimate(b, "mjls", diagnostics="none")
    run = Filter.for_trial(b, "mjls").run(df)
    for k in ("thigh", "knee"):
        np.testing.assert_array_equal(np.ma.filled(run.channels[k], 0), np.ma.filled(est.channels[k], 0))
    df["contact_left_ref"] = df["contact_left_ref"] == 1
    c = Trial.from_pandas(df.set_index("t"))
    np.testing.assert_array_equal(np.ma.filled(c.channels["contact_left_ref"], -1), np.ma.filled(tr.channels["contact_left_ref"], -1) == 1)
    with pytest.raises(LimbfuseError, match=r"`t`, sample 3: time cannot be missing"):
        Trial(df["t"].where(df.index != 3), {"thigh_gyr_z": df["thigh_gyr_z"]})


def test_estimate_file_round_trip(tmp_path, walking_trial):
    e = limbfuse.estimate(walking_trial, "global")
    p = tmp_path / "e.csv"
    e.write(p)
    back = limbfuse.read_estimate(p)
    assert back.columns == e.columns and back.header == e.header
    for k in e.channels:
        assert np.array_equal(bits(back.channels[k]), bits(e.channels[k])), k
    # An estimate made outside limbfuse, from arrays.
    ext = Estimate(walking_trial.t, {"thigh": walking_trial.channels["thigh_ref"] + 0.01}, method="external")
    ev = limbfuse.evaluate(walking_trial, ext)
    assert ev["method"] == "external" and abs(ev["mean_err_deg"]["thigh"] - np.degrees(0.01)) < 1e-9
    with pytest.raises(LimbfuseError, match="unknown estimate column `thighs`"):
        Estimate(walking_trial.t, {"thighs": walking_trial.t})


def test_filter_step_and_run_equal_estimate(walking_trial):
    ref = limbfuse.estimate(walking_trial, "mjls")
    f = Filter.for_trial(walking_trial, "mjls")
    assert f.header == ref.header
    names = list(walking_trial.channels)
    out = []
    for i in range(len(walking_trial)):
        sample = {"t": float(walking_trial.t[i])}
        sample.update({n: float(walking_trial.channels[n][i]) for n in names})
        out.append(f.step(sample))
    for k in ref.channels:
        got = np.array([np.nan if o[k] is None else o[k] for o in out])
        assert np.array_equal(bits(got), bits(ref.channels[k])), k
    f.reset()
    run = f.run({"t": walking_trial.t, **walking_trial.channels})
    for k in ref.channels:
        assert np.array_equal(bits(run.channels[k]), bits(ref.channels[k])), k


def test_issue_17_long_estimate_equals_filter_run_in_chunks():
    # A trial long enough for `estimate`'s output block to take the huge-page
    # path (>= 4 MiB: 300 s x 41 columns x 8 bytes = 9.8 MB); `Filter.run`
    # over chunks of 7 001 samples (2.2 MB each, normal pages, each ending
    # on a partial 8-row staging line) must give the same bits.
    trial = limbfuse.simulate("walking", duration=300.0, seed=5)
    n = len(trial)
    assert n % 256 != 0
    est = limbfuse.estimate(trial, "mjls")
    f = Filter.for_trial(trial, "mjls")
    parts = []
    for a in range(0, n, 7001):
        chunk = {k: v[a : a + 7001] for k, v in trial.channels.items()}
        parts.append(f.run({"t": trial.t[a : a + 7001], **chunk}))
    assert np.array_equal(bits(est.t), bits(trial.t))
    assert len(est) == n and est.channels.keys() == parts[0].channels.keys()
    for k, v in est.channels.items():
        assert v.shape == (n,)
        whole = np.concatenate([bits(p.channels[k]) for p in parts])
        assert np.array_equal(bits(v), whole), k
    # The columns are views of one block (read-only): no two overlap.
    thigh = np.ma.getdata(est.channels["thigh"])
    for k, v in est.channels.items():
        if k != "thigh":
            assert not np.shares_memory(thigh, np.ma.getdata(v)), k


def test_issue_17_estimate_of_any_length_equals_step_by_step(walking_trial):
    # `estimate` stages its rows a cache line (8 rows) at a time and tells
    # the Python layer which columns hold a NaN: trials of 1 to 19 samples
    # (whole lines, a partial last line, less than one line) must give the
    # bits of `Filter.step`, which does neither, masked exactly where a
    # value is missing. (The segments start on the first sample, the start
    # before 2026-12-06: with the default start a walking trial of under
    # 20 samples gives no estimate at all, docs/SEGMENT_FILTERS.md "When a
    # segment starts"; this test is about the rows, not the start.)
    first = {"first_sample_start": True}
    names = list(walking_trial.channels)
    f = Filter.for_trial(walking_trial, "mjls", first)
    steps = []
    for i in range(19):
        sample = {"t": float(walking_trial.t[i])}
        sample.update({n: float(walking_trial.channels[n][i]) for n in names})
        steps.append(f.step(sample))
    for n in range(1, 20):
        part = Trial(
            walking_trial.t[:n], {k: v[:n] for k, v in walking_trial.channels.items()}, walking_trial.meta
        )
        est = limbfuse.estimate(part, "mjls", first)
        assert len(est) == n
        for k, v in est.channels.items():
            want = np.array([np.nan if s[k] is None else s[k] for s in steps[:n]])
            assert np.array_equal(bits(v), bits(want)), (n, k)
            missing = np.isnan(want)
            assert np.ma.isMaskedArray(v) == bool(missing.any()), (n, k)
            assert np.array_equal(np.ma.getmaskarray(v), missing), (n, k)


def test_issue_17_filter_step_absent_axis_is_missing(walking_trial):
    # `step`: a channel left out of the dict is missing, as None is: one
    # absent axis makes the whole 3-axis vector missing (it used to be read
    # as 0.0, with the other two axes kept).
    names = list(walking_trial.channels)
    assert "thigh_acc_y" in names
    absent, none = Filter.for_trial(walking_trial, "mjls"), Filter.for_trial(walking_trial, "mjls")
    for i in range(40):
        sample = {"t": float(walking_trial.t[i])}
        sample.update({n: float(walking_trial.channels[n][i]) for n in names})
        if i >= 20:
            del sample["thigh_acc_y"]
        a = absent.step(sample)
        if i >= 20:
            sample["thigh_acc_y"] = None
        b = none.step(sample)
        assert a == b, i


def test_filter_bad_input(walking_trial):
    with pytest.raises(LimbfuseError, match="unknown method"):
        Filter("kalman", channels=["thigh_gyr_x"])
    with pytest.raises(LimbfuseError, match="thigh"):
        Filter("mjls", channels=["shank_gyr_x", "shank_gyr_y", "shank_gyr_z"])
    f = Filter.for_trial(walking_trial, "gyro-integration")
    with pytest.raises(LimbfuseError, match="`t` \\(time in s\\) is required"):
        f.step({"thigh_gyr_x": 0.1})
    with pytest.raises(LimbfuseError, match="not one of the filter's channels"):
        f.step({"t": 0.0, "thigh_gyro_x": 0.1})
    with pytest.raises(LimbfuseError, match="pass None for a missing sample"):
        f.step({"t": 0.0, "thigh_gyr_x": float("nan")})
    f.step({"t": 1.0, "thigh_gyr_x": None})
    with pytest.raises(LimbfuseError, match="t = 0.5"):
        f.step({"t": 0.5})
    with pytest.raises(LimbfuseError, match="need `t`"):
        f.run({"thigh_gyr_x": np.zeros(3)})


def test_filter_run_releases_the_gil():
    """The main thread runs Python code while the worker is inside the native
    run: it stamps a time after the worker has started, and the worker stamps
    one as soon as the run returns. Were the run holding the GIL, the main
    thread could stamp only after the worker's stamp (the worker keeps the GIL
    from the run's return to its stamp). Causal, not a ratio of durations, so
    the machine's load and the filter's speed do not matter."""
    import time

    trial = limbfuse.simulate("walking", duration=1200.0, seed=1)
    f = Filter.for_trial(trial, "mjls")
    _, t, names, arrays, _, _ = trial._native()
    errors = []
    done = []
    started = threading.Event()

    def work():
        started.set()
        try:
            f._native.run(t, names, arrays)
        except Exception as e:  # pragma: no cover - reported below
            errors.append(e)
        done.append(time.perf_counter())

    worker = threading.Thread(target=work)
    worker.start()
    started.wait()
    time.sleep(0.001)
    main_stamp = time.perf_counter()
    worker.join()
    assert not errors, errors
    assert main_stamp < done[0], (main_stamp, done[0])


def test_panics_become_internal_errors():
    with pytest.raises(limbfuse.InternalError, match="internal error: a test panic"):
        limbfuse._native._panic_for_test()
    assert issubclass(LimbfuseError, ValueError)


def test_evaluate_result_is_the_cli_json(cli, walking_file, tmp_path):
    est = tmp_path / "e.csv"
    cli("estimate", "--method", "mjls", walking_file, "-o", est)
    trial = limbfuse.read_trial(walking_file)
    for flags, kw in [((), {}), (("--offset-free", "--window", "1:8"), {"offset_free": True, "window": "1:8"}),
                      (("--max-lag", "4"), {"max_lag": 4})]:
        cli_json = json.loads(cli("evaluate", walking_file, est, "--json", *flags).stdout)
        py = limbfuse.evaluate(trial, limbfuse.read_estimate(est), **kw)
        assert py == cli_json
        assert limbfuse.evaluate(trial, limbfuse.estimate(trial, "mjls"), **kw) == cli_json


def test_a_time_column_in_milliseconds_is_named(walking_trial):
    """`t` in milliseconds (many loggers' unit) read as seconds: `estimate`
    says so with the CLI's stderr text, and says nothing for seconds."""
    ms = Trial(walking_trial.t * 1000.0, walking_trial.channels, walking_trial.meta)
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"time column `t` steps by a median 10.*looks like milliseconds"):
        limbfuse.estimate(ms, "mjls", diagnostics="none")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        limbfuse.estimate(walking_trial, "mjls", diagnostics="none")


def test_imu_units_other_than_spec_are_named(walking_trial):
    """Accelerometers in g and gyroscopes in deg/s: `estimate` names the
    unit with the CLI's stderr text."""
    ch = dict(walking_trial.channels)
    in_g = {k: (v / 9.81 if "_acc_" in k else v) for k, v in ch.items()}
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"accelerometer readings .* look like g"):
        limbfuse.estimate(Trial(walking_trial.t, in_g, walking_trial.meta), "mjls", diagnostics="none")
    in_deg = {k: (np.degrees(v) if "_gyr_" in k else v) for k, v in ch.items()}
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"gyroscope readings .* look like deg/s"):
        limbfuse.estimate(Trial(walking_trial.t, in_deg, walking_trial.meta), "mjls", diagnostics="none")
    enc_deg = {k: (np.degrees(v) if k.endswith("_enc") else v) for k, v in ch.items()}
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"joint-encoder readings .* look like degrees"):
        limbfuse.estimate(Trial(walking_trial.t, enc_deg, walking_trial.meta), "mjls", diagnostics="none")


def test_raw_frames_warn_methods_that_read_aligned_ones(walking_trial):
    """A trial declaring raw sensor frames (`# imu_frame: raw ...`, as the
    gaittoolbox and knee-rig importers write) and no alignment: the segment
    filters and `chain` read aligned frames, so `estimate` warns with the
    CLI's stderr text; methods reading raw frames and aligned trials do not."""
    raw = Trial(walking_trial.t, walking_trial.channels, {**walking_trial.meta, "imu_frame": "raw sensor frames (unaligned)"})
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"declares raw sensor frames .*`local` reads IMU frames aligned"):
        limbfuse.estimate(raw, "local", diagnostics="none")
    aligned = Trial(raw.t, raw.channels, {**raw.meta, "align_method": "limbfuse-align/1"})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        limbfuse.estimate(aligned, "local", diagnostics="none")
        limbfuse.estimate(raw, "knee-gyro-axis", diagnostics="none")


def test_issue_19_speed_estimate_of_a_trial_with_angle_references_is_scored_as_speed(walking_trial):
    """A trial with angle references and a `speed_ref` (as the gaittoolbox
    importer writes for the S02 walk): a `gait-events` estimate is scored for
    its events and stride speed (the CLI's rule, limbfuse_eval::evaluation_kind),
    an angle estimate for its angles."""
    channels = dict(walking_trial.channels)
    channels["speed_ref"] = np.full(len(walking_trial), 1.2)
    trial = Trial(walking_trial.t, channels, walking_trial.meta)
    ev = limbfuse.evaluate(trial, limbfuse.estimate(trial, "gait-events"))
    assert ev["method"] == "gait-events" and ev["n_strides"] > 0 and ev["speed_mae_mps"] is not None
    ev = limbfuse.evaluate(trial, limbfuse.estimate(trial, "local", diagnostics="none"))
    assert ev["rmse_deg"]["thigh"] > 0.0


def test_nothing_estimated_is_an_error_as_in_the_cli(walking_trial):
    """`limbfuse estimate` exits 1 when a knee-axis method identifies no
    axis or a gait method finds no gait; `limbfuse.estimate` raises the same
    message (before, it returned an estimate with every value missing)."""
    n = 300  # 3 s: shorter than the 5 s identification window
    short = Trial(walking_trial.t[:n], {k: v[:n] for k, v in walking_trial.channels.items()}, walking_trial.meta)
    with pytest.raises(LimbfuseError, match=r"identification window \(500 samples, --window\) is longer than the trial \(300 samples\)"):
        limbfuse.estimate(short, "knee-selfalign")
    still = Trial(walking_trial.t[:n], {k: (v[:n] * 0.0 if "gyr" in k else v[:n]) for k, v in walking_trial.channels.items()}, walking_trial.meta)
    with pytest.raises(LimbfuseError, match="no gait found in <in-memory trial>: `gait-events` detected no foot contact"):
        limbfuse.estimate(still, "gait-events")
    assert limbfuse.estimate(short, "knee-selfalign", window=100).channels["knee"].count() > 0


def test_issue_19_event_evaluation_window_and_angle_options(walking_trial):
    """`window` restricts an event evaluation to its rows (it was ignored);
    `offset_free` / `max_lag` are refused for it, as the CLI does."""
    channels = dict(walking_trial.channels)
    channels["speed_ref"] = np.full(len(walking_trial), 1.2)
    trial = Trial(walking_trial.t, channels, walking_trial.meta)
    est = limbfuse.estimate(trial, "gait-events")
    whole = limbfuse.evaluate(trial, est)
    half = limbfuse.evaluate(trial, est, window=f"0:{walking_trial.t[-1] / 2}")
    assert half["n_samples"] < whole["n_samples"] and half["n_strides"] < whole["n_strides"]
    with pytest.raises(LimbfuseError, match="offset_free: applies to angle errors only"):
        limbfuse.evaluate(trial, est, offset_free=True)


def test_inspect_a_trial_file(walking_file, tmp_path):
    """`limbfuse.inspect` gives `limbfuse inspect`'s summary as a dict."""
    info = limbfuse.inspect(walking_file)
    assert info["rows"] == 1000 and info["span"] == (0.0, 9.99)
    assert abs(info["median_step"] - 0.01) < 1e-12 and info["stated_hz"] == 100.0
    assert info["gaps"] == 0 and info["warnings"] == []
    assert info["inputs"]["thigh gyr"] == 0 and "knee_enc" in info["inputs"]
    assert info["methods"]["mjls"] == ("runs", "")
    kind, why = info["methods"]["imm-bslip"]
    assert kind == "missing columns" and "com_meas_x" in why
    assert info["methods"]["sdre"][0] == "needs a setting"
    # a trial shorter than the knee methods' window: ruled out by its data
    short = limbfuse.inspect(limbfuse.read_trial(walking_file)[:300])
    kind, why = short["methods"]["knee-selfalign"]
    assert kind == "no usable data" and "window (500 samples) is longer than the trial (300 rows)" in why
    # what the simulator's metadata sets in the methods that run on it
    read = info["metadata_settings"]
    assert any(line.startswith("lowback-speed: pendulum length") and "# height_m:" in line for line in read)
    assert any(line.startswith("chain: thigh") for line in read)
    # the walking thigh moves: knee-kinematic's fixed thigh does not hold
    assert info["thigh_spread_deg"] > 5.0
    assert [n.split(":")[0] for n in info["data_notes"]] == ["knee-kinematic"]
    # a seated leg's thigh does not: no walking for gait-events to find
    seated = limbfuse.inspect(limbfuse.simulate("knee-fes", duration=4.0))
    assert seated["thigh_spread_deg"] < 5.0
    kind, why = seated["methods"]["gait-events"]
    assert kind == "no usable data" and "no walking for it to find" in why and seated["data_notes"] == []
    with pytest.raises(LimbfuseError, match="nothing.csv"):
        limbfuse.inspect(tmp_path / "nothing.csv")
    # an in-memory trial: the same summary
    trial = limbfuse.read_trial(walking_file)
    same = limbfuse.inspect(trial)
    assert {k: same[k] for k in info if k != "span"} == {k: info[k] for k in info if k != "span"}
    assert same["span"] == info["span"]


def test_filter_warns_once_about_units(walking_trial):
    """`Filter` gives `estimate`'s unit warnings once, stepping or running:
    gyroscopes in deg/s here; SI samples say nothing."""
    in_deg = {k: (np.degrees(v) if "_gyr_" in k else v) for k, v in walking_trial.channels.items()}
    names = list(in_deg)
    f = Filter("mjls", channels=names, meta=walking_trial.meta)
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"the filter's samples: .* look like deg/s") as caught:
        for i in range(300):
            f.step({"t": float(walking_trial.t[i]), **{n: float(in_deg[n][i]) for n in names}})
    # (once; the gyro readings beyond the gate's range are said apart)
    assert len([w for w in caught if "look like deg/s" in str(w.message)]) == 1
    g = Filter("mjls", channels=names, meta=walking_trial.meta)
    with pytest.warns(limbfuse.LimbfuseWarning, match="look like deg/s"):
        g.run({"t": walking_trial.t, **in_deg})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        h = Filter.for_trial(walking_trial, "mjls")
        for i in range(300):
            h.step({"t": float(walking_trial.t[i]), **{n: float(walking_trial.channels[n][i]) for n in names}})
        h.run({"t": walking_trial.t + 10.0, **dict(walking_trial.channels)})


def test_references_in_degrees_are_named(walking_trial):
    """Angle references in degrees: `evaluate` warns and says so under
    `warnings`, as `limbfuse evaluate --json`; rad references say nothing."""
    ch = {k: (np.degrees(v) if k.endswith("_ref") else v) for k, v in walking_trial.channels.items()}
    deg = Trial(walking_trial.t, ch, walking_trial.meta)
    est = limbfuse.estimate(walking_trial, "mjls", diagnostics="none")
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"`thigh_ref`.*look like degrees"):
        result = limbfuse.evaluate(deg, est, allow_trial_mismatch=True)
    assert "look like degrees" in result["warnings"][0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert "warnings" not in limbfuse.evaluate(walking_trial, est)


def test_knee_kinematic_warns_on_a_moving_thigh(walking_trial):
    """`knee-kinematic` models a seated leg's fixed thigh: on a walking
    trial `estimate` says so (the CLI's warning), and still returns."""
    with pytest.warns(limbfuse.LimbfuseWarning, match="models a fixed thigh"):
        est = limbfuse.estimate(walking_trial, "knee-kinematic")
    assert len(est) == len(walking_trial.t)


def test_filter_warns_about_raw_frames(walking_trial):
    """A `Filter` of a method that reads aligned frames, made for metadata
    declaring raw ones, gives `estimate`'s raw-frame warning once, when it
    is made; a method that reads raw frames, or aligned metadata, says
    nothing."""
    names = list(walking_trial.channels)
    raw = {**walking_trial.meta, "imu_frame": "raw sensor frames (unaligned)"}
    with pytest.warns(limbfuse.LimbfuseWarning, match="declares raw sensor frames"):
        Filter("local", channels=names, meta=raw)
    with warnings.catch_warnings():
        warnings.simplefilter("error", limbfuse.LimbfuseWarning)
        Filter("knee-gyro-axis", channels=names, meta=raw)
        Filter("local", channels=names, meta=walking_trial.meta)


def test_filter_warns_about_a_moving_thigh(walking_trial):
    """`Filter("knee-kinematic")` gives `estimate`'s fixed-thigh warning
    once, stepping or running, on a walk; a seated knee-FES leg says
    nothing."""
    names = list(walking_trial.channels)
    f = Filter("knee-kinematic", channels=names, meta=walking_trial.meta)
    with pytest.warns(limbfuse.LimbfuseWarning, match="models a fixed thigh") as caught:
        for i in range(400):
            f.step({"t": float(walking_trial.t[i]), **{n: float(walking_trial.channels[n][i]) for n in names}})
    assert len([w for w in caught if "fixed thigh" in str(w.message)]) == 1
    g = Filter("knee-kinematic", channels=names, meta=walking_trial.meta)
    with pytest.warns(limbfuse.LimbfuseWarning, match="models a fixed thigh"):
        g.run({"t": walking_trial.t, **walking_trial.channels})
    seated = limbfuse.simulate("knee-fes", duration=8.0)
    h = Filter("knee-kinematic", channels=list(seated.channels), meta=seated.meta)
    with warnings.catch_warnings():
        warnings.simplefilter("error", limbfuse.LimbfuseWarning)
        h.run({"t": seated.t, **seated.channels})


def test_inspect_names_the_model_file_beside_the_trial(tmp_path):
    """`inspect` says, under `sdre` / `ekf` needing a model, which `--params`
    to add when a parameter file with a [model] table lies beside the trial
    (the shared independent FES trials ship one)."""
    trial = limbfuse.simulate("knee-fes", duration=4.0)
    meta = {k: v for k, v in trial.meta.items() if k != "model"}
    bare = Trial(trial.t, dict(trial.channels), meta)
    path = tmp_path / "bare.csv"
    bare.write(path)
    assert "beside the trial" not in limbfuse.inspect(path)["methods"]["sdre"][1]
    (tmp_path / "bare.toml").write_text("[model]\nt_a = 1.0\n")
    kind, why = limbfuse.inspect(path)["methods"]["sdre"]
    assert kind == "needs a setting" and "add `--params" in why and "bare.toml" in why


def test_rejected_readings_are_said_as_the_cli_says_them(cli, tmp_path):
    """An audit: the CLI's "N reading(s) were rejected" warning never reached
    Python, so readings the range gate dropped were invisible; it is now a
    `LimbfuseWarning` with the CLI's counts, and part of the error when
    nothing was estimated."""
    sim = limbfuse.simulate("walking", duration=12, seed=3)
    ch = {k: np.ma.array(v, copy=True) for k, v in sim.channels.items()}
    ch["thigh_acc_y"][900:905] = 500.0  # beyond the +-16 g range
    tr = limbfuse.Trial(sim.t, ch, sim.meta)
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"0 gyroscope, 5 accelerometer and 0 encoder reading\(s\) were rejected \(first at t = 9 s\)"):
        limbfuse.estimate(tr, "gyro-integration")
    tr.write(tmp_path / "g.csv")
    said = cli("estimate", "--method", "gyro-integration", tmp_path / "g.csv", "-o", tmp_path / "e.csv").stderr
    assert "0 gyroscope, 5 accelerometer and 0 encoder reading(s) were rejected (first at t = 9 s)" in said, said
    # Every gyro reading out of range: the error says so, not only that
    # the inputs are missing.
    for k in ch:
        if "_gyr_" in k:
            ch[k][:] = 100.0  # rad/s, beyond the +-2000 deg/s range
    with pytest.raises(limbfuse.LimbfuseError, match=r"(?s)gave no estimate.*were rejected"):
        limbfuse.estimate(limbfuse.Trial(sim.t, ch, sim.meta), "gyro-integration")


def test_the_default_parameters_as_a_dict_are_the_defaults():
    """An audit: `tomllib.loads(default_params(m))` passed back as `params`
    was refused for `inf` (the defaults' "off", e.g. `accel_max_rate`);
    `inf` now passes as the file's `inf`, and NaN is still refused."""
    tomllib = pytest.importorskip("tomllib")
    tr = limbfuse.simulate("walking", duration=6, seed=2)
    for method in ("local", "mjls", "global", "chain"):
        as_dict = tomllib.loads(limbfuse.default_params(method))
        assert any(v == float("inf") for v in _leaves(as_dict)), method
        a = limbfuse.estimate(tr, method, as_dict, diagnostics="none")
        b = limbfuse.estimate(tr, method, diagnostics="none")
        for k in b.channels:
            np.testing.assert_array_equal(np.ma.filled(a.channels[k], np.nan), np.ma.filled(b.channels[k], np.nan))
    with pytest.raises(limbfuse.LimbfuseError, match=r"`gravity` = inf: must be from 1 to 20"):
        limbfuse.estimate(tr, "mjls", {"gravity": float("inf")})
    with pytest.raises(limbfuse.LimbfuseError, match=r'params\["gravity"\]: expected a number, found nan'):
        limbfuse.estimate(tr, "mjls", {"gravity": float("nan")})


def _leaves(d):
    for v in d.values():
        if isinstance(v, dict):
            yield from _leaves(v)
        elif isinstance(v, list):
            yield from v
        else:
            yield v


def test_params_may_be_a_parameter_files_text():
    """An audit: `estimate(trial, m, default_params(m))` took the text for a
    file name; a string with a line break is the file's text (a path never
    holds one), named `<params text>` in errors."""
    tr = limbfuse.simulate("walking", duration=5, seed=2)
    text = limbfuse.default_params("mjls")
    a = limbfuse.estimate(tr, "mjls", text, diagnostics="none")
    b = limbfuse.estimate(tr, "mjls", diagnostics="none")
    for k in b.channels:
        np.testing.assert_array_equal(np.ma.filled(a.channels[k], 0), np.ma.filled(b.channels[k], 0))
    with pytest.raises(LimbfuseError, match=r"<params text>: `gravity` = -1: must be from 1 to 20"):
        limbfuse.estimate(tr, "mjls", text.replace("gravity = 9.81", "gravity = -1"))
    assert "gravity = 9.81" in text
    Filter.for_trial(tr, "mjls", text)  # the streaming filter too


def test_method_flags_are_named_as_keywords():
    """An audit: `estimate(trial, "mjls", window=500)` said "--window and
    --order apply to ..."; Python names its keywords."""
    tr = limbfuse.simulate("walking", duration=3, seed=2)
    with pytest.raises(LimbfuseError, match=r"^window and order apply to methods knee-selfalign and knee-gyro-axis only, not to `mjls`"):
        limbfuse.estimate(tr, "mjls", window=500)
    with pytest.raises(LimbfuseError, match=r": diagnostics: `bogus` is not a diagnostic of `mjls`"):
        limbfuse.estimate(tr, "mjls", diagnostics=["bogus"])


def test_filter_reset_of_imm_continuous_gives_a_new_filters_estimates(tmp_path):
    """An audit: after `Filter.reset()` the continuous `imm-bslip` restarted
    on the previous run's re-targeted gait, so a second run differed from
    the first (speed, CoM, weights) from sample 0; it now equals a new
    filter's, bit for bit."""
    lib = tmp_path / "lib.json"
    limbfuse.gait_library(lib, [0.6, 0.7, 0.8])
    tr = limbfuse.simulate("bslip", library=lib)
    arrays = {"t": tr.t, **tr.channels}
    opts = dict(library=lib, imm_config="continuous", imm_extend_library="off")
    f = Filter.for_trial(tr, "imm-bslip", **opts)
    first = f.run(arrays)
    f.reset()
    second = f.run(arrays)
    new = Filter.for_trial(tr, "imm-bslip", **opts).run(arrays)
    for other in (second, new):
        for k in first.channels:
            np.testing.assert_array_equal(bits(other.channels[k]), bits(first.channels[k]), err_msg=k)
        assert list(other.phase) == list(first.phase)


def test_smooth_is_the_clis_smoothed_chain(cli, tmp_path):
    """An audit: `estimate(trial, "chain", smooth=True)` was an unknown
    option where the CLI has `--smooth`; it now writes the CLI's file but
    its `# command:` line."""
    limbfuse.simulate("walking", duration=8, seed=2).write(tmp_path / "w.csv")
    cli("estimate", "--method", "chain", "--smooth", tmp_path / "w.csv", "-o", tmp_path / "cli.csv")
    limbfuse.estimate(limbfuse.read_trial(tmp_path / "w.csv"), "chain", smooth=True).write(tmp_path / "py.csv")
    lines = lambda p: [l for l in p.read_text().splitlines() if not l.startswith("# command:")]
    assert lines(tmp_path / "py.csv") == lines(tmp_path / "cli.csv")
    with pytest.raises(LimbfuseError, match=r"`mjls` has no offline smoother \(`smooth` applies to `chain`\)"):
        limbfuse.estimate(limbfuse.read_trial(tmp_path / "w.csv"), "mjls", smooth=True)
    with pytest.raises(LimbfuseError, match="cannot be used together"):
        limbfuse.estimate(limbfuse.read_trial(tmp_path / "w.csv"), "chain", smooth=True, backfill=True)


def test_second_audit_of_the_new_python_features(tmp_path):
    """A second audit of this session's additions: a trial's CSV and Arrow
    copies are one trial for an estimate made in this session (their file
    hashes differ); `window` refuses NaN and strings; `align` names its own
    options and refuses a wrong `imu_calibration`; an estimate of
    `gait-events` without its event diagnostics is scored with a warning."""
    t = limbfuse.simulate("walking", seed=1, duration=10)
    t.write(tmp_path / "t.csv")
    t.write(tmp_path / "t.arrow")
    est = limbfuse.estimate(limbfuse.read_trial(tmp_path / "t.csv"), "mjls", diagnostics="none")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        limbfuse.evaluate(limbfuse.read_trial(tmp_path / "t.arrow"), est)
    for start, end in ((float("nan"), 5.0), (2.0, float("nan")), ("2", "5")):
        with pytest.raises(LimbfuseError, match="expected a time in seconds or None"):
            t.window(start, end)
    with pytest.raises(LimbfuseError, match=r"align: unknown option `bogus` \(accepted: calibration, hinge, imu_calibration"):
        limbfuse.align(t, bogus=1)
    with pytest.raises(TypeError, match="expected a Calibration"):
        limbfuse.align(t, imu_calibration=5)
    g = limbfuse.simulate("walking", gait_reference=True, duration=20)
    with pytest.warns(limbfuse.LimbfuseWarning, match="no `diag_ic_\\*` / `diag_fc_\\*` / `diag_stride_\\*` columns"):
        limbfuse.evaluate(g, limbfuse.estimate(g, "gait-events", diagnostics="none"))


def test_filter_warns_of_rejected_readings(walking_trial):
    """A left-alone item of the twenty-sixth session: `estimate` warned of
    readings the sensor gate rejected, `Filter` said nothing, stepping or
    running. It now warns as `estimate` does: once per `run` that rejects
    (counts carried on between runs, so a second run without rejections says
    nothing), and once per stream of `step`s until `reset`."""
    names = [n for n in walking_trial.channels if not n.endswith("_ref")]
    ch = {n: np.ma.array(walking_trial.channels[n], copy=True) for n in names}
    ch["thigh_acc_y"][100:104] = 500.0  # beyond the +-16 g range
    t = walking_trial.t
    rejected = r"the filter's samples: 0 gyroscope, 4 accelerometer and 0 encoder reading\(s\) were rejected \(first at t = 1 s\)"
    f = Filter("mjls", channels=names, meta=walking_trial.meta)
    with pytest.warns(limbfuse.LimbfuseWarning, match=rejected):
        f.run({"t": t, **ch})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        f.run({"t": t + t[-1] + 0.01, **{n: walking_trial.channels[n] for n in names}})
    g = Filter("mjls", channels=names, meta=walking_trial.meta)
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"0 gyroscope, 1 accelerometer and 0 encoder reading\(s\) were rejected \(first at t = 1 s\)") as caught:
        for i in range(300):
            g.step({"t": float(t[i]), **{n: (None if ch[n][i] is np.ma.masked else float(ch[n][i])) for n in names}})
    assert len([w for w in caught if issubclass(w.category, limbfuse.LimbfuseWarning)]) == 1
    g.reset()
    with pytest.warns(limbfuse.LimbfuseWarning, match="were rejected"):
        for i in range(300):
            g.step({"t": float(t[i]), **{n: (None if ch[n][i] is np.ma.masked else float(ch[n][i])) for n in names}})


def test_both_leg_length_keys_with_different_values_warn_as_the_cli(walking_trial):
    """Review 28: `limbfuse estimate` warned (twice) when a trial stated both
    `# leg_length:` and `# leg_length_m:` with different values, Python not
    at all. Now both warn once, naming the key the method keeps."""
    meta = {**walking_trial.meta, "leg_length": "0.85", "leg_length_m": "0.95"}
    trial = limbfuse.Trial(walking_trial.t, walking_trial.channels, meta)
    with pytest.warns(limbfuse.LimbfuseWarning) as caught:
        limbfuse.estimate(trial, "lowback-speed")
    said = [str(w.message) for w in caught if "leg_length" in str(w.message)]
    assert len(said) == 1 and "`lowback-speed` reads `# leg_length:`" in said[0], said


def test_inspect_names_the_model_file_as_inspect_json_does(cli, tmp_path):
    """Session 30: with a parameter file with a [model] table beside the
    trial, Python's `inspect` added its hint to `sdre`'s and `ekf`'s reasons
    and `limbfuse inspect --json` did not; both now take the reasons from
    one function."""
    import json

    trial = limbfuse.simulate("knee-fes", duration=4.0)
    meta = {k: v for k, v in trial.meta.items() if k != "model"}
    path = tmp_path / "bare.csv"
    Trial(trial.t, dict(trial.channels), meta).write(path)
    (tmp_path / "bare.toml").write_text("[model]\nt_a = 1.0\n")
    py = limbfuse.inspect(path)
    js = json.loads(cli("inspect", "--json", path).stdout)[0]
    assert "bare.toml" in py["methods"]["sdre"][1]
    assert {k: list(v) for k, v in py["methods"].items()} == js["methods"]
    assert py["align"] == js["align"]



def test_issue_18_a_gyro_spike_the_encoders_contradict_is_refused(walking_trial):
    # mjls and global replace a thigh or shank gyroscope spike the joint
    # encoders contradict (docs/ROBUST_INPUT.md section 2p); the parameter
    # `rate_spike_test = false` applies it, as the papers do
    channels = dict(walking_trial.channels)
    shank = np.array(channels["shank_gyr_z"], dtype=float)
    shank[500] += 3.0  # 3 rad/s for one sample at 5 s
    channels["shank_gyr_z"] = shank
    spiked = Trial(walking_trial.t, channels, walking_trial.meta)
    for method in ("mjls", "global"):
        with pytest.warns(limbfuse.LimbfuseWarning, match="1 gyroscope, 0 accelerometer"):
            on = limbfuse.estimate(spiked, method)
        off = limbfuse.estimate(spiked, method, {"rate_spike_test": False})
        clean = limbfuse.estimate(walking_trial, method)
        assert on.channels["diag_rejected_gyro"][-1] == 1, method
        assert off.channels["diag_rejected_gyro"][-1] == 0, method
        assert clean.channels["diag_rejected_gyro"][-1] == 0, method
        late = slice(501, None)
        dev_on = np.nanmax(np.abs(on.channels["shank"][late] - clean.channels["shank"][late]))
        dev_off = np.nanmax(np.abs(off.channels["shank"][late] - clean.channels["shank"][late]))
        assert dev_off > 0.005 > dev_on, (method, dev_on, dev_off)  # rad
        with pytest.warns(limbfuse.LimbfuseWarning, match="1 gyroscope"):
            run = Filter.for_trial(spiked, method).run({"t": spiked.t, **spiked.channels})
        assert np.array_equal(bits(run.channels["shank"]), bits(on.channels["shank"])), method
    with pytest.raises(LimbfuseError, match="rate_spike_test"):
        limbfuse.estimate(spiked, "local", {"rate_spike_test": False})
