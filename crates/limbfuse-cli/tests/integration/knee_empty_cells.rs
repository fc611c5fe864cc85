//! The knee methods with empty IMU cells (2026-12-06): the shared
//! independent walks with a twentieth of their accelerometer and gyroscope
//! cells empty (a fixed pattern). A sample whose knee rate is missing holds
//! the last rate; the first rate after a short gap now replaces that
//! extrapolation by one trapezoid across the gap (both methods),
//! `knee-gyro-axis`' drift correction keeps acting between its
//! accelerometer angles (its bias state every sample, its error over the
//! time since the last angle), and the accelerometer angle's rate
//! derivative falls back to three samples when an outer one of its five
//! lacks a gyro reading (`rate_derivative3`): with every twentieth cell
//! empty the five-point angle comes on about one sample in six, with the
//! fallback on about three in ten. Knee RMSE (deg), complete -> empty cells,
//! before: `knee-selfalign` 1.416 -> 2.975, 1.062 -> 2.894, 0.182 -> 1.984;
//! `knee-gyro-axis` 1.286 -> 6.852, 0.838 -> 12.068, 0.265 -> 6.380; with
//! the first two fixes 2.716, 1.676, 0.588 and 2.594, 1.269, 0.688; with all
//! three 1.742, 1.118, 0.492 and 1.605, 1.046, 0.577 (at most 0.33 deg over
//! the complete walk; docs/RESULTS.md "Robust input").

use crate::s02_support::{evaluated_knee_rmse as knee_rmse, run_ok};
use crate::support::{shared_data, with_empty_cells};

#[test]
fn the_knee_methods_keep_the_knee_with_empty_imu_cells() {
    for walk in ["walk-v0.7-s300", "walk-v1.2-s301", "walk-v1.6-s302"] {
        let Some(path) = shared_data(&format!("independent-sim/{walk}.csv")) else {
            return;
        };
        let d = tempfile::tempdir().unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::write(d.path().join("full.csv"), &text).unwrap();
        std::fs::write(d.path().join("holes.csv"), with_empty_cells(&text, 20)).unwrap();
        for method in ["knee-selfalign", "knee-gyro-axis"] {
            let rmse = |trial: &str| {
                run_ok(
                    &["estimate", "--method", method, trial, "-o", "k.csv"],
                    d.path(),
                );
                knee_rmse(d.path(), &["evaluate", trial, "k.csv"])
            };
            let (full, holes) = (rmse("full.csv"), rmse("holes.csv"));
            println!("{walk} {method}: {full:.3} complete, {holes:.3} with empty cells");
            assert!(holes < full + 0.5, "{walk} {method}: {full} -> {holes}");
        }
    }
}
