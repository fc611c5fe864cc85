//! Issue 18 item 5: `limbfuse estimate` with `-` reads a trial from standard
//! input and writes estimates to standard output as the rows arrive.

use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use crate::support::limbfuse;

fn assert_ok(o: &Output) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "stderr: {e}");
}

/// A 3 s walking trial (300 rows) and its mjls estimate made from the file.
fn trial_and_file_estimate(dir: &Path) -> (String, String) {
    let sim = ["simulate", "walking", "--duration", "3", "--seed", "5"];
    assert_ok(&limbfuse(&[&sim[..], &["-o", "trial.csv"]].concat(), dir));
    assert_ok(&limbfuse(
        &["estimate", "--method", "mjls", "trial.csv", "-o", "est.csv"],
        dir,
    ));
    let read = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap();
    (read("trial.csv"), read("est.csv"))
}

/// Lines that are not `#` comments (header row and data rows).
fn table_lines(text: &str) -> Vec<&str> {
    text.lines().filter(|l| !l.starts_with('#')).collect()
}

fn header_value<'a>(text: &'a str, key: &str) -> Option<&'a str> {
    text.lines()
        .find_map(|l| l.strip_prefix(&format!("# {key}: ")))
}

#[test]
fn a_growing_trial_is_estimated_row_by_row_through_a_pipe() {
    let dir = tempfile::tempdir().unwrap();
    let (trial, from_file) = trial_and_file_estimate(dir.path());
    let (comments, rest): (Vec<&str>, Vec<&str>) = trial.lines().partition(|l| l.starts_with('#'));
    let (header, rows) = rest.split_first().unwrap();
    assert_eq!(rows.len(), 300);

    let mut child = Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(["estimate", "--method", "mjls", "-", "-o", "-"])
        .current_dir(dir.path())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let stdout = child.stdout.take().unwrap();
    let (tx, rx) = mpsc::channel::<String>();
    let reader = std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines() {
            if tx.send(line.unwrap()).is_err() {
                break;
            }
        }
    });
    let mut out: Vec<String> = Vec::new();
    // Collects output lines until `rows` estimate rows (after the header
    // row) have arrived; fails after 60 s without a line.
    let wait_for_rows = |out: &mut Vec<String>, rows: usize| {
        while table_lines(&out.join("\n")).len() < rows + 1 {
            let line = rx
                .recv_timeout(Duration::from_secs(60))
                .unwrap_or_else(|e| panic!("no estimate row after 60 s ({e}); so far: {out:?}"));
            out.push(line);
        }
    };
    // The trial arrives in three bursts; the estimates of each burst must
    // come out while the input is still open.
    let mut sent = 0;
    for (k, burst) in [100, 150, 50].into_iter().enumerate() {
        let mut chunk = String::new();
        if k == 0 {
            for c in &comments {
                chunk += &format!("{c}\n");
            }
            chunk += &format!("{header}\n");
        }
        for r in &rows[sent..sent + burst] {
            chunk += &format!("{r}\n");
        }
        stdin.write_all(chunk.as_bytes()).unwrap();
        stdin.flush().unwrap();
        sent += burst;
        wait_for_rows(&mut out, sent);
        assert_eq!(
            table_lines(&out.join("\n")).len(),
            sent + 1,
            "no row before its input"
        );
    }
    drop(stdin);
    let status = child.wait().unwrap();
    reader.join().unwrap();
    out.extend(rx.try_iter());
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
    assert!(status.success(), "stderr: {stderr}");

    let streamed = out.join("\n") + "\n";
    // Every estimate row equals the one made from the file.
    assert_eq!(table_lines(&streamed), table_lines(&from_file));
    // Header: the method's comments first, then the stream's provenance.
    assert_eq!(header_value(&streamed, "method"), Some("mjls"));
    assert_eq!(header_value(&streamed, "trial"), Some("<stdin>"));
    assert_eq!(header_value(&streamed, "trial_hash"), Some("streamed"));
    // The hash the header could not hold is on stderr: the file's.
    let file_hash = header_value(&from_file, "trial_hash").unwrap();
    assert!(
        stderr.contains(&format!("content hash {file_hash}")),
        "{stderr}"
    );

    // `evaluate` accepts a streamed estimate, with a warning that it cannot be checked.
    std::fs::write(dir.path().join("streamed.csv"), &streamed).unwrap();
    let ev = limbfuse(&["evaluate", "trial.csv", "streamed.csv"], dir.path());
    assert_ok(&ev);
    let e = String::from_utf8_lossy(&ev.stderr);
    assert!(
        e.contains("streamed") && e.contains("cannot be checked"),
        "{e}"
    );
}

#[test]
fn standard_input_to_a_file_records_the_hash_of_the_stream() {
    let dir = tempfile::tempdir().unwrap();
    let (trial, from_file) = trial_and_file_estimate(dir.path());
    let mut child = Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(["estimate", "--method", "mjls", "-", "-o", "piped.csv"])
        .current_dir(dir.path())
        .stdin(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(trial.as_bytes())
        .unwrap();
    let o = child.wait_with_output().unwrap();
    assert_ok(&o);
    let piped = std::fs::read_to_string(dir.path().join("piped.csv")).unwrap();
    assert_eq!(table_lines(&piped), table_lines(&from_file));
    assert_eq!(
        header_value(&piped, "trial_hash"),
        header_value(&from_file, "trial_hash")
    );
    // So `evaluate` checks it against the trial file without a warning.
    let ev = limbfuse(&["evaluate", "trial.csv", "piped.csv"], dir.path());
    assert_ok(&ev);
    let e = String::from_utf8_lossy(&ev.stderr);
    assert!(!e.contains("cannot be checked"), "{e}");
}

#[test]
fn a_bad_row_on_standard_input_is_named_by_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(["estimate", "--method", "gyro-integration", "-", "-o", "-"])
        .current_dir(dir.path())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let text = "t,thigh_gyr_x,thigh_gyr_y,thigh_gyr_z\n0,0,0,0.1\n0.01,0,zero,0.1\n";
    child
        .stdin
        .take()
        .unwrap()
        .write_all(text.as_bytes())
        .unwrap();
    let o = child.wait_with_output().unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("<stdin>:3: column 3 (`thigh_gyr_y`)"), "{e}");
    // The estimate of the good row was already out.
    assert_eq!(table_lines(&String::from_utf8_lossy(&o.stdout)).len(), 2);
}
