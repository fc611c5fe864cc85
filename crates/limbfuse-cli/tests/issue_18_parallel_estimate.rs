//! Issue 18 item 6: a file-to-file `estimate` parses its trial in blocks on
//! every core and formats its CSV estimate in blocks of 16384 rows on every
//! core (limbfuse-io `row_blocks`, `cell_rows`); an estimate streamed from
//! standard input to standard output is read and written row by row. Both
//! must give the same rows, and a malformed row must end both with the same
//! error after the same rows.

use std::path::Path;
use std::process::{Command, Output};

fn limbfuse(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

/// Runs the binary with the file `input` (in `dir`) as its standard input.
fn limbfuse_stdin(args: &[&str], dir: &Path, input: &str) -> Output {
    let file = std::fs::File::open(dir.join(input)).expect("the input file opens");
    Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(args)
        .current_dir(dir)
        .stdin(file)
        .output()
        .expect("the binary runs")
}

/// The data rows (and the column header) of an estimate, without the
/// `#` header lines that name the output and the trial's hash.
fn data_rows(text: &str) -> Vec<&str> {
    text.lines().filter(|l| !l.starts_with('#')).collect()
}

/// `seconds` at 100 Hz (100 rows of about 680 bytes a second: 1 MiB blocks).
fn simulate(dir: &Path, seconds: &str) {
    let o = limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            seconds,
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
fn issue_18_parallel_estimate_equals_the_streamed_one() {
    let d = tempfile::tempdir().unwrap();
    // 17 000 rows: 11 input blocks, two output blocks.
    simulate(d.path(), "170");
    for method in ["mjls", "gyro-integration"] {
        let file = limbfuse(
            &["estimate", "--method", method, "t.csv", "-o", "e.csv"],
            d.path(),
        );
        assert_eq!(file.status.code(), Some(0), "{method}");
        let piped = limbfuse_stdin(&["estimate", "--method", method, "-", "-o", "-"], d.path(), "t.csv");
        assert_eq!(piped.status.code(), Some(0), "{method}");
        let written = std::fs::read_to_string(d.path().join("e.csv")).unwrap();
        let streamed = String::from_utf8(piped.stdout).unwrap();
        let (a, b) = (data_rows(&written), data_rows(&streamed));
        assert_eq!(a.len(), 17_001, "{method}: header + 17 000 rows");
        assert!(
            a == b,
            "{method}: the parallel file rows differ from the streamed ones"
        );
    }
}

#[test]
fn issue_18_parallel_estimate_fails_on_a_late_malformed_row_like_the_streamed_one() {
    let d = tempfile::tempdir().unwrap();
    simulate(d.path(), "37.5");
    let text = std::fs::read_to_string(d.path().join("t.csv")).unwrap();
    // Break a row in the third 1 MiB block: a cell that is not a number.
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
    let piped = limbfuse_stdin(&["estimate", "--method", "mjls", "-", "-o", "-"], d.path(), "bad.csv");
    assert_eq!(file.status.code(), Some(1));
    assert_eq!(piped.status.code(), Some(1));
    let (fe, pe) = (
        String::from_utf8_lossy(&file.stderr),
        String::from_utf8_lossy(&piped.stderr),
    );
    let line = format!("bad.csv:{}", bad + 1);
    assert!(fe.contains(&line) && fe.contains("banana"), "{fe}");
    assert!(!fe.contains("panicked"), "{fe}");
    // The same error (the streamed run names its input `<stdin>`), apart
    // from the streamed run's note on its output.
    let piped_line = format!("<stdin>:{}", bad + 1);
    let first = |s: &str, at: &str| {
        s.lines()
            .find(|l| l.contains(at))
            .map(|l| l.replace("<stdin>", "bad.csv"))
    };
    assert!(first(&fe, &line).is_some());
    assert_eq!(first(&fe, &line), first(&pe, &piped_line), "{pe}");
    assert!(!d.path().join("e.csv").exists(), "no partial estimate file");
    // The streamed run wrote every row before the malformed one.
    let streamed = String::from_utf8(piped.stdout).unwrap();
    assert_eq!(data_rows(&streamed).len(), 1 + 3100);
}
