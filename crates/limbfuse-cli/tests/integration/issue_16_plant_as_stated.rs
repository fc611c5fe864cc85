//! Issue 16, "default configuration no worse than rmx" (the lead's
//! decision): a parameter file whose `[model]` states `t_a` and has no
//! `[states]` makes `sdre` / `ekf` carry the activation state and the gyro
//! and accelerometer bias states, with the shank accelerometer's lever arm
//! from the file, else the trial's `# shank_imu_m:`, else mid-shank for the
//! body height (Winter 2009); the run names the source. An explicit
//! `[states]` means what it says (the thesis estimator with `activation =
//! false`). Each test fails without that rule (checked: before it, the
//! `t_a` file ran the thesis model and printed no source).

use std::path::Path;

use crate::support::limbfuse;

/// Runs `method` on `trial` with `params`; returns (stderr, estimate
/// header lines without `# command:`, estimate rows).
fn run(method: &str, trial: &str, params: Option<&str>, dir: &Path) -> (String, String, String) {
    let mut args = vec!["estimate", "--method", method, trial, "-o", "e.csv"];
    if let Some(p) = params {
        args.extend(["--params", p]);
    }
    let o = limbfuse(&args, dir);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(o.status.success(), "{method}: {err}");
    let text = std::fs::read_to_string(dir.join("e.csv")).unwrap();
    let (mut header, mut rows) = (String::new(), String::new());
    for l in text.lines() {
        if l.starts_with("# command:") {
            continue;
        }
        let to = if l.starts_with('#') {
            &mut header
        } else {
            &mut rows
        };
        to.push_str(l);
        to.push('\n');
    }
    (err, header, rows)
}

/// An 8 s P2-R trial (`# shank_imu_m: 0.2`, `param.t_a: 1`) and a copy
/// without the lever-arm line, the copy with `# height_m: 1.6`.
fn trials(dir: &Path) {
    let o = limbfuse(
        &[
            "simulate",
            "knee-fes",
            "--subject",
            "P2-R",
            "--duration",
            "8",
            "-o",
            "k.csv",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(dir.join("k.csv")).unwrap();
    assert!(text.contains("# shank_imu_m: 0.2\n"));
    let bare = text.replace("# shank_imu_m: 0.2\n", "");
    std::fs::write(dir.join("bare.csv"), &bare).unwrap();
    let tall = bare.replace("# noise:", "# height_m: 1.6\n# noise:");
    assert_ne!(tall, bare);
    std::fs::write(dir.join("tall.csv"), tall).unwrap();
}

#[test]
fn issue_16_file_with_t_a_and_no_states_enables_the_states() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    trials(p);
    std::fs::write(p.join("ta.toml"), "[model]\nt_a = 1.0\n").unwrap();
    for m in ["sdre", "ekf"] {
        let (err, header, _) = run(m, "k.csv", Some("ta.toml"), p);
        assert!(
            err.contains("activation, gyro bias and accelerometer bias states"),
            "{m}: {err}"
        );
        for line in [
            "# activation: state, a_ke' = (u_ke - a_ke) / T_a, T_a = 1 s",
            "# gyro_bias_state: true",
            "# acc_bias_state: true",
            "# torque_disturbance_state: false",
            "# shank_imu_m: 0.2\n",
            "# shank_imu_m_source: trial metadata # shank_imu_m",
        ] {
            assert!(header.contains(line), "{m}: `{line}` not in\n{header}");
        }
    }
    // No `t_a`: the thesis estimator, no note.
    std::fs::write(p.join("no-ta.toml"), "[model]\ninertia = 0.45\n").unwrap();
    let (err, header, _) = run("sdre", "k.csv", Some("no-ta.toml"), p);
    assert!(!err.contains("t_a"), "{err}");
    assert!(!header.contains("gyro_bias_state"), "{header}");
}

#[test]
fn issue_16_explicit_states_table_is_respected() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    trials(p);
    // `activation = false`: exactly the thesis estimator of the trial's own
    // model (the file's t_a is the preset's), bit for bit.
    std::fs::write(
        p.join("thesis.toml"),
        "[model]\nt_a = 1.0\n[states]\nactivation = false\n",
    )
    .unwrap();
    for m in ["sdre", "ekf"] {
        let (err, header, rows) = run(m, "k.csv", Some("thesis.toml"), p);
        let (_, _, own) = run(m, "k.csv", None, p);
        assert!(!err.contains("[model] states t_a"), "{m}: {err}");
        assert!(!header.contains("gyro_bias_state"), "{m}: {header}");
        assert_eq!(
            rows, own,
            "{m}: [states] activation = false is the thesis estimator"
        );
    }
    // Only the stated option: activation, no bias states, thesis lever arm.
    std::fs::write(
        p.join("act.toml"),
        "[model]\nt_a = 1.0\n[states]\nactivation = true\n",
    )
    .unwrap();
    let (_, header, _) = run("ekf", "k.csv", Some("act.toml"), p);
    for line in [
        "# gyro_bias_state: false",
        "# acc_bias_state: false",
        "# shank_imu_m: 0\n",
    ] {
        assert!(header.contains(line), "`{line}` not in\n{header}");
    }
}

