//! A fresh-user audit (session 28: the README and docs followed literally
//! on a clone of main): what a new user stumbled on, one test per finding.
//! Messages are in `ux_audit_28_messages`.

use std::path::Path;
use std::process::Output;

use crate::support::{keep_columns, limbfuse, shared_data};

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
        &[
            "simulate",
            "walking",
            "--duration",
            "10",
            "--mounting",
            "random",
            "-o",
            "raw.csv",
        ],
        p,
    );
    ok(&["simulate", "calibration", "-o", "poses.csv"], p);
    ok(&["calibrate", "poses.csv", "-o", "cal.toml"], p);
    let o = limbfuse(
        &[
            "align",
            "raw.csv",
            "--calibration",
            "cal.toml",
            "-o",
            "a.csv",
        ],
        p,
    );
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
    let o = limbfuse(
        &[
            "align",
            "raw.csv",
            "--calibration",
            "poses.csv",
            "-o",
            "a.csv",
        ],
        p,
    );
    user_error(&o, &["--calibration", "--procedure static-rotation"]);
    assert!(!stderr(&o).contains("--imu-calibration"), "{}", stderr(&o));
    // Static rotation with an IMU calibration as the recording.
    let o = limbfuse(
        &[
            "align",
            "raw.csv",
            "--procedure",
            "static-rotation",
            "--calibration",
            "cal.toml",
            "-o",
            "a.csv",
        ],
        p,
    );
    user_error(
        &o,
        &[
            "--calibration cal.toml",
            "IMU calibration file",
            "--imu-calibration",
        ],
    );
    // The IMU calibration where it belongs still aligns.
    ok(
        &[
            "align",
            "raw.csv",
            "--imu-calibration",
            "cal.toml",
            "-o",
            "a.csv",
        ],
        p,
    );
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
    // `target/...` not after `$` (`$target/debug` is the variable's).
    for line in script.lines().filter(|l| !l.trim_start().starts_with('#')) {
        for fixed in ["target/debug", "target/pyvenv", "target/release"] {
            let hard_coded = line
                .match_indices(fixed)
                .any(|(i, _)| !line[..i].ends_with('$'));
            assert!(!hard_coded, "scripts/test-all hard-codes `{fixed}`: {line}");
        }
    }
}

/// Item 3: on a trial with a lower-back (trunk) IMU only, `inspect` listed
/// `gyro-integration (after limbfuse align ...)` and `align` failed with
/// "no walking found" (the cause: no leg IMU); on the imported knee rig
/// `inspect` listed `rmx (after limbfuse align)` and `align` failed with
/// "thigh: not enough motion". Now `align` names the missing leg IMUs and
/// `inspect` says that `align` cannot align the trial, and why.
#[test]
fn inspect_says_when_align_cannot_align_the_trial() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(
        &[
            "simulate",
            "walking",
            "--duration",
            "12",
            "--mounting",
            "random",
            "-o",
            "raw.csv",
        ],
        p,
    );
    keep_columns(p, "raw.csv", "back.csv", |n| n.starts_with("trunk_"));
    let o = limbfuse(&["align", "back.csv", "-o", "a.csv"], p);
    user_error(
        &o,
        &[
            "back.csv",
            "no leg IMU",
            "thigh, shank or foot",
            "trunk IMU only",
        ],
    );
    assert!(!stderr(&o).contains("no walking found"), "{}", stderr(&o));
    let out = stdout(&ok(&["inspect", "back.csv"], p));
    assert!(
        out.contains("`limbfuse align` cannot align this trial: no leg IMU"),
        "{out}"
    );
    assert!(!out.contains("after `limbfuse align`"), "{out}");
    // A trial align can align keeps the promise.
    let out = stdout(&ok(&["inspect", "raw.csv"], p));
    assert!(out.contains("mjls (after `limbfuse align`"), "{out}");
    assert!(!out.contains("cannot align"), "{out}");
    // The shared recordings of the audit.
    if let Some(back) = shared_data("mobgap-lowerback/HA001-test5-trial1.csv") {
        let back = back.to_str().unwrap();
        let out = stdout(&ok(&["inspect", back], p));
        assert!(out.contains("cannot align this trial: no leg IMU"), "{out}");
        user_error(
            &limbfuse(&["align", back, "-o", "b.csv"], p),
            &["no leg IMU"],
        );
    }
    if let Some(rig) = shared_data("knee-rig/Trial_01.csv") {
        ok(
            &[
                "import",
                "--format",
                "knee-rig",
                rig.to_str().unwrap(),
                "-o",
                "rig01.csv",
            ],
            p,
        );
        let out = stdout(&ok(&["inspect", "rig01.csv"], p));
        assert!(
            out.contains("`limbfuse align` cannot align this trial: thigh: not enough motion"),
            "{out}"
        );
        assert!(!out.contains("rmx (after `limbfuse align`"), "{out}");
    }
}

