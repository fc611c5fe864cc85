//! `limbfuse simulate knee`, `estimate --method knee-selfalign` and
//! `evaluate` end to end (paper 002), and the flags' validation.

use std::path::Path;
use std::process::{Command, Output};

fn limbfuse(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

fn ok(o: &Output) -> String {
    assert_eq!(
        o.status.code(),
        Some(0),
        "stderr: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn user_error(o: &Output, needle: &str) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    assert!(!e.contains("panicked"), "{e}");
    assert!(e.contains(needle), "expected `{needle}` in: {e}");
}

#[test]
fn simulate_estimate_evaluate_knee() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&limbfuse(
        &[
            "simulate",
            "knee",
            "-o",
            "k.csv",
            "--duration",
            "15",
            "--seed",
            "2",
        ],
        p,
    ));
    let trial = std::fs::read_to_string(p.join("k.csv")).unwrap();
    assert!(trial.contains("# knee_imu_positions_m: thigh="));
    assert!(trial.contains("# mounting: random"));
    ok(&limbfuse(
        &[
            "estimate",
            "--method",
            "knee-selfalign",
            "--window",
            "400",
            "--order",
            "4",
            "k.csv",
            "-o",
            "e.csv",
        ],
        p,
    ));
    let est = std::fs::read_to_string(p.join("e.csv")).unwrap();
    assert!(est.starts_with("# method: knee-selfalign\n"));
    assert!(est.contains("# window: 400\n") && est.contains("# order: 4\n"));
    let header = est.lines().find(|l| !l.starts_with('#')).unwrap();
    assert!(header.starts_with("t,knee,diag_identified,"), "{header}");
    let json = ok(&limbfuse(&["evaluate", "k.csv", "e.csv", "--json"], p));
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let corr = v["corr"]["knee"].as_f64().unwrap();
    assert!(corr > 0.99, "{json}");
    // The angle exists from the end of the first window (sample 400) on.
    assert_eq!(v["n_samples"].as_u64().unwrap(), 1500);
}

#[test]
fn knee_flags_are_validated() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(p.join("t.csv"), "t\n0\n0.01\n").unwrap();
    let run = |extra: &[&str], method: &str| {
        let mut args = vec!["estimate", "--method", method, "t.csv", "-o", "e.csv"];
        args.extend_from_slice(extra);
        limbfuse(&args, p)
    };
    user_error(&run(&["--window", "5"], "knee-selfalign"), "window = 5");
    user_error(&run(&["--order", "0"], "knee-selfalign"), "order = 0");
    user_error(
        &run(&["--window", "100"], "local"),
        "--window and --order apply to method knee-selfalign only",
    );
    user_error(
        &limbfuse(&["simulate", "knee", "-o", "k.csv", "--remount-at=-3"], p),
        "remount.t_s",
    );
}
