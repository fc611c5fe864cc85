//! A trial that declares raw sensor frames (`# imu_frame: raw ...`, what the
//! gaittoolbox and knee-rig importers write) given to a method that reads
//! frames aligned to the segments: `estimate` warns on stderr and names
//! `align` (found on the shared S02 walk, where `chain` on the imported raw
//! trial gives thigh 82 / shank 88 deg RMSE without a word). After `align`
//! the file restates `imu_frame` and the warning is gone.

use crate::support::limbfuse;

#[test]
fn raw_frames_warn_until_aligned() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let sim = limbfuse(
        &["simulate", "walking", "--duration", "6", "-o", "w.csv"],
        dir,
    );
    assert_eq!(sim.status.code(), Some(0));
    let text = std::fs::read_to_string(dir.join("w.csv")).unwrap();
    let raw = text.replacen("\n", "\n# imu_frame: raw sensor frames (unaligned)\n", 1);
    std::fs::write(dir.join("raw.csv"), raw).unwrap();
    let stderr = |args: &[&str]| {
        let o = limbfuse(args, dir);
        assert_eq!(o.status.code(), Some(0), "{args:?}");
        String::from_utf8(o.stderr).unwrap()
    };
    for method in ["local", "chain", "gyro-integration"] {
        let err = stderr(&["estimate", "--method", method, "raw.csv", "-o", "e.csv"]);
        assert!(
            err.contains("warning: raw.csv declares raw sensor frames")
                && err.contains(&format!("`{method}` reads IMU frames aligned"))
                && err.contains("limbfuse align"),
            "{method}: {err}"
        );
    }
    let err = stderr(&[
        "estimate",
        "--method",
        "knee-gyro-axis",
        "raw.csv",
        "-o",
        "k.csv",
    ]);
    assert!(!err.contains("warning"), "{err}");
    stderr(&["align", "raw.csv", "-o", "aligned.csv"]);
    let aligned = std::fs::read_to_string(dir.join("aligned.csv")).unwrap();
    assert!(
        aligned.lines().any(|l| l.starts_with(
            "# imu_frame: aligned to the segments by limbfuse align (SPEC section 1)"
        ) && l.ends_with("before: raw sensor frames (unaligned)")),
        "the aligned file restates imu_frame"
    );
    let err = stderr(&[
        "estimate",
        "--method",
        "local",
        "aligned.csv",
        "-o",
        "e.csv",
    ]);
    assert!(!err.contains("warning"), "{err}");
}

/// limbfuse's own raw trials declare their frames too: `simulate walking
/// --mounting random` (and `simulate knee`, mounted at random) and `mirror
/// --remount-seed` write `# imu_frame: raw ...`, and the paper-004 knee
/// methods (`rmx`, `knee-kinematic`) read aligned frames. Before
/// (2026-12-04): nothing said; `local` on a random-mounted walk 20-107 deg per segment
/// RMSE, `rmx` on the randomly mounted knee trial 70 deg.
#[test]
fn own_raw_trials_declare_their_frames() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let run = |args: &[&str]| {
        let o = limbfuse(args, dir);
        assert_eq!(o.status.code(), Some(0), "{args:?}");
        String::from_utf8(o.stderr).unwrap()
    };
    run(&[
        "simulate",
        "walking",
        "--duration",
        "6",
        "--mounting",
        "random",
        "-o",
        "raw.csv",
    ]);
    run(&["simulate", "walking", "--duration", "6", "-o", "w.csv"]);
    run(&["mirror", "w.csv", "--remount-seed", "1", "-o", "left.csv"]);
    run(&["simulate", "knee", "--duration", "12", "-o", "knee.csv"]);
    for (trial, method) in [
        ("raw.csv", "local"),
        ("left.csv", "chain"),
        ("knee.csv", "rmx"),
        ("raw.csv", "knee-kinematic"),
    ] {
        let err = run(&["estimate", "--method", method, trial, "-o", "e.csv"]);
        assert!(
            err.contains(&format!("warning: {trial} declares raw sensor frames")),
            "{trial} {method}: {err}"
        );
    }
    // the HTML report of an estimate of the raw walk says it too
    run(&[
        "estimate",
        "--method",
        "local",
        "raw.csv",
        "-o",
        "raw-local.csv",
    ]);
    run(&["report", "raw.csv", "raw-local.csv", "-o", "r.html"]);
    let html = std::fs::read_to_string(dir.join("r.html")).unwrap();
    assert!(
        html.contains(
            r#"<p class="warning">warning (raw-local.csv): raw.csv declares raw sensor frames"#
        ),
        "the report names the raw frames"
    );
    // aligned, the same walk says nothing
    run(&["align", "raw.csv", "-o", "aligned.csv"]);
    let err = run(&[
        "estimate",
        "--method",
        "local",
        "aligned.csv",
        "-o",
        "e.csv",
    ]);
    assert!(!err.contains("warning"), "{err}");
    run(&["report", "aligned.csv", "e.csv", "-o", "a.html"]);
    let html = std::fs::read_to_string(dir.join("a.html")).unwrap();
    assert!(
        !html.contains(r#"<p class="warning">"#),
        "aligned: no warning"
    );
}
