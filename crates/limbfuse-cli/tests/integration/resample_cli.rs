//! `limbfuse resample` says what it did (an audit, 2026-12-05): upsampling
//! reported and recorded a "windowed-sinc anti-alias" it never applied,
//! `--rate 1e-300` wrote a one-sample trial (exit 0), and `--rate 1e300`
//! printed a 301-digit number.

use crate::support::limbfuse;

#[test]
fn resample_says_whether_it_filtered_and_refuses_one_sample() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let o = limbfuse(
        &["simulate", "walking", "--duration", "5", "-o", "w.csv"],
        p,
    );
    assert!(o.status.success());
    let run = |rate: &str| limbfuse(&["resample", "w.csv", "--rate", rate, "-o", "r.csv"], p);
    for (rate, said) in [("200", "none needed"), ("50", "windowed-sinc")] {
        let o = run(rate);
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{e}");
        assert!(
            e.contains(&format!("(IMU anti-alias: {said}")),
            "{rate}: {e}"
        );
        let file = std::fs::read_to_string(p.join("r.csv")).unwrap();
        assert!(file.contains(&format!("(IMU anti-alias: {said}")), "{rate}");
    }
    for (rate, needle) in [
        ("0.001", "give one sample at it; expected at least 0.2004"),
        ("1e300", "found 1e300"),
    ] {
        let o = run(rate);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{rate}: {e}");
        assert!(e.contains(needle) && e.len() < 300, "{rate}: {e}");
    }
}

/// A reference contact marked on one row (the shared HA001 files' last
/// initial contact of a bout) survives a lower rate (an audit: 7 reference
/// initial contacts became 6 at 60 Hz; `resample::short_runs`).
#[test]
fn a_one_row_reference_contact_survives_resampling() {
    let Some(walk) = crate::support::shared_data("mobgap-lowerback/HA001-test5-trial2.csv") else {
        eprintln!("skipped: ../shared/data/mobgap-lowerback is absent");
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let w = walk.display().to_string();
    for args in [
        &["resample", &w, "--rate", "60", "-o", "r.csv"][..],
        &[
            "estimate",
            "--method",
            "lowback-speed",
            "r.csv",
            "-o",
            "e.csv",
        ],
    ] {
        let o = limbfuse(args, p);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let o = limbfuse(&["evaluate", "r.csv", "e.csv", "--json"], p);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["initial_contact"]["n_reference"], 7, "{v}");
}
