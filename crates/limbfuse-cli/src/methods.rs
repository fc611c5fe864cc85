//! The registry of estimation methods selectable with `--method`.

use anyhow::{bail, Result};
use limbfuse_core::Estimator;
use limbfuse_estimators::baseline::{AccelInclination, GyroIntegration};
use limbfuse_eval::params_file::{load_params, FilterMethod, FilterParams, Preset};

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
        "imm-bslip",
        "paper 003: gait phase and speed from CoM measurements, IMM over a B-SLIP gait library (--library)",
    ),
];

/// Methods named by SPEC section 4 that later issues add.
pub const PLANNED: &[&str] = &["knee-selfalign", "sdre", "ekf", "rmx"];

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

fn names() -> String {
    AVAILABLE
        .iter()
        .map(|(n, _)| *n)
        .collect::<Vec<_>>()
        .join(", ")
}
