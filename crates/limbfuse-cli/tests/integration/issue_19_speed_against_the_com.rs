//! `evaluate` scores a walking-speed estimate against the trial's CoM
//! velocity when the trial has `com_vx` .. `com_vz` but no `speed_ref`
//! (issue 19): the independent simulator's walks (their `com_*` is the hip
//! joint centre). Before, `gait-events` and `lowback-speed` on these walks
//! printed an empty angle table. Skipped when `../shared/data` is absent.

use crate::s02_support::run_ok;
use crate::support::shared_data;

#[test]
fn issue_19_speed_on_a_walk_with_a_com_velocity() {
    let Some(walk) = shared_data("independent-sim/walk-v1.2-s301.csv") else {
        eprintln!("skipped: ../shared/data/independent-sim is absent");
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::copy(&walk, p.join("w.csv")).unwrap();
    // measured: gait-events 0.023 m/s over 51 strides, lowback-speed 0.038
    // over 102; the issue's targets are 0.03 (feet) and 0.06 (lower back).
    for (method, strides, target) in [("gait-events", 45, 0.03), ("lowback-speed", 90, 0.06)] {
        run_ok(&["estimate", "--method", method, "w.csv", "-o", "e.csv"], p);
        let v: serde_json::Value =
            serde_json::from_slice(&run_ok(&["evaluate", "w.csv", "e.csv", "--json"], p)).unwrap();
        assert_eq!(v["speed_reference"], "com_velocity", "{method}: {v}");
        assert!(v["n_strides"].as_u64().unwrap() >= strides, "{method}: {v}");
        let mae = v["speed_mae_mps"].as_f64().unwrap();
        assert!(mae <= target, "{method}: {v}");
        let text = String::from_utf8(run_ok(&["evaluate", "w.csv", "e.csv"], p)).unwrap();
        assert!(
            text.contains("against the trial's horizontal CoM speed"),
            "{text}"
        );
    }
    // Angle estimates of the same walk keep the angle evaluation.
    run_ok(
        &["estimate", "--method", "chain", "w.csv", "-o", "c.csv"],
        p,
    );
    let v: serde_json::Value =
        serde_json::from_slice(&run_ok(&["evaluate", "w.csv", "c.csv", "--json"], p)).unwrap();
    assert!(v["rmse_deg"]["knee"].as_f64().is_some(), "{v}");
}
