//! Issue 14 through the binary: `limbfuse tune` from a parameter file with
//! a run-in (`startup_s`) must not return parameters that restart the
//! filter (each restart restarts the run-in) and so score fewer samples
//! than the start; the table reports the share of segment samples scored.
//! Before the fix this command wrote parameters scoring 5.0 % of the
//! segment samples (0.320 deg on those) against the start's 83.4 %
//! (checked with the binary of commit 0f15c58).

mod support;
use support::limbfuse;

fn ok(args: &[&str], dir: &std::path::Path) -> String {
    let o = limbfuse(args, dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The `scored %` figure of `evaluate --starts` output.
fn scored_pct(text: &str) -> f64 {
    let line = text
        .lines()
        .find(|l| l.starts_with("segment samples scored:"))
        .unwrap_or_else(|| panic!("no coverage line in:\n{text}"));
    line.split_whitespace().nth(3).unwrap().parse().unwrap()
}

#[test]
fn issue_14_tune_with_a_run_in_keeps_every_scored_sample() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(
        &[
            "simulate", "walking", "--seed", "2", "--speed", "0.4", "--duration", "12",
            "--imu-rate", "50", "-q", "-o", "w.csv",
        ],
        d,
    );
    std::fs::write(d.join("runin.toml"), "startup_s = 1\n").unwrap();
    let protocol = [
        "--window", "0:12", "--starts", "4", "--length", "6", "--method", "mjls",
    ];
    let mut tune = vec!["tune", "w.csv", "--validate", "none", "--seed", "12"];
    tune.extend(["--budget", "120", "--particles", "12", "--params", "runin.toml"]);
    tune.extend(["-q", "-o", "tuned.toml"]);
    tune.extend(protocol);
    let table = ok(&tune, d);
    let row = table
        .lines()
        .find(|l| l.starts_with("scored %"))
        .unwrap_or_else(|| panic!("no `scored %` row in:\n{table}"));
    let cells: Vec<&str> = row.split_whitespace().skip(2).collect();
    assert_eq!(cells[0], cells[1], "start and tuned scored shares: {row}");
    let mut eval = vec!["evaluate", "w.csv"];
    eval.extend(protocol);
    let mut start = eval.clone();
    start.extend(["--params", "runin.toml"]);
    let mut tuned = eval.clone();
    tuned.extend(["--params", "tuned.toml"]);
    let (s, t) = (scored_pct(&ok(&start, d)), scored_pct(&ok(&tuned, d)));
    // A 1 s run-in leaves out 1 s of each 6 s run and nothing more.
    assert!((s - 83.4).abs() < 0.1, "start scored {s} %");
    assert_eq!(s, t, "the tuned filter scores {t} % against the start's {s} %");
}
