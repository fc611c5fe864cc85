//! What every CLI integration test needs: the `limbfuse` binary built for
//! this test run, run with arguments in a directory.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the `limbfuse` binary of this build with `args` in `dir` and
/// returns its exit status and output (panics only when the binary cannot
/// be started at all, which is a broken build, not a test outcome).
pub fn limbfuse(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

/// The standard error of a run, as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A user error: exit status 1 (not a panic's 101, not an abort's 134, not
/// clap's 2), no panic, backtrace hint or internal error in stderr, and
/// every needle in it.
pub fn assert_user_error(o: &Output, needles: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    assert!(
        !e.contains("panicked") && !e.contains("RUST_BACKTRACE") && !e.contains("internal error"),
        "{e}"
    );
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
}

/// `../shared/data/REL` (or under `LIMBFUSE_DATA`) when it exists; `None`
/// with a skip message otherwise.
pub fn shared_data(rel: &str) -> Option<PathBuf> {
    let dir = std::env::var_os("LIMBFUSE_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"))
        });
    let path = dir.join(rel);
    if path.exists() {
        Some(path)
    } else {
        println!("skipping: ../shared/data/{rel} not found (set LIMBFUSE_DATA)");
        None
    }
}

/// A trial file's text with every accelerometer cell clipped at
/// `full_scale` (m/s^2), as a sensor of that full scale records it, and,
/// when `stated`, the range stated on a `# acc_range_m_s2:` line after the
/// first.
pub fn clip_accelerometers(text: &str, full_scale: f64, stated: bool) -> String {
    let clipped = edit_cells(text, |_, column, cell| {
        let v: f64 = cell.parse().ok()?;
        (column.contains("_acc_") && v.abs() > full_scale)
            .then(|| format!("{}", v.clamp(-full_scale, full_scale)))
    });
    if !stated {
        return clipped;
    }
    let (first, rest) = clipped.split_once('\n').unwrap();
    format!("{first}\n# acc_range_m_s2: {full_scale}\n{rest}")
}

/// A trial file's text with data cells rewritten: `f(row, column name,
/// cell)` (row 0 is the first data row) gives the new cell, or `None` to
/// keep it. Comment lines and the header are kept as they are.
pub fn edit_cells(text: &str, f: impl Fn(usize, &str, &str) -> Option<String>) -> String {
    let header = text
        .lines()
        .position(|l| l.starts_with("t,"))
        .expect("a header row");
    let names: Vec<&str> = text.lines().nth(header).unwrap().split(',').collect();
    let mut out = String::new();
    for (i, l) in text.lines().enumerate() {
        if i > header && !l.is_empty() {
            let cells: Vec<String> = l
                .split(',')
                .zip(&names)
                .map(|(c, n)| f(i - header - 1, n, c).unwrap_or_else(|| c.to_string()))
                .collect();
            out += &cells.join(",");
        } else {
            out += l;
        }
        out.push('\n');
    }
    out
}

/// A copy of the trial `from` without its `*_ref` columns, as `to`.
pub fn without_references(dir: &Path, from: &str, to: &str) {
    keep_columns(dir, from, to, |n| !n.ends_with("_ref"));
}

/// A copy of the trial `from` keeping `t` and the columns `keep` accepts,
/// as `to`.
pub fn keep_columns(dir: &Path, from: &str, to: &str, keep: impl Fn(&str) -> bool) {
    let text = std::fs::read_to_string(dir.join(from)).unwrap();
    let header = text.lines().position(|l| l.starts_with("t,")).unwrap();
    let names: Vec<&str> = text.lines().nth(header).unwrap().split(',').collect();
    let kept: Vec<bool> = names.iter().map(|n| *n == "t" || keep(n)).collect();
    let mut out = String::new();
    for (i, l) in text.lines().enumerate() {
        if i < header {
            out += l;
        } else {
            let cells: Vec<&str> = l
                .split(',')
                .zip(&kept)
                .filter(|(_, k)| **k)
                .map(|(c, _)| c)
                .collect();
            out += &cells.join(",");
        }
        out.push('\n');
    }
    std::fs::write(dir.join(to), out).unwrap();
}

/// `trial` (a trial file's text) with each accelerometer and gyroscope cell
/// empty with probability 1/`every` (a fixed linear congruential sequence).
pub fn with_empty_cells(trial: &str, every: u64) -> String {
    let mut state: u64 = 0x2545_F491_4F6C_DD1D;
    let mut header: Option<Vec<bool>> = None;
    let mut out = String::new();
    for line in trial.lines() {
        if line.starts_with('#') {
            out += line;
        } else if let Some(imu) = &header {
            let cells: Vec<&str> = line.split(',').collect();
            let kept: Vec<&str> = cells
                .iter()
                .zip(imu)
                .map(|(c, is_imu)| {
                    state = state
                        .wrapping_mul(6_364_136_223_846_793_005)
                        .wrapping_add(1_442_695_040_888_963_407);
                    if *is_imu && (state >> 33).is_multiple_of(every) {
                        ""
                    } else {
                        c
                    }
                })
                .collect();
            out += &kept.join(",");
        } else {
            header = Some(
                line.split(',')
                    .map(|n| n.contains("_acc_") || n.contains("_gyr_"))
                    .collect(),
            );
            out += line;
        }
        out.push('\n');
    }
    out
}
