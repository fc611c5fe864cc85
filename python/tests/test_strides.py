"""`Estimate.strides`: the per-stride table (docs/GAIT_EVENTS.md "Stride
table"), the same rows and numbers as ``limbfuse evaluate --strides`` and
the strides ``evaluate`` scores; bad input raises clear errors."""

import warnings

import numpy as np
import pytest

import limbfuse
from limbfuse import LimbfuseError

pd = pytest.importorskip("pandas")

COLUMNS = [
    "foot", "ic_s", "fc_s", "end_s", "decided_s", "stride_time_s", "stance_time_s", "swing_time_s",
    "stride_length_m", "speed_m_s", "acc_clipped_s", "step_length_1_m", "step_length_2_m", "turn_rate_rad_s",
    "speed_withheld", "ic_ref_s", "fc_ref_s", "stride_time_ref_s", "stance_time_ref_s",
    "swing_time_ref_s", "speed_ref_m_s", "stride_length_ref_m",
]


@pytest.mark.parametrize(
    "rel, method", [("gaitmap-foot-walk/trial.csv", "gait-events"), ("mobgap-lowerback/HA001-test11-trial1.csv", "lowback-speed")]
)
def test_strides_reproduce_evaluate_and_the_cli(rel, method, cli, tmp_path, shared_data):
    trial = limbfuse.read_trial(shared_data(rel))
    est = limbfuse.estimate(trial, method)
    df = est.strides(trial)
    assert list(df.columns) == COLUMNS
    assert len(df) > 10 and df["ic_s"].is_monotonic_increasing
    ev = limbfuse.evaluate(trial, est)
    scored = df.dropna(subset=["speed_m_s", "speed_ref_m_s"])
    assert len(scored) == ev["n_strides"]
    assert abs((scored["speed_m_s"] - scored["speed_ref_m_s"]).abs().mean() - ev["speed_mae_mps"]) < 1e-12
    # the CLI's table, same rows and numbers
    est.write(tmp_path / "e.csv")
    cli("evaluate", shared_data(rel), tmp_path / "e.csv", "--strides", tmp_path / "s.csv")
    csv = pd.read_csv(tmp_path / "s.csv")
    assert list(csv.columns) == COLUMNS
    text = ["foot", "speed_withheld"]
    pd.testing.assert_frame_equal(df.drop(columns=text), csv.drop(columns=text), check_exact=True)
    for name in text:
        cells = [[x if isinstance(x, str) else "" for x in f[name]] for f in (df, csv)]
        assert cells[0] == cells[1], name
    if method == "lowback-speed":
        # the foot of the stride's first contact when the method told it (since 2026-12-07)
        assert {"left", "right"} <= set(df["foot"]) <= {"left", "right", "unknown"}
        withheld = df[df["speed_withheld"].notna()]
        assert len(withheld) > 0 and withheld["speed_m_s"].isna().all()
        assert set(withheld["speed_withheld"]) <= {"turn", "after_turn"}
        assert df["stance_time_s"].isna().all() and ev["n_stance_swing"] == 0
    else:
        assert set(df["foot"]) == {"left", "right"}
        assert df["fc_s"].notna().all() and df["step_length_1_m"].isna().all()


def test_strides_stance_and_swing_errors_are_evaluates(shared_data):
    trial = limbfuse.read_trial(shared_data("gaitmap-foot-walk/trial.csv"))
    est = limbfuse.estimate(trial, "gait-events")
    df = est.strides(trial)
    ev = limbfuse.evaluate(trial, est)
    assert np.allclose(df["stance_time_s"], df["fc_s"] - df["ic_s"])
    assert np.allclose(df["swing_time_s"], df["end_s"] - df["fc_s"])
    ref = df.dropna(subset=["fc_ref_s", "ic_ref_s"])
    assert np.allclose(ref["stance_time_ref_s"], ref["fc_ref_s"] - ref["ic_ref_s"])
    scored = df.dropna(subset=["stance_time_ref_s", "swing_time_ref_s"])
    assert len(scored) == ev["n_stance_swing"] > 10
    stance = 1e3 * (scored["stance_time_s"] - scored["stance_time_ref_s"])
    swing = 1e3 * (scored["swing_time_s"] - scored["swing_time_ref_s"])
    for got, key in [
        (stance.abs().mean(), "stance_time_mae_ms"), (stance.mean(), "stance_time_bias_ms"),
        (swing.abs().mean(), "swing_time_mae_ms"), (swing.mean(), "swing_time_bias_ms"),
    ]:
        assert abs(got - ev[key]) < 1e-9, key


