//! `limbfuse inspect`: what a trial holds and which methods run on it.
//! Writing it found that `gyro-integration` and `accel-inclination` ran on a
//! trial without any IMU (the shared B-SLIP trials) and wrote an estimate
//! empty on every row with exit 0; they now refuse it (exit 1).

use crate::support::limbfuse;

fn run(args: &[&str], dir: &std::path::Path) -> (i32, String, String) {
    let o = limbfuse(args, dir);
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8(o.stdout).unwrap(),
        String::from_utf8(o.stderr).unwrap(),
    )
}

/// A simulated walk of `seconds` written to `w.csv` in `dir`, as text.
fn simulated_walk(dir: &std::path::Path, seconds: &str) -> String {
    let (code, ..) = run(
        &["simulate", "walking", "--duration", seconds, "-o", "w.csv"],
        dir,
    );
    assert_eq!(code, 0);
    std::fs::read_to_string(dir.join("w.csv")).unwrap()
}

#[test]
fn inspect_a_walking_trial_and_its_gaps() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let (code, ..) = run(
        &["simulate", "walking", "--duration", "3", "-o", "w.csv"],
        dir,
    );
    assert_eq!(code, 0);
    let (code, out, err) = run(&["inspect", "w.csv"], dir);
    assert_eq!(code, 0, "{err}");
    for want in [
        "w.csv: 300 rows, t = 0 to 2.99 s",
        "sample step: median 0.010000 s (100.00 Hz; the file states 100 Hz)",
        "gaps: none",
        "inputs: trunk acc, trunk gyr, thigh acc, thigh gyr, shank acc, shank gyr, foot acc, foot gyr, hip_enc, knee_enc, ankle_enc",
        "units: t in s, IMUs in m/s^2 and rad/s",
        "methods that run on it with their defaults: gyro-integration, accel-inclination, local, mjls, global, chain",
        "imm-bslip          method `imm-bslip` needs CoM measurement columns",
        // what the simulator's metadata sets in the methods that run
        "what the metadata sets (or its defaults, when it says nothing):",
        "  chain: thigh 0.429 m, shank 0.430 m from `# segment_lengths_m:`; IMU positions from `# imu_mounts_m:`",
        "  lowback-speed: pendulum length 0.9275 m, correction factor 1.25 (from 0.530 x the trial's `# height_m:`",
        "  knee-kinematic: shank accelerometer 0.2152 m below the knee (anthropometric default",
    ] {
        assert!(out.contains(want), "missing `{want}` in:\n{out}");
    }
    // sdre needs a model, not columns
    let settings = out
        .split("methods with the columns they need, but not their defaults' settings:")
        .nth(1)
        .unwrap();
    assert!(
        settings.contains("  sdre ") && settings.contains("# model:"),
        "{out}"
    );
    // rows 100-149 removed (a 0.51 s gap) and thigh gyro cells emptied on 30 rows
    let text = std::fs::read_to_string(dir.join("w.csv")).unwrap();
    let header_at = text.lines().position(|l| l.starts_with("t,")).unwrap();
    let names: Vec<&str> = text.lines().nth(header_at).unwrap().split(',').collect();
    let gyr: Vec<usize> = (0..names.len())
        .filter(|&i| names[i].starts_with("thigh_gyr_"))
        .collect();
    let mut out_text = String::new();
    for (k, line) in text.lines().enumerate() {
        let row = k as i64 - header_at as i64 - 1;
        if (100..150).contains(&row) {
            continue;
        }
        if (200..230).contains(&row) {
            let mut cells: Vec<&str> = line.split(',').collect();
            for &i in &gyr {
                cells[i] = "";
            }
            out_text += &cells.join(",");
        } else {
            out_text += line;
        }
        out_text.push('\n');
    }
    std::fs::write(dir.join("g.csv"), out_text).unwrap();
    let (code, out, _) = run(&["inspect", "g.csv"], dir);
    assert_eq!(code, 0);
    assert!(
        out.contains("gaps: 1 step over 1.5 median steps, the longest 0.51"),
        "{out}"
    );
    assert!(out.contains("thigh gyr (12.0 % of rows missing)"), "{out}");
}

