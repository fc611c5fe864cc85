//! Whether a gait method found any gait (`gait-events`, `lowback-speed`):
//! a recording in which it finds none is an error for `limbfuse estimate`
//! and Python's `limbfuse.estimate`, not an empty estimate (issue 19).

use limbfuse_core::estimator::Outputs;
use limbfuse_core::runner::{self, Observer};
use limbfuse_core::{Estimate, Record};

/// Whether an estimator with these outputs is a gait method: contacts, or
/// a walking speed without a CoM model (`imm-bslip` estimates a CoM).
pub fn is_gait_method(outputs: &Outputs) -> bool {
    outputs.contact || (outputs.speed && !outputs.com)
}

/// Watches whether any estimate carried a contact state or a walking speed.
#[derive(Debug, Default)]
pub struct GaitWatch {
    /// Some estimate carried one.
    pub found: bool,
}

impl GaitWatch {
    /// Adds one estimate.
    pub fn push(&mut self, e: &Estimate) {
        self.found |= e.speed.is_some() || e.contact.iter().any(Option::is_some);
    }
}

impl Observer for GaitWatch {
    fn observe(&mut self, _record: &Record, e: &Estimate) -> Result<(), runner::BoxError> {
        self.push(e);
        Ok(())
    }
}

/// The error for `trial`, on which `method` found no gait in `n_samples`;
/// `kept` says what became of the output ("no estimate written").
pub fn no_gait_message(trial: &str, method: &str, n_samples: u64, kept: &str) -> String {
    format!(
        "no gait found in {trial}: `{method}` detected no foot contact and no walking speed in \
         {n_samples} samples (the recording has no walking, or the IMU is not where the method \
         expects it); {kept}"
    )
}
