//! The registry of estimation methods selectable with `--method`.

use std::path::Path;

use anyhow::{bail, Result};
use limbfuse_core::{Estimator, Joint, Segment};
use limbfuse_estimators::baseline::{AccelInclination, GyroIntegration};
use limbfuse_estimators::knee_selfalign::{KneeSelfAlign, KneeSelfAlignParams};
use limbfuse_eval::params_file::{load_params, FilterMethod, FilterParams, Preset};
use limbfuse_io::TrialLayout;

/// Methods available now, with a one-line description.
pub const AVAILABLE: &[(&str, &str)] = &[
    (
        "gyro-integration",
        "baseline: trapezoidal integration of each aligned gyro's z rate",
    ),
    (
        "accel-inclination",
        "baseline: theta = atan2(acc_x, acc_y) per segment",
    ),
    (
        "local",
        "papers 000/001: per-segment error-state KFs (matricial local)",
    ),
    (
        "mjls",
        "papers 000/001: Markov-jump KF, 4 IMUs + 3 encoders",
    ),
    (
        "global",
        "paper 001: matricial global KF, 4 IMUs + relative rows + encoders",
    ),
    (
        "knee-selfalign",
        "paper 002: knee angle from raw thigh + shank IMUs, self-identified joint axis and position",
    ),
    (
        "sdre",
        "paper 004: SDRE estimator on the trial's model (knee-fes or fixed-hip metadata)",
    ),
    (
        "ekf",
        "paper 004: extended Kalman(-Bucy) filter on the trial's model",
    ),
    (
        "rmx",
        "paper 004: knee from the relative orientation of thigh and shank IMUs",
    ),
    (
        "imm-bslip",
        "paper 003: gait phase and speed from CoM measurements, IMM over a B-SLIP gait library (--library)",
    ),
];

/// Methods built from the trial itself (model metadata, channels): `estimate` builds them
/// through `commands::fes`.
pub const FROM_TRIAL: &[&str] = &["sdre", "ekf", "rmx"];

/// Methods named by SPEC section 4 that later issues add.
pub const PLANNED: &[&str] = &[];

/// Segment-angle methods `limbfuse demo` runs.
pub const DEMO: &[&str] = &[
    "gyro-integration",
    "accel-inclination",
    "local",
    "mjls",
    "global",
];

/// Builds the estimator named `name`.
pub fn build(name: &str, params: Option<&std::path::Path>) -> Result<Box<dyn Estimator>> {
    let est: Box<dyn Estimator> = match name {
        "gyro-integration" => Box::new(GyroIntegration::new()),
        "accel-inclination" => Box::new(AccelInclination::new()),
        "local" | "mjls" | "global" => return segment_filter(name, params),
        "knee-selfalign" => return knee_selfalign(&KneeOptions::default(), params),
        "sdre" | "ekf" | "rmx" => bail!(
            "method `{name}` is built from a trial's model metadata; use `limbfuse estimate --method {name} TRIAL`"
        ),
        "imm-bslip" => bail!("method `imm-bslip` needs a trial and --library (use `limbfuse estimate --method imm-bslip --library LIB.json TRIAL -o OUT`)"),
        other if PLANNED.contains(&other) => bail!(
            "method `{other}` is specified but not implemented yet in this version of limbfuse; available methods: {}",
            names()
        ),
        other => bail!("unknown method `{other}`; available methods: {}", names()),
    };
    if let Some(p) = params {
        bail!(
            "--params {}: method `{name}` has no tunable parameters",
            p.display()
        );
    }
    Ok(est)
}

/// Checks that a trial carries the channels `method` needs before any sample
/// is read: the segment filters (`local`, `mjls`, `global`) estimate all four
/// segments from their accelerometers and gyros, and `mjls` also needs the
/// three encoders (000 eq 17). Other methods check their own inputs.
pub fn check_trial_channels(method: &str, layout: &TrialLayout, trial: &Path) -> Result<()> {
    if FilterMethod::from_name(method).is_none() {
        return Ok(());
    }
    let mut missing = Vec::new();
    for s in Segment::ALL {
        let i = s.index();
        if !layout.acc[i] {
            missing.push(format!("{}_acc_x/y/z", s.name()));
        }
        if !layout.gyr[i] {
            missing.push(format!("{}_gyr_x/y/z", s.name()));
        }
    }
    if !missing.is_empty() {
        bail!(
            "{}: method `{method}` estimates all four segments from their IMUs, but the trial has no {} column(s)",
            trial.display(),
            missing.join(", ")
        );
    }
    let no_enc: Vec<String> = Joint::ALL
        .iter()
        .filter(|j| !layout.encoder[j.index()])
        .map(|j| format!("{}_enc", j.name()))
        .collect();
    if method == "mjls" && !no_enc.is_empty() {
        bail!(
            "{}: method `mjls` needs the joint encoders (its output rows are the most reliable accelerometer plus hip, knee and ankle encoders), but the trial has no {} column(s); use `local` or `global` on trials without encoders",
            trial.display(),
            no_enc.join(", ")
        );
    }
    Ok(())
}

/// A segment filter (`local`, `mjls`, `global`) with the default preset, or
/// with a parameter file (`--params`, `limbfuse_eval::params_file`).
fn segment_filter(name: &str, params: Option<&std::path::Path>) -> Result<Box<dyn Estimator>> {
    let Some(method) = FilterMethod::from_name(name) else {
        bail!("unknown segment filter `{name}`");
    };
    let p = match params {
        Some(path) => load_params(path, method)?,
        None => FilterParams::preset(method, Preset::Default),
    };
    Ok(p.build()?)
}

/// Flags of `knee-selfalign` (`--window`, `--order`); `None` = paper default.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct KneeOptions {
    /// Window length `s_w` (samples).
    pub window: Option<usize>,
    /// Iterations of the parameter EKF per window.
    pub order: Option<usize>,
}

/// The self-aligning knee estimator (paper 002) with its defaults overridden
/// by the flags; validated here, once.
pub fn knee_selfalign(
    opts: &KneeOptions,
    params: Option<&std::path::Path>,
) -> Result<Box<dyn Estimator>> {
    if let Some(p) = params {
        bail!(
            "--params {}: method `knee-selfalign` takes --window and --order, not a parameter file",
            p.display()
        );
    }
    let d = KneeSelfAlignParams::default();
    let p = KneeSelfAlignParams {
        window: opts.window.unwrap_or(d.window),
        order: opts.order.unwrap_or(d.order),
        ..d
    };
    let est = KneeSelfAlign::new(p).map_err(|e| {
        anyhow::anyhow!("{e} (--window counts samples: 20 to 100000; --order: 1 to 100)")
    })?;
    Ok(Box::new(est))
}

fn names() -> String {
    AVAILABLE
        .iter()
        .map(|(n, _)| *n)
        .collect::<Vec<_>>()
        .join(", ")
}
