//! A fresh-user audit (session 28), item 10: messages for a mistyped
//! method, a directory given as a trial, and a raw recording that
//! `limbfuse import` converts.

use std::path::Path;
use std::process::Output;

use crate::support::{limbfuse, shared_data};

fn user_error(o: &Output, needles: &[&str]) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    assert!(!e.contains("panicked"), "{e}");
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
}

fn estimate(dir: &Path, method: &str, trial: &str) -> Output {
    limbfuse(&["estimate", "--method", method, trial, "-o", "x.csv"], dir)
}

/// `--method mjsl` / `MJLS` listed every method; now "did you mean `mjls`?"
/// comes first (two edits at most, or the case); a name far from all gets
/// the list only.
#[test]
fn a_mistyped_method_gets_a_suggestion() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(p.join("t.csv"), "t\n0\n").unwrap();
    for typo in ["mjsl", "MJLS"] {
        user_error(
            &estimate(p, typo, "t.csv"),
            &[
                &format!("unknown method `{typo}`; did you mean `mjls`?"),
                "available methods",
            ],
        );
    }
    let o = estimate(p, "magic", "t.csv");
    user_error(&o, &["unknown method `magic`; available methods"]);
}

/// A directory given as the trial was "Is a directory (os error 21)"; now
/// it says a trial file is expected, and what the directory holds.
#[test]
fn a_directory_given_as_a_trial_says_so() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::create_dir(p.join("one")).unwrap();
    std::fs::write(p.join("one/trial.csv"), "t\n0\n").unwrap();
    std::fs::create_dir(p.join("empty")).unwrap();
    user_error(
        &estimate(p, "local", "one"),
        &["one: is a directory; a trial file is expected; it holds trial.csv"],
    );
    user_error(
        &limbfuse(&["inspect", "empty"], p),
        &["empty: is a directory; a trial file is expected"],
    );
    // A gaittoolbox folder: the importer.
    std::fs::create_dir(p.join("gt")).unwrap();
    std::fs::write(p.join("gt/imu-Pelvis.csv"), "// fs=100\nori_1\n").unwrap();
    user_error(
        &limbfuse(&["inspect", "gt"], p),
        &[
            "gt: is a directory",
            "limbfuse import --format gaittoolbox gt",
        ],
    );
}

/// A raw knee-rig log (`LOG INTERVAL,...`) or a gaittoolbox sensor file
/// given to `inspect` / `estimate` was "missing required column `t`";
/// now the importer command follows.
#[test]
fn a_raw_recording_given_as_a_trial_names_its_importer() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(
        p.join("Trial_01.csv"),
        "LOG INTERVAL,4000,microseconds\nTOTAL LOG TIME,175,seconds\n",
    )
    .unwrap();
    let hint = "limbfuse import --format knee-rig Trial_01.csv";
    user_error(
        &limbfuse(&["inspect", "Trial_01.csv"], p),
        &["missing required column `t`", hint],
    );
    user_error(&estimate(p, "knee-selfalign", "Trial_01.csv"), &[hint]);
    std::fs::create_dir(p.join("gt")).unwrap();
    std::fs::write(
        p.join("gt/imu-Pelvis.csv"),
        "// fs=100 nSamples=2\nori_1,acc_1\n1,2\n",
    )
    .unwrap();
    user_error(
        &limbfuse(&["inspect", "gt/imu-Pelvis.csv"], p),
        &["limbfuse import --format gaittoolbox gt"],
    );
    if let Some(rig) = shared_data("knee-rig/Trial_01.csv") {
        user_error(
            &limbfuse(&["inspect", rig.to_str().unwrap()], p),
            &["limbfuse import --format knee-rig"],
        );
        let folder = rig.parent().unwrap().to_str().unwrap();
        user_error(
            &limbfuse(&["inspect", folder], p),
            &[
                "is a directory",
                "raw knee-rig logs",
                "limbfuse import --format knee-rig",
            ],
        );
    }
    if let Some(gt) = shared_data("gaittoolbox-s02-walk") {
        user_error(
            &estimate(p, "local", gt.to_str().unwrap()),
            &["is a directory", "limbfuse import --format gaittoolbox"],
        );
    }
}

fn ok(args: &[&str], dir: &Path) -> String {
    let o = limbfuse(args, dir);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Item 11: `simulate walking --gait-reference`'s help said it writes
/// `contact_right_ref` "(or `_left_`)", but the file has both; `evaluate
/// --window` said its diagnostics were "averaged over the trial".
#[test]
fn help_and_evaluate_say_what_the_output_holds() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let help = ok(&["simulate", "walking", "--help"], p);
    assert!(
        help.contains("`contact_left_ref` and `contact_right_ref`")
            && !help.contains("(or `_left_`"),
        "{help}"
    );
    ok(
        &[
            "simulate",
            "walking",
            "--duration",
            "6",
            "--gait-reference",
            "-o",
            "w.csv",
        ],
        p,
    );
    let text = std::fs::read_to_string(p.join("w.csv")).unwrap();
    let header = text.lines().find(|l| l.starts_with("t,")).unwrap();
    assert!(header.contains("contact_left_ref") && header.contains("contact_right_ref"));
    ok(
        &["estimate", "--method", "local", "w.csv", "-o", "e.csv"],
        p,
    );
    let whole = ok(&["evaluate", "w.csv", "e.csv"], p);
    assert!(
        whole.contains("estimator diagnostics averaged over the trial"),
        "{whole}"
    );
    let window = ok(&["evaluate", "w.csv", "e.csv", "--window", "1:4"], p);
    assert!(
        window.contains("estimator diagnostics averaged over the window"),
        "{window}"
    );
}

/// Item 13: `limbfuse methods` tagged every method with where it comes
/// from ("paper NNN", "beyond the papers", "baseline") but knee-gyro-axis.
#[test]
fn every_method_says_where_it_comes_from() {
    let d = tempfile::tempdir().unwrap();
    let out = ok(&["methods"], d.path());
    let lines: Vec<&str> = out.lines().collect();
    let mut seen = 0;
    for (i, l) in lines.iter().enumerate() {
        if !l.starts_with(' ') && !l.is_empty() && !l.starts_with('`') {
            let summary = lines[i + 1].trim();
            assert!(
                ["paper ", "papers ", "beyond the papers", "baseline"]
                    .iter()
                    .any(|t| summary.starts_with(t)),
                "{l}: {summary}"
            );
            seen += 1;
        }
    }
    assert!(seen >= 15, "{out}");
    assert!(
        out.contains("knee-gyro-axis\n    beyond the papers:"),
        "{out}"
    );
}
