//! The `limbfuse` binary on bad input: exit status 1, a message naming the
//! file, line and column, never a panic.

use crate::support::{assert_user_error, edit_cells, limbfuse, stderr};

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

/// A hand-made trial with the given IMU segments (acc + gyr, static,
/// upright), optionally the three encoders, and a `thigh_ref` reference, 10
/// samples at 100 Hz (a segment filter starts once a segment has been
/// quasi-static for 0.05 s: from the sixth sample on).
fn trial_with(segments: &[&str], encoders: bool) -> String {
    let mut header = vec!["t".to_string()];
    for s in segments {
        for q in ["acc", "gyr"] {
            for a in ["x", "y", "z"] {
                header.push(format!("{s}_{q}_{a}"));
            }
        }
    }
    if encoders {
        header.extend(["hip_enc", "knee_enc", "ankle_enc"].map(String::from));
    }
    header.push("thigh_ref".to_string());
    let mut out = header.join(",") + "\n";
    for k in 0..10 {
        let mut row = vec![format!("{}", k as f64 * 0.01)];
        for _ in segments {
            row.extend(["0", "9.81", "0", "0", "0", "0"].map(String::from));
        }
        if encoders {
            row.extend(["0", "0", "0"].map(String::from));
        }
        row.push("0".to_string());
        out += &(row.join(",") + "\n");
    }
    out
}

/// Issue 3: `mjls` on a trial without encoders is a user error naming the
/// missing columns (it used to run on the accelerometers alone).
#[test]
fn issue3_mjls_without_encoders_names_the_missing_columns() {
    let d = tempfile::tempdir().unwrap();
    let all = ["trunk", "thigh", "shank", "foot"];
    std::fs::write(d.path().join("noenc.csv"), trial_with(&all, false)).unwrap();
    let o = limbfuse(
        &["estimate", "--method", "mjls", "noenc.csv", "-o", "e.csv"],
        d.path(),
    );
    assert_user_error(
        &o,
        &[
            "noenc.csv",
            "`mjls`",
            "hip_enc, knee_enc, ankle_enc",
            "`local` or `global`",
        ],
    );
    assert!(
        !d.path().join("e.csv").exists(),
        "no estimate file on error"
    );
    // local and global need no encoders.
    for m in ["local", "global"] {
        let o = limbfuse(
            &["estimate", "--method", m, "noenc.csv", "-o", "e.csv"],
            d.path(),
        );
        assert_eq!(o.status.code(), Some(0), "{m}: {}", stderr(&o));
    }
    // tune checks too, before any optimisation.
    let o = limbfuse(
        &[
            "tune",
            "--method",
            "mjls",
            "noenc.csv",
            "--window",
            "0:0.04",
            "-o",
            "p.toml",
        ],
        d.path(),
    );
    assert_user_error(&o, &["noenc.csv", "hip_enc"]);
}

/// Issue 3: a segment filter on a trial lacking one segment's IMU is a user
/// error naming that segment's columns.
#[test]
fn issue3_segment_filter_without_a_segment_imu_names_it() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(
        d.path().join("noshank.csv"),
        trial_with(&["trunk", "thigh", "foot"], true),
    )
    .unwrap();
    for m in ["local", "mjls", "global"] {
        let o = limbfuse(
            &["estimate", "--method", m, "noshank.csv", "-o", "e.csv"],
            d.path(),
        );
        assert_user_error(
            &o,
            &[
                "noshank.csv",
                &format!("`{m}`"),
                "shank_acc_x/y/z, shank_gyr_x/y/z",
            ],
        );
    }
}

/// An audit found `estimate c.csv -o c.csv` replaced the recording with
/// its estimate (exit 0); `resample`, `mirror` and `align` overwrote their
/// input the same way. Refused now, exit 1, the trial left as it was.
#[test]
fn an_output_naming_the_input_file_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let o = limbfuse(
        &["simulate", "walking", "--duration", "3", "-o", "c.csv"],
        d.path(),
    );
    assert_eq!(o.status.code(), Some(0));
    let before = std::fs::read(d.path().join("c.csv")).unwrap();
    for args in [
        &["estimate", "--method", "local", "c.csv", "-o", "./c.csv"][..],
        &["resample", "c.csv", "--rate", "50", "-o", "c.csv"][..],
        &["mirror", "c.csv", "-o", "c.csv"][..],
        &["align", "c.csv", "-o", "c.csv"][..],
        // a second audit: these replaced their input too
        &[
            "tune", "--method", "local", "--budget", "10", "c.csv", "-o", "c.csv",
        ][..],
        &["calibrate", "c.csv", "-o", "c.csv"][..],
        &["report", "c.csv", "e.csv", "-o", "c.csv"][..],
        &[
            "estimate", "--method", "mjls", "--params", "c.csv", "w.csv", "-o", "c.csv",
        ][..],
    ] {
        let o = limbfuse(args, d.path());
        assert_user_error(
            &o,
            &["that is the input file", "give the output another name"],
        );
        assert_eq!(
            std::fs::read(d.path().join("c.csv")).unwrap(),
            before,
            "{args:?}"
        );
    }
    // another name is fine
    let o = limbfuse(
        &["estimate", "--method", "local", "c.csv", "-o", "e.csv"],
        d.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let est = std::fs::read(d.path().join("e.csv")).unwrap();
    let o = limbfuse(&["report", "c.csv", "e.csv", "-o", "e.csv"], d.path());
    assert_user_error(&o, &["that is the input file", "e.csv"]);
    assert_eq!(std::fs::read(d.path().join("e.csv")).unwrap(), est);
}