/// Item 4: `estimate --window 0:20` / `--window 5s` gave clap's "invalid
/// digit found in string". Now the message says that `--window` is the
/// knee methods' identification window in samples, and where seconds go.
#[test]
fn estimate_window_that_is_not_a_sample_count_says_what_window_is() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(p.join("t.csv"), "t\n0\n0.01\n").unwrap();
    for w in ["0:20", "5s"] {
        let o = limbfuse(
            &[
                "estimate",
                "--method",
                "knee-selfalign",
                "t.csv",
                "--window",
                w,
                "-o",
                "e.csv",
            ],
            p,
        );
        user_error(
            &o,
            &[
                "--window",
                w,
                "identification window in",
                "samples",
                "500",
                "window_s",
                "evaluate --window",
            ],
        );
        assert!(!stderr(&o).contains("invalid digit"), "{}", stderr(&o));
    }
}

/// Item 5: `--order` on another method said "--window and --order apply to
/// method knee-selfalign only", though knee-gyro-axis takes both (and
/// `limbfuse methods` lists them); now the message names both methods, and
/// knee-gyro-axis accepts `--order`.
#[test]
fn order_and_window_name_both_knee_axis_methods() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(p.join("t.csv"), "t\n0\n0.01\n").unwrap();
    let o = limbfuse(
        &[
            "estimate", "--method", "local", "t.csv", "--order", "4", "-o", "e.csv",
        ],
        p,
    );
    user_error(
        &o,
        &["--window and --order apply to methods knee-selfalign and knee-gyro-axis only, not to `local`"],
    );
    // knee-gyro-axis takes --order: its error is about the trial, not the flag.
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "knee-gyro-axis",
            "t.csv",
            "--order",
            "4",
            "-o",
            "e.csv",
        ],
        p,
    );
    assert!(!stderr(&o).contains("apply to"), "{}", stderr(&o));
    let help = stdout(&ok(&["estimate", "--help"], p));
    assert!(
        help.contains("knee-selfalign / knee-gyro-axis: parameter-EKF iterations"),
        "{help}"
    );
}

/// Item 6: `evaluate walk-v1.2-s301.csv EST.csv` (a gait-events estimate
/// of the independent simulator's walk) said "no reference event to score
/// against (the trial's contact_*_ref has no transition)" though the trial
/// has no contact_*_ref column. Now it says the columns are absent; "has
/// no transition" stays for a column without one.
#[test]
fn gait_evaluation_says_the_trial_has_no_contact_reference_column() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(
        &[
            "simulate",
            "walking",
            "--duration",
            "12",
            "--gait-reference",
            "-o",
            "g.csv",
        ],
        p,
    );
    // Neither column: the CoM velocity is the speed reference.
    keep_columns(p, "g.csv", "nocontact.csv", |n| !n.starts_with("contact_"));
    ok(
        &[
            "estimate",
            "--method",
            "gait-events",
            "nocontact.csv",
            "-o",
            "e2.csv",
        ],
        p,
    );
    let out = stdout(&ok(&["evaluate", "nocontact.csv", "e2.csv"], p));
    assert!(
        out.contains("no reference event to score against (the trial has no contact_left_ref / contact_right_ref column)"),
        "{out}"
    );
    assert!(!out.contains("has no transition"), "{out}");
    // Columns without a transition (the right foot always down).
    let text = std::fs::read_to_string(p.join("g.csv")).unwrap();
    let flat = crate::support::edit_cells(&text, |_, name, _| {
        name.starts_with("contact_").then(|| "1".to_string())
    });
    std::fs::write(p.join("flat.csv"), flat).unwrap();
    ok(
        &[
            "estimate",
            "--method",
            "gait-events",
            "flat.csv",
            "-o",
            "e3.csv",
        ],
        p,
    );
    let out = stdout(&ok(&["evaluate", "flat.csv", "e3.csv"], p));
    assert!(out.contains("contact_*_ref has no transition"), "{out}");
    if let Some(walk) = shared_data("independent-sim/walk-v1.2-s301.csv") {
        let walk = walk.to_str().unwrap();
        ok(
            &["estimate", "--method", "gait-events", walk, "-o", "ind.csv"],
            p,
        );
        let out = stdout(&ok(&["evaluate", walk, "ind.csv"], p));
        assert!(
            out.contains("the trial has no contact_left_ref / contact_right_ref column"),
            "{out}"
        );
    }
}

