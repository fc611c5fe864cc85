//! `limbfuse estimate - --late-rows drop` (docs/STREAMING.md "Rows out of
//! time order"): a live stream with a row written twice, a swapped pair and
//! a stamp 0.5 s ahead ran until the first of them and stopped (SPEC's
//! strictly increasing `t`); with `drop` it runs through, and its estimate
//! is, bit for bit, the estimate of the rows it passed.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};

use crate::support::limbfuse;

fn assert_ok(o: &Output) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "stderr: {e}");
}

/// `estimate --method chain - -o -` fed `text`, with `extra` flags.
fn stream(text: &str, extra: &[&str], dir: &Path) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(
            [
                &["estimate", "--method", "chain", "-", "-o", "-"][..],
                extra,
            ]
            .concat(),
        )
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // (a refused stream exits before it has read everything: a broken pipe)
    let _ = child.stdin.take().unwrap().write_all(text.as_bytes());
    child.wait_with_output().unwrap()
}

/// Data rows (no comment lines, no header).
fn rows(text: &str) -> Vec<&str> {
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .collect()
}

#[test]
fn a_stream_with_repeated_swapped_and_far_ahead_stamps_runs_through_with_late_rows_drop() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let sim = ["simulate", "walking", "--duration", "4", "--seed", "7"];
    assert_ok(&limbfuse(&[&sim[..], &["-o", "trial.csv"]].concat(), dir));
    let clean = std::fs::read_to_string(dir.join("trial.csv")).unwrap();
    let (head, data): (Vec<&str>, Vec<&str>) = {
        let k = clean.lines().position(|l| !l.starts_with('#')).unwrap();
        let lines: Vec<&str> = clean.lines().collect();
        (lines[..=k].to_vec(), lines[k + 1..].to_vec())
    };
    // Row 100 written twice; rows 200 and 201 swapped; row 300's stamp 0.5 s ahead.
    let mut glitched: Vec<String> = data.iter().map(|s| s.to_string()).collect();
    glitched.swap(200, 201);
    let (t, rest) = glitched[300].split_once(',').unwrap();
    glitched[300] = format!("{},{rest}", t.parse::<f64>().unwrap() + 0.5);
    glitched.insert(101, data[100].to_string());
    let text = |rows: &[String]| format!("{}\n{}\n", head.join("\n"), rows.join("\n"));
    // What the rule passes: every row but the repeat, the second of the
    // swapped pair (row 200, after row 201) and row 300.
    let seen: Vec<String> = data
        .iter()
        .enumerate()
        .filter(|(k, _)| ![200, 300].contains(k))
        .map(|(_, s)| s.to_string())
        .collect();
    std::fs::write(dir.join("seen.csv"), text(&seen)).unwrap();
    assert_ok(&limbfuse(
        &[
            "estimate",
            "--method",
            "chain",
            "seen.csv",
            "-o",
            "seen-est.csv",
        ],
        dir,
    ));
    let expected = std::fs::read_to_string(dir.join("seen-est.csv")).unwrap();

    // SPEC's rule: the stream stops at the repeat, naming the flag.
    let refused = stream(&text(&glitched), &[], dir);
    let e = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(1), "{e}");
    assert!(
        e.contains("time must increase strictly") && e.contains("--late-rows drop"),
        "{e}"
    );

    let o = stream(&text(&glitched), &["--late-rows", "drop"], dir);
    assert_ok(&o);
    let out = String::from_utf8(o.stdout).unwrap();
    assert_eq!(rows(&out), rows(&expected));
    assert!(
        out.contains("--late-rows drop"),
        "the command line records the flag"
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("dropped 2 rows whose time was not after the row before them")
            && e.contains("1 rows whose time jumped ahead of the rows after them"),
        "{e}"
    );
    // (the lines of the trial as streamed: 1-based, comments and header counted)
    let first_data_line = head.len() as u64 + 1;
    let line_of = |k: u64| first_data_line + k;
    assert!(
        e.contains(&format!("line {}, {}", line_of(101), line_of(202)))
            && e.contains(&format!("line {};", line_of(301))),
        "{e}"
    );
}
