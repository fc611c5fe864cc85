//! `gait-events` on foot accelerometers that clip at heel strike
//! (docs/GAIT_EVENTS.md, "Clipped impacts"). Skipped when `../shared/data`
//! is absent.

use crate::cli_gait_events::{data_dir, evaluate_json, f};
use crate::support::edit_cells;

/// The shared two-foot walk (NilsPod, 16 g) with every accelerometer axis
/// clipped at 8 g = 78.45 m/s^2, the range stated (`# acc_range_m_s2:`),
/// as a foot sensor of 8 g full scale records it: most heel strikes clip.
/// The stride integration removed the velocity change the clipped impact
/// lost as a linear drift over the stride: per-stride length error 2.97 %,
/// speed MAE 0.037 m/s (bias -0.022; the 53 strides paired with a
/// reference stride), against 2.61 % / 0.031 unclipped. The clipped axis's
/// step (`strapdown` step 4) gives 2.32 % and 0.028 m/s (bias -0.007).
/// Events do not depend on the accelerometer's range.
#[test]
fn issue_19_clipped_foot_accelerometers_keep_the_stride_length() {
    let Some(data) = data_dir() else { return };
    let full_scale = 8.0 * 9.80665;
    let text = std::fs::read_to_string(data.join("gaitmap-foot-walk/trial.csv")).unwrap();
    let clipped = edit_cells(&text, |_, column, cell| {
        let v: f64 = cell.parse().ok()?;
        (column.contains("_acc_") && v.abs() > full_scale)
            .then(|| format!("{}", v.clamp(-full_scale, full_scale)))
    });
    let (first, rest) = clipped.split_once('\n').unwrap();
    let clipped = format!("{first}\n# acc_range_m_s2: {full_scale}\n{rest}");
    let d = tempfile::tempdir().unwrap();
    let path = d.path().join("clipped.csv");
    std::fs::write(&path, clipped).unwrap();
    let v = evaluate_json("gait-events", &path, d.path());
    eprintln!(
        "8 g: stride length {:.2} %, speed MAE {:.4} m/s",
        f(&v, &["stride_length_error_pct"]),
        f(&v, &["speed_mae_mps"])
    );
    assert!(f(&v, &["stride_length_error_pct"]) < 2.5, "{v}");
    assert!(f(&v, &["speed_mae_mps"]) < 0.031, "{v}");
    assert!(f(&v, &["speed_bias_mps"]).abs() < 0.015, "{v}");
    assert!(f(&v, &["n_strides"]) >= 50.0, "{v}");
    for kind in ["initial_contact", "final_contact"] {
        assert_eq!(f(&v, &[kind, "missed"]), 0.0, "{v}");
        assert!(f(&v, &[kind, "median_abs_ms"]) <= 5.0, "{v}");
    }
}
