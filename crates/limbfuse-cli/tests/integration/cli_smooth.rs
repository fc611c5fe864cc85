//! `limbfuse estimate --method chain --smooth` (issue 14, offline RTS
//! smoother): one row per trial row, the header says it was smoothed, the
//! angles differ from the filter's but the estimated rows are the same, and
//! `--smooth` with another method is a user error (exit 1).

use std::path::Path;
use std::process::Output;

use crate::support::limbfuse;

fn ok(o: &Output) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "stderr: {e}");
}

/// The data rows of an estimate file, split into cells.
fn rows(path: &Path) -> (String, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let header: String = text
        .lines()
        .filter(|l| l.starts_with('#'))
        .collect::<Vec<_>>()
        .join("\n");
    let rows = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

#[test]
fn smoothed_chain_writes_every_row_and_says_so() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "25",
            "--seed",
            "2",
            "-o",
            "w.csv",
        ],
        p,
    ));
    ok(&limbfuse(
        &["estimate", "--method", "chain", "w.csv", "-o", "f.csv"],
        p,
    ));
    ok(&limbfuse(
        &[
            "estimate", "--method", "chain", "--smooth", "w.csv", "-o", "s.csv",
        ],
        p,
    ));
    let (fh, f) = rows(&p.join("f.csv"));
    let (sh, s) = rows(&p.join("s.csv"));
    assert!(!fh.contains("smoother"), "{fh}");
    assert!(
        sh.contains("smoother: rts") && sh.contains("--smooth"),
        "{sh}"
    );
    assert_eq!(f.len(), 2500);
    assert_eq!(s.len(), f.len());
    let mut differ = 0;
    for (a, b) in f.iter().zip(&s) {
        assert_eq!(a[0], b[0], "time column");
        // thigh angle column (1: trunk, 2: thigh): estimated in the same rows.
        assert_eq!(a[2].is_empty(), b[2].is_empty());
        differ += usize::from(a[2] != b[2]);
    }
    assert!(differ > 2000, "{differ}");
    // The smoothed file scores better on this trial.
    let score = |e: &str| {
        let o = limbfuse(&["evaluate", "w.csv", e, "--offset-free", "--json"], p);
        ok(&o);
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    assert_ne!(score("f.csv"), score("s.csv"));
}

#[test]
fn smoothing_another_method_is_a_user_error() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &["simulate", "walking", "--duration", "3", "-o", "w.csv"],
        p,
    ));
    let o = limbfuse(
        &[
            "estimate", "--method", "global", "--smooth", "w.csv", "-o", "g.csv",
        ],
        p,
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("global") && e.contains("--smooth") && e.contains("w.csv"),
        "{e}"
    );
    assert!(!p.join("g.csv").exists());
}
