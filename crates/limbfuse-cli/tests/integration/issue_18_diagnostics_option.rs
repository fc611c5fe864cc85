//! Issue 18 item 6 (end to end "doing the same job"): `estimate
//! --diagnostics all|none|NAMES` writes only the diagnostic columns asked
//! for, in CSV and Arrow; `evaluate` reads such a file with the same figures
//! as the full one; a name the method does not have is a user error (exit 1)
//! naming the option, and leaves no output file.

use std::path::Path;
use std::process::Output;

use crate::support::limbfuse;

fn ok(o: Output) -> String {
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(0), "stderr: {e}");
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// A seeded simulated walking trial `w.csv` of `seconds`.
fn simulate(d: &Path, seconds: &str) {
    let args = ["simulate", "walking", "--duration", seconds, "--seed", "3"];
    ok(limbfuse(&[&args[..], &["-o", "w.csv"]].concat(), d));
}

fn header(d: &Path, name: &str) -> Vec<String> {
    let text = std::fs::read_to_string(d.join(name)).unwrap();
    let line = text.lines().find(|l| !l.starts_with('#')).unwrap();
    line.split(',').map(String::from).collect()
}

/// The data rows of a CSV estimate, each cut to its first `k` cells.
fn rows(d: &Path, name: &str, k: usize) -> Vec<String> {
    std::fs::read_to_string(d.join(name))
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').take(k).collect::<Vec<_>>().join(","))
        .collect()
}

const ANGLES: [&str; 8] = [
    "t", "trunk", "thigh", "shank", "foot", "hip", "knee", "ankle",
];

#[test]
fn issue_18_diagnostics_option_selects_columns_and_evaluates_alike() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    simulate(d, "8");
    let est = |extra: &[&str], out: &str| {
        let mut args = vec!["estimate", "--method", "mjls"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["w.csv", "-o", out]);
        ok(limbfuse(&args, d));
    };
    est(&[], "all.csv");
    est(&["--diagnostics", "all"], "all2.csv");
    est(&["--diagnostics", "none"], "none.csv");
    est(
        &["--diagnostics", "diag_sd_shank, resets,sd_thigh"],
        "some.csv",
    );
    est(&["--diagnostics", "none"], "none.arrow");

    let all = header(d, "all.csv");
    assert!(all.len() > 40, "{all:?}");
    assert_eq!(header(d, "all2.csv"), all);
    assert_eq!(header(d, "none.csv"), ANGLES);
    // Named ones keep the method's order.
    let mut some: Vec<String> = ANGLES.iter().map(|s| s.to_string()).collect();
    some.extend(["diag_sd_thigh", "diag_sd_shank", "diag_resets"].map(String::from));
    assert_eq!(header(d, "some.csv"), some);
    // The same numbers in the columns both have.
    assert_eq!(rows(d, "none.csv", 8), rows(d, "all.csv", 8));
    let pick = |name: &str, cols: &[&str]| -> Vec<String> {
        let h = header(d, name);
        let idx: Vec<usize> = cols
            .iter()
            .map(|c| h.iter().position(|x| x == c).unwrap())
            .collect();
        rows(d, name, h.len())
            .iter()
            .map(|r| {
                let cells: Vec<&str> = r.split(',').collect();
                idx.iter().map(|&i| cells[i]).collect::<Vec<_>>().join(",")
            })
            .collect()
    };
    let named = ["diag_sd_thigh", "diag_sd_shank", "diag_resets"];
    assert_eq!(pick("some.csv", &named), pick("all.csv", &named));
    // The command that made the file is in its header.
    let text = std::fs::read_to_string(d.join("none.csv")).unwrap();
    assert!(
        text.contains("# command: limbfuse estimate --method mjls --diagnostics none w.csv"),
        "{text}"
    );

    // Round trip: evaluate gives the same angle figures from every file;
    // the diagnostic summaries it adds need the columns they average.
    let report = |e: &str| ok(limbfuse(&["evaluate", "w.csv", e], d));
    let angles = |r: &str| -> String {
        let end = r.find("mean RMSE").expect("a mean RMSE line");
        r[..end + r[end..].find('\n').unwrap()].to_string()
    };
    let full = report("all.csv");
    assert!(full.contains("accelerometer reliability"), "{full}");
    for other in ["none.csv", "some.csv", "none.arrow"] {
        let r = report(other);
        assert_eq!(angles(&r), angles(&full), "{other}");
        assert!(!r.contains("accelerometer reliability"), "{other}: {r}");
    }
}

#[test]
fn issue_18_diagnostics_option_refuses_an_unknown_name_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    simulate(d, "2");
    for (value, needle) in [
        ("sd_knee", "`sd_knee` is not a diagnostic of `mjls`"),
        ("mode,,sd_thigh", "--diagnostics `mode,,sd_thigh`"),
    ] {
        let o = limbfuse(
            &[
                "estimate",
                "--method",
                "mjls",
                "--diagnostics",
                value,
                "w.csv",
                "-o",
                "e.csv",
            ],
            d,
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert!(err.contains(needle), "{err}");
        assert!(err.contains("--diagnostics"), "{err}");
        assert!(!d.join("e.csv").exists(), "no partial output");
    }
}
