//! Issue 18 item 6: `simulate`, `estimate` and `evaluate` read and write
//! Arrow IPC files chosen by extension (docs/ARROW.md), with the same
//! numbers as the CSV path; a mismatched or broken Arrow file is a user
//! error (exit 1) naming the file.

use std::path::Path;
use std::process::Output;

use crate::support::limbfuse;

fn ok(o: Output) -> String {
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(0), "stderr: {e}");
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn simulate(dir: &Path, seed: &str, out: &str) {
    ok(limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "8",
            "--seed",
            seed,
            "-o",
            out,
        ],
        dir,
    ));
}

#[test]
fn issue_18_arrow_trials_and_estimates_evaluate_as_csv_does() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    simulate(d, "4", "w.csv");
    simulate(d, "4", "w.arrow");
    ok(limbfuse(
        &["estimate", "--method", "mjls", "w.csv", "-o", "e.csv"],
        d,
    ));
    ok(limbfuse(
        &["estimate", "--method", "mjls", "w.arrow", "-o", "e.arrow"],
        d,
    ));
    ok(limbfuse(
        &["estimate", "--method", "mjls", "w.arrow", "-o", "e2.csv"],
        d,
    ));
    // The Arrow trial gives the CSV trial's estimate, cell for cell.
    let rows = |name: &str| -> Vec<String> {
        std::fs::read_to_string(d.join(name))
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(str::to_string)
            .collect()
    };
    assert_eq!(rows("e2.csv"), rows("e.csv"));
    assert_eq!(rows("e.csv").len(), 801);
    let csv = ok(limbfuse(&["evaluate", "--json", "w.csv", "e.csv"], d));
    let arrow = ok(limbfuse(&["evaluate", "--json", "w.arrow", "e.arrow"], d));
    let metrics = |text: &str| {
        let mut v: serde_json::Value = serde_json::from_str(text).unwrap();
        // Only the file names differ.
        for k in ["trial", "estimate"] {
            if let Some(o) = v.as_object_mut() {
                o.remove(k);
            }
        }
        v
    };
    assert_eq!(metrics(&arrow), metrics(&csv));
    assert!(arrow.contains("\"rmse"), "{arrow}");
}

#[test]
fn issue_18_an_arrow_estimate_of_another_trial_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    simulate(d, "4", "a.arrow");
    simulate(d, "5", "b.arrow");
    ok(limbfuse(
        &["estimate", "--method", "local", "a.arrow", "-o", "ea.arrow"],
        d,
    ));
    let o = limbfuse(&["evaluate", "b.arrow", "ea.arrow"], d);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("another trial") && !e.contains("panicked"),
        "{e}"
    );
    // A CSV file named .arrow: exit 1, the file named, no output left.
    std::fs::write(d.join("fake.arrow"), "t,hip_enc\n0,1\n").unwrap();
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "mjls",
            "fake.arrow",
            "-o",
            "x.arrow",
        ],
        d,
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("fake.arrow") && e.contains("Arrow IPC"), "{e}");
    assert!(!d.join("x.arrow").exists());
}

/// A corrupted Arrow trial is a user error (exit 1) or reads, never an
/// internal error: arrow-rs panics on some corrupted batches (limbfuse-io
/// catches them and names the file; the CLI's panic hook lets them unwind).
/// The window holds the first batch's message of this 2 s trial, where a
/// flipped byte made arrow-rs panic before the fix (e.g. bytes 7067, 7141).
#[test]
fn issue_18_a_corrupted_arrow_trial_is_a_user_error() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "2",
            "--seed",
            "1",
            "-o",
            "c.arrow",
        ],
        d,
    ));
    let bytes = std::fs::read(d.join("c.arrow")).unwrap();
    let mut caught = 0;
    for at in (6900..7300.min(bytes.len())).step_by(2) {
        let mut b = bytes.clone();
        b[at] ^= 0xff;
        std::fs::write(d.join("cc.arrow"), &b).unwrap();
        let o = limbfuse(
            &["estimate", "--method", "mjls", "cc.arrow", "-o", "e.csv"],
            d,
        );
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(matches!(o.status.code(), Some(0 | 1)), "byte {at}: {e}");
        assert!(!e.contains("internal error"), "byte {at}: {e}");
        caught += usize::from(e.contains("the file is corrupt"));
    }
    eprintln!("{caught} corrupted files on which arrow-rs panicked were reported as user errors");
}
