"""limbfuse.cohort when trials fail: `on_error="record"`, `--keep-going`,
worker deaths, Ctrl-C, duplicates, patterns and folders, row order."""

import os
import signal
import threading
import time
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import limbfuse
from limbfuse import LimbfuseError, LimbfuseWarning, cohort

SHARED = Path(__file__).resolve().parents[2].parent / "shared" / "data"


@pytest.fixture(scope="module")
def trials(tmp_path_factory):
    """Four short walking trials (the first three times longer), a broken
    one, a README.md and a parameter .toml beside them."""
    d = tmp_path_factory.mktemp("trials")
    for k in range(4):
        limbfuse.simulate("walking", duration=6.0 if k == 0 else 2.0, seed=300 + k).write(d / f"w{k}.csv")
    (d / "bad.csv").write_text("t,knee_enc\n0,x\n")
    (d / "README.md").write_text("# the trials\n")
    (d / "w0.toml").write_text("[model]\nmass = 4.5\n")
    return d


def good(d):
    return [str(d / f"w{k}.csv") for k in range(4)]


class ExitingTrial(limbfuse.Trial):
    """A trial that ends the process estimating it when that is a Dask
    worker (as a crash in native code would)."""

    __slots__ = ()

    def __reduce__(self):
        return (exiting_trial, (self.t, dict(self.channels), self.meta))

    def _native(self):
        try:
            from distributed import get_worker

            get_worker()
        except (ImportError, ValueError):
            return super()._native()
        os._exit(3)


def exiting_trial(t, channels, meta):
    return ExitingTrial(t, channels, meta)


def test_record_gives_the_other_trials_and_one_error_row_per_failure(trials):
    """`on_error="record"`: the broken trial is one row (channel None, its
    message naming the file and line in `error`), the other trials' rows
    are those of a run without it, in the order given (a longer first
    trial finishes last). Before, one bad file lost the whole run."""
    paths = [good(trials)[2], str(trials / "bad.csv"), *good(trials)[:2]]
    df = cohort.run(paths, "mjls", on_error="record")
    assert list(df["trial"].unique()) == paths
    bad = df[df["trial"] == paths[1]]
    assert len(bad) == 1 and pd.isna(bad["channel"].iloc[0]) and bad["rmse_deg"].isna().all()
    assert bad["error"].iloc[0].startswith(f"{paths[1]}:2: column 2 (`knee_enc`)")
    ok = df[df["trial"] != paths[1]]
    assert ok["error"].isna().all()
    ref = cohort.run([p for p in paths if p != paths[1]], "mjls", scheduler="sync")
    pd.testing.assert_frame_equal(ok.drop(columns="error").reset_index(drop=True), ref, check_exact=True, check_dtype=False)
    # no failure: the `error` column is still there, all None
    assert cohort.run(good(trials)[1:3], "mjls", on_error="record")["error"].isna().all()
    with pytest.raises(LimbfuseError, match=r'on_error: expected "raise" or "record", found \'skip\''):
        cohort.run(trials, "mjls", on_error="skip")


def test_a_trial_that_cannot_be_scored_fails_like_any_other(trials, tmp_path):
    """A trial without reference columns: estimate works, evaluate has
    nothing to score. Raised (naming the file, not `<in-memory trial>`) or
    recorded; never a trial without a row. In-memory trials are named by
    their place in the list (before, every error said `<trial 0>`)."""
    tr = limbfuse.read_trial(good(trials)[1])
    noref = limbfuse.Trial(tr.t, {k: v for k, v in tr.channels.items() if not k.endswith("_ref")}, tr.meta)
    noref.write(tmp_path / "noref.csv")
    with pytest.raises(LimbfuseError, match=r"noref.csv: the trial has no reference angle column") as e:
        cohort.run([tmp_path / "noref.csv"], "mjls", scheduler="sync")
    assert "<in-memory trial>" not in str(e.value)
    df = cohort.run([limbfuse.Trial(tr.t, tr.channels, tr.meta), noref], "mjls", on_error="record", scheduler="sync")
    assert list(df["trial"].unique()) == ["<trial 0>", "<trial 1>"]
    assert df["error"].iloc[-1].startswith("<trial 1>: the trial has no reference angle column")


