//! The fuzz audit of session 27, its messages: numbers printed with every
//! digit (`1e308` as 309 digits) and internal names (`mean_angle_rad[1]`,
//! `rate_hz`, `duration_s * imu_rate_hz`, "starts:") instead of the flag
//! the user gave. Now: the flag, and the number as `ShownNumber` shows it.

use std::path::Path;
use std::process::Output;

use crate::support::{edit_cells, limbfuse};

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The longest run of digits in `s`.
fn longest_digit_run(s: &str) -> usize {
    s.split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0)
}

/// Exit 1, every needle in stderr, no number written out with more than 20
/// digits, none of the `hidden` internal names.
fn assert_short_user_error(o: &Output, needles: &[&str], hidden: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    assert!(!e.contains("panicked"), "{e}");
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
    for h in hidden {
        assert!(!e.contains(h), "`{h}` (an internal name) in: {e}");
    }
    assert!(longest_digit_run(&e) <= 20, "a long number in: {e}");
}

/// A simulated walk of `seconds` s, `name` in `dir`.
fn walk(dir: &Path, seconds: &str, name: &str) {
    let o = limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            seconds,
            "--seed",
            "1",
            "-o",
            name,
        ],
        dir,
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

/// `align --mean-angle thigh=1e308` printed a 300-digit number of radians
/// and named `option mean_angle_rad[1]`.
#[test]
fn align_mean_angle_of_1e308_names_the_flag_with_the_number_short() {
    let d = tempfile::tempdir().unwrap();
    walk(d.path(), "5", "w.csv");
    let o = limbfuse(
        &[
            "align",
            "--mean-angle",
            "thigh=1e308",
            "w.csv",
            "-o",
            "o.csv",
        ],
        d.path(),
    );
    assert_short_user_error(
        &o,
        &["--mean-angle thigh=1e308", "[-180, 180]"],
        &["mean_angle_rad"],
    );
}

/// `simulate walking --imu-rate 1e308`, `knee-fes --rate 1e-300` (named
/// `rate_hz`), `knee-fes` / `fixed-hip --rate 5` (named `rate_hz`; now
/// `--rate`, the flag's alias and the Python option), `walking --duration
/// 1e-300` and `montecarlo --duration 1e-300` ("duration_s * imu_rate_hz =
/// 0") named internal fields or printed every digit.
#[test]
fn simulation_rates_and_durations_far_out_of_range_name_the_flag() {
    let d = tempfile::tempdir().unwrap();
    let cases: [(&[&str], &[&str]); 6] = [
        (
            &["simulate", "walking", "--imu-rate", "1e308", "-o", "x.csv"],
            &["--imu-rate 1e308", "--force"],
        ),
        (
            &["simulate", "knee-fes", "--rate", "1e-300", "-o", "x.csv"],
            &["--imu-rate 1e-300", "less than one sample"],
        ),
        (
            &["simulate", "knee-fes", "--rate", "5", "-o", "x.csv"],
            &["--rate 5", "[10, 2000] Hz"],
        ),
        (
            &["simulate", "fixed-hip", "--rate", "5", "-o", "x.csv"],
            &["--rate 5", "[10, 2000] Hz"],
        ),
        (
            &["simulate", "walking", "--duration", "1e-300", "-o", "x.csv"],
            &[
                "--duration 1e-300",
                "--imu-rate 100",
                "less than one sample",
            ],
        ),
        (
            &["montecarlo", "--duration", "1e-300", "-o", "mc.csv"],
            &["--duration 1e-300", "less than one sample"],
        ),
    ];
    for (args, needles) in cases {
        let o = limbfuse(args, d.path());
        assert_short_user_error(&o, needles, &["rate_hz", "duration_s"]);
    }
    assert!(!d.path().join("x.csv").exists());
}

/// `evaluate --method mjls --starts 0` and `tune --starts 0` said
/// "starting points: starts: ...", `tune --particles 0` "particles: ...":
/// no flag named.
#[test]
fn starts_and_particles_of_zero_name_the_flag() {
    let d = tempfile::tempdir().unwrap();
    walk(d.path(), "30", "w.csv");
    let cases: [(&[&str], &str); 3] = [
        (
            &["evaluate", "w.csv", "--method", "mjls", "--starts", "0"],
            "--starts 0",
        ),
        (
            &[
                "tune", "w.csv", "--method", "mjls", "--starts", "0", "-o", "p.toml",
            ],
            "--starts 0",
        ),
        (
            &[
                "tune",
                "w.csv",
                "--method",
                "mjls",
                "--particles",
                "0",
                "-o",
                "p.toml",
            ],
            "--particles 0",
        ),
    ];
    for (args, flag) in cases {
        let o = limbfuse(args, d.path());
        assert_short_user_error(&o, &[flag], &["starts: ", "particles: "]);
    }
}

/// Left open by that audit (session 28): `tune --budget 5` (fewer than two
/// generations of the swarm) and `--budget 20000000` said "tuning mjls on
/// w.csv: budget: expected at least two generations ...", the tuner's field
/// and not the flag. Now the flag with its value, the bound from
/// `--particles`, before the trial is read.
#[test]
fn a_tuning_budget_out_of_range_names_the_flag() {
    let d = tempfile::tempdir().unwrap();
    walk(d.path(), "30", "w.csv");
    let tune = |extra: &[&str]| {
        let mut args = vec!["tune", "w.csv", "--method", "mjls", "-o", "p.toml"];
        args.extend_from_slice(extra);
        limbfuse(&args, d.path())
    };
    let cases: [(&[&str], &[&str]); 3] = [
        (
            &["--budget", "5"],
            &[
                "--budget 5: expected at least two generations",
                "2 x --particles 20 = 40",
            ],
        ),
        (
            &["--budget", "15", "--particles", "10"],
            &["--budget 15:", "2 x --particles 10 = 20"],
        ),
        (
            &["--budget", "20000000"],
            &["--budget 20000000:", "at most 10000000 evaluations"],
        ),
    ];
    for (extra, needles) in cases {
        let o = tune(extra);
        assert_short_user_error(&o, needles, &["budget: ", "tuning mjls on"]);
        assert!(!d.path().join("p.toml").exists());
    }
}

