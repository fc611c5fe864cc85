//! A reader that closes its end of the pipe (`limbfuse ... | head`) is not
//! an error: limbfuse stops quietly, exit status 0, no "internal error"
//! (found in issue 18 work: `limbfuse evaluate ... | head` printed
//! "internal error: failed printing to stdout: Broken pipe").

use std::io::Write;
use std::process::{Command, Stdio};

#[test]
fn a_closed_standard_output_ends_the_run_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let trial = dir.path().join("walk.csv");
    let sim = Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(["--quiet", "simulate", "walking", "--duration", "20", "-o"])
        .arg(&trial)
        .output()
        .unwrap();
    assert!(
        sim.status.success(),
        "{}",
        String::from_utf8_lossy(&sim.stderr)
    );
    let text = std::fs::read(&trial).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(["estimate", "--method", "mjls", "-", "-o", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The reader goes away before a single row is written.
    drop(child.stdout.take());
    let mut stdin = child.stdin.take().unwrap();
    // The writer may stop reading its input once its output is gone.
    let _ = stdin.write_all(&text);
    drop(stdin);
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "status {:?}: {err}", out.status);
    assert!(!err.contains("error"), "{err}");
}
