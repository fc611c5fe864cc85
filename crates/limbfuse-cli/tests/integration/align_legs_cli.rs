//! `limbfuse align` on both legs and its refusals (issue 14 item 1), running
//! the binary: a mirrored left leg is detected and aligned; a trial without
//! walking and a sensor that never rotates are refused by name, exit 1.

use std::path::Path;
use std::process::Output;

use crate::support::{edit_cells, limbfuse};

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn ok(o: &Output) -> String {
    assert_eq!(o.status.code(), Some(0), "stderr: {}", text(&o.stderr));
    text(&o.stdout)
}

fn user_error(o: &Output, needles: &[&str]) {
    let e = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    assert!(!e.contains("panicked"), "{e}");
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
}

/// A sensor that never moves: the columns starting with `prefix` hold the
/// accelerometer reading of the first data row and a zero rate.
fn freeze(path: &Path, prefix: &str) {
    let src = std::fs::read_to_string(path).unwrap();
    let mut lines = src.lines();
    let mut out = String::new();
    let mut header: Vec<String> = Vec::new();
    for l in lines.by_ref() {
        out += l;
        out += "\n";
        if !l.starts_with('#') {
            header = l.split(',').map(str::to_string).collect();
            break;
        }
    }
    let mut first: Option<Vec<String>> = None;
    for l in lines {
        let mut cells: Vec<String> = l.split(',').map(str::to_string).collect();
        let f = first.get_or_insert_with(|| cells.clone());
        for (i, h) in header.iter().enumerate() {
            if h.starts_with(prefix) {
                cells[i] = if h.contains("_gyr_") {
                    "0".into()
                } else {
                    f[i].clone()
                };
            }
        }
        out += &cells.join(",");
        out += "\n";
    }
    std::fs::write(path, out).unwrap();
}

#[test]
fn left_leg_with_turns_is_detected_and_aligned_and_confidence_printed() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &[
            "simulate",
            "walking",
            "--mounting",
            "random",
            "--leg",
            "left",
            "--turn-every",
            "8",
            "--duration",
            "20",
            "--seed",
            "4",
            "-o",
            "left.csv",
        ],
        p,
    ));
    let trial = std::fs::read_to_string(p.join("left.csv")).unwrap();
    assert!(trial.contains("# leg: left\n") && trial.contains("# turns: every_s=8"));
    // Declared wrong on purpose: the data say left.
    std::fs::write(
        p.join("wrong.csv"),
        trial.replace("# leg: left\n", "# leg: right\n"),
    )
    .unwrap();
    let o = limbfuse(&["align", "wrong.csv", "-o", "al.csv"], p);
    let out = ok(&o);
    assert!(out.contains("sensor  axis_energy  axis_ratio"), "{out}");
    assert!(out.contains("leg: left (detected"), "{out}");
    assert!(text(&o.stderr).contains("warning: leg: left (detected"));
    let al = std::fs::read_to_string(p.join("al.csv")).unwrap();
    assert!(al.contains("# leg: left\n") && al.contains("# leg_declared: right\n"));
    // Its mirror image is a right leg.
    ok(&limbfuse(
        &[
            "mirror",
            "left.csv",
            "--remount-seed",
            "2",
            "-o",
            "right.csv",
        ],
        p,
    ));
    let out = ok(&limbfuse(&["align", "right.csv", "-o", "al-r.csv"], p));
    assert!(out.contains("leg: right (detected"), "{out}");
}

#[test]
fn a_trial_without_walking_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    // 8 s of a still leg (tiny deterministic wobble, below any gait).
    let mut csv = String::from("# leg: right\nt");
    for s in ["thigh", "shank", "foot"] {
        for q in ["acc", "gyr"] {
            for a in ["x", "y", "z"] {
                csv += &format!(",{s}_{q}_{a}");
            }
        }
    }
    csv += "\n";
    for k in 0..800 {
        let e = 0.003 * ((k * 7919) % 13) as f64;
        csv += &format!("{:.2}", k as f64 * 0.01);
        for _ in 0..3 {
            csv += &format!(",{e},9.81,{e},{e},{},{e}", -e);
        }
        csv += "\n";
    }
    std::fs::write(p.join("still.csv"), csv).unwrap();
    for extra in [&[][..], &["--partial"][..]] {
        let mut args = vec!["align", "still.csv", "-o", "x.csv"];
        args.extend_from_slice(extra);
        user_error(
            &limbfuse(&args, p),
            &["still.csv", "no walking found", "need >= 3 s"],
        );
        assert!(!p.join("x.csv").exists());
    }
}

#[test]
fn a_sensor_that_never_rotates_is_refused_by_name() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &[
            "simulate",
            "walking",
            "--mounting",
            "random",
            "--duration",
            "10",
            "-o",
            "w.csv",
        ],
        p,
    ));
    freeze(&p.join("w.csv"), "shank_");
    user_error(
        &limbfuse(&["align", "w.csv", "-o", "x.csv"], p),
        &["shank: not enough motion to identify the axis"],
    );
    // --partial writes what is determinable and names what is not.
    let out = ok(&limbfuse(
        &["align", "w.csv", "-o", "x.csv", "--partial"],
        p,
    ));
    assert!(
        out.contains("shank_align_skipped: shank: not enough motion"),
        "{out}"
    );
    assert!(
        out.contains("thigh_align_quat:") && out.contains("foot_align_quat:"),
        "{out}"
    );
}

