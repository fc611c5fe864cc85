//! Small leftovers of session 28's audits: messages that named nonsense
//! or came late.

use std::path::Path;
use std::process::Output;

use crate::support::{assert_user_error, limbfuse, stderr};

/// Runs `args` in `dir` and expects success.
fn ok(args: &[&str], dir: &Path) -> Output {
    let o = limbfuse(args, dir);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    o
}

/// The trial `from` cut to its comment lines, header and first `rows`
/// data rows, written to `to`.
fn first_rows(dir: &Path, from: &str, to: &str, rows: usize) {
    let text = std::fs::read_to_string(dir.join(from)).unwrap();
    let header = text.lines().position(|l| l.starts_with("t,")).unwrap();
    let kept: Vec<&str> = text.lines().take(header + 1 + rows).collect();
    std::fs::write(dir.join(to), kept.join("\n") + "\n").unwrap();
}

/// `align` of a trial with one data row said "the trial's samples span
/// 1 s" (a made-up interval). Now it says the trial has only one sample
/// and how much walking alignment needs.
#[test]
fn align_of_one_sample_says_one_sample() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(
        &["simulate", "walking", "--duration", "2", "-o", "raw.csv"],
        p,
    );
    first_rows(p, "raw.csv", "one.csv", 1);
    let o = limbfuse(&["align", "one.csv", "-o", "a.csv"], p);
    assert_user_error(&o, &["one.csv", "only one sample", "3 s of walking"]);
    assert!(!stderr(&o).contains("span 1 s"), "{}", stderr(&o));
}

/// `calibrate --acc-std-max 1e-30` (and Python's `calibrate(min_pose=1e30)`,
/// which reaches the same message) printed the limit with 31 digits
/// (`0.000000000000000000000000000001`) in "no static pose" and in every
/// rejected hold. Now the settings are shown short, as in other messages.
#[test]
fn calibrate_shows_extreme_settings_short() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&["simulate", "calibration", "-o", "cal.csv"], p);
    let o = limbfuse(
        &[
            "calibrate",
            "cal.csv",
            "--acc-std-max",
            "1e-30",
            "-o",
            "c.toml",
        ],
        p,
    );
    assert_user_error(
        &o,
        &[
            "cal.csv",
            "no static pose",
            "below 1e-30 m/s^2",
            "(limit 1e-30)",
        ],
    );
    assert!(!stderr(&o).contains("0.00000000000"), "{}", stderr(&o));
}

/// `gait-library build --speeds 0.6:0.8:0.1 -o DIR` with DIR an existing
/// folder searched its gaits for seconds, then failed with "DIR: Is a
/// directory (os error 21)". Now it is refused at once, naming the path;
/// an output in a missing folder likewise.
#[test]
fn gait_library_build_into_a_folder_fails_fast() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::create_dir(p.join("adir")).unwrap();
    for (out, needle) in [
        ("adir", "adir: that is a folder"),
        ("nodir/x.json", "the folder nodir does not exist"),
    ] {
        let t0 = std::time::Instant::now();
        let o = limbfuse(
            &[
                "gait-library",
                "build",
                "--speeds",
                "0.6:0.8:0.1",
                "-q",
                "-o",
                out,
            ],
            p,
        );
        let took = t0.elapsed().as_secs_f64();
        assert_user_error(&o, &[needle]);
        assert!(took < 1.0, "{out}: refused after {took} s");
    }
}
