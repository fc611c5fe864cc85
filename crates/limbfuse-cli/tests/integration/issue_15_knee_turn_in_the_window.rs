//! Issue 15 (a knee estimator that works on real sensors), found on the
//! shared gaittoolbox S02 walk at the default window (5 s): the first
//! window (0-5 s) holds the first straight pass *and* the turn on the spot
//! (3.6-4.4 s). As a whole it turns mainly about the segments' long axes, so
//! the upright-leg prior found "no flexion" and the first window fell back to
//! eq 2's axes, 20-45 deg off on this soft-tissue thigh: the second pass came
//! out flipped (offset-free RMSE 35.7 deg, correlation -0.95) for both
//! `knee-selfalign` and `knee-gyro-axis`, at 50, 60, 100 and 200 Hz. The
//! prior now leaves the window's one-second turn blocks out when the rest
//! holds most of it (`upright::TURN_BLOCK_S`, `upright::TURN_RATE`):
//! 3.5 deg, correlation 0.995. Skipped when `../shared/data` is absent.

use crate::s02_support::{imported_s02, run_ok, s02_dir};

#[test]
fn issue_15_knee_turn_in_the_first_window() {
    let tmp = tempfile::tempdir().unwrap();
    if imported_s02(tmp.path()) {
        second_pass_knee_fits(tmp.path());
    }
}

/// The same walk with its second shank sensor (`imu-R_LowLeg2.csv`, mounted
/// differently), which the fix was not designed on: 25.2 deg, correlation
/// 0.61 before it.
#[test]
fn issue_15_knee_turn_in_the_first_window_other_shank_sensor() {
    let Some(s02) = s02_dir() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let folder = dir.join("s02-lowleg2");
    std::fs::create_dir(&folder).unwrap();
    for (from, to) in [
        ("imu-Pelvis.csv", "imu-Pelvis.csv"),
        ("imu-R_UpLeg.csv", "imu-R_UpLeg.csv"),
        ("imu-R_LowLeg2.csv", "imu-R_LowLeg.csv"),
        ("imu-R_Foot.csv", "imu-R_Foot.csv"),
        ("vicon-right.csv", "vicon-right.csv"),
    ] {
        std::fs::copy(s02.join(from), folder.join(to)).unwrap();
    }
    run_ok(
        &[
            "import",
            "--format",
            "gaittoolbox",
            "s02-lowleg2",
            "-o",
            "s02.csv",
        ],
        dir,
    );
    second_pass_knee_fits(dir);
}

/// Both knee methods with the default window on `dir/s02.csv`: the second
/// straight pass within 5 deg offset-free, correlation above 0.98.
fn second_pass_knee_fits(dir: &std::path::Path) {
    for method in ["knee-selfalign", "knee-gyro-axis"] {
        let est = format!("{method}.csv");
        run_ok(
            &["estimate", "--method", method, "s02.csv", "-o", &est],
            dir,
        );
        let json = run_ok(
            &[
                "evaluate",
                "s02.csv",
                &est,
                "--window",
                "4.4:8.72",
                "--offset-free",
                "--max-lag",
                "2",
                "--json",
            ],
            dir,
        );
        let v: serde_json::Value = serde_json::from_slice(&json).unwrap();
        let rmse = v["rmse_deg"]["knee"].as_f64().unwrap();
        let corr = v["corr"]["knee"].as_f64().unwrap();
        assert!(
            corr > 0.98 && rmse < 5.0,
            "{method}, default window, second pass: offset-free RMSE {rmse} deg, corr {corr}"
        );
    }
}
