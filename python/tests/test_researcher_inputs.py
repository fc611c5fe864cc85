"""Inputs researchers hand the package, from an audit (session 28, branch
py28): each test names the input, what happened before, and what is
expected now."""

import copy
import os
import pickle

import numpy as np
import pytest

import limbfuse
from limbfuse import Filter, LimbfuseError, Trial

pd = pytest.importorskip("pandas")


def test_a_filter_is_not_copied_or_pickled_with_a_clear_error(walking_trial):
    """`copy.copy(filter)` returned a Filter sharing the original's running
    estimator: stepping the copy moved the original (its next sample was
    refused as "not after the previous sample"). `pickle` and
    `copy.deepcopy` said only "cannot pickle
    'limbfuse._native.NativeFilter' object". All three now raise a
    `TypeError` saying what to do, and the original is untouched."""
    f = Filter.for_trial(walking_trial, "gyro-integration")
    for make in (copy.copy, copy.deepcopy, pickle.dumps):
        with pytest.raises(TypeError, match="cannot be copied or pickled.*Filter.for_trial"):
            make(f)
    s = {"t": 0.0, **{n: float(walking_trial.channels[n][0]) for n in f.channels}}
    assert f.step(s)["t"] == 0.0


def test_integer_and_bool_options_take_numpy_scalars(walking_trial):
    """`window=np.int64(200)` (a value from numpy, e.g. `arange` in a
    sweep) was refused with "expected a non-negative integer", as was
    `seed=np.int64(3)`, and `smooth=np.bool_(True)` with "expected True or
    False"; `{"window": np.int64(200)}` in a params dict became `200.0` and
    was refused as a float. All are taken as their Python values now."""
    knee = limbfuse.simulate("knee", duration=20, seed=1)
    a = limbfuse.estimate(knee, "knee-selfalign", window=200)
    b = limbfuse.estimate(knee, "knee-selfalign", window=np.int64(200))
    assert np.array_equal(np.ma.filled(a.channels["knee"], 9.0), np.ma.filled(b.channels["knee"], 9.0))
    c = limbfuse.estimate(knee, "knee-selfalign", {"method": "knee-selfalign", "window": np.int64(200)})
    assert np.array_equal(np.ma.filled(a.channels["knee"], 9.0), np.ma.filled(c.channels["knee"], 9.0))
    assert len(limbfuse.simulate("walking", duration=1, seed=np.int64(3))) == 100
    limbfuse.estimate(walking_trial, "chain", smooth=np.bool_(True))
    # still refused: a float, a bool, a negative number; the value is named
    with pytest.raises(LimbfuseError, match=r"`window`: expected a non-negative integer, found 200\.5"):
        limbfuse.estimate(knee, "knee-selfalign", window=200.5)
    with pytest.raises(LimbfuseError, match="`window`: expected a non-negative integer, found True"):
        limbfuse.estimate(knee, "knee-selfalign", window=True)
    with pytest.raises(LimbfuseError, match="found -5"):
        limbfuse.simulate("walking", duration=1, seed=-5)


def test_filter_step_takes_pandas_na_as_missing(walking_trial):
    """A row of a nullable (`Float64`) DataFrame, `df.iloc[i].to_dict()`,
    holds `pd.NA` where a sample is missing: `step` raised `TypeError`
    ("expected a number or None, found <NA>"). It is a missing sample, as
    None is."""
    f = Filter.for_trial(walking_trial, "gyro-integration")
    g = Filter.for_trial(walking_trial, "gyro-integration")
    s = {"t": 0.0, **{n: float(walking_trial.channels[n][0]) for n in f.channels}}
    assert f.step(dict(s, thigh_gyr_z=pd.NA)) == g.step(dict(s, thigh_gyr_z=None))
    # a number numpy cannot hold: named, shortened
    with pytest.raises(TypeError, match=r"sample `thigh_gyr_z`: expected a number or None, found 1000+\.\.\.$"):
        f.step(dict(s, t=1.0, thigh_gyr_z=10**400))
    with pytest.raises(TypeError, match="step: expected a dict"):
        f.step(None)


def test_a_series_from_another_dataframe_is_refused_not_paired_by_position(walking_trial):
    """`Trial(df["t"], {"thigh_gyr_z": other["thigh_gyr_z"]})` with `other`
    sorted or filtered otherwise paired values with times by position,
    silently (pandas users expect labels to align). Series whose index is
    not `t`'s are refused now; one DataFrame's Series, or arrays, are
    taken as before."""
    df = walking_trial.to_pandas()
    gyr = ["thigh_gyr_x", "thigh_gyr_y", "thigh_gyr_z"]
    shuffled = df.sample(frac=1.0, random_state=1)
    with pytest.raises(LimbfuseError, match="channel `thigh_gyr_x`: its pandas index is not `t`'s"):
        Trial(df["t"], {c: shuffled[c] for c in gyr})
    ok = Trial(df["t"], {c: df[c] for c in gyr})
    assert np.array_equal(ok.channels["thigh_gyr_z"], df["thigh_gyr_z"].to_numpy())
    Trial(df["t"], {c: shuffled[c].to_numpy() for c in gyr})  # arrays: by position, as asked
    f = Filter("gyro-integration", channels=gyr)
    with pytest.raises(LimbfuseError, match="pandas index is not `t`'s"):
        f.run({"t": df["t"], **{c: shuffled[c] for c in gyr}})


