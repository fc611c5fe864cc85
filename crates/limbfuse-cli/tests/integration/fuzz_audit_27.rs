//! A fuzz audit (session 27): panics, unbounded memory, hangs and unclear
//! messages on hostile inputs. Each case exits with status 1 and a message
//! naming the file or flag and what was expected.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::support::{assert_user_error, edit_cells, limbfuse, stderr};

/// A 5 s simulated walk, `w.csv` in `dir`.
fn walk(dir: &Path) {
    let o = limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "5",
            "--seed",
            "1",
            "-o",
            "w.csv",
        ],
        dir,
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

/// Runs the binary with `args` in `dir`, killed after `limit`: `None` when
/// it had to be killed (a hang).
fn limbfuse_within(args: &[&str], dir: &Path, limit: Duration) -> Option<Output> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let start = Instant::now();
    while child.try_wait().expect("waits").is_none() {
        if start.elapsed() > limit {
            child.kill().ok();
            child.wait().ok();
            return None;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    Some(child.wait_with_output().expect("output"))
}

/// Item 1: every `t` of a walk times 1e-20 made `align` panic ("index out
/// of bounds", gait_window.rs: the stride lag saturated to usize::MAX and
/// `lag + 10` overflowed). Now: no walking, the trial's span said.
#[test]
fn align_of_a_walk_with_times_of_1e_minus_20_s_says_the_trial_is_too_short() {
    let d = tempfile::tempdir().unwrap();
    walk(d.path());
    let text = std::fs::read_to_string(d.path().join("w.csv")).unwrap();
    let tiny = edit_cells(&text, |_, name, cell| {
        (name == "t").then(|| format!("{:e}", cell.parse::<f64>().unwrap() * 1e-20))
    });
    std::fs::write(d.path().join("tiny_t.csv"), tiny).unwrap();
    let o = limbfuse(&["align", "tiny_t.csv", "-o", "o.csv"], d.path());
    assert_user_error(
        &o,
        &[
            "tiny_t.csv",
            "no walking found",
            "span",
            "are its times in seconds",
        ],
    );
    assert!(!d.path().join("o.csv").exists());
}

/// Item 2: a walk with 1e6 s added to `t` from data row 251 on aborted
/// `resample --rate 50` allocating 103 GB. Now refused before allocating,
/// with the flag, the size in memory and the limit.
#[test]
fn resample_across_a_jump_of_1e6_s_is_refused_with_the_memory_it_would_take() {
    let d = tempfile::tempdir().unwrap();
    walk(d.path());
    let text = std::fs::read_to_string(d.path().join("w.csv")).unwrap();
    let gap = edit_cells(&text, |row, name, cell| {
        (name == "t" && row >= 250).then(|| (cell.parse::<f64>().unwrap() + 1e6).to_string())
    });
    std::fs::write(d.path().join("gap.csv"), gap).unwrap();
    let o = limbfuse(
        &["resample", "--rate", "50", "gap.csv", "-o", "x.csv"],
        d.path(),
    );
    assert_user_error(
        &o,
        &[
            "gap.csv",
            "--rate 50 Hz",
            "GB in memory",
            "limit of 10 GiB",
            "jump",
        ],
    );
}

/// Item 3: `import --format knee-rig /dev/zero` grew one line without
/// bound. A line over the trial reader's 64 MiB is now refused by line
/// (here a 65 MiB file without a line break, which was read whole).
#[test]
fn import_refuses_a_line_over_64_mib() {
    let d = tempfile::tempdir().unwrap();
    let mut f = std::fs::File::create(d.path().join("Trial_01.csv")).unwrap();
    let block = vec![b'0'; 1 << 20];
    for _ in 0..65 {
        f.write_all(&block).unwrap();
    }
    drop(f);
    let o = limbfuse(
        &[
            "import",
            "--format",
            "knee-rig",
            "Trial_01.csv",
            "-o",
            "o.csv",
        ],
        d.path(),
    );
    assert_user_error(&o, &["Trial_01.csv:1", "no line break", "at most 64 MiB"]);
}

/// Item 4: `evaluate FIFO e.csv` opened the FIFO twice and hung on the
/// second open; `report w.csv FIFO` blamed the FIFO's header. Inputs read
/// twice must be regular files: refused up front, at once.
#[test]
fn evaluate_and_report_refuse_a_fifo_instead_of_hanging() {
    let d = tempfile::tempdir().unwrap();
    walk(d.path());
    let o = limbfuse(
        &["estimate", "--method", "mjls", "w.csv", "-o", "e.csv"],
        d.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let made = Command::new("mkfifo")
        .arg("f")
        .current_dir(d.path())
        .status();
    if !made.is_ok_and(|s| s.success()) {
        println!("skipping: mkfifo not available");
        return;
    }
    let cases: [&[&str]; 3] = [
        &["evaluate", "f", "e.csv"],
        &["evaluate", "w.csv", "f"],
        &["report", "w.csv", "f", "-o", "o.html"],
    ];
    for args in cases {
        // A writer that feeds the FIFO once, as `cat w.csv > f &` did.
        let fifo = d.path().join("f");
        let source = d
            .path()
            .join(if args[1] == "f" { "w.csv" } else { "e.csv" });
        let writer = std::thread::spawn(move || {
            if let Ok(mut out) = std::fs::OpenOptions::new().write(true).open(&fifo) {
                let _ = out.write_all(&std::fs::read(source).unwrap());
            }
        });
        let o = limbfuse_within(args, d.path(), Duration::from_secs(20))
            .unwrap_or_else(|| panic!("`limbfuse {}` hung (killed after 20 s)", args.join(" ")));
        let command = format!("`{}` reads its inputs twice", args[0]);
        assert_user_error(&o, &["f: a pipe or other non-regular file", &command]);
        // Release the writer if nothing opened the FIFO for reading.
        if !writer.is_finished() {
            let _ = std::fs::File::open(d.path().join("f"));
        }
        writer.join().unwrap();
    }
}

/// Item 5: a parameter or calibration file was read whole, `/dev/zero`
/// until memory ran out ("out of memory"). Now bounded at 16 MiB, with
/// what was expected (a 17 MiB file stands for `/dev/zero`).
#[test]
fn params_and_calibration_files_over_16_mib_are_refused() {
    let d = tempfile::tempdir().unwrap();
    walk(d.path());
    std::fs::write(d.path().join("big.toml"), vec![b'#'; 17 << 20]).unwrap();
    let o = limbfuse(
        &[
            "estimate", "--method", "mjls", "--params", "big.toml", "w.csv", "-o", "e.csv",
        ],
        d.path(),
    );
    assert_user_error(&o, &["big.toml", "more than 16 MiB", "a parameter file"]);
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "mjls",
            "--calibration",
            "big.toml",
            "w.csv",
            "-o",
            "e.csv",
        ],
        d.path(),
    );
    assert_user_error(&o, &["big.toml", "more than 16 MiB", "a calibration file"]);
}