def test_folders_patterns_and_duplicates(trials, tmp_path):
    """A folder runs its trial files only (not README.md, not the .toml);
    a pattern skips sub-folders; several patterns or folders in a list (or
    on the command line) are each expanded (before: read as file names);
    a file given twice runs once, with a warning (before: its rows twice);
    a pattern or folder with no trial file is an error naming it."""
    df = cohort.run(trials, "mjls", on_error="record", scheduler="sync")
    assert [os.path.basename(t) for t in df["trial"].unique()] == ["bad.csv", "w0.csv", "w1.csv", "w2.csv", "w3.csv"]
    (tmp_path / "sub.csv").mkdir()
    with pytest.raises(LimbfuseError, match="no trial file matches"):
        cohort.run(str(tmp_path / "*.csv"), "mjls")
    with pytest.raises(LimbfuseError, match=r"the folder `.*` holds no trial file \(\*.csv, \*.arrow, \*.feather\)"):
        cohort.run(tmp_path, "mjls")
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        df = cohort.run([good(trials)[1], str(trials / "w[12].csv"), f"{trials}/../{trials.name}/w3.csv",
                         str(trials / "w3.csv")], "mjls", scheduler="sync")
    assert [os.path.basename(t) for t in df["trial"].unique()] == ["w1.csv", "w2.csv", "w3.csv"]
    said = [str(x.message) for x in w if issubclass(x.category, LimbfuseWarning)]
    assert said == [f"cohort: `{good(trials)[1]}` is given twice: it runs once",
                    f"cohort: `{trials / 'w3.csv'}` is given twice (as `{trials}/../{trials.name}/w3.csv`): it runs once"]


def test_params_as_a_dict_a_file_or_text_give_the_same_rows(trials, tmp_path):
    """`params` as a dict, a TOML file (str or Path) and TOML text: the same
    figures; a missing file is refused before any trial runs."""
    paths = good(trials)[1:3]
    toml = tmp_path / "p.toml"
    toml.write_text("p0_angle_sigma = 0.5\naccel_hold_s = 0.2\n")
    dfs = [cohort.run(paths, "mjls", p, scheduler="sync") for p in (str(toml), toml, toml.read_text())]
    dfs.append(cohort.run(paths, "mjls", {"p0_angle_sigma": 0.5, "accel_hold_s": 0.2}, scheduler="sync"))
    for df in dfs[1:]:
        pd.testing.assert_frame_equal(df, dfs[0], check_exact=True)
    assert not dfs[0]["rmse_deg"].equals(cohort.run(paths, "mjls", scheduler="sync")["rmse_deg"])
    with pytest.raises(LimbfuseError, match="params `.*nope.toml`: no such file"):
        cohort.run(paths, "mjls", tmp_path / "nope.toml", on_error="record")


def test_keep_going_writes_the_others_and_exits_1_with_a_summary(trials, tmp_path, capsys):
    """`limbfuse-cohort --keep-going`: the metrics of the good trials and
    the failed one's row are written, "1 of 5 trials failed:" and its
    message on stderr, exit status 1; several patterns are expanded."""
    out = tmp_path / "m.csv"
    argv = [str(trials / "w[12].csv"), str(trials / "bad.csv"), "--method", "mjls", "--quiet", "-o", str(out)]
    assert cohort.main(argv) == 1
    assert "error: " in capsys.readouterr().err and not out.exists()
    assert cohort.main([*argv, "--keep-going"]) == 1
    err = capsys.readouterr().err
    assert f"1 of 3 trials failed:\n  {trials / 'bad.csv'}:2: column 2" in err
    df = pd.read_csv(out)
    assert df["trial"].nunique() == 3 and df["error"].notna().sum() == 1 and len(df) == 2 * 7 + 1
    assert cohort.main([*argv[:1], *argv[2:], "-k"]) == 0
    assert "failed" not in capsys.readouterr().err


