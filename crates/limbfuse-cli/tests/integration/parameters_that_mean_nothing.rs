//! An audit of every method's parameter file (each numeric key set to 0,
//! -1, 1e300, 1e-300, nan, inf, ...): values with no physical meaning were
//! accepted and gave an estimate anyway, exit 0. `encoder_sigma = 1e-300`
//! squared to 0 and then acted exactly as `1e300` (no encoder update ever);
//! `gravity = 1e-300` turned every accelerometer row off; `correction =
//! 1e300` gave walking speeds of 7e299 m/s; `rescale_height = 1e300` a
//! constant phase, and with it `mass = nan` went unchecked; `g = 1e300` froze
//! the FES estimate; `imu_trunk = [a, b, c, d]` was read as its first three;
//! gait-events thresholds at 1e300 found no contact, `highpass_hz = 1e300`
//! passed.
//! Each is now refused with exit 1, naming the file, the key and the range.

use crate::support::limbfuse;

fn refused(dir: &std::path::Path, method: &str, trial: &str, params: &str, needles: &[&str]) {
    std::fs::write(dir.join("p.toml"), params).unwrap();
    let o = limbfuse(
        &[
            "estimate", "--method", method, "--params", "p.toml", trial, "-o", "e.csv",
        ],
        dir,
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{method} {params:?}: {e}");
    for n in needles {
        assert!(e.contains(n), "{method} {params:?}: expected `{n}` in: {e}");
    }
    assert!(
        !dir.join("e.csv").exists(),
        "{method}: an estimate was written"
    );
}

fn simulate(dir: &std::path::Path, args: &[&str]) {
    let o = limbfuse(args, dir);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn segment_filters_refuse_sigmas_whose_square_means_nothing() {
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    simulate(
        d,
        &["simulate", "walking", "--duration", "5", "-o", "w.csv"],
    );
    for v in ["1e-300", "1e300"] {
        refused(
            d,
            "mjls",
            "w.csv",
            &format!("method = \"mjls\"\nencoder_sigma = {v}\n"),
            &[
                "p.toml",
                "`encoder_sigma` = ",
                v,
                "must be from 1e-12 to 1e12",
            ],
        );
        refused(
            d,
            "local",
            "w.csv",
            &format!("method = \"local\"\ngravity = {v}\n"),
            &["p.toml", "`gravity`", "must be from 1 to 20"],
        );
    }
    refused(
        d,
        "local",
        "w.csv",
        "method = \"local\"\n[segments.shank]\ninitial_gyro_bias = 1e300\n",
        &["`segments.shank.initial_gyro_bias` = 1e300", "+-1 rad/s"],
    );
    refused(
        d,
        "chain",
        "w.csv",
        "method = \"chain\"\nleg_jerk = 1e300\n",
        &["`leg_jerk` = 1e300 is outside 1e-12 to 1e12"],
    );
    refused(
        d,
        "chain",
        "w.csv",
        "method = \"chain\"\n[geometry]\nimu_trunk = [-0.1, 0.08, 0, 42]\n",
        &["p.toml:3", "expected 3 numbers, found 4"],
    );
    refused(
        d,
        "gait-events",
        "w.csv",
        "method = \"gait-events\"\nswing_rate = 1e300\n",
        &["p.toml", "`swing_rate` = 1e300: expected 0.001 to 35 rad/s"],
    );
    refused(
        d,
        "gait-events",
        "w.csv",
        "method = \"gait-events\"\nmin_swing_time = 1e300\n",
        &["`min_swing_time` = 1e300: expected 0.001 to 2 s"],
    );
    refused(
        d,
        "gait-events",
        "w.csv",
        "method = \"gait-events\"\naxis_time_constant = 1e-300\n",
        &["`axis_time_constant` = 1e-300: expected 1 to 1000000 s"],
    );
    refused(
        d,
        "lowback-speed",
        "w.csv",
        "method = \"lowback-speed\"\ncorrection = 1e300\n",
        &["p.toml", "`correction` = 1e300: expected 0.5 to 2"],
    );
    refused(
        d,
        "lowback-speed",
        "w.csv",
        "method = \"lowback-speed\"\nleg_length = 1e-300\n",
        &["`leg_length` = 1e-300: expected 0.5 to 1.4 m"],
    );
}

#[test]
fn gait_and_fes_methods_refuse_bodies_and_models_no_human_has() {
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    simulate(d, &["simulate", "bslip", "--duration", "2", "-o", "b.csv"]);
    simulate(
        d,
        &[
            "gait-library",
            "build",
            "--speeds",
            "0.6:0.8:0.1",
            "-o",
            "lib.json",
        ],
    );
    refused(
        d,
        "imm-bslip",
        "b.csv",
        "library = \"lib.json\"\nrescale_height = 1e300\n",
        &["p.toml: `rescale_height` 1e300", "0.5 to 1.4 m"],
    );
    refused(
        d,
        "imm-bslip",
        "b.csv",
        "library = \"lib.json\"\nrescale_height = 0.95\nmass = nan\n",
        &["p.toml: `mass` NaN", "20 to 250 kg"],
    );
    simulate(d, &["simulate", "knee", "--duration", "10", "-o", "k.csv"]);
    refused(
        d,
        "knee-selfalign",
        "k.csv",
        "method = \"knee-selfalign\"\nhighpass_hz = 1e300\n",
        &["p.toml: method `knee-selfalign`: parameter highpass_hz = 1e300 is outside (0, 10] Hz"],
    );
    // (the file is named, and `--window`'s hint follows window errors only)
    std::fs::write(
        d.join("p.toml"),
        "method = \"knee-selfalign\"\nacc_max_spread = 2\n",
    )
    .unwrap();
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "knee-selfalign",
            "--params",
            "p.toml",
            "k.csv",
            "-o",
            "e.csv",
        ],
        d,
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains(
            "p.toml: method `knee-selfalign`: parameter acc_max_spread = 2 is outside [0, 1]"
        ),
        "{e}"
    );
    assert!(!e.contains("--window counts"), "{e}");
    simulate(
        d,
        &["simulate", "knee-fes", "--duration", "3", "-o", "f.csv"],
    );
    refused(
        d,
        "ekf",
        "f.csv",
        "method = \"ekf\"\n[model]\ng = 1e300\n",
        &[
            "p.toml [model] `g`: unphysical",
            "`g` = 1e300 is outside [1, 20] m/s^2",
        ],
    );
    // A value from the trial's metadata names that line, not a file that did
    // not give it (the message named only the trial before).
    let text = std::fs::read_to_string(d.join("f.csv")).unwrap();
    let text: String = text
        .lines()
        .map(|l| match l.starts_with("# param.mass:") {
            true => "# param.mass: 1e300\n".to_string(),
            false => format!("{l}\n"),
        })
        .collect();
    std::fs::write(d.join("f.csv"), text).unwrap();
    refused(
        d,
        "sdre",
        "f.csv",
        "method = \"sdre\"\n",
        &[
            "the trial's `# param.mass:` line: unphysical",
            "`mass` = 1e300",
        ],
    );
}