/// Item 6: `simulate bslip --rate 1e-300` wrote a one-row trial (exit 0);
/// the other simulators take at least 1 Hz.
#[test]
fn simulate_bslip_needs_a_rate_of_at_least_1_hz() {
    let d = tempfile::tempdir().unwrap();
    let o = limbfuse(
        &[
            "simulate",
            "bslip",
            "--duration",
            "1",
            "--rate",
            "1e-300",
            "-o",
            "f.csv",
        ],
        d.path(),
    );
    assert_user_error(&o, &["--rate 1e-300", "at least 1 Hz"]);
    assert!(!d.path().join("f.csv").exists());
}

/// Item 8: a 2,000,000-number `encoder_sigma` in --params was echoed whole
/// (a 12 MB message); a 5 MB `method` name likewise. Echoed values are cut
/// with their full length.
#[test]
fn long_values_in_a_params_file_are_not_echoed_whole() {
    let d = tempfile::tempdir().unwrap();
    walk(d.path());
    let numbers = vec!["0.01"; 2_000_000].join(",");
    std::fs::write(
        d.path().join("es.toml"),
        format!("encoder_sigma = [{numbers}]\n"),
    )
    .unwrap();
    let o = limbfuse(
        &[
            "estimate", "--method", "mjls", "--params", "es.toml", "w.csv", "-o", "e.csv",
        ],
        d.path(),
    );
    assert_user_error(
        &o,
        &["es.toml", "`encoder_sigma`", "0.01, ...] (2000000 numbers)"],
    );
    assert!(o.stderr.len() < 2000, "{} bytes", o.stderr.len());
    let name = "m".repeat(5_000_000);
    std::fs::write(d.path().join("m.toml"), format!("method = \"{name}\"\n")).unwrap();
    let o = limbfuse(
        &[
            "estimate", "--method", "mjls", "--params", "m.toml", "w.csv", "-o", "e.csv",
        ],
        d.path(),
    );
    assert_user_error(&o, &["m.toml", "... (5000000 characters)"]);
    assert!(o.stderr.len() < 4000, "{} bytes", o.stderr.len());
}
