//! [`build`]: a resolved method and a trial's metadata and columns in, a
//! running estimator out. Never reads a file.

use limbfuse_core::Estimator;
use limbfuse_estimators::baseline::{AccelInclination, GyroIntegration};
use limbfuse_io::{TrialLayout, TrialMeta};

use crate::fes_params::build_fes_estimator;
use crate::imm_params::build_imm;
use crate::knee_params::build_knee;
use crate::{MethodError, MethodName, MethodSpec};

/// Why a method needs its columns, and what to use instead.
const fn column_use(method: MethodName) -> (&'static str, &'static str) {
    match method {
        MethodName::Mjls => (
            "needs the four IMUs and the joint encoders (its output rows are the most reliable accelerometer plus hip, knee and ankle encoders)",
            "; use `local` or `global` on trials without encoders",
        ),
        MethodName::Local | MethodName::Global => (
            "estimates all four segments from their IMUs",
            "",
        ),
        MethodName::KneeSelfAlign => (
            "needs the thigh and shank accelerometers and gyroscopes (the knee axis and angle come from both)",
            "",
        ),
        MethodName::Rmx | MethodName::Sdre | MethodName::Ekf => {
            ("needs the IMUs its model measures", "")
        }
        MethodName::ImmBslip => ("needs CoM measurement columns", ""),
        MethodName::GyroIntegration | MethodName::AccelInclination => ("", ""),
    }
}

/// Checks the trial's columns against [`MethodName::required_channels`].
pub fn check_channels(method: MethodName, layout: &TrialLayout) -> Result<(), MethodError> {
    let missing = method.required_channels().missing(layout);
    if missing.is_empty() {
        return Ok(());
    }
    let (why, hint) = column_use(method);
    Err(MethodError::MissingChannels {
        method,
        why,
        missing,
        hint,
    })
}

/// A new estimator of `spec` for a trial with this metadata and these
/// columns. Model errors (paper 004: the trial's `# model:`) come first,
/// then missing columns.
pub fn build(
    spec: &MethodSpec,
    meta: &TrialMeta,
    layout: &TrialLayout,
) -> Result<Box<dyn Estimator + Send>, MethodError> {
    let est: Box<dyn Estimator + Send> = match spec {
        MethodSpec::GyroIntegration => Box::new(GyroIntegration::new()),
        MethodSpec::AccelInclination => Box::new(AccelInclination::new()),
        MethodSpec::SegmentFilter(p) => p.build()?,
        MethodSpec::KneeSelfAlign(p) => Box::new(build_knee(p)?),
        MethodSpec::Fes(m, file) => {
            build_fes_estimator(*m, meta, layout, file).map_err(|source| MethodError::Fes {
                method: m.method(),
                source,
            })?
        }
        MethodSpec::ImmBslip(s) => Box::new(build_imm(s, layout)?),
    };
    check_channels(spec.method(), layout)?;
    Ok(est)
}
