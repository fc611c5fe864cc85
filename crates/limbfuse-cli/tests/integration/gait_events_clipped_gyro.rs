//! Twenty-seventh session's generalisation audit: `gait-events` on foot
//! gyroscopes clipped at a consumer IMU's 250 deg/s full scale.

use crate::support::{edit_cells, limbfuse};

/// A simulated 1.4 m/s walk (20 s, seed 5, gait reference; its foot swing
/// peaks well above 250 deg/s) with every gyroscope axis clipped at
/// 250 deg/s = 4.3633 rad/s and the range stated (`# gyro_range_rad_s:`),
/// as `c.csv` in the directory returned.
fn clipped_walk() -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    let o = limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "20",
            "--speed",
            "1.4",
            "--seed",
            "5",
            "--gait-reference",
            "-o",
            "w.csv",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let full_scale = 250f64.to_radians();
    let text = std::fs::read_to_string(d.path().join("w.csv")).unwrap();
    let mut clipped_any = false;
    let clipped = edit_cells(&text, |_, column, cell| {
        let v: f64 = cell.parse().ok()?;
        (column.contains("_gyr_") && v.abs() > full_scale)
            .then(|| format!("{}", v.clamp(-full_scale, full_scale)))
    });
    for line in clipped.lines().filter(|l| !l.starts_with('#')).skip(1) {
        clipped_any |= line.contains(&format!("{full_scale}"));
    }
    assert!(clipped_any, "the walk never reaches 250 deg/s");
    // (the range line after the format line)
    let (first, rest) = clipped.split_once('\n').unwrap();
    let clipped = format!("{first}\n# gyro_range_rad_s: {full_scale}\n{rest}");
    std::fs::write(d.path().join("c.csv"), clipped).unwrap();
    d
}

/// A simulated 1.4 m/s walk (foot swing peaks well above 250 deg/s) with
/// every gyroscope axis clipped at 250 deg/s = 4.3633 rad/s and the range
/// stated (`# gyro_range_rad_s:`). The sensor gate rejected the clipped
/// readings as saturated, every swing went missing and `gait-events` found
/// "no gait" (exit 1; the gaitmap walk clipped so: 22 of 56 contacts
/// missed, 0.53 m/s). It now keeps clipped gyroscope readings
/// (`MethodInfo::keeps_clipped_gyro`): a rate at the full scale still says
/// the foot swings.
#[test]
fn gait_events_keeps_clipped_gyroscope_readings() {
    let d = clipped_walk();
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "gait-events",
            "c.csv",
            "-o",
            "e.csv",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = limbfuse(&["evaluate", "c.csv", "e.csv", "--json"], d.path());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let mae = v["speed_mae_mps"].as_f64().unwrap();
    eprintln!("clipped at 250 deg/s: stride speed MAE {mae:.3} m/s");
    assert!(mae < 0.1, "{v}");
}

/// The same walk resampled to 50 Hz: `resample` left the clipped gyroscope
/// readings out (2999 of them on a 60 s walk), every swing went missing and
/// `gait-events` found "no gait" in the resampled file. It now carries a
/// clipped cell through at the rail, on the output samples it is nearest
/// to (`clip_marks`), and says so; the file's own rate and the resampled one
/// then give `gait-events` the same strides, and the angle methods reject
/// the rail as at the trial's own rate.
#[test]
fn gait_events_on_a_resampled_trial_with_clipped_gyroscopes() {
    let d = clipped_walk();
    let o = limbfuse(
        &["resample", "c.csv", "--rate", "50", "-o", "c50.csv"],
        d.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("carried through at the rail"), "{stderr}");
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "gait-events",
            "c50.csv",
            "-o",
            "e.csv",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = limbfuse(&["evaluate", "c50.csv", "e.csv", "--json"], d.path());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let mae = v["speed_mae_mps"].as_f64().unwrap();
    eprintln!("clipped at 250 deg/s, resampled to 50 Hz: stride speed MAE {mae:.3} m/s");
    assert!(mae < 0.1, "{v}");
    assert_eq!(v["initial_contact"]["missed"].as_f64(), Some(0.0), "{v}");
}