#[test]
fn issue_16_lever_arm_source_is_reported() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    trials(p);
    std::fs::write(p.join("ta.toml"), "[model]\nt_a = 1.0\n").unwrap();
    // The file's own value wins over the trial's.
    std::fs::write(
        p.join("file-r.toml"),
        "[model]\nt_a = 1.0\n[measurement]\nshank_imu_m = 0.25\n",
    )
    .unwrap();
    let (err, header, _) = run("sdre", "k.csv", Some("file-r.toml"), p);
    assert!(
        err.contains("0.2500 m below the knee (parameter file"),
        "{err}"
    );
    assert!(
        header.contains("# shank_imu_m: 0.25\n# shank_imu_m_source: parameter file"),
        "{header}"
    );
    // Neither: mid-shank of a 1.75 m body, 0.5 x 0.246 x 1.75 = 0.21525 m.
    let (err, header, _) = run("sdre", "bare.csv", Some("ta.toml"), p);
    assert!(
        err.contains("0.2152 m below the knee (anthropometric"),
        "{err}"
    );
    assert!(header.contains("# shank_imu_m: 0.21525\n"), "{header}");
    assert!(header.contains("Winter 2009"), "{header}");
    // `# height_m: 1.6`: 0.5 x 0.246 x 1.6 = 0.1968 m.
    let (err, _, _) = run("ekf", "tall.csv", Some("ta.toml"), p);
    assert!(err.contains("0.1968 m below the knee"), "{err}");
    assert!(err.contains("# height_m"), "{err}");
    // A malformed lever arm in the metadata: exit 1 naming the key.
    let text = std::fs::read_to_string(p.join("k.csv")).unwrap();
    std::fs::write(
        p.join("bad.csv"),
        text.replace("# shank_imu_m: 0.2\n", "# shank_imu_m: 3\n"),
    )
    .unwrap();
    let o = limbfuse(
        &[
            "estimate", "--method", "sdre", "bad.csv", "-o", "x.csv", "--params", "ta.toml",
        ],
        p,
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("shank_imu_m: 3") && !e.contains("panicked"),
        "{e}"
    );
}

/// The independent FES simulator's `# param_r_imu:` is the lever arm when
/// the trial has no `# shank_imu_m:` (which wins when both are there); a
/// value out of range is an error naming the key. Before: ignored, the
/// anthropometric 0.215 m.
#[test]
fn issue_16_param_r_imu_is_the_lever_arm() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    trials(p);
    std::fs::write(p.join("ta.toml"), "[model]\nt_a = 1.0\n").unwrap();
    let bare = std::fs::read_to_string(p.join("bare.csv")).unwrap();
    let with = |line: &str| bare.replace("# noise:", &format!("{line}\n# noise:"));
    std::fs::write(p.join("r.csv"), with("# param_r_imu: 0.3")).unwrap();
    let (err, header, _) = run("sdre", "r.csv", Some("ta.toml"), p);
    assert!(
        err.contains("0.3000 m below the knee (trial metadata # param_r_imu)"),
        "{err}"
    );
    assert!(header.contains("# shank_imu_m: 0.3\n"), "{header}");
    let both = std::fs::read_to_string(p.join("k.csv"))
        .unwrap()
        .replace("# noise:", "# param_r_imu: 0.3\n# noise:");
    std::fs::write(p.join("both.csv"), both).unwrap();
    let (err, _, _) = run("ekf", "both.csv", Some("ta.toml"), p);
    assert!(
        err.contains("0.2000 m below the knee (trial metadata # shank_imu_m)"),
        "{err}"
    );
    std::fs::write(p.join("bad.csv"), with("# param_r_imu: 3")).unwrap();
    let o = limbfuse(
        &[
            "estimate", "--method", "sdre", "bad.csv", "-o", "x.csv", "--params", "ta.toml",
        ],
        p,
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("param_r_imu: 3") && !e.contains("panicked"),
        "{e}"
    );
}

