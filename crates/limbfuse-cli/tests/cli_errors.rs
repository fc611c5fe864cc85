//! The `limbfuse` binary on bad input: exit status 1, a message naming the
//! file, line and column, never a panic.

use std::path::Path;
use std::process::{Command, Output};

fn limbfuse(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn assert_user_error(o: &Output, needles: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    assert!(
        !e.contains("panicked") && !e.contains("RUST_BACKTRACE"),
        "{e}"
    );
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
}

#[test]
fn nan_in_trial_names_file_line_and_column() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(
        d.path().join("t.csv"),
        "t,thigh_acc_x,thigh_acc_y,thigh_acc_z\n0,0,9.81,0\n0.01,0,NaN,0\n",
    )
    .unwrap();
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "accel-inclination",
            "t.csv",
            "-o",
            "e.csv",
        ],
        d.path(),
    );
    assert_user_error(&o, &["t.csv:3: column 3 (`thigh_acc_y`)", "finite"]);
}

#[test]
fn unknown_and_planned_methods_are_user_errors() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("t.csv"), "t\n0\n").unwrap();
    let o = limbfuse(
        &["estimate", "--method", "magic", "t.csv", "-o", "e.csv"],
        d.path(),
    );
    assert_user_error(&o, &["unknown method `magic`", "gyro-integration"]);
    let o = limbfuse(
        &["estimate", "--method", "sdre", "t.csv", "-o", "e.csv"],
        d.path(),
    );
    // sdre exists now (paper 004); without model metadata it is a user error.
    assert_user_error(&o, &["t.csv", "# model:"]);
}

#[test]
fn missing_trial_file_and_bad_flags_exit_1() {
    let d = tempfile::tempdir().unwrap();
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "gyro-integration",
            "nope.csv",
            "-o",
            "e.csv",
        ],
        d.path(),
    );
    assert_user_error(&o, &["nope.csv"]);
    let o = limbfuse(&["evaluate", "a.csv"], d.path());
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let o = limbfuse(&["frobnicate"], d.path());
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let o = limbfuse(&["--help"], d.path());
    assert_eq!(o.status.code(), Some(0));
}

#[test]
fn evaluate_rejects_mismatched_time_bases_and_bad_windows() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("t.csv"), "t,thigh_ref\n0,0.1\n0.01,0.2\n").unwrap();
    std::fs::write(
        d.path().join("e.csv"),
        "# method: x\nt,thigh\n0,0.1\n0.02,0.2\n",
    )
    .unwrap();
    let o = limbfuse(&["evaluate", "t.csv", "e.csv"], d.path());
    assert_user_error(&o, &["e.csv:4", "does not match"]);
    std::fs::write(
        d.path().join("e2.csv"),
        "# method: x\nt,thigh\n0,0.1\n0.01,0.2\n",
    )
    .unwrap();
    let o = limbfuse(
        &["evaluate", "t.csv", "e2.csv", "--window", "5:1"],
        d.path(),
    );
    assert_user_error(&o, &["--window"]);
    std::fs::write(d.path().join("noref.csv"), "t,knee_enc\n0,0.1\n").unwrap();
    let o = limbfuse(&["evaluate", "noref.csv", "e2.csv"], d.path());
    assert_user_error(&o, &["noref.csv", "no reference"]);
}

#[test]
fn estimate_then_evaluate_json_on_a_hand_made_trial() {
    let d = tempfile::tempdir().unwrap();
    // Static thigh at 0.2 rad: acc = g (sin 0.2, cos 0.2, 0). accel-inclination is exact.
    let (s, c) = (9.81 * 0.2f64.sin(), 9.81 * 0.2f64.cos());
    let mut text = String::from(
        "# format: limbfuse-trial/1\nt,thigh_acc_x,thigh_acc_y,thigh_acc_z,thigh_ref\n",
    );
    for k in 0..10 {
        let acc = if k == 4 {
            ",,".to_string()
        } else {
            format!("{s},{c},0")
        };
        text += &format!("{},{acc},0.2\n", k as f64 * 0.01);
    }
    std::fs::write(d.path().join("t.csv"), text).unwrap();
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "accel-inclination",
            "t.csv",
            "-o",
            "e.csv",
        ],
        d.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let est = std::fs::read_to_string(d.path().join("e.csv")).unwrap();
    assert!(est.starts_with("# method: accel-inclination\n"), "{est}");
    let o = limbfuse(&["evaluate", "t.csv", "e.csv", "--json"], d.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["method"], "accel-inclination");
    assert_eq!(v["n_samples"], 10);
    assert!(v["rmse_deg"]["thigh"].as_f64().unwrap() < 1e-12);
    assert!(v["mean_rmse_deg"].as_f64().unwrap() < 1e-12);
    assert_eq!(v["offset_free"], false);
}
