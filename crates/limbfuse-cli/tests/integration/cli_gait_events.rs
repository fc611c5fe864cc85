//! `gait-events` (and bad input of both gait methods) through the binary:
//! the shared real recordings (skipped with a message when `../shared/data`
//! is absent), and bad input (no foot IMU, no walking); `lowback-speed` on
//! the shared HA001 recordings is in `cli_lowback_speed`.

use std::path::{Path, PathBuf};

use crate::support::limbfuse;

pub(crate) fn data_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("LIMBFUSE_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"))
        });
    if dir.join("gaitmap-foot-walk").is_dir() && dir.join("mobgap-lowerback").is_dir() {
        Some(dir)
    } else {
        println!("skipping: ../shared/data not found (set LIMBFUSE_DATA)");
        None
    }
}

/// Runs `limbfuse` with `args` in `dir`; exit 0 or the test fails with its stderr.
pub(crate) fn succeed(args: &[&str], dir: &Path) -> std::process::Output {
    let o = limbfuse(args, dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

pub(crate) fn evaluate_json(method: &str, trial: &Path, dir: &Path) -> serde_json::Value {
    let trial = trial.to_str().unwrap();
    succeed(&["estimate", "--method", method, trial, "-o", "e.csv"], dir);
    let o = succeed(&["evaluate", trial, "e.csv", "--json"], dir);
    serde_json::from_slice(&o.stdout).unwrap()
}

pub(crate) fn f(v: &serde_json::Value, path: &[&str]) -> f64 {
    let mut x = v;
    for k in path {
        x = &x[*k];
    }
    x.as_f64().unwrap_or_else(|| panic!("{path:?} in {v}"))
}

/// Issue 19 targets on the shared two-foot walk: contacts within 20 ms
/// (median) / 40 ms (p95), none missed; measured 4.6 / 12.6 ms (initial),
/// 3.6 / 8.5 ms (final; 5.8 / 11.2 with the parabolic toe off). Each
/// stride against the blended reference: length 2.47 %, speed 0.029 m/s
/// since the clipped heel strikes' velocity steps (2026-12-06; 2.61 % and
/// 0.034 before, test `issue_19_clipped_foot_accelerometers_keep_the_stride_length`)
/// and the speed scored on the strides paired with a reference stride
/// (0.033 on all 56 with a speed reference): the issue's 2.5 % and 0.03 m/s
/// are met. The 2.45 % / 0.032 m/s measured until 2026-12-06 came
/// from the first-order stride integration, whose bias moved with the
/// sampling rate (+0.019 m/s at 50 Hz, -0.009 at 800 Hz; the second-order
/// integration gives -0.011 at every rate, test
/// `issue_19_stride_speed_does_not_move_with_the_sampling_rate`). Compared
/// like with like (blended) 0.024 m/s and 2.09 %, within 0.03 m/s and
/// 2.5 % (docs/RESULTS.md).
#[test]
fn foot_recording_meets_the_event_targets() {
    let Some(data) = data_dir() else { return };
    let d = tempfile::tempdir().unwrap();
    let v = evaluate_json(
        "gait-events",
        &data.join("gaitmap-foot-walk/trial.csv"),
        d.path(),
    );
    for kind in ["initial_contact", "final_contact"] {
        assert!(f(&v, &[kind, "median_abs_ms"]) <= 20.0, "{v}");
        assert!(f(&v, &[kind, "p95_abs_ms"]) <= 40.0, "{v}");
        assert_eq!(f(&v, &[kind, "missed"]), 0.0, "{v}");
        assert_eq!(f(&v, &[kind, "n_reference"]), 56.0, "{v}");
    }
    // No extra event (until 2026-12-05 one final contact: the turning step
    // at 16.2 s, test `a_turning_step_toe_off_is_its_push_off_not_its_loading`).
    assert_eq!(f(&v, &["initial_contact", "extra"]), 0.0, "{v}");
    assert_eq!(f(&v, &["final_contact", "extra"]), 0.0, "{v}");
    // Per stride on the strides paired with a reference stride (53; the
    // speed was scored on 56 until 2026-12-06, three of them strides the
    // reference does not list, among them the turn's left stride against
    // the right foot's speed: 0.033 m/s then), as the length always was.
    assert!(f(&v, &["speed_mae_mps"]) <= 0.03, "{v}");
    assert_eq!(f(&v, &["n_strides"]), f(&v, &["n_lengths"]), "{v}");
    assert!(f(&v, &["stride_length_error_pct"]) <= 2.5, "{v}");
    // Like with like (the estimate blended as speed_ref is): measured
    // 0.023 m/s and 2.03 % (0.024 and 2.09 before the clipped impacts'
    // steps), the issue's targets 0.03 m/s and 2.5 %.
    assert!(f(&v, &["blended", "speed_mae_mps"]) <= 0.03, "{v}");
    assert!(f(&v, &["blended", "stride_length_error_pct"]) <= 2.5, "{v}");
    assert!(f(&v, &["blended", "n_strides"]) >= 50.0, "{v}");
    assert!(f(&v, &["n_strides"]) >= 50.0, "{v}");
    assert!(f(&v, &["phase_accuracy_pct"]) > 90.0, "{v}");
}

/// Issue 19, final contacts at the sample rates of commercial foot sensors:
/// the shared walk resampled to 50 and 60 Hz (`limbfuse resample`, default
/// anti-alias filter). The parabola through the push-off extremum and its
/// neighbours put the toe off 25.6 / 33.4 ms (50 Hz) and 21.9 / 31.9 ms
/// (60 Hz) from the reference, early (the sharp corner of the trough,
/// rounded by the filter, has its minimum on the push-off side); the corner
/// of the push-off and release lines gives 11.6 / 21.1 and 10.3 / 18.2 ms.
/// Initial contacts unchanged (4.1 / 14.6 and 5.9 / 14.1 ms).
#[test]
fn issue_19_final_contacts_at_50_hz() {
    let Some(data) = data_dir() else { return };
    let d = tempfile::tempdir().unwrap();
    let trial = data.join("gaitmap-foot-walk/trial.csv");
    for rate in ["50", "60"] {
        let file = format!("gm-{rate}.csv");
        succeed(
            &[
                "resample",
                trial.to_str().unwrap(),
                "--rate",
                rate,
                "-o",
                &file,
            ],
            d.path(),
        );
        let v = evaluate_json("gait-events", &d.path().join(&file), d.path());
        for kind in ["initial_contact", "final_contact"] {
            assert!(f(&v, &[kind, "median_abs_ms"]) <= 20.0, "{rate} Hz: {v}");
            assert!(f(&v, &[kind, "p95_abs_ms"]) <= 40.0, "{rate} Hz: {v}");
            assert_eq!(f(&v, &[kind, "missed"]), 0.0, "{rate} Hz: {v}");
            assert_eq!(f(&v, &[kind, "n_reference"]), 56.0, "{rate} Hz: {v}");
        }
        // No extra (one, the turning step at 16.2 s, until 2026-12-05).
        assert_eq!(f(&v, &["final_contact", "extra"]), 0.0, "{rate} Hz: {v}");
    }
}

/// The foot's stride integration is second order (2026-12-06): on the
/// independent simulator's three walks (CoM speed as the reference) the
/// stride speed bias is 0.005 / 0.005 / -0.001 m/s at 100 Hz and 0.005 /
/// 0.007 / 0.001 at 50 Hz (`limbfuse resample`), MAE 0.006-0.017 at both.
/// The first-order rectangle rule before it read every stride long by a
/// bias that doubled with the sampling period: 0.021 / 0.023 / 0.020 m/s
/// at 100 Hz, 0.037 / 0.042 / 0.041 at 50 Hz.
#[test]
fn issue_19_stride_speed_does_not_move_with_the_sampling_rate() {
    let Some(data) = data_dir() else { return };
    let d = tempfile::tempdir().unwrap();
    for walk in ["walk-v0.7-s300", "walk-v1.2-s301", "walk-v1.6-s302"] {
        let trial = data.join(format!("independent-sim/{walk}.csv"));
        let mut biases = Vec::new();
        for rate in ["100", "50"] {
            let file = format!("{walk}-{rate}.csv");
            let t = trial.to_str().unwrap();
            succeed(&["resample", t, "--rate", rate, "-o", &file], d.path());
            let v = evaluate_json("gait-events", &d.path().join(&file), d.path());
            let bias = f(&v, &["speed_bias_mps"]);
            assert!(bias.abs() <= 0.01, "{walk} at {rate} Hz: {v}");
            assert!(
                f(&v, &["speed_mae_mps"]) <= 0.02,
                "{walk} at {rate} Hz: {v}"
            );
            biases.push(bias);
        }
        assert!((biases[0] - biases[1]).abs() <= 0.005, "{walk}: {biases:?}");
    }
}

fn write(dir: &Path, name: &str, header: &str, row: impl Fn(usize) -> String, n: usize) {
    let mut s = format!("# sample_rate_hz: 100\n{header}\n");
    for k in 0..n {
        s += &format!("{},{}\n", k as f64 / 100.0, row(k));
    }
    std::fs::write(dir.join(name), s).unwrap();
}

#[test]
fn no_foot_or_shank_imu_is_a_clear_error() {
    let d = tempfile::tempdir().unwrap();
    write(
        d.path(),
        "back.csv",
        "t,trunk_acc_x,trunk_acc_y,trunk_acc_z,trunk_gyr_x,trunk_gyr_y,trunk_gyr_z",
        |_| "9.81,0,0,0,0,0".into(),
        50,
    );
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "gait-events",
            "back.csv",
            "-o",
            "e.csv",
        ],
        d.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    let msg = String::from_utf8_lossy(&o.stderr);
    assert!(
        msg.contains("foot_acc_x/y/z")
            && msg.contains("shank_gyr_x/y/z")
            && msg.contains("gait-events"),
        "{msg}"
    );
    assert!(!d.path().join("e.csv").exists());
    // A shank-only trial with `leg_imu = "foot"`: refused, naming the setting.
    write(
        d.path(),
        "shank.csv",
        "t,shank_acc_x,shank_acc_y,shank_acc_z,shank_gyr_x,shank_gyr_y,shank_gyr_z",
        |_| "0,9.81,0,0,0,0".into(),
        50,
    );
    std::fs::write(d.path().join("foot.toml"), "leg_imu = \"foot\"\n").unwrap();
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "gait-events",
            "--params",
            "foot.toml",
            "shank.csv",
            "-o",
            "e.csv",
        ],
        d.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    let msg = String::from_utf8_lossy(&o.stderr);
    assert!(msg.contains("leg_imu = \"foot\""), "{msg}");
    assert!(!d.path().join("e.csv").exists());
}

