//! Issue 18 item 7: every command bounded and atomic. Each case exits with
//! status 1 and a message naming the flag or files, never aborts, and
//! leaves no partial output file behind.

use std::path::Path;
use std::process::Output;

use crate::support::limbfuse;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn assert_ok(o: &Output) {
    assert_eq!(o.status.code(), Some(0), "stderr: {}", stderr(o));
}

/// Exit 1 (not 134 from an abort, not 2), no panic, every needle in stderr.
fn assert_user_error(o: &Output, needles: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    assert!(
        !e.contains("panicked") && !e.contains("memory allocation"),
        "{e}"
    );
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
}

/// The names in `dir`, sorted (temporary files start with `.`).
fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// A 10 s walking trial (1000 samples) and its gyro-integration estimate.
fn trial_and_estimate(dir: &Path, seed: &str, trial: &str, estimate: &str) {
    assert_ok(&limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "10",
            "--seed",
            seed,
            "-o",
            trial,
        ],
        dir,
    ));
    assert_ok(&limbfuse(
        &[
            "estimate",
            "--method",
            "gyro-integration",
            trial,
            "-o",
            estimate,
        ],
        dir,
    ));
}

#[test]
fn issue_18_huge_max_lag_is_a_user_error() {
    let d = tempfile::tempdir().unwrap();
    trial_and_estimate(d.path(), "3", "t.csv", "e.csv");
    // Before: an abort (4 TB allocation), 24 GB then killed, and `n 1` at a
    // lag of -5999 samples with exit 0.
    for lag in ["99999999999", "100000000", "100000", "501"] {
        let o = limbfuse(&["evaluate", "t.csv", "e.csv", "--max-lag", lag], d.path());
        assert_user_error(
            &o,
            &[
                &format!("--max-lag {lag}"),
                "t.csv (1000 samples)",
                "at most 500",
            ],
        );
    }
    let o = limbfuse(
        &["evaluate", "t.csv", "e.csv", "--max-lag", "500", "--json"],
        d.path(),
    );
    assert_ok(&o);
    assert!(String::from_utf8_lossy(&o.stdout).contains("sync_lag"));
}

#[test]
fn issue_18_huge_duration_is_a_user_error() {
    let d = tempfile::tempdir().unwrap();
    let commands: [&[&str]; 7] = [
        &["simulate", "walking", "-o", "out.csv"],
        &["simulate", "knee", "-o", "out.csv"],
        &["simulate", "knee-fes", "-o", "out.csv"],
        &["simulate", "fixed-hip", "-o", "out.csv"],
        &["simulate", "bslip", "-o", "out.csv"],
        &["montecarlo", "--runs", "1", "-o", "out.csv"],
        &["demo", "--out", "demo"],
    ];
    for cmd in commands {
        let mut args = cmd.to_vec();
        args.extend(["--duration", "1e8"]);
        let o = limbfuse(&args, d.path());
        assert_user_error(&o, &["--duration 100000000", "86400 s", "--force"]);
        for bad in [
            "--duration=nan",
            "--duration=-5",
            "--duration=inf",
            "--duration=0",
        ] {
            let mut args = cmd.to_vec();
            args.push(bad);
            let o = limbfuse(&args, d.path());
            assert_user_error(&o, &["--duration", "positive number of seconds"]);
        }
        assert_eq!(listing(d.path()), Vec::<String>::new(), "{cmd:?}");
    }
    // The sample count is capped too: 1 h at 1 GHz.
    let o = limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "3600",
            "--imu-rate",
            "1e9",
            "-o",
            "out.csv",
        ],
        d.path(),
    );
    assert_user_error(&o, &["--imu-rate", "samples", "--force"]);
    assert_eq!(listing(d.path()), Vec::<String>::new());
}

#[test]
fn issue_18_a_failing_run_leaves_no_output_file() {
    let d = tempfile::tempdir().unwrap();
    assert_ok(&limbfuse(
        &["simulate", "walking", "--duration", "5", "-o", "t.csv"],
        d.path(),
    ));
    let text = std::fs::read_to_string(d.path().join("t.csv")).unwrap();
    // A row broken in two by a line break (a file cut short at its end is
    // read without its last line since 2026-12-07: docs/ROBUST_INPUT.md 2o).
    let n = text.len() * 2 / 3;
    std::fs::write(
        d.path().join("cut.csv"),
        format!("{}\n{}", &text[..n], &text[n..]),
    )
    .unwrap();
    let o = limbfuse(
        &["estimate", "--method", "mjls", "cut.csv", "-o", "e.csv"],
        d.path(),
    );
    assert_user_error(&o, &["cut.csv:", "cells"]);
    assert_eq!(listing(d.path()), vec!["cut.csv", "t.csv"]);
    // An existing output is left as it was.
    std::fs::write(d.path().join("e.csv"), "old").unwrap();
    let o = limbfuse(
        &["estimate", "--method", "mjls", "cut.csv", "-o", "e.csv"],
        d.path(),
    );
    assert_user_error(&o, &["cut.csv:"]);
    assert_eq!(
        std::fs::read_to_string(d.path().join("e.csv")).unwrap(),
        "old"
    );
    assert_eq!(listing(d.path()), vec!["cut.csv", "e.csv", "t.csv"]);
    // The same through other writers: resample and align read the trial whole.
    for cmd in [
        &["resample", "cut.csv", "--rate", "50", "-o", "r.csv"][..],
        &["align", "cut.csv", "-o", "r.csv"][..],
    ] {
        assert_user_error(&limbfuse(cmd, d.path()), &["cut.csv:"]);
    }
    assert_eq!(listing(d.path()), vec!["cut.csv", "e.csv", "t.csv"]);
}

#[test]
fn issue_18_an_estimate_of_another_trial_is_refused() {
    let d = tempfile::tempdir().unwrap();
    trial_and_estimate(d.path(), "3", "a.csv", "ea.csv");
    // Same time base (10 s at 100 Hz), other content.
    assert_ok(&limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "10",
            "--seed",
            "4",
            "-o",
            "b.csv",
        ],
        d.path(),
    ));
    let head = std::fs::read_to_string(d.path().join("ea.csv")).unwrap();
    assert!(
        head.contains("\n# trial: a.csv\n# trial_hash: xxh3:"),
        "{head}"
    );

    let same = limbfuse(&["evaluate", "a.csv", "ea.csv"], d.path());
    assert_ok(&same);
    assert!(!stderr(&same).contains("warning"), "{}", stderr(&same));

    let o = limbfuse(&["evaluate", "b.csv", "ea.csv"], d.path());
    assert_user_error(
        &o,
        &[
            "ea.csv",
            "`a.csv` (xxh3:",
            "b.csv has the content hash xxh3:",
            "--allow-trial-mismatch",
        ],
    );
    assert!(o.stdout.is_empty());

    let o = limbfuse(
        &["evaluate", "b.csv", "ea.csv", "--allow-trial-mismatch"],
        d.path(),
    );
    assert_ok(&o);
    assert!(stderr(&o).contains("warning: ea.csv was made from the trial `a.csv`"));
    assert!(String::from_utf8_lossy(&o.stdout).contains("RMSE"));

    // An estimate file from before the header (no `# trial:` lines) is
    // accepted with a warning.
    let old: String = head
        .lines()
        .filter(|l| !l.starts_with("# trial"))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(d.path().join("old.csv"), old).unwrap();
    let o = limbfuse(&["evaluate", "b.csv", "old.csv"], d.path());
    assert_ok(&o);
    assert!(
        stderr(&o).contains("old.csv: the estimate file does not record the trial"),
        "{}",
        stderr(&o)
    );
}
