//! `limbfuse simulate calibration`, `limbfuse calibrate` and the
//! `--calibration` of `import`, `align` and `estimate`, run as a user
//! would: the whole path, and bad input (exit 1, the problem named).

use std::path::{Path, PathBuf};
use std::process::Output;

use crate::support::limbfuse;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn ok(o: &Output) {
    assert_eq!(o.status.code(), Some(0), "stderr: {}", stderr(o));
}

fn assert_user_error(o: &Output, needles: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    assert!(!e.contains("panicked"), "{e}");
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
}

/// A short calibration recording (9 poses, 2 s holds) of seed 3's sensors.
fn poses(dir: &Path, name: &str, extra: &[&str]) {
    let mut args = vec![
        "simulate",
        "calibration",
        "--seed",
        "3",
        "--hold",
        "2",
        "--transition",
        "1",
        "-o",
        name,
    ];
    args.extend_from_slice(extra);
    ok(&limbfuse(&args, dir));
}

#[test]
fn calibrate_then_estimate_and_align_with_the_file() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    poses(p, "poses.csv", &["--poses", "10"]);
    let o = limbfuse(&["calibrate", "poses.csv", "-o", "cal.toml"], p);
    ok(&o);
    let text = std::fs::read_to_string(p.join("cal.toml")).unwrap();
    for s in [
        "[sensors.trunk]",
        "[sensors.thigh]",
        "[sensors.shank]",
        "[sensors.foot]",
    ] {
        assert!(text.contains(s), "{text}");
    }
    assert!(
        text.contains("format = \"limbfuse-imu-calibration/1\""),
        "{text}"
    );
    ok(&limbfuse(
        &[
            "simulate",
            "walking",
            "--seed",
            "3",
            "--duration",
            "4",
            "-o",
            "walk.csv",
        ],
        p,
    ));
    let est = |trial: &str, out: &str, cal: bool| {
        let mut a = vec!["estimate", "--method", "mjls", trial, "-o", out];
        if cal {
            a.extend_from_slice(&["--calibration", "cal.toml"]);
        }
        limbfuse(&a, p)
    };
    ok(&est("walk.csv", "raw.csv", false));
    ok(&est("walk.csv", "cal.csv", true));
    // The calibration changes the estimate.
    let raw = std::fs::read_to_string(p.join("raw.csv")).unwrap();
    let cal = std::fs::read_to_string(p.join("cal.csv")).unwrap();
    assert_ne!(raw.lines().last(), cal.lines().last());
    // align applies it to the raw channels and records it; a second
    // calibration of that trial is refused.
    ok(&limbfuse(
        &[
            "align",
            "walk.csv",
            "--imu-calibration",
            "cal.toml",
            "-o",
            "aligned.csv",
        ],
        p,
    ));
    let aligned = std::fs::read_to_string(p.join("aligned.csv")).unwrap();
    assert!(
        aligned.contains("# imu_calibration: cal.toml"),
        "{}",
        &aligned[..2000]
    );
    let o = est("aligned.csv", "twice.csv", true);
    assert_user_error(&o, &["aligned.csv", "already calibrated"]);
}

#[test]
fn a_calibration_of_other_sensors_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(
        p.join("thigh.toml"),
        "format = \"limbfuse-imu-calibration/1\"\nmodel = \"full\"\ngravity = 9.81\n\n[sensors.thigh]\nacc_bias = [0.0, 0.0, 0.0]\nacc_matrix = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n",
    )
    .unwrap();
    ok(&limbfuse(
        &["simulate", "walking", "--duration", "2", "-o", "walk.csv"],
        p,
    ));
    for args in [
        &[
            "estimate",
            "--method",
            "mjls",
            "walk.csv",
            "-o",
            "e.csv",
            "--calibration",
            "thigh.toml",
        ][..],
        &[
            "align",
            "walk.csv",
            "-o",
            "a.csv",
            "--imu-calibration",
            "thigh.toml",
        ][..],
    ] {
        let o = limbfuse(args, p);
        assert_user_error(
            &o,
            &[
                "thigh.toml",
                "calibrates the sensors thigh",
                "also has trunk, shank, foot",
            ],
        );
        assert!(!p.join("e.csv").exists() && !p.join("a.csv").exists());
    }
    // A file that is not a calibration: line and column.
    std::fs::write(p.join("bad.toml"), "format = \"limbfuse-imu-calibration/1\"\nmodel = \"full\"\ngravity = 9.81\n[sensors.knee]\n").unwrap();
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "mjls",
            "walk.csv",
            "-o",
            "e.csv",
            "--calibration",
            "bad.toml",
        ],
        p,
    );
    assert_user_error(&o, &["bad.toml:4:", "knee"]);
}