/// The `diag_<name>` values of an estimate file.
pub(crate) fn diag_values(path: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == format!("diag_{name}"))
        .unwrap_or_else(|| panic!("no diag_{name} in {}", path.display()));
    lines
        .filter_map(|l| l.split(',').nth(col).and_then(|v| v.parse().ok()))
        .collect()
}

/// Issue 19 item 3, shank IMUs, on the shared gaittoolbox walk (right leg:
/// foot and shank IMUs, 100 Hz, no event reference): the shank's events
/// against the foot IMU's (whose landmarks are within 5 ms of motion capture
/// on the gaitmap recording). Measured: initial contacts (zero crossing)
/// -5 to +7 ms from the foot's, with the literature's valley +51 to +62 ms;
/// toe offs +20 to +41 ms (valley before mid-swing). Every foot event paired.
#[test]
fn issue_19_shank_events_agree_with_the_foot_imu() {
    let Some(data) = data_dir() else { return };
    let gtb = data.join("gaittoolbox-s02-walk");
    if !gtb.is_dir() {
        println!("skipping: gaittoolbox-s02-walk not found");
        return;
    }
    let d = tempfile::tempdir().unwrap();
    let o = limbfuse(
        &[
            "import",
            "--format",
            "gaittoolbox",
            gtb.to_str().unwrap(),
            "-o",
            "t.csv",
            "-q",
        ],
        d.path(),
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let run = |name: &str, params: &str| -> (Vec<f64>, Vec<f64>) {
        std::fs::write(d.path().join("p.toml"), params).unwrap();
        let out = format!("{name}.csv");
        let o = limbfuse(
            &[
                "estimate",
                "--method",
                "gait-events",
                "--params",
                "p.toml",
                "t.csv",
                "-o",
                &out,
            ],
            d.path(),
        );
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        let p = d.path().join(&out);
        (diag_values(&p, "ic_right"), diag_values(&p, "fc_right"))
    };
    let (foot_ic, foot_fc) = run("foot", "leg_imu = \"foot\"\n");
    let (shank_ic, shank_fc) = run("shank", "leg_imu = \"shank\"\n");
    let (valley_ic, _) = run(
        "valley",
        "leg_imu = \"shank\"\nshank_contact = \"valley\"\n",
    );
    assert!(
        foot_ic.len() >= 4 && foot_fc.len() >= 4,
        "{foot_ic:?} {foot_fc:?}"
    );
    // Signed offset of the nearest shank event for each foot event.
    let offsets = |foot: &[f64], shank: &[f64]| -> Vec<f64> {
        foot.iter()
            .map(|&f| {
                shank
                    .iter()
                    .map(|&s| s - f)
                    .min_by(|a, b| a.abs().total_cmp(&b.abs()))
                    .unwrap()
            })
            .collect()
    };
    let ic = offsets(&foot_ic, &shank_ic);
    let valley = offsets(&foot_ic, &valley_ic);
    let fc = offsets(&foot_fc, &shank_fc);
    println!("IC zero crossing {ic:?}\nIC valley {valley:?}\nFC {fc:?}");
    assert!(ic.iter().all(|x| x.abs() <= 0.01), "{ic:?}");
    assert!(
        valley.iter().all(|x| (0.045..=0.07).contains(x)),
        "{valley:?}"
    );
    assert!(fc.iter().all(|x| (0.0..=0.05).contains(x)), "{fc:?}");
}

#[test]
fn standing_still_is_no_gait_found() {
    let d = tempfile::tempdir().unwrap();
    // Five seconds of quiet standing: both feet and the lower back still.
    let still = |k: usize| {
        let n = 0.001 * ((k * 7919) % 13) as f64;
        format!("0,{},9.81,0.01,{n},-0.002", 0.02 + n)
    };
    write(
        d.path(),
        "stand.csv",
        "t,foot_gyr_x,foot_gyr_y,foot_gyr_z,foot_acc_x,foot_acc_y,foot_acc_z",
        still,
        500,
    );
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "gait-events",
            "stand.csv",
            "-o",
            "e.csv",
        ],
        d.path(),
    );
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(String::from_utf8_lossy(&o.stderr).contains("no gait found"));
    assert!(!d.path().join("e.csv").exists());
    write(
        d.path(),
        "back.csv",
        "t,trunk_acc_x,trunk_acc_y,trunk_acc_z",
        |k| format!("9.6,{},0.3", 0.001 * ((k * 31) % 7) as f64),
        500,
    );
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "lowback-speed",
            "back.csv",
            "-o",
            "e.csv",
        ],
        d.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no gait found"));
}

