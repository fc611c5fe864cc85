//! Twenty-seventh session's generalisation audit: `gait-events` on foot
//! gyroscopes clipped at a consumer IMU's 250 deg/s full scale.

use crate::support::{edit_cells, limbfuse};

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