/// `tune --window 0:1e308`, `--validate 1e308:1e308` and `evaluate --starts
/// 3 --length 1e-300` printed their numbers with every digit.
#[test]
fn windows_and_lengths_far_out_of_range_show_their_numbers_short() {
    let d = tempfile::tempdir().unwrap();
    walk(d.path(), "30", "w.csv");
    let tune = |flag: &str, value: &str| {
        limbfuse(
            &[
                "tune", "w.csv", "--method", "mjls", flag, value, "-o", "p.toml",
            ],
            d.path(),
        )
    };
    assert_short_user_error(&tune("--window", "0:1e308"), &["1e308 s"], &[]);
    assert_short_user_error(
        &tune("--validate", "1e308:1e308"),
        &["--validate", "1e308"],
        &[],
    );
    let o = limbfuse(
        &[
            "evaluate", "w.csv", "--method", "mjls", "--starts", "3", "--length", "1e-300",
        ],
        d.path(),
    );
    assert_short_user_error(&o, &["1e-300 s"], &[]);
}

/// `estimate` of a walk whose `t` is scaled by 1e-300 warned that `t`
/// "steps by a median 0.000...0001" (300 zeros), and the rejection warning
/// said "first at t = 0.000...".
#[test]
fn the_time_unit_warning_shows_a_tiny_step_short() {
    let d = tempfile::tempdir().unwrap();
    walk(d.path(), "5", "w.csv");
    let text = std::fs::read_to_string(d.path().join("w.csv")).unwrap();
    let tiny = edit_cells(&text, |_, name, cell| {
        (name == "t").then(|| format!("{:e}", cell.parse::<f64>().unwrap() * 1e-300))
    });
    std::fs::write(d.path().join("tiny.csv"), tiny).unwrap();
    let o = limbfuse(
        &["estimate", "tiny.csv", "--method", "mjls", "-o", "e.csv"],
        d.path(),
    );
    let e = stderr(&o);
    assert!(e.contains("steps by a median 1"), "{e}");
    assert!(e.contains("e-302"), "{e}");
    assert!(longest_digit_run(&e) <= 20, "a long number in: {e}");
}

/// A `chain` parameter file with `height_m = 1e30` printed 31 digits.
#[test]
fn a_chain_height_of_1e30_is_shown_short() {
    let d = tempfile::tempdir().unwrap();
    walk(d.path(), "5", "w.csv");
    std::fs::write(d.path().join("p.toml"), "[geometry]\nheight_m = 1e30\n").unwrap();
    let o = limbfuse(
        &[
            "estimate", "w.csv", "--method", "chain", "--params", "p.toml", "-o", "e.csv",
        ],
        d.path(),
    );
    assert_short_user_error(&o, &["p.toml", "height_m = 1e30", "1 to 2.5 m"], &[]);
}

/// `w.csv` in `dir` with its `# key:` line set to `value`, as `bad.csv` and
/// (through `mirror`, which keeps the metadata) as `bad.arrow`.
fn bad_metadata(dir: &Path, key: &str, value: &str) {
    let text = std::fs::read_to_string(dir.join("w.csv")).unwrap();
    let prefix = format!("# {key}:");
    let bad: String = text
        .lines()
        .map(|l| {
            if l.starts_with(&prefix) {
                format!("{prefix} {value}\n")
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    std::fs::write(dir.join("bad.csv"), bad).unwrap();
    let _ = std::fs::remove_file(dir.join("bad.arrow"));
    let o = limbfuse(&["mirror", "bad.csv", "-o", "bad.arrow"], dir);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

/// `# sample_rate_hz: abc` (or `nan`, `-100`, `0`) was taken for no rate
/// by `estimate` and `align` (exit 0), in CSV and Arrow trials alike. Now
/// both formats: exit 1 naming the file, the line and what was expected.
/// (`# g: nan` / `-9.81`: refused by the commands that use gravity, the
/// same in both formats; kept here so they stay the same.)
#[test]
fn bad_sample_rate_or_gravity_metadata_is_refused_in_csv_and_arrow_alike() {
    let d = tempfile::tempdir().unwrap();
    walk(d.path(), "5", "w.csv");
    for v in ["abc", "nan", "-100", "0"] {
        bad_metadata(d.path(), "sample_rate_hz", v);
        for f in ["bad.csv", "bad.arrow"] {
            for args in [
                &["estimate", f, "--method", "mjls", "-o", "e.csv"][..],
                &["align", f, "-o", "a.csv"][..],
            ] {
                let o = limbfuse(args, d.path());
                let line = format!("`# sample_rate_hz: {v}`");
                assert_short_user_error(&o, &[f, &line, "expected the sample rate in Hz"], &[]);
            }
        }
    }
    for v in ["nan", "-9.81"] {
        bad_metadata(d.path(), "g", v);
        for f in ["bad.csv", "bad.arrow"] {
            let o = limbfuse(
                &["estimate", f, "--method", "chain", "-o", "e.csv"],
                d.path(),
            );
            let line = format!("`# g: {v}`");
            assert_short_user_error(&o, &[f, &line, "expected gravity"], &[]);
        }
    }
    assert!(!d.path().join("e.csv").exists() && !d.path().join("a.csv").exists());
}