/// Item 7: `evaluate --offset-free` printed max|e| and mean e, which are
/// not offset-free, unlabelled ("(mean error shown)"). The numbers stay;
/// the note says they are as measured, before the mean is removed; the
/// RMSE is the offset-free one.
#[test]
fn offset_free_evaluation_says_max_and_mean_error_are_as_measured() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(
        &["simulate", "walking", "--duration", "8", "-o", "w.csv"],
        p,
    );
    ok(
        &["estimate", "--method", "local", "w.csv", "-o", "e.csv"],
        p,
    );
    let plain = stdout(&ok(&["evaluate", "w.csv", "e.csv"], p));
    let free = stdout(&ok(&["evaluate", "w.csv", "e.csv", "--offset-free"], p));
    assert!(
        free.contains("max|e| and mean e as measured, before the mean is removed"),
        "{free}"
    );
    // Same max|e| and mean e columns in both tables.
    let cols = |t: &str| -> Vec<String> {
        t.lines()
            .filter(|l| l.starts_with("thigh") || l.starts_with("shank"))
            .map(|l| {
                l.split_whitespace()
                    .skip(2)
                    .take(2)
                    .collect::<Vec<_>>()
                    .join(" ")
            })
            .collect()
    };
    assert_eq!(cols(&plain), cols(&free), "{plain}\n{free}");
    assert!(!cols(&plain).is_empty(), "{plain}");
}

/// Item 8: `estimate --method mjls` on a foot-only trial (the gaitmap foot
/// walk) ended "use `local` or `global` on trials without encoders", which
/// fail there too (no trunk, thigh or shank IMU). Now that hint comes only
/// when they could run; otherwise the message names the methods that run
/// on the trial (as `inspect` lists them).
#[test]
fn a_foot_only_trial_is_told_the_methods_that_run_on_it() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(
        &["simulate", "walking", "--duration", "8", "-o", "w.csv"],
        p,
    );
    keep_columns(p, "w.csv", "foot.csv", |n| n.starts_with("foot_"));
    let o = limbfuse(
        &["estimate", "--method", "mjls", "foot.csv", "-o", "x.csv"],
        p,
    );
    user_error(
        &o,
        &[
            "foot.csv",
            "methods that run on it:",
            "gait-events",
            "limbfuse inspect foot.csv",
        ],
    );
    assert!(
        !stderr(&o).contains("use `local` or `global`"),
        "{}",
        stderr(&o)
    );
    // Every IMU, no encoder: the hint holds and stays.
    keep_columns(p, "w.csv", "imus.csv", |n| !n.ends_with("_enc"));
    let o = limbfuse(
        &["estimate", "--method", "mjls", "imus.csv", "-o", "x.csv"],
        p,
    );
    user_error(&o, &["use `local` or `global` on trials without encoders"]);
    if let Some(gaitmap) = shared_data("gaitmap-foot-walk/trial.csv") {
        let o = limbfuse(
            &[
                "estimate",
                "--method",
                "mjls",
                gaitmap.to_str().unwrap(),
                "-o",
                "x.csv",
            ],
            p,
        );
        user_error(&o, &["methods that run on it:", "gait-events"]);
        assert!(
            !stderr(&o).contains("use `local` or `global`"),
            "{}",
            stderr(&o)
        );
    }
}
