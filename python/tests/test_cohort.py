"""limbfuse.cohort: Dask over a generated cohort equals the serial loop."""

import pandas as pd
import pytest

import limbfuse
from limbfuse import LimbfuseError, cohort

N_TRIALS = 12


@pytest.fixture(scope="module")
def cohort_dir(tmp_path_factory):
    d = tmp_path_factory.mktemp("cohort")
    for k in range(N_TRIALS):
        limbfuse.simulate("walking", duration=4.0, seed=100 + k, speed=0.8 + 0.05 * k).write(d / f"s{k:02}.csv")
    return d


def serial(paths, method):
    rows = []
    for p in paths:
        tr = limbfuse.read_trial(p)
        rows += cohort.rows_of(str(p), limbfuse.evaluate(tr, limbfuse.estimate(tr, method)))
    return pd.DataFrame(rows, columns=list(cohort.COLUMNS))


def test_threads_equal_the_serial_loop(cohort_dir):
    assert limbfuse.cohort is cohort
    paths = sorted(str(p) for p in cohort_dir.glob("*.csv"))
    df = cohort.run(str(cohort_dir / "*.csv"), "mjls")
    assert len(df) == N_TRIALS * 7 and df["trial"].nunique() == N_TRIALS
    pd.testing.assert_frame_equal(df, serial(paths, "mjls"), check_exact=True)
    # a directory and a list give the same
    pd.testing.assert_frame_equal(cohort.run(cohort_dir, "mjls", scheduler="sync"), df, check_exact=True)


def test_local_cluster_of_two_workers(cohort_dir):
    distributed = pytest.importorskip("distributed")
    paths = sorted(str(p) for p in cohort_dir.glob("*.csv"))
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        df = cohort.run(paths, "local", client=client)
    pd.testing.assert_frame_equal(df, serial(paths, "local"), check_exact=True)


def test_cohort_errors(cohort_dir, tmp_path):
    with pytest.raises(LimbfuseError, match="no trial file matches"):
        cohort.run(str(tmp_path / "*.csv"), "mjls")
    with pytest.raises(LimbfuseError, match="unknown method"):
        cohort.run(str(cohort_dir / "*.csv"), "nope", scheduler="sync")
    bad = tmp_path / "bad.csv"
    bad.write_text("t,knee_enc\n0,x\n")
    with pytest.raises(LimbfuseError, match="bad.csv:2"):
        cohort.run([bad], "mjls", scheduler="sync")


def test_command_line(cohort_dir, tmp_path, capsys):
    out = tmp_path / "m.csv"
    assert cohort.main([str(cohort_dir / "*.csv"), "--method", "gyro-integration", "-o", str(out), "--quiet"]) == 0
    df = pd.read_csv(out)
    assert set(df.columns) == set(cohort.COLUMNS) and df["trial"].nunique() == N_TRIALS
    assert cohort.main([str(cohort_dir / "*.csv"), "--method", "nope", "--quiet"]) == 1
    assert "unknown method" in capsys.readouterr().err


def test_issue_19_gait_event_cohort_has_one_row_per_trial(tmp_path):
    """`gait-events` over trials with a walking-speed reference: one row per
    trial (channel `events`) with evaluate's event and stride-speed figures,
    equal to the serial loop (before, the cohort of a gait-events or
    lowback-speed method was an empty DataFrame)."""
    paths = []
    for k in range(4):
        speed = 0.9 + 0.1 * k
        tr = limbfuse.simulate("walking", duration=10.0, seed=200 + k, speed=speed)
        tr = limbfuse.Trial(tr.t, {**tr.channels, "speed_ref": [speed] * len(tr)}, tr.meta)
        tr.write(tmp_path / f"w{k}.csv")
        paths.append(str(tmp_path / f"w{k}.csv"))
    df = cohort.run(paths, "gait-events", scheduler="sync")
    assert len(df) == 4 and (df["channel"] == "events").all()
    assert set(cohort.EVENT_METRICS) <= set(df.columns)
    assert (df["n_strides"] > 0).all() and df["speed_mae_mps"].notna().all()
    rows = []
    for p in paths:
        tr = limbfuse.read_trial(p)
        rows += cohort.rows_of(p, limbfuse.evaluate(tr, limbfuse.estimate(tr, "gait-events")))
    expected = pd.DataFrame(rows, columns=cohort.columns_of(rows))
    for c in cohort.EVENT_METRICS:  # (no contact reference: None, a NaN column since session 31)
        if expected[c].dtype == object:
            expected[c] = pd.to_numeric(expected[c])
    pd.testing.assert_frame_equal(df, expected, check_exact=True)


