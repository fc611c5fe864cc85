//! Typed errors for model parameters that make a model unphysical.

/// A parameter set that does not describe a physical limb.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// A parameter is NaN or infinite.
    #[error("model parameter `{name}` is not a finite number ({value})")]
    NonFinite {
        /// Parameter name.
        name: &'static str,
        /// Offending value.
        value: f64,
    },
    /// A parameter that must be strictly positive (mass, inertia, length, g) is not.
    #[error("model parameter `{name}` = {value} must be > 0 (a limb needs positive mass, inertia and lengths)")]
    NotPositive {
        /// Parameter name.
        name: &'static str,
        /// Offending value.
        value: f64,
    },
    /// A parameter is outside its physical range.
    #[error("model parameter `{name}` = {value} is outside {range}")]
    OutOfRange {
        /// Parameter name.
        name: &'static str,
        /// Offending value.
        value: f64,
        /// The accepted range, in words.
        range: &'static str,
    },
}

/// `Ok` when `value` is finite.
pub fn finite(name: &'static str, value: f64) -> Result<(), ModelError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(ModelError::NonFinite { name, value })
    }
}

/// `Ok` when `value` is finite and strictly positive.
pub fn positive(name: &'static str, value: f64) -> Result<(), ModelError> {
    finite(name, value)?;
    if value > 0.0 {
        Ok(())
    } else {
        Err(ModelError::NotPositive { name, value })
    }
}
