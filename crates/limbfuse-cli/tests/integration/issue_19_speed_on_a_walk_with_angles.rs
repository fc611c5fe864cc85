//! Issue 19 (walking speed on real recordings): a trial with angle
//! references *and* a walking-speed reference (the gaittoolbox S02 walk,
//! whose importer writes `speed_ref` from the Vicon pelvis). `evaluate`
//! chose the angle table whenever the trial had an angle reference, so a
//! `lowback-speed` or `gait-events` estimate got an empty table; it now
//! scores events and stride speeds when the estimate holds those and no
//! angle, and angles otherwise. Skipped when `../shared/data` is absent.

use crate::s02_support::{imported_s02, run_ok};

#[test]
fn issue_19_speed_scored_on_a_walk_with_angle_references() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    if !imported_s02(dir) {
        return;
    }
    let json = |est: &str| -> serde_json::Value {
        serde_json::from_slice(&run_ok(&["evaluate", "s02.csv", est, "--json"], dir)).unwrap()
    };
    for (method, min_strides) in [("lowback-speed", 4), ("gait-events", 2)] {
        let est = format!("{method}.csv");
        run_ok(
            &["estimate", "--method", method, "s02.csv", "-o", &est],
            dir,
        );
        let v = json(&est);
        let strides = v["n_strides"].as_u64().unwrap();
        let mae = v["speed_mae_mps"].as_f64().unwrap();
        println!("{method}: stride speed MAE {mae:.3} m/s over {strides} strides");
        assert!(strides >= min_strides, "{method}: {strides} strides scored");
        assert!(mae < 0.1, "{method}: MAE {mae} m/s");
    }
    run_ok(
        &[
            "estimate",
            "--method",
            "local",
            "s02.csv",
            "-o",
            "local.csv",
        ],
        dir,
    );
    let v = json("local.csv");
    assert!(v["rmse_deg"]["thigh"].as_f64().is_some(), "{v}");
}