def test_strides_without_a_trial_have_no_reference(shared_data):
    trial = limbfuse.read_trial(shared_data("gaitmap-foot-walk/trial.csv"))
    est = limbfuse.estimate(trial, "gait-events")
    df = est.strides()
    assert len(df) == len(est.strides(trial))
    refs = ["ic_ref_s", "fc_ref_s", "stride_time_ref_s", "stance_time_ref_s", "swing_time_ref_s",
            "speed_ref_m_s", "stride_length_ref_m"]
    assert df[refs].isna().all().all() and df["stance_time_s"].notna().all()
    assert np.allclose(df["speed_m_s"], df["stride_length_m"] / df["stride_time_s"], equal_nan=True)
    # a stride without a length turns (faster than 15 deg/s), and says so
    no_length = df["stride_length_m"].isna()
    assert no_length.sum() == 7
    assert (df.loc[no_length, "speed_withheld"] == "turn").all()
    assert (np.degrees(df.loc[no_length, "turn_rate_rad_s"].abs()) > 15).all()
    assert (np.degrees(df.loc[~no_length, "turn_rate_rad_s"].abs()) < 15).all()


def test_strides_of_a_method_without_strides_is_a_clear_error(walking_trial):
    est = limbfuse.estimate(walking_trial, "mjls")
    with pytest.raises(LimbfuseError, match="no stride columns"):
        est.strides()
    with pytest.raises(LimbfuseError, match="no stride columns"):
        est.strides(walking_trial)


def test_strides_bad_arguments(walking_trial):
    est = limbfuse.estimate(walking_trial, "mjls")
    with pytest.raises(TypeError, match="trial must be a limbfuse.Trial"):
        est.strides("walk.csv")
    with pytest.raises(TypeError):
        est.strides(walking_trial, allow_trial_mismatch="yes")


def test_strides_refuse_another_trial(walking_trial, shared_data):
    trial = limbfuse.read_trial(shared_data("gaitmap-foot-walk/trial.csv"))
    est = limbfuse.estimate(trial, "gait-events")
    other = limbfuse.Trial(trial.t, {n: v * 1.01 if "_ref" not in n else v for n, v in trial.channels.items()}, meta=trial.meta)
    with pytest.raises(LimbfuseError, match="another trial"):
        est.strides(other)
    with pytest.raises(LimbfuseError):
        est.strides(walking_trial)  # (other length)


def test_strides_in_a_window_pair_references_as_evaluate_scores_them(cli, tmp_path, shared_data):
    # (session 32: `evaluate` took a window, `strides` did not, so the table
    # paired references `evaluate(..., window=...)` had not scored)
    rel = "gaitmap-foot-walk/trial.csv"
    trial = limbfuse.read_trial(shared_data(rel))
    est = limbfuse.estimate(trial, "gait-events")
    whole = est.strides(trial)
    df = est.strides(trial, window=(5, 15))
    assert len(df) == len(whole)
    ev = limbfuse.evaluate(trial, est, window="5:15")
    scored = df.dropna(subset=["speed_m_s", "speed_ref_m_s"])
    assert 0 < len(scored) == ev["n_strides"] < len(whole.dropna(subset=["speed_m_s", "speed_ref_m_s"]))
    assert abs((scored["speed_m_s"] - scored["speed_ref_m_s"]).abs().mean() - ev["speed_mae_mps"]) < 1e-12
    est.write(tmp_path / "e.csv")
    cli("evaluate", shared_data(rel), tmp_path / "e.csv", "--window", "5:15", "--strides", tmp_path / "s.csv")
    csv = pd.read_csv(tmp_path / "s.csv")
    text = ["foot", "speed_withheld"]
    pd.testing.assert_frame_equal(df.drop(columns=text), csv.drop(columns=text), check_exact=True)
    with pytest.raises(ValueError, match="give the trial"):
        est.strides(window=(5, 15))
    with pytest.raises(LimbfuseError, match="window"):
        est.strides(trial, window="15:5")


def test_a_swing_clipped_at_2_g_is_warned_of(shared_data):
    """A 2 g foot sensor clips through the swing (the strides come out short,
    docs/GAIT_EVENTS.md "Clipped swings"): `estimate` warns, as the CLI does,
    and each stride's clipped time is in the estimate."""
    trial = limbfuse.read_trial(shared_data("gaitmap-foot-walk/trial.csv"))
    rail = 2 * 9.80665
    ch = {k: (np.clip(np.ma.filled(np.ma.asarray(v, dtype=float), np.nan), -rail, rail) if "_acc_" in k else v)
          for k, v in trial.channels.items()}
    clipped = limbfuse.Trial(trial.t, ch, {**trial.meta, "acc_range_m_s2": str(rail)})
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"of \d+ strides had a foot accelerometer at its full scale"):
        est = limbfuse.estimate(clipped, "gait-events")
    df = est.to_pandas()
    assert df["diag_stride_clipped_right"].max() > 0.2
    strides = est.strides(clipped)
    assert (strides["acc_clipped_s"] > 0.04).mean() > 0.9, strides["acc_clipped_s"].describe()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        est = limbfuse.estimate(trial, "gait-events")
    assert est.to_pandas()["diag_stride_clipped_right"].max() <= 0.01
    assert est.strides()["acc_clipped_s"].max() <= 0.01