/// Session 32: on a trial that states no body (no `# height_m:`, segment
/// lengths, leg or sensor height), `inspect` named a 1.75 m body for `chain`
/// and `knee-kinematic` but a 1.70 m one for `lowback-speed` (pendulum
/// 0.9 m = 0.530 x 1.70 m). Every method's defaults now assume the one body
/// `limbfuse_models::DEFAULT_BODY_HEIGHT_M`, and the pendulum is 0.530 x it.
#[test]
fn one_default_body_height_for_every_method() {
    use limbfuse_models::DEFAULT_BODY_HEIGHT_M;
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // A simulated walk without a word about the body.
    let text = simulated_walk(dir, "3");
    let body_keys = ["# height_m:", "# segment_lengths_m:", "# imu_mounts_m:"];
    let kept: String = text
        .lines()
        .filter(|l| !body_keys.iter().any(|k| l.starts_with(k)))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(dir.join("nobody.csv"), kept).unwrap();
    let (code, out, err) = run(&["inspect", "nobody.csv"], dir);
    assert_eq!(code, 0, "{err}");
    let line = |method: &str| {
        out.lines()
            .find(|l| l.starts_with(&format!("  {method}: ")))
            .unwrap_or_else(|| panic!("no `{method}` line in:\n{out}"))
            .to_string()
    };
    // The length (m) a line names after `before`: the last word before " m".
    let height_after = |line: &str, before: &str| -> f64 {
        let rest = line
            .split(before)
            .nth(1)
            .unwrap_or_else(|| panic!("no `{before}` in `{line}`"));
        let words = rest.split(" m").next().unwrap();
        words.rsplit(' ').next().unwrap().parse().unwrap()
    };
    let chain = height_after(&line("chain"), "the default height ");
    let knee = height_after(&line("knee-kinematic"), "0.5 x 0.246 x ");
    let lowback_line = line("lowback-speed");
    let lowback = height_after(&lowback_line, "(from the default (0.530 x ");
    assert_eq!(
        [chain, knee, lowback],
        [DEFAULT_BODY_HEIGHT_M; 3],
        "chain, knee-kinematic and lowback-speed assume different bodies:\n{out}"
    );
    let pendulum = height_after(&lowback_line, "pendulum length ");
    assert_eq!(pendulum, 0.530 * DEFAULT_BODY_HEIGHT_M, "{lowback_line}");
}

#[test]
fn inspect_names_units_and_refuses_nothing_to_estimate() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let (code, ..) = run(
        &[
            "simulate",
            "bslip",
            "--speed",
            "0.8",
            "--duration",
            "3",
            "-o",
            "b.csv",
        ],
        dir,
    );
    assert_eq!(code, 0);
    let (code, out, err) = run(&["inspect", "b.csv"], dir);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("inputs: com_meas"), "{out}");
    assert!(out.contains("units: t in s as far as"), "{out}");
    assert!(
        out.contains("methods that run on it with their defaults: none"),
        "{out}"
    );
    for method in ["gyro-integration", "accel-inclination"] {
        let (code, _, err) = run(
            &["estimate", "--method", method, "b.csv", "-o", "e.csv"],
            dir,
        );
        assert_eq!(code, 1, "{method}: {err}");
        assert!(
            err.contains("but the trial has no trunk_, thigh_, shank_ or foot_"),
            "{err}"
        );
        assert!(!dir.join("e.csv").exists());
    }
    let (code, _, err) = run(&["inspect", "missing.csv"], dir);
    assert_eq!(code, 1);
    assert!(err.contains("missing.csv"), "{err}");
}

#[test]
fn inspect_several_files_as_json() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let (code, ..) = run(
        &["simulate", "walking", "--duration", "2", "-o", "w.csv"],
        dir,
    );
    assert_eq!(code, 0);
    let (code, ..) = run(
        &[
            "simulate",
            "bslip",
            "--speed",
            "0.8",
            "--duration",
            "2",
            "-o",
            "b.csv",
        ],
        dir,
    );
    assert_eq!(code, 0);
    let (code, out, err) = run(&["inspect", "--json", "w.csv", "b.csv"], dir);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let trials = v.as_array().unwrap();
    assert_eq!(trials.len(), 2);
    assert_eq!(trials[0]["trial"], "w.csv");
    assert_eq!(trials[0]["rows"], 200);
    assert_eq!(trials[0]["methods"]["mjls"][0], "runs");
    assert_eq!(trials[1]["methods"]["mjls"][0], "missing columns");
    assert_eq!(trials[1]["methods"]["imm-bslip"][0], "needs a setting");
    assert_eq!(trials[1]["inputs"]["com_meas"], 0);
    let read = trials[0]["metadata_settings"].as_array().unwrap();
    assert_eq!(read.len(), 3, "{read:?}");
    // limbfuse's B-SLIP trial states no body: the library's is used
    let read = trials[1]["metadata_settings"].as_array().unwrap();
    assert!(
        read.len() == 1 && read[0].as_str().unwrap().starts_with("imm-bslip: no body"),
        "{read:?}"
    );
    // a file that cannot be read: the others are printed, then exit 1
    let (code, out, err) = run(&["inspect", "w.csv", "missing.csv", "b.csv"], dir);
    assert_eq!(code, 1);
    assert_eq!(out.matches(" rows, t = ").count(), 2, "{out}");
    assert!(
        err.contains("missing.csv") && err.contains("1 of 3 trial files could not be read"),
        "{err}"
    );
}

