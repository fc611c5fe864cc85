//! Issue 15 item 5: the knee-axis methods (`knee-selfalign`,
//! `knee-gyro-axis`) say in one line when the knee axis was identified and
//! how sure the sign is, and refuse, with exit status 1 and no estimate
//! file, a trial with one IMU only, accelerometers but no gyroscopes (no
//! columns, or empty cells), no knee motion, or a window longer than the
//! trial.

use std::path::Path;
use std::process::Output;

use crate::support::limbfuse;

const METHODS: [&str; 2] = ["knee-selfalign", "knee-gyro-axis"];

fn user_error(o: &Output, needle: &str) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    assert!(!e.contains("panicked"), "{e}");
    assert!(e.contains(needle), "expected `{needle}` in: {e}");
}

/// A 12 s simulated knee trial split into its comment lines, header and rows.
fn trial(dir: &Path) -> (Vec<String>, Vec<String>, Vec<Vec<String>>) {
    let o = limbfuse(
        &[
            "simulate",
            "knee",
            "--duration",
            "12",
            "--seed",
            "4",
            "-o",
            "k.csv",
        ],
        dir,
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let text = std::fs::read_to_string(dir.join("k.csv")).unwrap();
    let mut lines = text.lines();
    let mut meta = Vec::new();
    let header = loop {
        let l = lines.next().unwrap();
        if l.starts_with('#') {
            meta.push(l.to_string());
        } else {
            break l.split(',').map(str::to_string).collect::<Vec<_>>();
        }
    };
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (meta, header, rows)
}

/// Writes the columns `keep` says of the trial, each cell through `cell`.
fn write(
    dir: &Path,
    name: &str,
    (meta, header, rows): &(Vec<String>, Vec<String>, Vec<Vec<String>>),
    keep: impl Fn(&str) -> bool,
    cell: impl Fn(&str, usize, &str) -> String,
) {
    let cols: Vec<usize> = (0..header.len()).filter(|&i| keep(&header[i])).collect();
    let mut s = meta.join("\n") + "\n";
    s += &cols
        .iter()
        .map(|&i| header[i].as_str())
        .collect::<Vec<_>>()
        .join(",");
    s += "\n";
    for (k, r) in rows.iter().enumerate() {
        let cells: Vec<String> = cols.iter().map(|&i| cell(&header[i], k, &r[i])).collect();
        s += &(cells.join(",") + "\n");
    }
    std::fs::write(dir.join(name), s).unwrap();
}

fn refused(dir: &Path, file: &str, extra: &[&str], needle: &str) {
    for m in METHODS {
        let mut args = vec!["estimate", "--method", m];
        args.extend_from_slice(extra);
        args.extend_from_slice(&[file, "-o", "out.csv"]);
        let o = limbfuse(&args, dir);
        user_error(&o, needle);
        assert!(
            !dir.join("out.csv").exists(),
            "{m} on {file}: an estimate was written"
        );
    }
}

#[test]
fn knee_axis_methods_summarise_and_refuse_bad_trials() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let t = trial(p);
    // A good trial: the one-line summary.
    for m in METHODS {
        let o = limbfuse(&["estimate", "--method", m, "k.csv", "-o", "e.csv"], p);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{e}");
        assert!(
            e.contains(&format!(
                "{m}: knee axis identified at t = 5.0 s, sign confidence "
            )),
            "{e}"
        );
    }
    let same = |_: &str, _: usize, v: &str| v.to_string();
    // One IMU only.
    write(p, "one.csv", &t, |h| !h.starts_with("shank_"), same);
    refused(
        p,
        "one.csv",
        &[],
        "no shank_acc_x/y/z, shank_gyr_x/y/z column(s)",
    );
    // Accelerometers but no gyroscope columns, or gyroscope columns left empty.
    write(p, "nogyr.csv", &t, |h| !h.contains("_gyr_"), same);
    refused(
        p,
        "nogyr.csv",
        &[],
        "no thigh_gyr_x/y/z, shank_gyr_x/y/z column(s)",
    );
    let empty_gyr = |h: &str, _: usize, v: &str| {
        if h.contains("_gyr_") {
            String::new()
        } else {
            v.to_string()
        }
    };
    write(p, "emptygyr.csv", &t, |_| true, empty_gyr);
    refused(
        p,
        "emptygyr.csv",
        &[],
        "no sample with both the thigh and the shank gyroscope",
    );
    // No knee motion: sensors at rest (gravity on the accelerometers, a
    // deterministic +-0.003 rad/s wobble on the gyros).
    let still = |h: &str, k: usize, v: &str| {
        let axis = h.as_bytes()[h.len() - 1];
        if h.contains("_gyr_") {
            format!("{:.6}", 0.003 * (0.37 * k as f64 + f64::from(axis)).sin())
        } else if h.contains("_acc_") {
            format!(
                "{:.4}",
                [0.5, 9.7, 1.0][usize::from(axis - b'x')] + 0.02 * (1.3 * k as f64).cos()
            )
        } else {
            v.to_string()
        }
    };
    write(p, "still.csv", &t, |_| true, still);
    refused(
        p,
        "still.csv",
        &[],
        "the knee axis is unidentifiable: no knee motion",
    );
    // Too few complete samples (2026-12-06; before, "no knee motion"): the
    // shank's accelerometer x empty on two rows in three.
    let holes = |h: &str, k: usize, v: &str| {
        if h == "shank_acc_x" && !k.is_multiple_of(3) {
            String::new()
        } else {
            v.to_string()
        }
    };
    write(p, "holes.csv", &t, |_| true, holes);
    refused(
        p,
        "holes.csv",
        &[],
        "only 400 of the 1200 samples (33 %) have both IMUs complete",
    );
    // A window longer than the trial (1200 samples).
    refused(
        p,
        "k.csv",
        &["--window", "2000"],
        "(2000 samples, --window) is longer than the trial (1200 samples): no window was \
         completed; give `--window N` with N at most 1200",
    );
}

/// `--leg` belongs to the gaittoolbox import: a knee-rig log refuses it.
#[test]
fn issue_14_import_leg_only_for_gaittoolbox() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("Trial_01.csv"), "x\n").unwrap();
    let o = crate::support::limbfuse(
        &[
            "import",
            "--format",
            "knee-rig",
            "--leg",
            "left",
            "Trial_01.csv",
            "-o",
            "t.csv",
        ],
        d.path(),
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("--leg applies to --format gaittoolbox"), "{e}");
}
