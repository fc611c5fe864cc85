"""Trial: construction from arrays and DataFrames, file I/O, bad input."""

import numpy as np
import pytest

import limbfuse
from limbfuse import LimbfuseError, Trial


def gyro_trial(n=10, **extra):
    t = np.arange(n) * 0.01
    ch = {f"thigh_gyr_{a}": np.full(n, 0.1) for a in "xyz"}
    ch.update(extra)
    return t, ch


def test_trial_from_arrays_keeps_the_arrays_without_copy():
    t, ch = gyro_trial()
    tr = Trial(t, ch, {"sample_rate_hz": 100})
    assert len(tr) == 10
    # a read-only view of the caller's array, not a copy
    assert np.shares_memory(tr.channels["thigh_gyr_x"], ch["thigh_gyr_x"])
    assert tr.meta == {"sample_rate_hz": "100"}
    assert tr.phase_ref is None and tr.source is None


def test_a_checked_trial_cannot_be_changed_in_place(tmp_path):
    """An audit found `trial.channels["knee_enc"][3] = np.nan` after the
    checks: `estimate` then read the NaN as a missing sample, and an
    estimate's channel set to NaN left `evaluate` silently without it.
    The arrays of a Trial and an Estimate are read-only views."""
    t, ch = gyro_trial()
    enc = np.ma.MaskedArray(np.linspace(0.0, 1.0, 10), mask=[False] * 3 + [True] + [False] * 6)
    tr = Trial(t, {**ch, "knee_enc": enc})
    for a in (tr.t, tr.channels["thigh_gyr_x"], tr.channels["knee_enc"]):
        with pytest.raises(ValueError, match="read-only"):
            a[1] = np.nan
    with pytest.raises(ValueError, match="read-only"):
        tr.channels["knee_enc"][1] = np.ma.masked
    tr.write(tmp_path / "a.csv")
    back = limbfuse.read_trial(tmp_path / "a.csv")
    with pytest.raises(ValueError, match="read-only"):
        back.channels["knee_enc"][0] = np.nan
    est = limbfuse.Estimate(back.t, {"thigh": np.zeros(len(back))}, method="mine")
    with pytest.raises(ValueError, match="read-only"):
        est.channels["thigh"][:] = np.nan
    # the caller's own array stays theirs
    ch["thigh_gyr_x"][0] = 0.2


def test_file_round_trip_is_exact_and_keeps_missing_samples(tmp_path):
    t, ch = gyro_trial()
    enc = np.ma.MaskedArray(np.linspace(0.0, 1.0, 10), mask=[False] * 3 + [True] + [False] * 6)
    tr = Trial(t, {**ch, "knee_enc": enc, "knee_ref": np.sin(t) / 3.0}, {"format": "limbfuse-trial/1"})
    p = tmp_path / "a.csv"
    limbfuse.write_trial(tr, p)
    back = limbfuse.read_trial(p)
    assert back.source[0] == "a.csv" and back.source[1].startswith("xxh3:")
    assert back.meta == {"format": "limbfuse-trial/1"}
    np.testing.assert_array_equal(back.t, t)
    k = back.channels["knee_enc"]
    assert np.ma.isMaskedArray(k) and list(np.ma.getmaskarray(k)) == list(enc.mask)
    assert np.array_equal(np.ma.filled(k, 7.0), np.ma.filled(enc, 7.0))
    assert np.array_equal(back.channels["knee_ref"], np.sin(t) / 3.0)  # ryu: bit for bit
    # Writing what was read gives the same bytes.
    p2 = tmp_path / "b.csv"
    back.write(p2)
    assert p.read_bytes() == p2.read_bytes()


def test_every_spec_channel_round_trips(tmp_path):
    n = 4
    t = np.arange(n, dtype=float)
    names = []
    for s in ("trunk", "thigh", "shank", "foot"):
        names += [f"{s}_acc_{a}" for a in "xyz"] + [f"{s}_gyr_{a}" for a in "xyz"]
        names += [f"{s}_quat_{c}" for c in "wxyz"] + [f"{s}_ref"]
    names += [f"{j}_{k}" for j in ("hip", "knee", "ankle") for k in ("enc", "ref")]
    names += ["u_ke", "u_kf", "u_he", "u_hf", "tau_hip_motor", "tau_knee_motor", "tau_ankle_motor"]
    names += [f"com_meas_{c}" for c in ("x", "y", "z", "vx", "vy", "vz")]
    names += [f"com_{c}" for c in ("x", "y", "z", "vx", "vy", "vz")]
    ch = {name: np.arange(n) + 0.5 * i for i, name in enumerate(names)}
    tr = Trial(t, ch, phase_ref=["SS1", None, "DS", "SS2"])
    p = tmp_path / "all.csv"
    tr.write(p)
    back = limbfuse.read_trial(p)
    assert set(back.channels) == set(names)
    for name in names:
        assert np.array_equal(back.channels[name], ch[name]), name
    assert list(back.phase_ref) == ["SS1", None, "DS", "SS2"]