def test_in_memory_trials_arrow_files_and_estimate_keywords(tmp_path, cohort_dir):
    """An audit: a list of `Trial`s raised TypeError, a directory skipped its
    `.arrow` files, `diagnostics="none"` was an unexpected keyword, and a
    misspelt method was reported as the first trial's error."""
    trials = [limbfuse.read_trial(cohort_dir / "s00.csv"), limbfuse.simulate("walking", duration=4.0, seed=3)]
    df = cohort.run(trials, "mjls", diagnostics="none", scheduler="sync")
    assert list(df["trial"].unique()) == ["s00.csv", "<trial 1>"]
    ref = cohort.run([cohort_dir / "s00.csv"], "mjls", scheduler="sync")
    pd.testing.assert_frame_equal(
        df[df["trial"] == "s00.csv"].drop(columns="trial").reset_index(drop=True),
        ref.drop(columns="trial"),
        check_exact=True,
    )
    d = tmp_path / "mixed"
    d.mkdir()
    trials[1].write(d / "a.csv")
    trials[1].write(d / "b.arrow")
    mixed = cohort.run(d, "mjls", scheduler="sync")
    assert [p.rsplit("/", 1)[-1] for p in mixed["trial"].unique()] == ["a.csv", "b.arrow"]
    with pytest.raises(LimbfuseError, match=r"^cohort: unknown method `mjlss` \(one of: gyro-integration"):
        cohort.run(d, "mjlss")


def test_arguments_are_checked_first_and_the_first_failing_trial_is_named(cohort_dir, tmp_path, capsys):
    """An audit: `--params missing.toml` and `--window 10:2` failed on every
    trial and were reported as a different trial's error at every run;
    `--workers -1` hung, `--workers 0` used threads without a word, `-o` in
    a missing folder failed after the whole run, an unparsable `--address`
    gave a traceback."""
    pattern = str(cohort_dir / "*.csv")
    with pytest.raises(LimbfuseError, match="params `missing.toml`: no such file"):
        cohort.run(pattern, "mjls", "missing.toml")
    with pytest.raises(LimbfuseError, match="window `10:2`: expected START:END"):
        cohort.run(pattern, "mjls", eval_options={"window": "10:2"})
    # Trials 3 and 7 fail: whichever task ends first, the error is trial 3's.
    paths = sorted(str(p) for p in cohort_dir.glob("*.csv"))
    for k in (3, 7):
        broken = tmp_path / f"broken{k}.csv"
        broken.write_text("t,knee_enc\n0,x\n")
        paths[k] = str(broken)
    for _ in range(3):
        with pytest.raises(LimbfuseError, match="broken3.csv:2"):
            cohort.run(paths, "mjls", scheduler="threads")
    for argv in (["--workers", "-1"], ["--workers", "0"]):
        with pytest.raises(SystemExit):
            cohort.main([pattern, "--method", "mjls", "--quiet", *argv])
        assert "expected a positive number of workers" in capsys.readouterr().err
    assert cohort.main([pattern, "--method", "mjls", "--quiet", "-o", str(tmp_path / "no" / "m.csv")]) == 1
    assert "the folder" in capsys.readouterr().err
    assert cohort.main([pattern, "--method", "mjls", "--quiet", "--address", "foo"]) == 1
    assert "--address foo" in capsys.readouterr().err


def test_event_cohort_carries_stance_and_swing_errors(tmp_path):
    """Session 32: the stance and swing time errors `evaluate` gives a
    gait-events estimate are cohort columns too (they were left out)."""
    paths = []
    for k in range(2):
        tr = limbfuse.simulate("walking", duration=20.0, seed=300 + k, gait_reference=True)
        tr.write(tmp_path / f"g{k}.csv")
        paths.append(str(tmp_path / f"g{k}.csv"))
    df = cohort.run(paths, "gait-events", scheduler="sync")
    for p, (_, row) in zip(paths, df.iterrows()):
        tr = limbfuse.read_trial(p)
        ev = limbfuse.evaluate(tr, limbfuse.estimate(tr, "gait-events"))
        assert ev["n_stance_swing"] > 0
        for k in ("stance_time_mae_ms", "stance_time_bias_ms", "swing_time_mae_ms", "swing_time_bias_ms", "n_stance_swing"):
            assert row[k] == ev[k], k
