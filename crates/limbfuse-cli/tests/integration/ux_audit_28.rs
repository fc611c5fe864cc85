//! A fresh-user audit (session 28: the README and docs followed literally
//! on a clone of main): what a new user stumbled on, one test per finding.
//! Messages are in `ux_audit_28_messages`.

use std::path::Path;
use std::process::Output;

use crate::support::{limbfuse, shared_data};

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Exit status 1 and every needle in stderr.
fn user_error(o: &Output, needles: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    assert!(!e.contains("panicked"), "{e}");
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
}

/// Runs `args` in `dir` and expects success.
fn ok(args: &[&str], dir: &Path) -> Output {
    let o = limbfuse(args, dir);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    o
}

/// Item 1: `align raw.csv --calibration cal.toml -o a.csv` (an IMU
/// calibration from `calibrate`, the walking procedure) exited 0 with the
/// file ignored, the output identical to no calibration. Now refused
/// (exit 1) naming the flag and the procedure, and `--imu-calibration` for
/// an IMU calibration file; under static-rotation too.
#[test]
fn align_refuses_calibration_outside_the_static_rotation_procedure() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(
        &["simulate", "walking", "--duration", "10", "--mounting", "random", "-o", "raw.csv"],
        p,
    );
    ok(&["simulate", "calibration", "-o", "poses.csv"], p);
    ok(&["calibrate", "poses.csv", "-o", "cal.toml"], p);
    let o = limbfuse(&["align", "raw.csv", "--calibration", "cal.toml", "-o", "a.csv"], p);
    user_error(
        &o,
        &[
            "--calibration",
            "--procedure static-rotation",
            "walking procedure",
            "cal.toml is an IMU calibration file",
            "--imu-calibration",
        ],
    );
    assert!(!p.join("a.csv").exists());
    // A recording (not an IMU calibration) is refused too, without the hint.
    let o = limbfuse(&["align", "raw.csv", "--calibration", "poses.csv", "-o", "a.csv"], p);
    user_error(&o, &["--calibration", "--procedure static-rotation"]);
    assert!(!stderr(&o).contains("--imu-calibration"), "{}", stderr(&o));
    // Static rotation with an IMU calibration as the recording.
    let o = limbfuse(
        &[
            "align", "raw.csv", "--procedure", "static-rotation", "--calibration", "cal.toml", "-o",
            "a.csv",
        ],
        p,
    );
    user_error(&o, &["--calibration cal.toml", "IMU calibration file", "--imu-calibration"]);
    // The IMU calibration where it belongs still aligns.
    ok(&["align", "raw.csv", "--imu-calibration", "cal.toml", "-o", "a.csv"], p);
}

/// Item 2: `scripts/test-all` (the README's test command) hard-coded
/// `target/debug/limbfuse` and `target/pyvenv`, and failed with
/// `CARGO_TARGET_DIR` set. Now every path under the target directory comes
/// from `${CARGO_TARGET_DIR:-target}`.
#[test]
fn test_all_takes_the_target_directory_from_cargo_target_dir() {
    let script = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scripts/test-all"
    ))
    .unwrap();
    assert!(
        script.contains("${CARGO_TARGET_DIR:-target}"),
        "scripts/test-all does not read CARGO_TARGET_DIR"
    );
    for line in script.lines().filter(|l| !l.trim_start().starts_with('#')) {
        for fixed in ["target/debug", "target/pyvenv", "target/release"] {
            assert!(
                !line.contains(fixed),
                "scripts/test-all hard-codes `{fixed}`: {line}"
            );
        }
    }
}