/// `knee-kinematic` (ours: no thesis measurement to keep) takes the lever
/// arm the trial states, else mid-shank, and says so; a parameter file's
/// `[measurement]` wins. Before: 0 m (the accelerometer on the knee axis)
/// unless the file stated it.
#[test]
fn issue_16_knee_kinematic_lever_arm_from_the_trial() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    trials(p);
    std::fs::write(p.join("r02.toml"), "[measurement]\nshank_imu_m = 0.2\n").unwrap();
    std::fs::write(p.join("r0.toml"), "[measurement]\nshank_imu_m = 0\n").unwrap();
    let (err, _, rows) = run("knee-kinematic", "k.csv", None, p);
    assert!(
        err.contains("0.2000 m below the knee (trial metadata # shank_imu_m"),
        "{err}"
    );
    let (err_file, _, same) = run("knee-kinematic", "k.csv", Some("r02.toml"), p);
    assert!(!err_file.contains("below the knee"), "{err_file}");
    assert_eq!(rows, same, "the trial's 0.2 m is the file's 0.2 m");
    let (_, _, at_axis) = run("knee-kinematic", "k.csv", Some("r0.toml"), p);
    assert_ne!(rows, at_axis, "0 m is not the default");
    let (err, _, _) = run("knee-kinematic", "bare.csv", None, p);
    assert!(
        err.contains("0.2152 m below the knee (anthropometric"),
        "{err}"
    );
}

/// Issue 16 item 1 on the fixed hip: `[states] activation = true` runs the
/// four activation states; a `[model]` that states `t_a` without
/// `[states]` does too (and says so); the knee's other states and
/// `[measurement]` are refused. Before: every `[states]` on the fixed hip
/// was refused.
#[test]
fn issue_16_fixed_hip_activation_states_from_the_file() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let o = limbfuse(
        &[
            "simulate",
            "fixed-hip",
            "--duration",
            "4",
            "--activation-t-a",
            "0.25",
            "-o",
            "h.csv",
        ],
        p,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let trial = std::fs::read_to_string(p.join("h.csv")).unwrap();
    assert!(trial.contains("# param.t_a: 0.25"), "{}", &trial[..600]);
    std::fs::write(p.join("act.toml"), "[states]\nactivation = true\n").unwrap();
    std::fs::write(p.join("ta.toml"), "[model]\nt_a = 0.25\n").unwrap();
    for (file, note) in [("act.toml", false), ("ta.toml", true)] {
        for m in ["sdre", "ekf"] {
            let (err, header, _) = run(m, "h.csv", Some(file), p);
            assert!(
                header.contains("# activation: states a_hf, a_he, a_kf, a_ke"),
                "{m} {file}: {header}"
            );
            assert_eq!(
                err.contains("the fixed hip's four activation states"),
                note,
                "{m} {file}: {err}"
            );
        }
    }
    // Without a file: the thesis estimator.
    let (_, header, _) = run("sdre", "h.csv", None, p);
    assert!(!header.contains("activation"), "{header}");
    for (name, text) in [
        (
            "bias.toml",
            "[states]\nactivation = true\ngyro_bias = true\n",
        ),
        ("r.toml", "[measurement]\nshank_imu_m = 0.2\n"),
    ] {
        std::fs::write(p.join(name), text).unwrap();
        let o = limbfuse(
            &[
                "estimate", "--method", "ekf", "h.csv", "-o", "x.csv", "--params", name,
            ],
            p,
        );
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{name}: {e}");
        assert!(e.contains("knee-fes model only"), "{name}: {e}");
    }
}
