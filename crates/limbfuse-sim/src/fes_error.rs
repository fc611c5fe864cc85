//! Errors of the FES simulators.

use limbfuse_models::ModelError;

/// Why an FES simulation could not be set up.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum FesSimError {
    /// The model parameters are unphysical.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A configuration value is outside its range.
    #[error("{name} = {} is outside the allowed range {range}", limbfuse_core::ShownNumber(*value))]
    OutOfRange {
        /// Config field name.
        name: &'static str,
        /// Offending value.
        value: f64,
        /// Allowed range, human readable.
        range: &'static str,
    },
    /// No stimulation level in [0, 1] holds the leg at any target extension.
    #[error("subject {subject}: no stimulation in [0, 1] holds the leg between 40 and 70 deg")]
    NoHoldingStimulation {
        /// Subject label.
        subject: &'static str,
    },
}

/// `Ok` when `lo <= value <= hi` and finite.
pub fn in_range(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    range: &'static str,
) -> Result<(), FesSimError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(FesSimError::OutOfRange { name, value, range })
    }
}
