//! Twenty-seventh session's generalisation audit: knee-gyro-axis and
//! knee-selfalign on the independent simulator's walks with 0.5 s of rows
//! removed (a time gap).

use crate::s02_support::{evaluated_knee_rmse, run_ok};
use crate::support::shared_data;

/// Knee RMSE (deg) of `method` on `dir/trial`.
fn knee_rmse(dir: &std::path::Path, method: &str, trial: &str) -> f64 {
    run_ok(&["estimate", "--method", method, trial, "-o", "e.csv"], dir);
    evaluated_knee_rmse(dir, &["evaluate", trial, "e.csv"])
}

/// The rows of 30.3-30.8 s removed. knee-gyro-axis: before the fix 8.78 /
/// 3.98 / 2.57 deg RMSE over the 0.7 / 1.2 / 1.6 m/s walks (1.29 / 0.84 /
/// 0.27 without the gap); now within 0.1 deg of the gapless walks.
/// knee-selfalign: 2.60 / 1.46 / 0.73 (1.42 / 1.06 / 0.18 without); now
/// 1.79 / 1.15 / 0.40, the rest being the first samples after the gap,
/// whose accelerometer angle (two samples late) is from before it.
#[test]
fn knee_gyro_axis_on_walks_with_rows_removed() {
    let d = tempfile::tempdir().unwrap();
    for walk in ["walk-v0.7-s300", "walk-v1.2-s301", "walk-v1.6-s302"] {
        let Some(path) = shared_data(&format!("independent-sim/{walk}.csv")) else {
            return;
        };
        let text = std::fs::read_to_string(&path).unwrap();
        let mut header = false;
        let kept: Vec<&str> = text
            .lines()
            .filter(|l| {
                if l.starts_with("t,") {
                    header = true;
                    return true;
                }
                let t: Option<f64> = header
                    .then(|| l.split(',').next().and_then(|c| c.parse().ok()))
                    .flatten();
                !t.is_some_and(|t| (30.3 - 1e-9..30.8 - 1e-9).contains(&t))
            })
            .collect();
        std::fs::write(d.path().join("gap.csv"), kept.join("\n") + "\n").unwrap();
        std::fs::copy(&path, d.path().join("clean.csv")).unwrap();
        for (method, margin) in [("knee-gyro-axis", 0.1), ("knee-selfalign", 0.5)] {
            let gap = knee_rmse(d.path(), method, "gap.csv");
            let clean = knee_rmse(d.path(), method, "clean.csv");
            eprintln!(
                "{walk}, {method}: knee RMSE {gap:.3} deg with 0.5 s of rows removed, {clean:.3} without"
            );
            assert!(
                gap < clean + margin,
                "{walk} {method}: {gap} ({clean} without)"
            );
        }
    }
}