/// Issue 19 (invariance audit): `mirror` on a two-leg recording wrote
/// `# leg: left` but kept the other leg's columns as `foot_left_...`, left
/// them unmirrored and the contact references on their sides, so the
/// mirrored two-foot walk read back with one foot and no events. Now the
/// other leg's columns are `foot_right_...`, mirrored like the recorded
/// leg's, and `contact_right_ref` becomes `contact_left_ref`.
#[test]
fn issue_19_mirror_names_the_other_legs_columns() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let mut csv = String::from(
        "# leg: right\n# legs: right leg = foot_ (no suffix), left leg = foot_left_\nt",
    );
    for s in ["foot", "foot_left"] {
        for q in ["acc", "gyr"] {
            for a in ["x", "y", "z"] {
                csv += &format!(",{s}_{q}_{a}");
            }
        }
    }
    csv += ",contact_left_ref,contact_right_ref\n";
    for k in 0..4 {
        csv += &format!(
            "{:.2},1,2,3,0.1,0.2,0.3,4,5,6,0.4,0.5,0.6,0,1\n",
            k as f64 * 0.01
        );
    }
    std::fs::write(p.join("two.csv"), csv).unwrap();
    ok(&limbfuse(&["mirror", "two.csv", "-o", "m.csv"], p));
    let m = std::fs::read_to_string(p.join("m.csv")).unwrap();
    assert!(m.contains("# leg: left\n"), "{m}");
    // The recording's own description of its columns no longer holds: it
    // is marked, and the `mirrored` line gives the new naming (an audit).
    assert!(
        m.contains("# legs: (before `limbfuse mirror`) right leg = foot_"),
        "{m}"
    );
    assert!(
        m.contains("without a leg suffix are now the left leg's, the `_right_` ones the right"),
        "{m}"
    );
    let header = m.lines().find(|l| !l.starts_with('#')).unwrap();
    assert!(
        header.contains("foot_right_acc_x") && !header.contains("foot_left_"),
        "{header}"
    );
    let cols: Vec<&str> = header.split(',').collect();
    let row: Vec<&str> = m
        .lines()
        .rfind(|l| !l.starts_with('#'))
        .unwrap()
        .split(',')
        .collect();
    let cell = |name: &str| -> f64 {
        let i = cols.iter().position(|c| *c == name).unwrap();
        row[i].parse().unwrap()
    };
    // acc (x, y, -z), gyro (-x, -y, z) on both legs
    assert_eq!((cell("foot_acc_z"), cell("foot_gyr_x")), (-3.0, -0.1));
    assert_eq!(
        (cell("foot_right_acc_z"), cell("foot_right_gyr_y")),
        (-6.0, -0.5)
    );
    assert_eq!(
        (cell("contact_left_ref"), cell("contact_right_ref")),
        (1.0, 0.0)
    );
}

/// An audit: `mirror` on a trial without IMU columns (a B-SLIP CoM trial)
/// said "mirrored 401 samples", exit 0, and changed only `# leg:`.
#[test]
fn mirror_refuses_a_trial_without_imu_channels() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(&["simulate", "bslip", "-o", "b.csv"], p));
    user_error(
        &limbfuse(&["mirror", "b.csv", "-o", "m.csv"], p),
        &["b.csv", "no IMU channel to mirror"],
    );
    assert!(!p.join("m.csv").exists());
}

/// An audit: one 1e308 gyro cell made `align` refuse the thigh as "axis
/// undetermined ... is it on a walking leg?", blaming the placement. The
/// axes now come from the readings `estimate` keeps (the sensor gate), with
/// a warning; the written trial keeps every reading.
#[test]
fn one_absurd_reading_is_left_out_of_the_alignment() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    ok(&limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "20",
            "--seed",
            "4",
            "--mounting",
            "random",
            "-o",
            "raw.csv",
        ],
        d,
    ));
    let raw = std::fs::read_to_string(d.join("raw.csv")).unwrap();
    let out = edit_cells(&raw, |row, n, _| {
        (row == 499 && n == "thigh_gyr_x").then(|| "1e308".to_string())
    });
    std::fs::write(d.join("big.csv"), out).unwrap();
    let o = limbfuse(&["align", "big.csv", "-o", "al.csv"], d);
    ok(&o);
    let err = text(&o.stderr);
    assert!(
        err.contains("1 gyroscope and 0 accelerometer readings")
            && err.contains("left out of the alignment"),
        "{err}"
    );
    let aligned = std::fs::read_to_string(d.join("al.csv")).unwrap();
    assert!(aligned.contains("# thigh_align_quat:"));
}
