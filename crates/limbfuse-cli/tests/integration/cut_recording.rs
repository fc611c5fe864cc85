//! A recording cut off while it was written (its last line short, with no
//! line break): `estimate` gave no estimate at all ("expected 35 cells ...,
//! found 34", exit 1, no output file); now the line is left out with a
//! warning, and `inspect` says so (docs/ROBUST_INPUT.md 2o).

use std::path::Path;

use crate::support::limbfuse;

fn rows(path: &Path) -> Vec<String> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(str::to_string)
        .collect()
}

/// Simulates `seconds` of walking into `dir/w.csv` and writes beside it
/// `short.csv` (the file without its last line) and `cut.csv` (the file cut
/// 40 bytes before its end); returns the cut line's number.
fn short_and_cut(dir: &Path, seconds: &str, seed: &str) -> usize {
    let sim = [
        "simulate",
        "walking",
        "--duration",
        seconds,
        "--seed",
        seed,
        "-o",
        "w.csv",
    ];
    assert_eq!(limbfuse(&sim, dir).status.code(), Some(0));
    let whole = std::fs::read_to_string(dir.join("w.csv")).unwrap();
    let last = whole.trim_end_matches('\n').rfind('\n').unwrap();
    std::fs::write(dir.join("short.csv"), &whole[..=last]).unwrap();
    std::fs::write(dir.join("cut.csv"), &whole[..whole.len() - 40]).unwrap();
    whole[..last].lines().count() + 1
}

#[test]
fn a_recording_cut_mid_line_is_estimated_without_its_last_line() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let line = short_and_cut(dir, "3", "2");
    let est = |trial: &str, out: &str| {
        limbfuse(&["estimate", "--method", "chain", trial, "-o", out], dir)
    };
    assert_eq!(est("short.csv", "short-e.csv").status.code(), Some(0));
    let o = est("cut.csv", "cut-e.csv");
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{e}");
    assert!(
        e.contains(&format!(
            "cut.csv:{line}: the last line has 34 of 35 cells and no line break"
        )),
        "{e}"
    );
    assert_eq!(rows(&dir.join("cut-e.csv")), rows(&dir.join("short-e.csv")));
    let i = limbfuse(&["inspect", "cut.csv"], dir);
    let out = String::from_utf8_lossy(&i.stdout);
    assert!(
        out.contains("the recording was cut off while it was written"),
        "{out}"
    );
}

/// The commands that write a new trial from a recording (`resample`, `align`,
/// `mirror`) left a cut last line out without a word; now they say so, and
/// their outputs are those of the file without that line.
#[test]
fn commands_that_rewrite_a_cut_recording_say_they_left_its_last_line_out() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let line = short_and_cut(dir, "12", "3");
    let runs: [&[&str]; 3] = [&["resample", "--rate", "50"], &["align"], &["mirror"]];
    for args in runs {
        let mut outputs = Vec::new();
        for trial in ["short.csv", "cut.csv"] {
            let out = format!("{}-{trial}", args[0]);
            let mut a = args.to_vec();
            a.extend([trial, "-o", out.as_str()]);
            let o = limbfuse(&a, dir);
            let e = String::from_utf8_lossy(&o.stderr).to_string();
            assert_eq!(o.status.code(), Some(0), "{args:?} {trial}: {e}");
            let said = e.contains(&format!(
                "warning: cut.csv:{line}: the last line has 34 of 35 cells and no line break"
            ));
            assert_eq!(said, trial == "cut.csv", "{args:?} {trial}: {e}");
            outputs.push(rows(&dir.join(&out)));
        }
        assert_eq!(outputs[0], outputs[1], "{args:?}");
    }
    let meta = std::fs::read_to_string(dir.join("resample-cut.csv")).unwrap();
    assert!(
        meta.contains(&format!("its line {line} left out, cut off mid-line")),
        "{meta}"
    );
}

/// `evaluate` scored a cut trial without a word (session 43's note; the
/// other commands warn). Now it warns of a cut last line in the trial or
/// the estimate (also in `--json`'s `warnings`), for angles and gait
/// events alike, and when a cut estimate is a row short of its trial the
/// error names the cut line, the likely cause.
#[test]
fn evaluate_says_a_cut_last_line_was_left_out() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let line = short_and_cut(dir, "3", "2");
    let said = format!("cut.csv:{line}: the last line has 34 of 35 cells and no line break");
    let ok = |args: &[&str]| {
        let o = limbfuse(args, dir);
        let e = String::from_utf8_lossy(&o.stderr).to_string();
        assert_eq!(o.status.code(), Some(0), "{args:?}: {e}");
        (String::from_utf8_lossy(&o.stdout).to_string(), e)
    };
    ok(&["estimate", "--method", "chain", "cut.csv", "-o", "e.csv"]);
    let (_, e) = ok(&["evaluate", "cut.csv", "e.csv"]);
    assert!(e.contains(&format!("warning: {said}")), "{e}");
    let (json, _) = ok(&["evaluate", "cut.csv", "e.csv", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let warned = v["warnings"].as_array().expect("warnings");
    assert!(
        warned.iter().any(|w| w.as_str().unwrap().contains(&said)),
        "{json}"
    );
    // The whole file gives no such warning.
    ok(&["estimate", "--method", "chain", "w.csv", "-o", "w-e.csv"]);
    let (json, e) = ok(&["evaluate", "w.csv", "w-e.csv", "--json"]);
    assert!(
        !e.contains("cut off") && !json.contains("cut off"),
        "{e}{json}"
    );
    // Gait events (a trial with contact references, cut the same way).
    let sim = ["simulate", "walking", "--duration", "6", "--gait-reference"];
    ok(&[&sim[..], &["-o", "gw.csv"]].concat());
    let whole = std::fs::read_to_string(dir.join("gw.csv")).unwrap();
    std::fs::write(dir.join("gcut.csv"), &whole[..whole.len() - 40]).unwrap();
    let gait_line = whole.lines().count();
    ok(&[
        "estimate",
        "--method",
        "gait-events",
        "gcut.csv",
        "-o",
        "g.csv",
    ]);
    let (_, e) = ok(&["evaluate", "gcut.csv", "g.csv"]);
    assert!(
        e.contains(&format!("warning: gcut.csv:{gait_line}: the last line has")),
        "{e}"
    );
    // An estimate cut in its last line: one row short of its trial.
    let est = std::fs::read_to_string(dir.join("e.csv")).unwrap();
    std::fs::write(dir.join("e-cut.csv"), &est[..est.len() - 20]).unwrap();
    let est_line = est.lines().count();
    let o = limbfuse(&["evaluate", "cut.csv", "e-cut.csv"], dir);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("the estimate ends after")
            && e.contains(&format!("e-cut.csv:{est_line}: the last line has")),
        "{e}"
    );
}
