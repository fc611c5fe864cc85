//! Issue 14, S02 pass 2: `chain` with the device's own orientation as an
//! angle row per segment (docs/CHAIN.md, "Device orientation"). The
//! gaittoolbox S02 walk, aligned: offset-free thigh / shank / foot mean over
//! each straight pass (lag within +-5 samples) 1.708 / 1.934 deg, against
//! 1.953 / 2.507 without the rows (`device_orientation = false`). The same
//! trial with every quaternion conjugated (world to sensor, another
//! convention) gives the output without the rows, bit for bit: the rate
//! check refuses them. Skipped when `../shared/data` is absent.

use std::path::Path;

mod s02_support;
mod support;
use s02_support::{run_ok, s02_dir};

/// Mean offset-free RMSE (deg) of thigh, shank and foot over `window`.
fn pass_mean(dir: &Path, trial: &str, est: &str, window: &str) -> f64 {
    let json = run_ok(
        &[
            "evaluate",
            trial,
            est,
            "--window",
            window,
            "--offset-free",
            "--max-lag",
            "5",
            "--json",
        ],
        dir,
    );
    let v: serde_json::Value = serde_json::from_slice(&json).unwrap();
    ["thigh", "shank", "foot"]
        .iter()
        .map(|s| v["rmse_deg"][*s].as_f64().unwrap())
        .sum::<f64>()
        / 3.0
}

/// `src` with the vector part of every `*_quat_*` cell negated.
fn conjugate(src: &Path, dst: &Path) {
    let text = std::fs::read_to_string(src).unwrap();
    let mut out = String::new();
    let mut negate: Vec<bool> = Vec::new();
    for line in text.lines() {
        if line.starts_with('#') {
            out += line;
        } else if negate.is_empty() {
            negate = line
                .split(',')
                .map(|c| c.contains("_quat_") && !c.ends_with("_quat_w"))
                .collect();
            out += line;
        } else {
            let cells: Vec<String> = line
                .split(',')
                .zip(&negate)
                .map(|(c, &n)| match (n, c.parse::<f64>()) {
                    (true, Ok(v)) => format!("{}", -v),
                    _ => c.to_string(),
                })
                .collect();
            out += &cells.join(",");
        }
        out += "\n";
    }
    std::fs::write(dst, out).unwrap();
}

#[test]
fn issue_14_chain_device_orientation() {
    let Some(s02) = s02_dir() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let s02 = s02.to_str().unwrap();
    run_ok(
        &["import", "--format", "gaittoolbox", s02, "-o", "s02.csv"],
        dir,
    );
    run_ok(&["align", "s02.csv", "-o", "s02al.csv"], dir);
    std::fs::write(dir.join("off.toml"), "device_orientation = false\n").unwrap();
    run_ok(
        &["estimate", "--method", "chain", "s02al.csv", "-o", "on.csv"],
        dir,
    );
    run_ok(
        &[
            "estimate",
            "--method",
            "chain",
            "--params",
            "off.toml",
            "s02al.csv",
            "-o",
            "off.csv",
        ],
        dir,
    );
    let mut means = Vec::new();
    for est in ["on.csv", "off.csv"] {
        for window in ["0.45:3.55", "4.40:8.72"] {
            let m = pass_mean(dir, "s02al.csv", est, window);
            println!("{est} {window}: {m:.3} deg");
            means.push(m);
        }
    }
    assert!(
        means[0] < 1.75 && means[1] < 2.0,
        "with the rows: {means:?}"
    );
    assert!(
        means[2] > 1.90 && means[3] > 2.40,
        "without the rows: {means:?}"
    );
    conjugate(&dir.join("s02al.csv"), &dir.join("conj.csv"));
    run_ok(
        &[
            "estimate",
            "--method",
            "chain",
            "conj.csv",
            "-o",
            "conj-est.csv",
        ],
        dir,
    );
    let rows = |f: &str| -> Vec<String> {
        std::fs::read_to_string(dir.join(f))
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(str::to_string)
            .collect()
    };
    assert_eq!(
        rows("conj-est.csv"),
        rows("off.csv"),
        "conjugated quaternions were used"
    );
}