def test_pandas_round_trip_nan_is_missing():
    t, ch = gyro_trial()
    enc = np.ma.MaskedArray(np.ones(10), mask=[True] + [False] * 9)
    tr = Trial(t, {**ch, "knee_enc": enc}, {"leg": "right"})
    df = tr.to_pandas()
    assert list(df.columns) == ["t", "thigh_gyr_x", "thigh_gyr_y", "thigh_gyr_z", "knee_enc"]
    assert np.isnan(df["knee_enc"][0]) and df.attrs["meta"] == {"leg": "right"}
    back = Trial.from_pandas(df)
    assert back.meta == {"leg": "right"}
    assert list(np.ma.getmaskarray(back.channels["knee_enc"])) == list(enc.mask)


def test_wrong_dtype_is_a_type_error():
    t, ch = gyro_trial()
    with pytest.raises(TypeError, match="channel `knee_enc`: expected a numeric"):
        Trial(t, {**ch, "knee_enc": np.array(["a"] * 10)})
    with pytest.raises(TypeError, match="`t`: expected a numeric"):
        Trial(np.array(["0"] * 10), ch)
    import pandas as pd

    df = pd.DataFrame({"t": t, "knee_enc": ["x"] * 10})
    with pytest.raises(TypeError, match="knee_enc"):
        Trial.from_pandas(df)


def test_mismatched_lengths():
    t, ch = gyro_trial()
    with pytest.raises(LimbfuseError, match="channel `knee_enc` has 9 samples but `t` has 10"):
        Trial(t, {**ch, "knee_enc": np.zeros(9)})


def test_nan_is_refused_with_the_way_to_mark_missing():
    t, ch = gyro_trial()
    bad = np.zeros(10)
    bad[4] = np.nan
    with pytest.raises(LimbfuseError, match=r"channel `knee_enc`, sample 4: nan is not a value.*masked"):
        Trial(t, {**ch, "knee_enc": bad})
    bad[4] = np.inf
    with pytest.raises(LimbfuseError, match="sample 4: inf"):
        Trial(t, {**ch, "knee_enc": bad})
    t2 = t.copy()
    t2[2] = np.nan
    with pytest.raises(LimbfuseError, match="`t`, sample 2"):
        Trial(t2, ch)


def test_unknown_channel_incomplete_group_and_time_order():
    t, ch = gyro_trial()
    with pytest.raises(LimbfuseError, match="unknown channel `thigh_gyro_x`"):
        Trial(t, {"thigh_gyro_x": np.zeros(10)})
    # (session 32: a misspelt channel holding a NaN was reported as the NaN)
    with pytest.raises(LimbfuseError, match="unknown channel `thigh_gyro_x`"):
        Trial(t, {**ch, "thigh_gyro_x": np.r_[np.nan, np.zeros(9)]})
    with pytest.raises(LimbfuseError, match="incomplete channel group: channel `thigh_gyr_z` is missing"):
        Trial(t, {"thigh_gyr_x": np.zeros(10), "thigh_gyr_y": np.zeros(10)})
    t2 = t.copy()
    t2[5] = t2[4]
    with pytest.raises(LimbfuseError, match="time must increase strictly"):
        Trial(t2, ch)
    with pytest.raises(LimbfuseError, match="expected a 1-D array") as e:
        Trial(t, {"knee_enc": np.zeros((10, 2))})
    assert "three axes" not in str(e.value)
    with pytest.raises(LimbfuseError, match="gait phase"):
        Trial(t, ch, phase_ref=["XX"] * 10)


def test_a_three_axis_block_is_told_to_split_into_channels():
    """Session 31 audit: peers' tools hold a sensor's axes in one N x 3
    array; the message named only the shape. It now names the three SPEC
    channels and how to split the block (either orientation)."""
    t, _ = gyro_trial()
    for name, block, split in (
        ("thigh_gyr", np.zeros((10, 3)), "'thigh_gyr_y': a[:, 1]"),
        ("shank_acc_x", np.zeros((3, 10)), "'shank_acc_z': a[2]"),
        ("thigh_gyr", np.zeros((10, 3)).tolist(), "'thigh_gyr_y': a[:, 1]"),
    ):
        with pytest.raises(LimbfuseError, match="expected a 1-D array") as e:
            Trial(t, {name: block})
        msg = str(e.value)
        base = name.removesuffix("_x")
        assert f"`{base}_x`, `{base}_y`, `{base}_z`" in msg, msg
        assert split in msg, msg