/// Issue 19 (invariance audit): a one-foot recording that carries both
/// feet's contact references (the gaitmap walk with the right shoe's
/// columns removed) counted the unmeasured right foot's 29 initial
/// contacts as missed (27 of 56 found). A foot with no IMU in the trial and
/// nothing in the estimate is not scored now: 27 of 27, as on the full walk.
#[test]
fn issue_19_one_foot_recording_scores_only_that_foot() {
    let Some(data) = data_dir() else { return };
    let d = tempfile::tempdir().unwrap();
    let src = std::fs::read_to_string(data.join("gaitmap-foot-walk/trial.csv")).unwrap();
    let mut keep: Vec<usize> = Vec::new();
    let mut out = String::new();
    for line in src.lines() {
        if line.starts_with('#') {
            out += line;
        } else {
            let cells: Vec<&str> = line.split(',').collect();
            if keep.is_empty() {
                keep = (0..cells.len())
                    .filter(|&i| {
                        !cells[i].starts_with("foot_") || cells[i].starts_with("foot_left_")
                    })
                    .collect();
            }
            out += &keep.iter().map(|&i| cells[i]).collect::<Vec<_>>().join(",");
        }
        out += "\n";
    }
    let path = d.path().join("left-shoe.csv");
    std::fs::write(&path, out).unwrap();
    let v = evaluate_json("gait-events", &path, d.path());
    for kind in ["initial_contact", "final_contact"] {
        assert_eq!(f(&v, &[kind, "missed"]), 0.0, "{v}");
        assert_eq!(f(&v, &[kind, "n_reference"]), 27.0, "{v}");
    }
}