/// A second audit found two outputs of one command given the same name
/// reported both written (exit 0) while one replaced the other. Refused
/// now, exit 1, nothing written.
#[test]
fn two_outputs_with_one_name_are_refused() {
    let d = tempfile::tempdir().unwrap();
    for args in [
        &[
            "montecarlo",
            "--runs",
            "1",
            "--duration",
            "2",
            "-o",
            "m.csv",
            "--svg",
            "./m.csv",
        ][..],
        &[
            "simulate",
            "knee-fes",
            "--duration",
            "2",
            "--calibration",
            "s.csv",
            "-o",
            "s.csv",
        ][..],
    ] {
        let o = limbfuse(args, d.path());
        assert_user_error(
            &o,
            &["the same file as -o", "give each output its own name"],
        );
    }
    assert!(
        std::fs::read_dir(d.path()).unwrap().next().is_none(),
        "nothing written"
    );
}

/// An audit found `evaluate` printing an empty table with exit 0 when
/// nothing could be scored: a trial file given as the estimate (with a
/// false warning that it came from an older limbfuse), a window beyond the
/// trial, references empty on every row. Each is now an error, exit 1.
#[test]
fn evaluate_refuses_when_nothing_can_be_scored() {
    let d = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| limbfuse(args, d.path());
    assert_eq!(
        run(&["simulate", "walking", "--duration", "3", "-o", "w.csv"])
            .status
            .code(),
        Some(0)
    );
    assert_eq!(
        run(&["estimate", "--method", "local", "w.csv", "-o", "e.csv"])
            .status
            .code(),
        Some(0)
    );
    assert_user_error(
        &run(&["evaluate", "w.csv", "w.csv"]),
        &[
            "w.csv",
            "no estimate column",
            "a trial file, not an estimate?",
        ],
    );
    assert_user_error(
        &run(&["report", "w.csv", "w.csv", "-o", "r.html"]),
        &["no estimate column"],
    );
    assert_user_error(
        &run(&["evaluate", "w.csv", "e.csv", "--window", "50:60"]),
        &["no sample of the trial inside the window (50:60 s"],
    );
    // every reference cell emptied
    let text = std::fs::read_to_string(d.path().join("w.csv")).unwrap();
    let out = edit_cells(&text, |_, n, _| n.ends_with("_ref").then(String::new));
    std::fs::write(d.path().join("noref.csv"), out).unwrap();
    assert_eq!(
        run(&["estimate", "--method", "local", "noref.csv", "-o", "en.csv"])
            .status
            .code(),
        Some(0)
    );
    assert_user_error(
        &run(&["evaluate", "noref.csv", "en.csv"]),
        &["none of the 300 samples", "nothing to score"],
    );
}

/// `# g: abc` (or 0, -9.81, nan) was silently taken for 9.81 by the
/// methods that read the trial's gravity; it is now an error naming the
/// file and the line's value.
#[test]
fn a_trial_gravity_that_is_not_a_number_is_an_error() {
    let d = tempfile::tempdir().unwrap();
    let o = limbfuse(
        &["simulate", "walking", "--duration", "3", "-o", "w.csv"],
        d.path(),
    );
    assert_eq!(o.status.code(), Some(0));
    let text = std::fs::read_to_string(d.path().join("w.csv")).unwrap();
    assert!(text.contains("\n# g: 9.81\n"));
    std::fs::write(
        d.path().join("g.csv"),
        text.replace("\n# g: 9.81\n", "\n# g: -9.81\n"),
    )
    .unwrap();
    for m in ["gait-events", "chain"] {
        let o = limbfuse(
            &["estimate", "--method", m, "g.csv", "-o", "e.csv"],
            d.path(),
        );
        assert_user_error(&o, &["g.csv", "`# g: -9.81`", "expected gravity in m/s^2"]);
    }
}