#[test]
fn pose_recordings_with_motion_or_too_few_poses_are_refused() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &["simulate", "walking", "--duration", "6", "-o", "walk.csv"],
        p,
    ));
    let o = limbfuse(&["calibrate", "walk.csv", "-o", "cal.toml"], p);
    assert_user_error(
        &o,
        &["walk.csv", "trunk: no static pose", "moves throughout"],
    );
    assert!(!p.join("cal.toml").exists());
    poses(p, "five.csv", &["--poses", "5"]);
    let o = limbfuse(&["calibrate", "five.csv", "-o", "cal.toml"], p);
    assert_user_error(
        &o,
        &["five.csv", "5 distinct static poses", "needs at least 9"],
    );
    // A gravity off the Earth's would be fitted into the scales (an audit:
    // `--gravity 5` gave scales of 0.51, exit 0; 1e300 blamed the poses).
    poses(p, "ten.csv", &["--poses", "10"]);
    for g in ["5", "1e300"] {
        let o = limbfuse(&["calibrate", "ten.csv", "--gravity", g, "-o", "g.toml"], p);
        assert_user_error(&o, &[&format!("`gravity` = {g}: must be 9.7 to 9.9 m/s^2")]);
    }
    // The reduced scale model needs 6 (the six faces).
    poses(p, "six.csv", &["--poses", "6"]);
    ok(&limbfuse(
        &["calibrate", "six.csv", "--model", "scale", "-o", "cal.toml"],
        p,
    ));
    // The bias-only model takes five poses, but cannot absorb the sensors'
    // 0.5 % scale errors: the residual check refuses it.
    let o = limbfuse(
        &["calibrate", "five.csv", "--model", "bias", "-o", "b.toml"],
        p,
    );
    assert_user_error(&o, &["do not fit one calibration", "worst pose"]);
    // A wobbling pose among ten: rejected, named by its time span, the rest used.
    poses(p, "wobble.csv", &["--poses", "10", "--wobble-pose", "2"]);
    let o = limbfuse(&["calibrate", "wobble.csv", "-o", "w.toml"], p);
    ok(&o);
    let e = stderr(&o);
    // Pose 2 is held from 3 s to 5 s (2 s holds, 1 s turns).
    let start: f64 = e
        .split("thigh: pose rejected: ")
        .nth(1)
        .and_then(|r| r.split('-').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no rejected thigh pose in: {e}"));
    assert!(
        (2.0..=3.5).contains(&start) && e.contains("not static"),
        "{e}"
    );
    // Nine poses left: still enough; with the wobbling one among nine, too few.
    poses(p, "wobble9.csv", &["--poses", "9", "--wobble-pose", "9"]);
    let o = limbfuse(&["calibrate", "wobble9.csv", "-o", "w9.toml"], p);
    assert_user_error(&o, &["8 distinct static poses", "rejected:", "not static"]);
}

fn knee_rig() -> Option<PathBuf> {
    crate::support::shared_data("knee-rig/Trial_01.csv")
}