/// `inspect` listed `gait-events` as running on a seated knee-FES trial,
/// where `estimate` then finds no gait (exit 1), and `knee-kinematic` as
/// running on a walk, where its fixed thigh does not hold: both with
/// nothing said. It now says what the thigh's motion (the angular
/// deviation of the thigh accelerometer's direction) says about them.
#[test]
fn inspect_says_what_the_thighs_motion_means_for_the_methods() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for args in [
        &["simulate", "walking", "--duration", "4", "-o", "w.csv"][..],
        &[
            "simulate",
            "knee-fes",
            "--duration",
            "4",
            "-o",
            "seated.csv",
        ][..],
    ] {
        assert_eq!(run(args, dir).0, 0);
    }
    let title = "what the thigh's motion says about them:";
    let (code, out, err) = run(&["inspect", "w.csv"], dir);
    assert_eq!(code, 0, "{err}");
    let notes = out.split(title).nth(1).expect(title);
    assert!(
        notes.contains("  knee-kinematic: models a fixed (seated) thigh, but the thigh accelerometer's direction spreads by")
            && !notes.contains("gait-events"),
        "{out}"
    );
    // (since the inspect audit of 2026-12-05 the seated thigh puts
    // gait-events in the data's group, with the reason, rather than a note)
    let (code, out, err) = run(&["inspect", "seated.csv"], dir);
    assert_eq!(code, 0, "{err}");
    let ruled = out
        .split("the data rule out:")
        .nth(1)
        .expect("a group of methods the data rule out");
    assert!(
        ruled.contains("  gait-events        the thigh accelerometer's direction spreads by only")
            && ruled.contains("no walking for it to find")
            && !out.contains(title),
        "{out}"
    );
    // what it foretells: `estimate` finds no gait there
    let (code, _, err) = run(
        &[
            "estimate",
            "--method",
            "gait-events",
            "seated.csv",
            "-o",
            "e.csv",
        ],
        dir,
    );
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("no gait found"), "{err}");
    // JSON: the spread, and gait-events ruled out with the reason
    let (code, out, _) = run(&["inspect", "--json", "seated.csv"], dir);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v[0]["thigh_spread_deg"].as_f64().unwrap() < 5.0);
    let g = &v[0]["methods"]["gait-events"];
    assert_eq!(g[0], "no usable data", "{g}");
    assert!(g[1].as_str().unwrap().contains("no walking for it to find"));
    assert!(v[0]["data_notes"].as_array().unwrap().is_empty());
}

/// An audit: `# sample_rate_hz: abc` (or 0, nan) was shown as "the file
/// states no rate"; it now says the line is not a rate.
#[test]
fn inspect_names_a_stated_rate_that_is_not_one() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let text = simulated_walk(dir, "2");
    assert!(text.contains("# sample_rate_hz: 100\n"));
    for bad in ["abc", "0", "nan"] {
        let name = format!("r-{bad}.csv");
        std::fs::write(
            dir.join(&name),
            text.replace(
                "# sample_rate_hz: 100\n",
                &format!("# sample_rate_hz: {bad}\n"),
            ),
        )
        .unwrap();
        let (code, out, err) = run(&["inspect", &name], dir);
        assert_eq!(code, 0, "{err}");
        assert!(
            out.contains(&format!(
                "the file's `# sample_rate_hz: {bad}` is not a rate"
            )),
            "{out}"
        );
    }
}