def test_mixed_trial_kinds_in_record_mode(tmp_path):
    """`lowback-speed` over every CSV of ../shared/data: the lower-back
    walks are scored, every other file has its reason; the run succeeds."""
    if not SHARED.is_dir():
        pytest.skip(f"the shared data {SHARED} is absent (../shared/data next to the repository)")
    df = cohort.run(str(SHARED / "mobgap-lowerback" / "*.csv"), "lowback-speed", on_error="record")
    assert df["error"].isna().all() and (df["channel"] == "events").all()
    df = cohort.run([SHARED / "knee-rig" / "Trial_01.csv", SHARED / "independent-sim" / "bslip-v0.85-s21.csv",
                     SHARED / "mobgap-lowerback" / "HA001-test5-trial2.csv"], "lowback-speed", on_error="record")
    assert list(df["channel"].fillna("")) == ["", "", "events"]
    assert "raw knee-rig log" in df["error"].iloc[0] and "no trunk_acc_x/y/z" in df["error"].iloc[1]
    assert df["error"].iloc[1].startswith(f"{SHARED / 'independent-sim' / 'bslip-v0.85-s21.csv'}: method")


def test_ctrl_c_stops_the_threads_before_their_next_trial(monkeypatch):
    """Ctrl-C during a threaded run: KeyboardInterrupt, and the running
    tasks stop before their next trial (before, each thread ran on through
    its chunk: here 16 trials each)."""
    calls = []

    def slow(trial, *args, **kwargs):
        calls.append(trial)
        time.sleep(0.05)
        return [{"trial": trial, "method": "mjls", "channel": "knee"}]

    monkeypatch.setattr(cohort, "evaluate_trial", slow)
    monkeypatch.setattr(cohort.os, "cpu_count", lambda: 1)  # 4 chunks of 16
    main = threading.main_thread().ident
    threading.Timer(0.3, signal.pthread_kill, (main, signal.SIGINT)).start()
    with pytest.raises(KeyboardInterrupt):
        cohort.run([f"t{k}.csv" for k in range(64)], "mjls")
    n = len(calls)
    time.sleep(1.0)
    assert len(calls) <= n + 2 < 32


def test_a_trial_that_kills_its_worker(trials):
    """On a LocalCluster, a large in-memory trial, and a trial that makes its
    worker process exit: with
    "record" its row says the worker died and the other trials' rows are
    there, in order; with "raise" a LimbfuseError names the trials of the
    task (before: `KilledWorker` naming a task key, and the run lost)."""
    distributed = pytest.importorskip("distributed")
    import dask

    tr = limbfuse.read_trial(good(trials)[1])
    killer = ExitingTrial(tr.t, tr.channels, tr.meta)
    paths = [good(trials)[2], killer]
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}), distributed.LocalCluster(
        n_workers=3, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        # a large in-memory trial (12 MB) is scattered, not put in the task
        # graph (before: "Sending large graph of size 12 MiB")
        big = limbfuse.Trial(np.arange(750_000) / 100.0, {"knee_enc": np.zeros(750_000)})
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            bigdf = cohort.run([big], "gyro-integration", client=client, on_error="record")
        assert not [x for x in w if "large graph" in str(x.message)]
        assert bigdf["error"].iloc[0].startswith("<trial 0>: ")
        df = cohort.run(paths, "mjls", client=client, on_error="record")
        with pytest.raises(LimbfuseError, match=r"^cohort: <trial 0>: the Dask worker running it died"):
            cohort.run([killer], "mjls", client=client)
    assert list(df["trial"].unique()) == [paths[0], "<trial 1>"] and len(df) == 8
    assert df["error"].iloc[7] == "<trial 1>: the Dask worker running it died (KilledWorker; the worker's log may say why)"
    assert df["error"].iloc[:7].isna().all()