#[test]
fn import_applies_a_calibration_or_refuses_one_of_other_sensors() {
    let Some(trial) = knee_rig() else { return };
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let trial = trial.to_str().unwrap();
    std::fs::write(
        p.join("trunk.toml"),
        "format = \"limbfuse-imu-calibration/1\"\nmodel = \"bias\"\ngravity = 9.81\n\n[sensors.trunk]\nacc_bias = [0.0, 0.0, 0.0]\nacc_matrix = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n",
    )
    .unwrap();
    let o = limbfuse(
        &[
            "import",
            "--format",
            "knee-rig",
            trial,
            "-o",
            "t.csv",
            "--calibration",
            "trunk.toml",
        ],
        p,
    );
    assert_user_error(
        &o,
        &[
            "trunk.toml",
            "calibrates the sensors trunk",
            "also has thigh, shank",
        ],
    );
    poses(p, "poses.csv", &["--poses", "9"]);
    ok(&limbfuse(&["calibrate", "poses.csv", "-o", "cal.toml"], p));
    let o = limbfuse(
        &[
            "import",
            "--format",
            "knee-rig",
            trial,
            "-o",
            "t.csv",
            "--calibration",
            "cal.toml",
        ],
        p,
    );
    ok(&o);
    assert!(
        stderr(&o).contains("also calibrates trunk, foot"),
        "{}",
        stderr(&o)
    );
    let t = std::fs::read_to_string(p.join("t.csv")).unwrap();
    assert!(t.contains("# imu_calibration: cal.toml"));
}

/// An audit: `simulate calibration --poses 0` and `--hold nan` were
/// reported as `--duration 0` / `--duration NaN`, a flag this command does
/// not have. Each flag is now named.
#[test]
fn simulate_calibration_names_the_flag_that_is_wrong() {
    let tmp = tempfile::tempdir().unwrap();
    let run = |flag: &str, value: &str| {
        limbfuse(
            &["simulate", "calibration", flag, value, "-o", "c.csv"],
            tmp.path(),
        )
    };
    assert_user_error(&run("--poses", "0"), &["--poses 0: expected 1 to 14"]);
    assert_user_error(&run("--poses", "15"), &["--poses 15"]);
    assert_user_error(&run("--hold", "nan"), &["--hold NaN"]);
    assert_user_error(&run("--transition", "-1"), &["--transition -1"]);
    for o in [run("--poses", "0"), run("--hold", "nan")] {
        assert!(!stderr(&o).contains("--duration"), "{}", stderr(&o));
    }
}

/// An audit (session 28): a calibration file's top-level `gravity` took any
/// finite positive number (1e300, 1 for g); 0 and negatives said only "a
/// finite number > 0". Now `estimate --calibration` and `align
/// --imu-calibration` refuse anything off 9.0-10.5 m/s^2 with the file, the
/// key and the range, the number short; 9.0 and 10.5 load.
#[test]
fn a_calibration_gravity_off_the_earths_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &["simulate", "walking", "--duration", "2", "-o", "walk.csv"],
        p,
    ));
    let identity = "acc_bias = [0.0, 0.0, 0.0]\nacc_matrix = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n";
    let file = |g: &str| {
        let mut text =
            format!("format = \"limbfuse-imu-calibration/1\"\nmodel = \"full\"\ngravity = {g}\n");
        for seg in ["trunk", "thigh", "shank", "foot"] {
            text += &format!("\n[sensors.{seg}]\n{identity}");
        }
        std::fs::write(p.join("g.toml"), text).unwrap();
    };
    let estimate = || {
        limbfuse(
            &[
                "estimate",
                "--method",
                "mjls",
                "walk.csv",
                "--calibration",
                "g.toml",
                "-o",
                "e.csv",
            ],
            p,
        )
    };
    for g in ["9.0", "9.81", "10.5"] {
        file(g);
        ok(&estimate());
    }
    std::fs::remove_file(p.join("e.csv")).unwrap();
    for (g, shown) in [
        ("1e300", "1e300"),
        ("0.0", "found 0"),
        ("-9.81", "-9.81"),
        ("1.0", "found 1"),
        ("981.0", "981"),
        ("nan", "NaN"),
    ] {
        file(g);
        let align = limbfuse(
            &[
                "align",
                "walk.csv",
                "--imu-calibration",
                "g.toml",
                "-o",
                "a.csv",
            ],
            p,
        );
        for o in [estimate(), align] {
            assert_user_error(&o, &["g.toml", "`gravity`", "within 9 to 10.5", shown]);
        }
        assert!(!p.join("e.csv").exists() && !p.join("a.csv").exists());
    }
}