def test_a_filter_warns_of_a_swing_clipped_at_2_g(shared_data):
    """`Filter` warns of clipped swings as `estimate` does: once per `run`
    that has them, and once per stream of `step`s."""
    trial = limbfuse.read_trial(shared_data("gaitmap-foot-walk/trial.csv"))
    rail = 2 * 9.80665
    names = [n for n in trial.channels if n.startswith("foot_")]
    ch = {n: np.clip(np.ma.filled(np.ma.asarray(trial.channels[n], dtype=float), np.nan), -rail, rail)
          for n in names}
    meta = {**trial.meta, "acc_range_m_s2": str(rail)}
    said = r"the filter's samples: \d+ of \d+ strides had a foot accelerometer at its full scale"
    f = limbfuse.Filter("gait-events", channels=names, meta=meta)
    with pytest.warns(limbfuse.LimbfuseWarning, match=said):
        f.run({"t": trial.t, **ch})
    g = limbfuse.Filter("gait-events", channels=names, meta=meta)
    with pytest.warns(limbfuse.LimbfuseWarning, match=said) as caught:
        for i in range(1200):
            g.step({"t": float(trial.t[i]), **{n: (None if np.isnan(ch[n][i]) else float(ch[n][i])) for n in names}})
    assert len([w for w in caught if issubclass(w.category, limbfuse.LimbfuseWarning)]) == 1


def test_an_accelerometer_rail_below_the_assumed_full_scale_is_warned_of(shared_data):
    """As `limbfuse estimate`: a 2 g sensor in a trial that states no range
    (16 g assumed) repeats its rail exactly; `estimate` says so and asks for
    the range. Stated, the gate rejects those readings and says that instead."""
    trial = limbfuse.read_trial(shared_data("independent-sim/walk-v1.6-s302.csv"))
    rail = 2 * 9.80665
    ch = {k: (np.clip(np.ma.filled(np.ma.asarray(v, dtype=float), np.nan), -rail, rail) if "_acc_" in k else v)
          for k, v in trial.channels.items()}
    said = r"chain on .*: accelerometer readings repeat exactly at their largest value: .*the foot accelerometer's x, y at \+-19.6133 m/s\^2 \(2.00 g;"
    with pytest.warns(limbfuse.LimbfuseWarning, match=said):
        limbfuse.estimate(limbfuse.Trial(trial.t, ch, trial.meta), "chain")
    stated = limbfuse.Trial(trial.t, ch, {**trial.meta, "acc_range_m_s2": str(rail)})
    with pytest.warns(limbfuse.LimbfuseWarning, match="accelerometer and 0 encoder reading") as caught:
        limbfuse.estimate(stated, "chain")
    assert not any("repeat exactly" in str(w.message) for w in caught)


def test_lowback_sides_as_the_cli_scores_them(cli, tmp_path, shared_data):
    """Session 48: `lowback-speed` tells each contact's foot (`diag_ic_right`
    / `diag_ic_left`, 2 s after it); `evaluate` scores them apart
    (`contact_sides`, as `limbfuse evaluate --json`) and a stride's `foot` is
    its first contact's side."""
    import json

    path = shared_data("mobgap-lowerback/HA001-test5-trial2.csv")
    trial = limbfuse.read_trial(path)
    est = limbfuse.estimate(trial, "lowback-speed")
    ev = limbfuse.evaluate(trial, est)
    assert ev["contact_sides"] == {"n_paired": 7, "n_sided": 7, "n_correct": 7, "accuracy_pct": 100.0}
    est.write(tmp_path / "e.csv")
    out = cli("evaluate", path, tmp_path / "e.csv", "--json").stdout
    assert json.loads(out)["contact_sides"] == ev["contact_sides"]
    right = est.to_pandas()["diag_ic_right"].dropna().to_numpy()
    strides = est.strides(trial)
    told = strides[strides["foot"] == "right"]["ic_s"].to_numpy()
    assert len(told) > 0 and all(np.any(np.abs(right - t) < 1e-9) for t in told)