/// An audit: `estimate --method gait-events --diagnostics none` changed
/// `evaluate`'s scores without a word (14 strides became 0, the events
/// moved to the causal contact switches); evaluate now says so.
#[test]
fn an_estimate_without_its_event_diagnostics_is_scored_with_a_warning() {
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    let run = |args: &[&str]| crate::support::limbfuse(args, d);
    assert!(run(&[
        "simulate",
        "walking",
        "--gait-reference",
        "--duration",
        "20",
        "-o",
        "g.csv"
    ])
    .status
    .success());
    assert!(run(&[
        "estimate",
        "--method",
        "gait-events",
        "--diagnostics",
        "none",
        "g.csv",
        "-o",
        "n.csv"
    ])
    .status
    .success());
    assert!(run(&[
        "estimate",
        "--method",
        "gait-events",
        "g.csv",
        "-o",
        "a.csv"
    ])
    .status
    .success());
    let o = run(&["evaluate", "g.csv", "n.csv", "--json"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && e.contains("no `diag_ic_*` / `diag_fc_*` / `diag_stride_*` columns"),
        "{e}"
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["warnings"][0]
        .as_str()
        .unwrap()
        .contains("strides not at all"));
    let o = run(&["evaluate", "g.csv", "a.csv"]);
    assert!(!String::from_utf8_lossy(&o.stderr).contains("diag_ic_"));
}

/// Twenty-seventh session: a walk on which `shoe_gamma = 1e12` (the
/// zero-velocity threshold 3e7 times its default) finds no gait blamed the
/// recording alone ("the recording has no walking, or the IMU is not where
/// the method expects it"); the message now names the parameter file and
/// how to get the defaults.
#[test]
fn no_gait_found_names_the_parameter_file() {
    let d = tempfile::tempdir().unwrap();
    succeed(
        &[
            "simulate",
            "walking",
            "--duration",
            "8",
            "--seed",
            "2",
            "-o",
            "w.csv",
        ],
        d.path(),
    );
    succeed(
        &[
            "estimate",
            "--method",
            "gait-events",
            "w.csv",
            "-o",
            "e.csv",
        ],
        d.path(),
    );
    std::fs::write(d.path().join("g.toml"), "shoe_gamma = 1e12\n").unwrap();
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "gait-events",
            "w.csv",
            "--params",
            "g.toml",
            "-o",
            "e2.csv",
        ],
        d.path(),
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("no gait found"), "{err}");
    assert!(
        err.contains("--params g.toml") && err.contains("limbfuse params gait-events"),
        "{err}"
    );
}
