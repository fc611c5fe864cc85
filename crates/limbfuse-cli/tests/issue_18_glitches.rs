//! Issue 18 item 1: one corrupted cell (a bus glitch far beyond any sensor's
//! range) must not ruin the rest of a trial. Before the range gate, a single
//! thigh gyro cell of 1e300 left `mjls`, `global` and `local` ~91 deg off
//! for the rest of the trial, and nothing was reported.

use std::path::Path;
use std::process::{Command, Output};

fn limbfuse(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

fn assert_ok(o: &Output) {
    assert_eq!(
        o.status.code(),
        Some(0),
        "stderr: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// A copy of trial `from` with the cell (`row` after the header, `column`)
/// replaced by `value`.
fn corrupt(dir: &Path, from: &str, to: &str, cells: &[(usize, &str, &str)]) {
    let text = std::fs::read_to_string(dir.join(from)).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let header = lines.iter().position(|l| l.starts_with("t,")).unwrap();
    let cols: Vec<String> = lines[header].split(',').map(str::to_string).collect();
    for (row, column, value) in cells {
        let c = cols.iter().position(|x| x == column).unwrap();
        let mut fields: Vec<String> = lines[header + 1 + row]
            .split(',')
            .map(str::to_string)
            .collect();
        fields[c] = value.to_string();
        lines[header + 1 + row] = fields.join(",");
    }
    std::fs::write(dir.join(to), lines.join("\n") + "\n").unwrap();
}

/// Column `name` of an estimate file, from data row `from` on.
fn column(dir: &Path, file: &str, name: &str, from: usize) -> Vec<f64> {
    let text = std::fs::read_to_string(dir.join(file)).unwrap();
    let mut rows = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = rows.next().unwrap().split(',').collect();
    let c = header.iter().position(|h| *h == name).unwrap();
    rows.skip(from)
        .map(|l| l.split(',').nth(c).unwrap().parse().unwrap())
        .collect()
}

#[test]
fn issue_18_one_glitched_cell_does_not_ruin_the_rest_of_the_trial() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    assert_ok(&limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "20",
            "--seed",
            "5",
            "-o",
            "clean.csv",
        ],
        p,
    ));
    corrupt(
        p,
        "clean.csv",
        "glitch.csv",
        &[
            (800, "thigh_gyr_z", "1e300"),
            (1200, "shank_acc_x", "-1e308"),
        ],
    );
    for method in ["mjls", "global", "local"] {
        for trial in ["clean", "glitch"] {
            let o = limbfuse(
                &[
                    "estimate",
                    "--method",
                    method,
                    &format!("{trial}.csv"),
                    "-o",
                    &format!("{trial}-{method}.csv"),
                ],
                p,
            );
            assert_ok(&o);
            let err = String::from_utf8_lossy(&o.stderr);
            if trial == "glitch" {
                assert!(
                    err.contains("1 gyroscope, 1 accelerometer and 0 encoder reading(s) were outside the sensors' range (first at t = 8 s)"),
                    "{err}"
                );
            } else {
                assert!(!err.contains("outside the sensors' range"), "{err}");
            }
        }
        for seg in ["thigh", "shank"] {
            let a = column(p, &format!("clean-{method}.csv"), seg, 800);
            let b = column(p, &format!("glitch-{method}.csv"), seg, 800);
            let worst = a
                .iter()
                .zip(&b)
                .map(|(x, y)| (x - y).abs().to_degrees())
                .fold(0.0, f64::max);
            // One missing update moves the estimate by a fraction of a degree.
            assert!(worst < 0.5, "{method} {seg}: {worst} deg after the glitch");
        }
        let rejected = column(p, &format!("glitch-{method}.csv"), "diag_rejected_gyro", 0);
        assert_eq!(rejected[799], 0.0);
        assert_eq!(rejected[800], 1.0);
        assert_eq!(*rejected.last().unwrap(), 1.0);
    }
}

#[test]
fn issue_18_sensor_range_comes_from_the_trial_metadata_and_a_bad_one_is_an_error() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    assert_ok(&limbfuse(
        &["simulate", "walking", "--duration", "5", "-o", "w.csv"],
        p,
    ));
    let text = std::fs::read_to_string(p.join("w.csv")).unwrap();
    // A 1 rad/s gyro range: walking thigh rates exceed it, so readings go.
    std::fs::write(
        p.join("narrow.csv"),
        format!("# gyro_range_rad_s: 1\n{text}"),
    )
    .unwrap();
    let o = limbfuse(
        &["estimate", "--method", "mjls", "narrow.csv", "-o", "n.csv"],
        p,
    );
    assert_ok(&o);
    assert!(String::from_utf8_lossy(&o.stderr).contains("gyroscope"));
    let rejected = column(p, "n.csv", "diag_rejected_gyro", 0);
    assert!(*rejected.last().unwrap() > 100.0, "{:?}", rejected.last());

    std::fs::write(p.join("bad.csv"), format!("# acc_range_m_s2: -3\n{text}")).unwrap();
    let o = limbfuse(
        &["estimate", "--method", "mjls", "bad.csv", "-o", "b.csv"],
        p,
    );
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("acc_range_m_s2: -3") && err.contains("positive number"),
        "{err}"
    );
    assert!(!p.join("b.csv").exists());
}
