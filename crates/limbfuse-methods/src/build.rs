//! [`build`]: a resolved method and a trial's metadata and columns in, a
//! running estimator out. Never reads a file.

use limbfuse_core::Estimator;
use limbfuse_io::{TrialLayout, TrialMeta};

use crate::{MethodError, MethodName, MethodSpec};

/// Checks the trial's columns against [`MethodName::required_channels`].
pub fn check_channels(method: MethodName, layout: &TrialLayout) -> Result<(), MethodError> {
    crate::channels::check_info(&method.info(), layout)
}

/// A new estimator of `spec` for a trial with this metadata and these
/// columns. The method's own errors (paper 004: the trial's `# model:`)
/// come first, then missing columns. The estimator sees its samples
/// through the trial's sensor-range gate ([`crate::gated`]).
pub fn build(
    spec: &MethodSpec,
    meta: &TrialMeta,
    layout: &TrialLayout,
) -> Result<Box<dyn Estimator + Send>, MethodError> {
    // (without the clipping test for an estimator that keeps clipped
    // gyroscope readings, `Estimator::keeps_clipped_gyro`: the gate does it)
    let ranges = crate::gated::sensor_ranges(meta)?;
    let inner = spec.build_estimator(meta, layout)?;
    Ok(Box::new(crate::gated::GatedEstimator::new(inner, ranges)))
}

/// `inner` behind the sensor-range gate of a trial with this metadata, as
/// [`build`] gives every estimator (for an estimator built another way,
/// e.g. over an extended gait family).
pub fn gate(
    inner: Box<dyn Estimator + Send>,
    meta: &TrialMeta,
) -> Result<Box<dyn Estimator + Send>, MethodError> {
    let ranges = crate::gated::sensor_ranges(meta)?;
    Ok(Box::new(crate::gated::GatedEstimator::new(inner, ranges)))
}
