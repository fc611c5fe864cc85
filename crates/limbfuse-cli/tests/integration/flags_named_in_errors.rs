//! An audit of the less-used commands: errors that named a simulator's
//! internal field (`turns.angle_rad`, `speed_mps`, `gyro_drift` in rad/s),
//! a flag the command does not have (`--duration` of `simulate
//! calibration`), a speed that was not asked for (`gait-library build
//! --leg-length 0.01`: "no periodic gait at 1 m/s"), the wrong cause
//! (`--activation-t-a 0`: "a limb needs positive mass"; `calibrate
//! --min-pose 1e9`: "the sensor moves throughout"), or another method's
//! parameter file by its first unknown key. Each now names the flag or the
//! file's `method` line, exit 1.

use std::process::Output;

use crate::support::limbfuse;

fn user_error(o: &Output, needles: &[&str]) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
    for internal in [
        "turns.",
        "speed_mps",
        "gyro_drift",
        "min_pose_s",
        "1745329251994",
        "ap_offset_sd_m",
        "remount.",
        "lever_arm_m",
        "hold_s",
        "0000001e",
    ] {
        assert!(!e.contains(internal), "internal name `{internal}` in: {e}");
    }
}

#[test]
fn errors_name_the_flag_in_its_unit() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let cases: &[(&[&str], &[&str])] = &[
        (
            &[
                "simulate",
                "walking",
                "--turn-every",
                "5",
                "--turn-deg",
                "1e300",
                "-o",
                "w.csv",
            ],
            &["--turn-deg 1e300", "[-1800, 1800] deg"],
        ),
        (
            &["simulate", "walking", "--speed", "10", "-o", "w.csv"],
            &["--speed 10", "[0.4, 1.8] m/s"],
        ),
        (
            &["montecarlo", "--runs", "1", "--speed", "10", "-o", "m.csv"],
            &["--speed 10"],
        ),
        (
            &["simulate", "knee-fes", "--gyro-drift", "100", "-o", "k.csv"],
            &["--gyro-drift 100", "deg/s"],
        ),
        (
            &[
                "simulate",
                "fixed-hip",
                "--activation-t-a",
                "0",
                "-o",
                "h.csv",
            ],
            &["--activation-t-a 0", "time constant"],
        ),
        (
            &["simulate", "calibration", "--hold", "1e9", "-o", "c.csv"],
            &["--poses x (--hold + --transition)", "--force"],
        ),
        (
            &[
                "simulate",
                "calibration",
                "--poses",
                "3",
                "--wobble-pose",
                "5",
                "-o",
                "c.csv",
            ],
            &["--wobble-pose 5", "1 to 3"],
        ),
        (
            &[
                "gait-library",
                "build",
                "--speeds",
                "0.5:0.6:0.1",
                "--leg-length",
                "0.01",
                "-o",
                "l.json",
            ],
            &["--leg-length 0.01", "0.5 to 1.4 m"],
        ),
        (
            &[
                "gait-library",
                "build",
                "--speeds",
                "0.5:0.6:0.1",
                "--mass",
                "1e9",
                "-o",
                "l.json",
            ],
            &["--mass 1e9", "20 to 250 kg"],
        ),
        (
            &[
                "simulate",
                "knee",
                "--remount-at",
                "1000",
                "--duration",
                "5",
                "-o",
                "k.csv",
            ],
            &["--remount-at 1000", "within the trial"],
        ),
        (
            &["simulate", "knee", "--speed", "10", "-o", "k.csv"],
            &["--speed 10", "[0.4, 1.8] m/s"],
        ),
        (
            &[
                "simulate",
                "knee",
                "--ap-offset-sd-cm",
                "1e9",
                "-o",
                "k.csv",
            ],
            &["--ap-offset-sd-cm 1e9", "[0, 5] cm"],
        ),
        (
            &[
                "simulate",
                "knee",
                "--remount-at",
                "2",
                "--remount-deg",
                "1e9",
                "--duration",
                "5",
                "-o",
                "k.csv",
            ],
            &["--remount-deg 1e9:", "[-180, 180] deg"],
        ),
        (
            &[
                "simulate",
                "calibration",
                "--lever-arm",
                "100",
                "-o",
                "c.csv",
            ],
            &["--lever-arm 100", "[0, 1] m"],
        ),
        (
            &["simulate", "calibration", "--hold", "700", "-o", "c.csv"],
            &["--hold 700", "(0, 600] s"],
        ),
    ];
    for (args, needles) in cases {
        user_error(&limbfuse(args, p), needles);
    }
    assert!(
        std::fs::read_dir(p).unwrap().next().is_none(),
        "nothing written"
    );
}

#[test]
fn calibrate_and_params_files_say_what_is_wrong() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let ok = |args: &[&str]| {
        let o = limbfuse(args, p);
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
    };
    ok(&[
        "simulate",
        "calibration",
        "--poses",
        "6",
        "--hold",
        "3",
        "-o",
        "c.csv",
    ]);
    user_error(
        &limbfuse(
            &["calibrate", "c.csv", "--min-pose", "1e9", "-o", "cal.toml"],
            p,
        ),
        &["--min-pose 1e9", "longer than the recording c.csv"],
    );
    user_error(
        &limbfuse(
            &["calibrate", "c.csv", "--min-pose", "0", "-o", "cal.toml"],
            p,
        ),
        &["--min-pose 0"],
    );
    ok(&["params", "--method", "sdre", "-o", "sdre.toml"]);
    ok(&["params", "--method", "mjls", "-o", "mjls.toml"]);
    ok(&["simulate", "walking", "--duration", "3", "-o", "w.csv"]);
    for (method, file, other) in [
        ("mjls", "sdre.toml", "sdre"),
        ("sdre", "mjls.toml", "mjls"),
        ("knee-selfalign", "mjls.toml", "mjls"),
    ] {
        user_error(
            &limbfuse(
                &[
                    "estimate", "--method", method, "--params", file, "w.csv", "-o", "e.csv",
                ],
                p,
            ),
            &[
                file,
                &format!("`method` = \"{other}\" but the file is read for method `{method}`"),
            ],
        );
    }
}

/// The same audit: `montecarlo` printed levels as `14.000000000000002` and
/// `0.30000000000000004` (percent times a fraction).
#[test]
fn montecarlo_levels_are_printed_as_given() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let o = limbfuse(
        &[
            "montecarlo",
            "--runs",
            "1",
            "--duration",
            "2",
            "--levels",
            "0:1:0.1",
            "-o",
            "m.csv",
        ],
        p,
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let csv = std::fs::read_to_string(p.join("m.csv")).unwrap();
    // (past the provenance comments, docs/OUTPUTS.md section 3, and the
    // column names)
    let levels: Vec<&str> = csv
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap())
        .collect();
    assert_eq!(
        &levels[..11],
        &["0", "0.1", "0.2", "0.3", "0.4", "0.5", "0.6", "0.7", "0.8", "0.9", "1"]
    );
}