def test_dataframe_shapes_researchers_have_are_named(walking_trial):
    """A DataFrame with a column twice raised AttributeError "'DataFrame'
    object has no attribute 'dtype'" (so did a one-column DataFrame given as
    a channel); MultiIndex columns "has no `t` column"; a dict given to
    `from_pandas` and a list as `channels` AttributeError. Each is named
    now."""
    df = walking_trial.to_pandas()
    with pytest.raises(LimbfuseError, match="the column `thigh_gyr_z` more than once"):
        Trial.from_pandas(pd.concat([df, df[["thigh_gyr_z"]]], axis=1))
    with pytest.raises(TypeError, match="channel `knee_enc`: expected one column"):
        Trial(df["t"], {"knee_enc": df[["knee_enc"]]})
    multi = df.copy()
    multi.columns = pd.MultiIndex.from_tuples([("s1", c) for c in df.columns])
    with pytest.raises(LimbfuseError, match="MultiIndex.*get_level_values"):
        Trial.from_pandas(multi)
    with pytest.raises(TypeError, match="from_pandas: expected a pandas DataFrame, found dict"):
        Trial.from_pandas({"t": [0.0, 0.01]})
    with pytest.raises(TypeError, match="channels: expected a mapping"):
        Trial(df["t"], [("knee_enc", df["knee_enc"])])


def test_time_as_durations_is_seconds_and_dates_are_refused_with_a_recipe(walking_trial):
    """A `t` of pandas Timedelta (a `TimedeltaIndex`, `pd.to_timedelta`) or
    numpy `timedelta64` was refused as "not numeric"; it is elapsed time and
    is taken in seconds now. Dates (`datetime64`, a `DatetimeIndex`, with
    or without a time zone: "found dtype object") are refused with how to
    make seconds of them; a `Float64` `t` with `pd.NA` says time cannot be
    missing (it said "mark missing samples with a masked array")."""
    df = walking_trial.to_pandas()
    td = df.assign(t=pd.to_timedelta(df["t"], unit="s"))
    a = Trial.from_pandas(td)
    assert np.allclose(a.t, walking_trial.t, rtol=0, atol=1e-9)
    b = Trial.from_pandas(td.set_index("t"))
    assert np.array_equal(a.t, b.t)
    t = np.round(walking_trial.t * 1e9).astype(np.int64).astype("timedelta64[ns]")
    assert np.array_equal(Trial(t, {}).t, a.t)
    for dates in (
        df.assign(t=pd.Timestamp("2024-01-01") + pd.to_timedelta(df["t"], unit="s")),
        df.assign(t=pd.to_datetime(df["t"], unit="s").dt.tz_localize("UTC")),
    ):
        with pytest.raises(TypeError, match=r"found dates and times.*total_seconds"):
            Trial.from_pandas(dates)
    na = df.astype({"t": "Float64"})
    na.loc[3, "t"] = pd.NA
    with pytest.raises(LimbfuseError, match=r"`t`, sample 3: time cannot be missing"):
        Trial.from_pandas(na)
    stamped = df.set_index(pd.to_datetime(df["t"], unit="s").rename("time")).drop(columns="t")
    with pytest.raises(LimbfuseError, match="no `t` column or index.*index `time` holds datetime64"):
        Trial.from_pandas(stamped)


def test_bytes_paths_and_huge_times_in_messages(walking_trial, tmp_path):
    """A `bytes` path (`os.fsencode`, `glob` of bytes) raised "argument
    'path': 'bytes' object cannot be converted to 'PyString'"; it is a path
    as `open` takes it now. A time of 1e300 was printed as 301 digits in
    "time must increase strictly"; it is `1e300` now."""
    path = os.fsencode(str(tmp_path / "w.csv"))
    walking_trial.write(path)
    back = limbfuse.read_trial(path)
    assert len(back) == len(walking_trial)
    limbfuse.estimate(back, "gyro-integration").write(os.fsencode(str(tmp_path / "e.csv")))
    assert len(limbfuse.read_estimate(os.fsencode(str(tmp_path / "e.csv")))) == len(back)
    with pytest.raises(LimbfuseError, match=r"time must increase strictly, but 1e300 follows 1e300$"):
        Trial(walking_trial.t + 1e300, {})


def test_gait_library_names_a_speed_that_is_not_a_number(tmp_path):
    """`gait_library(path, ["a"])` raised "could not convert string to
    float: 'a'" without saying which argument."""
    with pytest.raises(TypeError, match=r"speeds\[1\]: expected a number, found 'a'"):
        limbfuse.gait_library(tmp_path / "lib.json", [0.6, "a"])
    with pytest.raises(TypeError, match="mass: expected a number, found '80'"):
        limbfuse.gait_library(tmp_path / "lib.json", [0.6], mass="80")


def test_cohort_names_a_bytes_path_a_bad_item_a_bad_client_and_evaluate_options(walking_file):
    """`cohort.run(b"walk.csv", ...)` took the bytes for a list of paths and
    said "expected str, bytes or os.PathLike object, not int" (so did a list
    holding a number); `client="tcp://..."` raised AttributeError "'str'
    object has no attribute 'nthreads'"; `max_lag=3` among the keywords was
    "unknown option" of estimate, without saying it belongs to evaluate."""
    from limbfuse import cohort

    df = cohort.run(os.fsencode(str(walking_file)), "gyro-integration", scheduler="sync")
    assert set(df["trial"]) == {str(walking_file)}
    with pytest.raises(TypeError, match="item 1 of the list: expected a trial file path or a limbfuse.Trial, found int"):
        cohort.run([str(walking_file), 3], "gyro-integration")
    with pytest.raises(TypeError, match="client: expected a dask.distributed Client"):
        cohort.run(str(walking_file), "gyro-integration", client="tcp://127.0.0.1:8786")
    with pytest.raises(LimbfuseError, match=r"`max_lag` is an option of evaluate.*eval_options=\{'max_lag': \.\.\.\}"):
        cohort.run(str(walking_file), "gyro-integration", max_lag=3)
