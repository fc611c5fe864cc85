//! Issue 18 item 1, `resample`: a reading no sensor can produce is left out
//! before interpolation, as every estimator leaves it out. Before, one
//! thigh gyro cell of 1e308 was low-passed into every output sample within
//! the anti-alias kernel's 0.2 s (values around 1e306), so the resampled
//! trial carried the glitch as a burst of plausible-looking samples.

use std::path::Path;

use crate::support::{edit_cells, limbfuse};

/// Column `name` of a trial file as (t, value) pairs, empty cells skipped.
fn column(p: &Path, file: &str, name: &str) -> Vec<(f64, f64)> {
    let text = std::fs::read_to_string(p.join(file)).unwrap();
    let mut rows = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = rows.next().unwrap().split(',').collect();
    let c = header.iter().position(|h| *h == name).unwrap();
    rows.filter_map(|l| {
        let cells: Vec<&str> = l.split(',').collect();
        Some((cells[0].parse().unwrap(), cells[c].parse().ok()?))
    })
    .collect()
}

#[test]
fn issue_18_resample_leaves_out_a_reading_beyond_the_sensor_range() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let o = limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "20",
            "--seed",
            "3",
            "-o",
            "w.csv",
        ],
        p,
    );
    assert_eq!(o.status.code(), Some(0));
    let text = std::fs::read_to_string(p.join("w.csv")).unwrap();
    // Row 1000 is t = 10 s at 100 Hz.
    let bad = edit_cells(&text, |row, name, _| {
        (row == 1000 && name == "thigh_gyr_z").then(|| "1e308".to_string())
    });
    std::fs::write(p.join("bad.csv"), bad).unwrap();
    for (from, to) in [("w.csv", "w50.csv"), ("bad.csv", "bad50.csv")] {
        let o = limbfuse(&["resample", from, "--rate", "50", "-o", to], p);
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(
            err.contains("warning"),
            from == "bad.csv",
            "a warning for the glitch only: {err}"
        );
        if from == "bad.csv" {
            assert!(
                err.contains("1 gyroscope") && err.contains("t = 10 s"),
                "{err}"
            );
        }
    }
    let clean = column(p, "w50.csv", "thigh_gyr_z");
    let out = column(p, "bad50.csv", "thigh_gyr_z");
    assert_eq!(clean.len(), out.len(), "no output sample lost");
    for ((t, a), (_, b)) in clean.iter().zip(&out) {
        // Walking thigh rates stay within a few rad/s.
        assert!(b.abs() < 10.0, "t = {t} s: {b} rad/s");
        // Beyond the kernel's half-width (0.2 s) and one output period the
        // output is the clean trial's, bit for bit.
        if (t - 10.0).abs() > 0.25 {
            assert_eq!(a, b, "t = {t} s");
        }
    }
    let meta = std::fs::read_to_string(p.join("bad50.csv")).unwrap();
    assert!(
        meta.lines()
            .any(|l| l.starts_with("# resampled:") && l.contains("1 gyroscope")),
        "the file says what was left out"
    );

    // The trial's own range is used, and a bad one is an error naming it.
    std::fs::write(p.join("r.csv"), format!("# gyro_range_rad_s: -1\n{text}")).unwrap();
    let o = limbfuse(&["resample", "r.csv", "--rate", "50", "-o", "r50.csv"], p);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("r.csv") && err.contains("gyro_range_rad_s: -1"),
        "{err}"
    );
    assert!(!p.join("r50.csv").exists());
}
