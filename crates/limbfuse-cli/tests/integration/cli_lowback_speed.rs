//! `lowback-speed` through the binary on the shared HA001 recordings
//! (skipped with a message when `../shared/data` is absent): the straight
//! walks, the course's turning strides and first stride, the sensor height.

use std::path::Path;

use crate::cli_gait_events::{data_dir, evaluate_json, f};
use crate::support::limbfuse;

/// HA001 straight walk: contacts found, 40 ms median (target: within 40),
/// stride speed MAE 0.028 m/s with the sensor height of the file's
/// `# subject:` line (0.054 before it was read; target 0.06).
#[test]
fn lowback_straight_walk() {
    let Some(data) = data_dir() else { return };
    let d = tempfile::tempdir().unwrap();
    let v = evaluate_json(
        "lowback-speed",
        &data.join("mobgap-lowerback/HA001-test5-trial1.csv"),
        d.path(),
    );
    assert_eq!(f(&v, &["initial_contact", "missed"]), 0.0, "{v}");
    // 40 ms up to rounding (10 ms samples).
    assert!(f(&v, &["initial_contact", "median_abs_ms"]) < 40.5, "{v}");
    assert!(f(&v, &["speed_mae_mps"]) <= 0.06, "{v}");
    assert!(v["final_contact"].is_null());
}

/// Issue 19, lower-back speed on the daily-living course (HA001 test11):
/// turning strides (mean heading rate above 15 deg/s) and the strides after
/// them report no speed. Measured: 13 of 41 strides keep a speed, MAE
/// 0.088 m/s with the sensor height of the file's `# subject:` line (0.133
/// with the default pendulum; 0.179 over all 41 without the turn rule);
/// contacts 35 ms median (30 ms with the plain gravity mean).
#[test]
fn issue_19_lowback_course_turning_strides_have_no_speed() {
    let Some(data) = data_dir() else { return };
    let d = tempfile::tempdir().unwrap();
    let v = evaluate_json(
        "lowback-speed",
        &data.join("mobgap-lowerback/HA001-test11-trial1.csv"),
        d.path(),
    );
    let n = f(&v, &["n_strides"]);
    assert!((10.0..=22.0).contains(&n), "{v}");
    assert!(f(&v, &["speed_mae_mps"]) <= 0.10, "{v}");
    // The issue's 40 ms up to rounding (10 ms samples).
    assert!(f(&v, &["initial_contact", "median_abs_ms"]) < 40.5, "{v}");
}

/// The data rows of a limbfuse CSV file, by column name (empty = `None`).
fn columns(path: &Path, names: &[&str]) -> Vec<Vec<Option<f64>>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let index: Vec<usize> = names
        .iter()
        .map(|n| header.iter().position(|h| h == n).expect(n))
        .collect();
    lines
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            index.iter().map(|&i| cells[i].parse().ok()).collect()
        })
        .collect()
}

/// Issue 19, lower-back speed, first stride of a bout on the HA001 course:
/// the first stride with a speed and a reference (6.42-7.70 s, after the
/// subject stands up) was 0.25 m/s slow with the plain 2 s gravity mean
/// (which lagged the standing-up tilt by 5-9 deg); with the mean rotated
/// by the gyroscope it is 0.01 m/s slow. Held within 0.06 m/s.
#[test]
fn issue_19_lowback_course_first_stride_after_standing_up() {
    let Some(data) = data_dir() else { return };
    let d = tempfile::tempdir().unwrap();
    let trial = data.join("mobgap-lowerback/HA001-test11-trial1.csv");
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "lowback-speed",
            trial.to_str().unwrap(),
            "-o",
            "e.csv",
        ],
        d.path(),
    );
    assert_eq!(o.status.code(), Some(0));
    let reference = columns(&trial, &["t", "speed_ref"]);
    let est = columns(
        &d.path().join("e.csv"),
        &["diag_ic", "diag_stride_length", "diag_stride_time"],
    );
    let first = est.iter().find_map(|row| {
        let (end, length, time) = (row[0]?, row[1]?, row[2]?);
        let refs: Option<Vec<f64>> = reference
            .iter()
            .filter(|r| r[0].is_some_and(|t| t >= end - time - 1e-9 && t < end - 1e-9))
            .map(|r| r[1])
            .collect();
        let refs = refs.filter(|r| !r.is_empty())?;
        Some((
            end,
            length / time,
            refs.iter().sum::<f64>() / refs.len() as f64,
        ))
    });
    let (end, v, v_ref) = first.expect("a stride with a reference");
    assert!((7.6..7.8).contains(&end), "first stride ends at {end} s");
    assert!((v - v_ref).abs() < 0.06, "{v} m/s vs {v_ref} m/s");
}

/// Issue 19, lower-back speed: the pendulum length the lower-back literature
/// uses is the sensor's height above the ground (Soltani et al. 2021, the
/// Mobilise-D `SlZijlstra`: `l` = sensor height, factor 4.587 / 4). A trial
/// with `# sensor_height_m:` gets that pair. The HA001 files state the
/// sensor height (96.4 cm) only in free text (`# subject: ..., sensor
/// height 96.4 cm`), which is read too: as shipped and with the line
/// added, measured stride speed MAE 0.028 / 0.024 m/s on the straight walks
/// and 0.088 on the course (default pendulum: 0.054 / 0.065 / 0.133).
#[test]
fn issue_19_lowback_sensor_height_is_the_pendulum_length() {
    let Some(data) = data_dir() else { return };
    let d = tempfile::tempdir().unwrap();
    for (name, limit) in [
        ("HA001-test5-trial1.csv", 0.06),
        ("HA001-test5-trial2.csv", 0.06),
        ("HA001-test11-trial1.csv", 0.10),
    ] {
        let shipped = data.join("mobgap-lowerback").join(name);
        let text = std::fs::read_to_string(&shipped).unwrap();
        let trial = d.path().join(name);
        std::fs::write(&trial, format!("# sensor_height_m: 0.964\n{text}")).unwrap();
        for trial in [&trial, &shipped] {
            let v = evaluate_json("lowback-speed", trial, d.path());
            let header = std::fs::read_to_string(d.path().join("e.csv")).unwrap();
            assert!(header.contains("# leg_length: 0.964 m"), "{name}");
            assert!(header.contains("# correction: 1.14675"), "{name}");
            assert!(f(&v, &["speed_mae_mps"]) <= limit, "{name}: {v}");
        }
    }
}

/// A walk too slow for the walking test (limbfuse's simulator at 0.4 m/s:
/// the trunk's vertical acceleration is the pendulum's alone, 2 s RMS near
/// 0.3 m/s^2): "no gait found" now says how large that RMS got and which
/// setting it is compared with (2026-12-06; docs/RESULTS.md "lowback-speed:
/// the walking test and slow walking").
#[test]
fn no_gait_on_a_very_slow_walk_says_the_vertical_rms() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let sim = limbfuse(
        &[
            "simulate",
            "walking",
            "--speed",
            "0.4",
            "--duration",
            "20",
            "--seed",
            "4",
            "-o",
            "slow.csv",
        ],
        p,
    );
    assert!(sim.status.success());
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "lowback-speed",
            "slow.csv",
            "-o",
            "e.csv",
        ],
        p,
    );
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    for needle in ["no gait found", "2 s RMS peaked at 0.", "walking_rms"] {
        assert!(err.contains(needle), "{needle}: {err}");
    }
}
