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