/// An audit: `--kappa nan` was reported against the trial file with the
/// estimator's words ("kappa must be non-negative"); it names the flag.
#[test]
fn a_bad_kappa_names_the_flag() {
    let d = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| limbfuse(args, d.path());
    for args in [
        &[
            "gait-library",
            "build",
            "--speeds",
            "0.7:0.7:0.1",
            "-o",
            "l.json",
        ][..],
        &[
            "simulate",
            "bslip",
            "--speed",
            "0.7",
            "--library",
            "l.json",
            "--duration",
            "2",
            "-o",
            "b.csv",
        ][..],
    ] {
        assert_eq!(run(args).status.code(), Some(0), "{args:?}");
    }
    for k in ["nan", "-1"] {
        let o = run(&[
            "estimate",
            "--method",
            "imm-bslip",
            "--library",
            "l.json",
            "--kappa",
            k,
            "b.csv",
            "-o",
            "e.csv",
        ]);
        assert_user_error(&o, &["--kappa", "expected a gain of 0 (off) or more"]);
    }
}

/// An audit: `knee-kinematic` on a trial whose IMU cells were all empty
/// wrote a constant 90 deg knee (the filter's prior) with exit 0, and
/// `imm-bslip` with every `com_meas_*` cell empty an estimate empty on
/// every row. The paper-004 filters give no angle before their first
/// measurement, and a run that gives no value on any row is an error.
#[test]
fn no_measurement_no_estimate() {
    let d = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| limbfuse(args, d.path());
    assert_eq!(
        run(&["simulate", "knee-fes", "--duration", "3", "-o", "k.csv"])
            .status
            .code(),
        Some(0)
    );
    let text = std::fs::read_to_string(d.path().join("k.csv")).unwrap();
    // IMU cells emptied on the first `rows` data rows
    let blank = |rows: usize| {
        edit_cells(&text, |row, n, _| {
            (row < rows && (n.contains("_acc_") || n.contains("_gyr_"))).then(String::new)
        })
    };
    std::fs::write(d.path().join("none.csv"), blank(1_000_000)).unwrap();
    std::fs::write(d.path().join("late.csv"), blank(100)).unwrap();
    for m in ["knee-kinematic", "sdre", "ekf"] {
        let o = run(&["estimate", "--method", m, "none.csv", "-o", "e.csv"]);
        assert_user_error(
            &o,
            &["none.csv", "gave no estimate on any of its 300 samples"],
        );
        assert!(!d.path().join("e.csv").exists());
        let o = run(&["estimate", "--method", m, "late.csv", "-o", "e.csv"]);
        assert_eq!(o.status.code(), Some(0), "{m}: {}", stderr(&o));
        let est = std::fs::read_to_string(d.path().join("e.csv")).unwrap();
        let rows: Vec<&str> = est
            .lines()
            .filter(|l| !l.starts_with('#'))
            .skip(1)
            .collect();
        let knee = |r: &str| r.split(',').nth(3).unwrap().to_string();
        assert!(
            rows[..100].iter().all(|r| knee(r).is_empty()),
            "{m}: {}",
            rows[0]
        );
        assert!(
            rows[100..].iter().all(|r| !knee(r).is_empty()),
            "{m}: {}",
            rows[100]
        );
    }
}

/// A sweep over short clips of the shared recordings (2026-12-07): the
/// segment filters on 0.5 s of a walk (complete inputs, no
/// quasi-static moment, so no start before their 2 s window) were refused
/// with "the inputs it reads are missing on every row, or rejected", which
/// sent the user looking for a data problem. The message now names the
/// trial's length first.
#[test]
fn a_clip_shorter_than_the_start_window_is_named_as_short() {
    let d = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| limbfuse(args, d.path());
    let o = run(&["simulate", "walking", "--duration", "4", "-o", "w.csv"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = std::fs::read_to_string(d.path().join("w.csv")).unwrap();
    // the header and half a second of rows mid-walk (2 <= t < 2.5)
    let mid_walk = |l: &str| {
        let t = l.split(',').next().and_then(|t| t.parse::<f64>().ok());
        t.is_some_and(|t| (2.0..2.5).contains(&t))
    };
    let clip: String = text
        .lines()
        .filter(|l| l.starts_with('#') || l.starts_with("t,") || mid_walk(l))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(d.path().join("clip.csv"), clip).unwrap();
    for m in ["local", "mjls", "global"] {
        let o = run(&["estimate", "--method", m, "clip.csv", "-o", "e.csv"]);
        assert_user_error(
            &o,
            &[
                "clip.csv",
                "gave no estimate on any of its",
                "(the trial lasts 0.",
                "the segment filters wait up to 2 s",
            ],
        );
    }
    // the whole walk starts and is not called short
    let o = run(&["estimate", "--method", "mjls", "w.csv", "-o", "e.csv"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}
