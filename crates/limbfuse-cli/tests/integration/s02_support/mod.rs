//! What the tests on the shared gaittoolbox S02 walk need: its folder (or a
//! skip message when `../shared/data` is absent) and a `limbfuse` run that
//! must succeed; also the gaitmap walk's `gait-events` run.

use std::path::{Path, PathBuf};

use crate::support::{limbfuse, shared_data};

/// `../shared/data/gaittoolbox-s02-walk` (or under `LIMBFUSE_DATA`); `None`
/// with a message when it is absent.
pub fn s02_dir() -> Option<PathBuf> {
    shared_data("gaittoolbox-s02-walk")
}

/// Runs `limbfuse args` in `dir`, asserts exit 0, returns its stdout.
pub fn run_ok(args: &[&str], dir: &Path) -> Vec<u8> {
    let o = limbfuse(args, dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o.stdout
}

/// Imports the S02 walk into `dir` as `s02.csv`; `false` (with the skip
/// message) when the shared data is absent.
pub fn imported_s02(dir: &Path) -> bool {
    let Some(s02) = s02_dir() else {
        return false;
    };
    let s02 = s02.to_str().unwrap();
    run_ok(
        &["import", "--format", "gaittoolbox", s02, "-o", "s02.csv"],
        dir,
    );
    true
}

/// Imports and aligns the S02 walk into `dir` as `s02al.csv`; `false` (with
/// the skip message) when the shared data is absent.
pub fn aligned_s02(dir: &Path) -> bool {
    if !imported_s02(dir) {
        return false;
    }
    run_ok(&["align", "s02.csv", "-o", "s02al.csv"], dir);
    true
}

/// Offset-free RMSE (deg) of thigh, shank and foot of `est` against `trial`
/// over `window`, each at its best lag within +-5 samples (the ~20 ms IMU
/// lag the data README reports, with margin).
pub fn leg_rmse(dir: &Path, trial: &str, est: &str, window: &str) -> [f64; 3] {
    let json = run_ok(
        &[
            "evaluate",
            trial,
            est,
            "--window",
            window,
            "--offset-free",
            "--max-lag",
            "5",
            "--json",
        ],
        dir,
    );
    let v: serde_json::Value = serde_json::from_slice(&json).unwrap();
    ["thigh", "shank", "foot"].map(|s| v["rmse_deg"][s].as_f64().unwrap())
}

/// Runs `gait-events` on the shared gaitmap walk into `dir/ge.csv` and
/// returns the walk's path; `None` (with the skip message) when the shared
/// data is absent.
pub fn gaitmap_events(dir: &Path) -> Option<String> {
    let trial = shared_data("gaitmap-foot-walk/trial.csv")?;
    let trial = trial.to_str().unwrap().to_string();
    run_ok(
        &[
            "estimate",
            "--method",
            "gait-events",
            &trial,
            "-o",
            "ge.csv",
        ],
        dir,
    );
    Some(trial)
}

/// The knee row's RMSE (deg) of `limbfuse evaluate ARGS...` run in `dir`
/// (`args` starts with `evaluate`).
pub fn evaluated_knee_rmse(dir: &Path, args: &[&str]) -> f64 {
    let o = crate::support::limbfuse(args, dir);
    let out = String::from_utf8_lossy(&o.stdout);
    out.lines()
        .find(|l| l.starts_with("knee "))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no knee row in\n{out}"))
}
