//! Issue 18 item 6: a file-to-file `estimate` parses, filters and writes on
//! three threads (`commands/estimate_pipeline.rs`); an estimate streamed to
//! standard output runs on one. Both must give the same rows, and a
//! malformed row must end both with the same error after the same rows.

use std::path::Path;
use std::process::{Command, Output};

fn limbfuse(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

/// The data rows (and the column header) of an estimate, without the
/// `#` header lines that name the output and the trial's hash.
fn data_rows(text: &str) -> Vec<&str> {
    text.lines().filter(|l| !l.starts_with('#')).collect()
}

/// 37.5 s at 100 Hz: 3750 rows, three full batches of 1024 and a partial one.
fn simulate(dir: &Path) {
    let o = limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "37.5",
            "--seed",
            "4",
            "-o",
            "t.csv",
        ],
        dir,
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn issue_18_pipelined_estimate_equals_the_single_threaded_one() {
    let d = tempfile::tempdir().unwrap();
    simulate(d.path());
    for method in ["mjls", "chain", "gyro-integration"] {
        let file = limbfuse(
            &["estimate", "--method", method, "t.csv", "-o", "e.csv"],
            d.path(),
        );
        assert_eq!(file.status.code(), Some(0), "{method}");
        let piped = limbfuse(
            &["estimate", "--method", method, "t.csv", "-o", "-"],
            d.path(),
        );
        assert_eq!(piped.status.code(), Some(0), "{method}");
        let written = std::fs::read_to_string(d.path().join("e.csv")).unwrap();
        let streamed = String::from_utf8(piped.stdout).unwrap();
        let (a, b) = (data_rows(&written), data_rows(&streamed));
        assert_eq!(a.len(), 3751, "{method}: header + 3750 rows");
        assert!(
            a == b,
            "{method}: the pipelined rows differ from the streamed ones"
        );
    }
}

#[test]
fn issue_18_pipelined_estimate_fails_on_a_late_malformed_row_like_the_single_threaded_one() {
    let d = tempfile::tempdir().unwrap();
    simulate(d.path());
    let text = std::fs::read_to_string(d.path().join("t.csv")).unwrap();
    // Break the row in the fourth batch: a cell that is not a number.
    let lines: Vec<&str> = text.lines().collect();
    let first_data = lines
        .iter()
        .position(|l| l.starts_with("0,") || l.starts_with("0.0"))
        .unwrap();
    let bad = first_data + 3100;
    let mut out = String::new();
    for (i, l) in lines.iter().enumerate() {
        if i == bad {
            let mut cells: Vec<&str> = l.split(',').collect();
            cells[1] = "banana";
            out += &cells.join(",");
        } else {
            out += l;
        }
        out.push('\n');
    }
    std::fs::write(d.path().join("bad.csv"), out).unwrap();
    let file = limbfuse(
        &["estimate", "--method", "mjls", "bad.csv", "-o", "e.csv"],
        d.path(),
    );
    let piped = limbfuse(
        &["estimate", "--method", "mjls", "bad.csv", "-o", "-"],
        d.path(),
    );
    assert_eq!(file.status.code(), Some(1));
    assert_eq!(piped.status.code(), Some(1));
    let (fe, pe) = (
        String::from_utf8_lossy(&file.stderr),
        String::from_utf8_lossy(&piped.stderr),
    );
    let line = format!("bad.csv:{}", bad + 1);
    assert!(fe.contains(&line) && fe.contains("banana"), "{fe}");
    assert!(!fe.contains("panicked"), "{fe}");
    // The same error, apart from the streamed run's note on its output.
    let first = |s: &str| s.lines().find(|l| l.contains(&line)).map(str::to_string);
    assert_eq!(first(&fe), first(&pe));
    assert!(!d.path().join("e.csv").exists(), "no partial estimate file");
    // The streamed run wrote every row before the malformed one.
    let streamed = String::from_utf8(piped.stdout).unwrap();
    assert_eq!(data_rows(&streamed).len(), 1 + 3100);
}
