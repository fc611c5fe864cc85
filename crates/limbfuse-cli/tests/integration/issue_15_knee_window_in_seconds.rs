//! Issue 15 (a knee estimator that works on real sensors), found on the
//! shared 250 Hz knee rig: `knee-selfalign`'s default window was paper
//! 002's `s_w = 500` *samples*, five seconds at the paper's 100 Hz but two
//! at the rig's 250 Hz, and with two-second windows of the rig's slow motion
//! Trial_03-05 lost the knee after 100 s (RMSE 24-36 deg, correlation
//! 0.09-0.42). The default is now five seconds at the trial's rate
//! (`limbfuse_methods::knee_window`): 1250 samples here, RMSE 9.6 deg
//! (offset-free 2.3), correlation 0.98. Since issue knee31b the 500-sample
//! windows no longer lose it either (a window of Trial_03-05 near 102 s
//! trusted the accelerometer angle by chance; the rig's accelerometers read
//! 1.1-1.24 g at rest, so the rest check stops trusting them from ~6 s on):
//! RMSE 9.2 deg, correlation 0.99. Skipped when `../shared/data` is absent.

use std::path::Path;

use crate::s02_support::run_ok;
use crate::support::shared_data;

/// Knee RMSE (deg) and correlation of `est` against `rig.csv`.
fn knee_fit(dir: &Path, est: &str) -> (f64, f64) {
    let json = run_ok(&["evaluate", "rig.csv", est, "--json"], dir);
    let v: serde_json::Value = serde_json::from_slice(&json).unwrap();
    let rmse = v["rmse_deg"]["knee"].as_f64().unwrap();
    let corr = v["corr"]["knee"].as_f64().unwrap();
    (rmse, corr)
}

#[test]
fn issue_15_knee_window_in_seconds_on_the_250_hz_rig() {
    let Some(trial) = shared_data("knee-rig/Trial_05.csv") else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let trial = trial.to_str().unwrap();
    run_ok(
        &["import", "--format", "knee-rig", trial, "-o", "rig.csv"],
        dir,
    );
    run_ok(
        &[
            "estimate",
            "--method",
            "knee-selfalign",
            "rig.csv",
            "-o",
            "default.csv",
        ],
        dir,
    );
    let header = std::fs::read_to_string(dir.join("default.csv")).unwrap();
    assert!(
        header.lines().any(|l| l == "# window: 1250"),
        "the default window at 250 Hz is 1250 samples"
    );
    let (rmse, corr) = knee_fit(dir, "default.csv");
    assert!(
        corr > 0.95 && rmse < 12.0,
        "default: RMSE {rmse} deg, corr {corr}"
    );
    // The window given in samples is used as given (the paper's 500
    // samples, the default before); since issue knee31b they keep the knee
    // too (RMSE 36.4 deg, corr 0.09 before).
    run_ok(
        &[
            "estimate",
            "--method",
            "knee-selfalign",
            "--window",
            "500",
            "rig.csv",
            "-o",
            "w500.csv",
        ],
        dir,
    );
    let header = std::fs::read_to_string(dir.join("w500.csv")).unwrap();
    assert!(header.lines().any(|l| l == "# window: 500"));
    let (rmse, corr) = knee_fit(dir, "w500.csv");
    assert!(
        corr > 0.95 && rmse < 12.0,
        "--window 500: RMSE {rmse} deg, corr {corr}"
    );
}
