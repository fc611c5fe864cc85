"""Options and inputs an audit found unchecked (2026-12-04): each raised a
bare numpy/PyO3 error without the parameter's name, was silently coerced,
or left a file no reader took. Each now raises naming what is wrong."""

import threading

import numpy as np
import pytest

import limbfuse
from limbfuse import Filter, LimbfuseError, Trial, cohort


def test_evaluate_and_report_name_their_options(walking_trial, tmp_path):
    est = limbfuse.estimate(walking_trial, "gyro-integration")
    with pytest.raises(TypeError, match="offset_free: expected True or False"):
        limbfuse.evaluate(walking_trial, est, offset_free="no")  # was: truthy, ran offset-free
    with pytest.raises(TypeError, match="window: expected numbers"):
        limbfuse.evaluate(walking_trial, est, window=("a", "b"))
    # far beyond any trial: the trial's bound, not an OverflowError
    with pytest.raises(LimbfuseError, match="maximum lag"):
        limbfuse.evaluate(walking_trial, est, max_lag=10**20)
    for bad, kind in ((-5, LimbfuseError), (2**70, LimbfuseError), (0.5, TypeError), (True, TypeError)):
        with pytest.raises(kind, match="buckets"):
            limbfuse.report(walking_trial, [est], tmp_path / "r.html", buckets=bad)
    # one estimate, not a list of them: taken as one (a string was split into characters)
    est.write(tmp_path / "e.csv")
    walking_trial.write(tmp_path / "w.csv")
    assert limbfuse.report(tmp_path / "w.csv", str(tmp_path / "e.csv"), tmp_path / "r.html") > 0
    assert limbfuse.report(walking_trial, est, tmp_path / "r2.html") > 0


def test_strings_where_sequences_are_expected(tmp_path):
    with pytest.raises(TypeError, match="channels: expected a sequence of channel names"):
        Filter("gyro-integration", channels="thigh_gyr_z")
    with pytest.raises(TypeError, match="speeds: expected a sequence"):
        limbfuse.gait_library(tmp_path / "lib.json", "12")  # built speeds [1, 2] before


def test_filter_step_takes_masked_and_names_a_string(walking_trial):
    names = list(walking_trial.channels)
    f = Filter.for_trial(walking_trial, "gyro-integration")
    g = Filter.for_trial(walking_trial, "gyro-integration")
    for k in range(3):
        s = {"t": float(walking_trial.t[k]), **{n: float(walking_trial.channels[n][k]) for n in names}}
        if k == 1:
            masked = dict(s, thigh_gyr_z=np.ma.masked)
            none = dict(s, thigh_gyr_z=None)
            assert f.step(masked) == g.step(none)  # masked = missing, as in arrays
        else:
            assert f.step(s) == g.step(s)
    with pytest.raises(TypeError, match="sample `thigh_gyr_z`: expected a number or None"):
        f.step({"t": 1.0, "thigh_gyr_z": "abc"})
    with pytest.raises(TypeError, match="sample `thigh_gyr_z`: expected a number or None, found a bool"):
        f.step({"t": 1.0, "thigh_gyr_z": True})
    with pytest.raises(LimbfuseError, match="NaN|nan"):
        f.step({"t": 1.0, "thigh_gyr_z": float("nan")})


def test_a_filter_used_from_two_threads_says_so(walking_trial):
    f = Filter.for_trial(walking_trial, "mjls")
    arrays = {"t": walking_trial.t, **walking_trial.channels}
    errors = []

    def stepper():
        for k in range(2000):
            try:
                f.step({"t": 1000.0 + k * 0.01})
            except RuntimeError as e:
                errors.append(str(e))
                return
            except LimbfuseError:
                pass

    def runner():
        for _ in range(5):
            try:
                f.reset()
                f.run(arrays)
            except RuntimeError as e:
                errors.append(str(e))
                return
            except LimbfuseError:
                pass

    threads = [threading.Thread(target=stepper), threading.Thread(target=runner)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    # Contention is likely, not certain: whatever was raised names the cause.
    for e in errors:
        assert "in use by another thread" in e, e


def test_metadata_key_that_would_not_read_back_is_refused(tmp_path):
    t = np.arange(5) * 0.01
    ch = {f"thigh_gyr_{a}": np.zeros(5) for a in "xyz"}
    for key in ("a\nb", "a: b"):
        with pytest.raises(LimbfuseError, match="metadata key"):
            Trial(t, ch, {key: "c"}).write(tmp_path / "m.csv")
    Trial(t, ch, {"note": "two\nlines"}).write(tmp_path / "ok.csv")
    assert limbfuse.read_trial(tmp_path / "ok.csv").meta["note"] == "two lines"


def test_cohort_errors_name_the_path_given(tmp_path, walking_trial):
    for sub in ("s1", "s2"):
        (tmp_path / sub).mkdir()
    walking_trial.write(tmp_path / "s1" / "trial.csv")
    t = walking_trial.t
    Trial(t, {f"thigh_gyr_{a}": walking_trial.channels[f"thigh_gyr_{a}"] for a in "xyz"}).write(
        tmp_path / "s2" / "trial.csv"
    )
    with pytest.raises(LimbfuseError, match=r"s2[/\\]trial\.csv"):
        cohort.run(str(tmp_path / "s*" / "trial.csv"), "mjls")


def test_a_trial_file_is_not_an_estimate(walking_file):
    with pytest.raises(LimbfuseError, match="a trial file, not an estimate"):
        limbfuse.read_estimate(walking_file)


def test_evaluate_refuses_when_nothing_is_scored(walking_trial):
    """As `limbfuse evaluate`: an empty result was returned before."""
    est = limbfuse.estimate(walking_trial, "gyro-integration")
    with pytest.raises(LimbfuseError, match="no sample of the trial inside the window"):
        limbfuse.evaluate(walking_trial, est, window=(50, 60))
    events = limbfuse.estimate(walking_trial, "gait-events")
    with pytest.raises(LimbfuseError, match="the estimate has no angle column"):
        limbfuse.evaluate(walking_trial, events)


def test_no_measurement_no_estimate():
    """As `limbfuse estimate`: a run that gives no value on any row is an
    error (knee-kinematic wrote its prior, a constant 90 deg knee)."""
    seated = limbfuse.simulate("knee-fes", duration=3.0)
    n = len(seated)
    masked = {
        k: (np.ma.masked_all(n) if ("_acc_" in k or "_gyr_" in k) else v)
        for k, v in seated.channels.items()
    }
    trial = Trial(seated.t, masked, seated.meta)
    with pytest.raises(LimbfuseError, match="gave no estimate on any of its"):
        limbfuse.estimate(trial, "knee-kinematic")


def test_unknown_options_list_what_the_call_accepts(walking_trial):
    """An audit: `Filter(..., bogus=1)` did not list `calibration`, which it
    takes, and `estimate`'s list showed the internal `calibration_toml`."""
    with pytest.raises(LimbfuseError, match="unknown option `bogus`") as e:
        Filter.for_trial(walking_trial, "mjls", bogus=1)
    assert "calibration" in str(e.value) and "_toml" not in str(e.value)
    with pytest.raises(LimbfuseError, match="unknown option `bogus`") as e:
        limbfuse.estimate(walking_trial, "mjls", bogus=1)
    assert "calibration" in str(e.value) and "_toml" not in str(e.value)
