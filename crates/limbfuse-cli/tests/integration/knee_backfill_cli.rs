//! `limbfuse estimate --backfill` (knee-selfalign, knee-gyro-axis; ours,
//! docs/KNEE_SELFALIGN.md "Backfill"): the knee angle over the first
//! identification window, offline, anchored on the estimator's converged
//! output; every row from the first identification on as without it.

use std::f64::consts::{PI, TAU};
use std::path::Path;
use std::process::Output;

use crate::support::{limbfuse, shared_data};

fn ok(o: &Output) -> String {
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(0), "stderr: {e}");
    e
}

/// The cells of one column of a trial or estimate file, by row.
fn column(path: &Path, name: &str) -> Vec<Option<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let c = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(c).and_then(|v| v.parse().ok()))
        .collect()
}

/// The data rows of a file as text.
fn rows(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(str::to_string)
        .collect()
}

/// RMSE (deg) of the estimate's knee against the trial's `knee_ref` over
/// rows `range`, the difference wrapped to +-180 deg.
fn knee_rmse(trial: &Path, est: &Path, range: std::ops::Range<usize>) -> f64 {
    let (r, e) = (column(trial, "knee_ref"), column(est, "knee"));
    let n = range.len() as f64;
    let sq: f64 = range
        .map(|k| {
            // The files hold radians.
            let d = e[k].expect("a knee angle") - r[k].expect("a reference");
            let w = (d + PI).rem_euclid(TAU) - PI;
            w.to_degrees().powi(2)
        })
        .sum();
    (sq / n).sqrt()
}

/// Runs `method` with and without `--backfill` over `trial` (in `dir`);
/// returns the first row with a knee angle without it, after checking that
/// the backfilled file has a knee angle on every row and that its rows from
/// that one on are the real-time run's, character for character.
fn both_runs(dir: &Path, trial: &str, method: &str) -> (usize, String) {
    ok(&limbfuse(
        &["estimate", "--method", method, trial, "-o", "plain.csv"],
        dir,
    ));
    let said = ok(&limbfuse(
        &[
            "estimate",
            "--method",
            method,
            "--backfill",
            trial,
            "-o",
            "filled.csv",
        ],
        dir,
    ));
    let plain = column(&dir.join("plain.csv"), "knee");
    let filled = column(&dir.join("filled.csv"), "knee");
    let first = plain.iter().position(Option::is_some).expect("identified");
    assert!(first > 0, "nothing to backfill");
    assert!(filled.iter().all(Option::is_some), "a row without a knee");
    let (p, f) = (rows(&dir.join("plain.csv")), rows(&dir.join("filled.csv")));
    assert_eq!(p.len(), f.len());
    assert_eq!(p[first..], f[first..], "rows from the first estimate on");
    (first, said)
}

#[test]
fn knee_backfill_fills_the_first_window_and_keeps_the_rest() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &[
            "simulate",
            "knee",
            "-o",
            "k.csv",
            "--duration",
            "15",
            "--seed",
            "2",
        ],
        p,
    ));
    for method in ["knee-selfalign", "knee-gyro-axis"] {
        let (first, said) = both_runs(p, "k.csv", method);
        assert!(
            said.contains("knee backfilled over 0.00-4.98 s"),
            "{method}: {said}"
        );
        let trial = p.join("k.csv");
        let before = knee_rmse(&trial, &p.join("filled.csv"), 0..first);
        let after = knee_rmse(&trial, &p.join("filled.csv"), first..2 * first);
        println!(
            "{method}: knee RMSE {before:.2} deg backfilled, {after:.2} deg over the next window"
        );
        assert!(
            before < after + 1.0,
            "{method}: backfilled {before:.2} deg, then {after:.2}"
        );
    }
    // Without --backfill the verdict says what is missing and how to get it.
    let said = ok(&limbfuse(
        &[
            "estimate",
            "--method",
            "knee-selfalign",
            "k.csv",
            "-o",
            "x.csv",
        ],
        p,
    ));
    assert!(said.contains("`--backfill` fills it offline"), "{said}");
}

/// The independent simulator's 0.7 m/s walk: `knee-selfalign`'s first
/// output is 9.4 deg off (its fusion starts afresh with the axes and
/// converges within 10 samples). Anchored on that output alone the backfill
/// was 10.0 deg RMSE; on the mean over the next stride, 0.41.
#[test]
fn knee_backfill_anchors_on_the_converged_output() {
    let Some(walk) = shared_data("independent-sim/walk-v0.7-s300.csv") else {
        eprintln!("skipped: ../shared/data/independent-sim is absent");
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::copy(&walk, p.join("w.csv")).unwrap();
    let (first, _) = both_runs(p, "w.csv", "knee-selfalign");
    let rmse = knee_rmse(&p.join("w.csv"), &p.join("filled.csv"), 0..first);
    println!("backfilled knee RMSE {rmse:.2} deg over {first} rows");
    assert!(rmse < 1.0, "{rmse:.2} deg");
}

#[test]
fn knee_backfill_is_refused_for_other_methods() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &["simulate", "walking", "--duration", "3", "-o", "w.csv"],
        p,
    ));
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "global",
            "--backfill",
            "w.csv",
            "-o",
            "e.csv",
        ],
        p,
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("w.csv: method `global` has nothing to backfill"),
        "{e}"
    );
    assert!(!p.join("e.csv").exists());
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "chain",
            "--smooth",
            "--backfill",
            "w.csv",
            "-o",
            "e.csv",
        ],
        p,
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("cannot be used with"));
}