def test_read_errors_name_file_line_and_column(tmp_path):
    with pytest.raises(LimbfuseError, match="nope.csv"):
        limbfuse.read_trial(tmp_path / "nope.csv")
    p = tmp_path / "bad.csv"
    p.write_text("# format: limbfuse-trial/1\nt,knee_enc\n0,1\n0.01,abc\n")
    with pytest.raises(LimbfuseError, match=r"bad.csv:4: column 2 \(`knee_enc`\): expected a number"):
        limbfuse.read_trial(p)
    p.write_text("t,knee_enc\n0,1\n0.01,NaN\n")
    with pytest.raises(LimbfuseError, match=r"bad.csv:3: column 2 .*NaN and inf are not allowed"):
        limbfuse.read_trial(p)


def test_cli_trial_reads_and_writes_back_byte_for_byte(cli, tmp_path):
    p = tmp_path / "w.csv"
    cli("simulate", "walking", "--duration", "3", "--seed", "5", "-o", p)
    tr = limbfuse.read_trial(p)
    assert len(tr) == 300 and "walking" in tr.meta["source"]
    q = tmp_path / "w2.csv"
    tr.write(q)
    assert p.read_bytes() == q.read_bytes()


def test_a_trial_slices_by_samples_and_by_time(tmp_path):
    """An audit: `trial[100:200]` raised "'Trial' object is not
    subscriptable"; a slice is a new trial of those samples (metadata kept,
    no longer the file: `source` None), `window(t0, t1)` the same by time."""
    tr = limbfuse.simulate("walking", duration=6, seed=2)
    tr.write(tmp_path / "w.csv")
    tr = limbfuse.read_trial(tmp_path / "w.csv")
    part = tr[100:350]
    assert len(part) == 250 and part.source is None and part.meta == tr.meta
    np.testing.assert_array_equal(part.t, tr.t[100:350])
    np.testing.assert_array_equal(part.channels["knee_enc"], tr.channels["knee_enc"][100:350])
    by_time = tr.window(1.0, 3.5)
    np.testing.assert_array_equal(by_time.t, part.t)
    est = limbfuse.estimate(part, "mjls", diagnostics="none")
    assert len(est) == 250 and limbfuse.evaluate(part, est)["n_samples"] == 250
    with pytest.raises(TypeError, match="sliced by samples"):
        tr[5]
    with pytest.raises(limbfuse.LimbfuseError, match="a step would change the sample rate"):
        tr[::2]
    with pytest.raises(limbfuse.LimbfuseError, match="no samples"):
        tr.window(100, 200)


def test_attributes_are_set_once_and_errors_pickle(walking_trial):
    """An audit: `trial.t = np.zeros(3)` was accepted (3 times beside
    1000-sample channels), and a LimbfuseError raised in a multiprocessing
    worker came back as a PicklingError (its class lived in `_native`)."""
    import pickle

    with pytest.raises(AttributeError, match="Trial.t is read-only"):
        walking_trial.t = np.zeros(3)
    with pytest.raises(AttributeError, match="cannot be deleted"):
        del walking_trial.channels
    est = limbfuse.estimate(walking_trial, "gyro-integration")
    with pytest.raises(AttributeError, match="Estimate.method is read-only"):
        est.method = "mjls"
    assert len(walking_trial.t) == len(walking_trial) and est.method == "gyro-integration"
    for kind in (limbfuse.LimbfuseError, limbfuse.InternalError):
        back = pickle.loads(pickle.dumps(kind("trial.csv:3: bad")))
        assert type(back) is kind and str(back) == "trial.csv:3: bad"
    with pytest.raises(TypeError, match="max_lag: expected an integer"):
        limbfuse.evaluate(walking_trial, est, max_lag=1.5)  # (was LimbfuseError; every option: TypeError)
    assert "sync_lag_samples" in limbfuse.evaluate(walking_trial, est, max_lag=np.int64(2))


def test_inspect_gives_the_align_verdict(cli, tmp_path):
    """`limbfuse inspect` says when `limbfuse align` cannot align a trial
    (a trunk IMU alone: no leg IMU), but `limbfuse.inspect` had no such key
    (session 29). It now has `align`, the CLI's `--json` object: needed,
    possible (True / False / None: not checked) and the reason, the text
    the CLI prints."""
    raw = limbfuse.simulate("walking", duration=12, mounting="random")
    back = Trial(raw.t, {k: v for k, v in raw.channels.items() if k.startswith("trunk_")}, raw.meta)
    assert limbfuse.inspect(raw)["align"] == {"needed": True, "possible": True, "reason": None}
    aligned = limbfuse.simulate("walking", duration=12)
    assert limbfuse.inspect(aligned)["align"] == {"needed": False, "possible": None, "reason": None}
    verdict = limbfuse.inspect(back)["align"]
    assert verdict["needed"] is True and verdict["possible"] is False
    assert verdict["reason"].startswith("no leg IMU")
    back.write(tmp_path / "back.csv")
    text = cli("inspect", tmp_path / "back.csv").stdout
    assert f"`limbfuse align` cannot align this trial: {verdict['reason']}\n" in text
    import json

    (cli_json,) = json.loads(cli("inspect", "--json", tmp_path / "back.csv").stdout)
    assert cli_json["align"] == verdict