/// An audit (164 pairs where `inspect` said "runs" and `estimate` exited 1):
/// a trial shorter than the knee methods' identification window, and an
/// input needed on every row that has no reading, are now "no usable data",
/// with `estimate`'s reason.
#[test]
fn inspect_says_when_the_data_rule_a_method_out() {
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    let (code, _, e) = run(
        &["simulate", "walking", "--duration", "3", "-o", "w.csv"],
        d,
    );
    assert_eq!(code, 0, "{e}");
    let (code, out, e) = run(&["inspect", "--json", "w.csv"], d);
    assert_eq!(code, 0, "{e}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let knee = &v[0]["methods"]["knee-selfalign"];
    assert_eq!(knee[0], "no usable data", "{knee}");
    assert!(knee[1]
        .as_str()
        .unwrap()
        .contains("window (500 samples) is longer than the trial (300 rows)"));
    assert_eq!(v[0]["methods"]["mjls"][0], "runs");
    let (code, _, e) = run(
        &[
            "estimate",
            "--method",
            "knee-selfalign",
            "w.csv",
            "-o",
            "k.csv",
        ],
        d,
    );
    assert!(code == 1 && e.contains("longer than the trial"), "{e}");
    // The thigh gyro empty on every row of a trial long enough for the
    // window: the knee-axis methods are ruled out; mjls still runs (it
    // estimates the thigh from its encoders and accelerometer).
    let (code, _, e) = run(
        &["simulate", "walking", "--duration", "8", "-o", "w8.csv"],
        d,
    );
    assert_eq!(code, 0, "{e}");
    let text = std::fs::read_to_string(d.join("w8.csv")).unwrap();
    let blank = crate::support::edit_cells(&text, |_, name, _| {
        name.starts_with("thigh_gyr").then(String::new)
    });
    std::fs::write(d.join("blank.csv"), blank).unwrap();
    let (code, out, e) = run(&["inspect", "blank.csv"], d);
    assert_eq!(code, 0, "{e}");
    let ruled = out.split("the data rule out:").nth(1).unwrap_or("");
    assert!(
        ruled.contains("knee-gyro-axis")
            && ruled.contains("`thigh gyr` has no reading on any of the 800 rows"),
        "{out}"
    );
    assert!(!ruled.contains("mjls"), "{out}");
    let (code, _, _) = run(
        &["estimate", "--method", "mjls", "blank.csv", "-o", "m.csv"],
        d,
    );
    assert_eq!(code, 0);
    let (code, _, _) = run(
        &[
            "estimate",
            "--method",
            "knee-gyro-axis",
            "blank.csv",
            "-o",
            "k.csv",
        ],
        d,
    );
    assert_eq!(code, 1);
}

/// An audit: `simulate knee-fes --mounting random` declared no raw frames,
/// so `inspect` said sdre / ekf run and they restarted on every sample of
/// the raw channels without a word. The trial now declares them (as
/// `simulate walking --mounting random` does); the static-rotation
/// alignment restates them as aligned.
#[test]
fn a_randomly_mounted_fes_trial_declares_raw_frames_until_aligned() {
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    let (code, _, e) = run(
        &[
            "simulate",
            "knee-fes",
            "--duration",
            "10",
            "--mounting",
            "random",
            "--calibration",
            "rec.csv",
            "-o",
            "raw.csv",
        ],
        d,
    );
    assert_eq!(code, 0, "{e}");
    let (_, out, _) = run(&["inspect", "--json", "raw.csv"], d);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v[0]["methods"]["sdre"][0], "runs after align", "{out}");
    let (code, _, e) = run(
        &[
            "align",
            "raw.csv",
            "--procedure",
            "static-rotation",
            "--calibration",
            "rec.csv",
            "-o",
            "aligned.csv",
        ],
        d,
    );
    assert_eq!(code, 0, "{e}");
    let (_, out, _) = run(&["inspect", "--json", "aligned.csv"], d);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v[0]["methods"]["sdre"][0], "runs", "{out}");
    let (code, _, e) = run(
        &["estimate", "--method", "sdre", "aligned.csv", "-o", "e.csv"],
        d,
    );
    assert!(code == 0 && !e.contains("restarted"), "{e}");
}

/// `inspect` printed "`limbfuse align` cannot align this trial: WHY" (a
/// trunk IMU alone: no leg IMU), but `inspect --json` had no such key: a
/// script could not tell that the methods listed "runs after align" would
/// never run (session 29). Each trial's object now has `align`: `needed`,
/// `possible` (true / false / null: not checked) and `reason`, the text
/// the human output prints.
#[test]
fn inspect_json_gives_the_align_verdict() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for (mounting, file) in [("random", "raw.csv"), ("aligned", "w.csv")] {
        let args = [
            "simulate",
            "walking",
            "--duration",
            "12",
            "--mounting",
            mounting,
            "-o",
            file,
        ];
        assert_eq!(run(&args, dir).0, 0);
    }
    crate::support::keep_columns(dir, "raw.csv", "back.csv", |n| n.starts_with("trunk_"));
    let (code, out, err) = run(&["inspect", "--json", "raw.csv", "back.csv", "w.csv"], dir);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let align = |i: usize| v[i]["align"].clone();
    assert_eq!(
        align(0),
        serde_json::json!({"needed": true, "possible": true, "reason": null})
    );
    assert_eq!(align(1)["needed"], true);
    assert_eq!(align(1)["possible"], false);
    let reason = align(1)["reason"].as_str().unwrap().to_string();
    assert!(reason.starts_with("no leg IMU"), "{reason}");
    assert_eq!(
        align(2),
        serde_json::json!({"needed": false, "possible": null, "reason": null})
    );
    // the same text as the human output
    let (code, text, _) = run(&["inspect", "back.csv"], dir);
    assert_eq!(code, 0);
    assert!(
        text.lines()
            .any(|l| l == format!("`limbfuse align` cannot align this trial: {reason}")),
        "{text}"
    );
}
