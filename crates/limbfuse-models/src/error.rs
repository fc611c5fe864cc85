//! Typed errors for model parameters that make a model unphysical.

/// A parameter set that does not describe a physical limb.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// A parameter is NaN or infinite.
    #[error("model parameter `{name}` is not a finite number ({})", limbfuse_core::ShownNumber(*value))]
    NonFinite {
        /// Parameter name.
        name: &'static str,
        /// Offending value.
        value: f64,
    },
    /// A parameter that must be strictly positive (mass, inertia, length, g) is not.
    #[error("model parameter `{name}` = {} must be > 0 (a limb needs positive mass, inertia and lengths)", limbfuse_core::ShownNumber(*value))]
    NotPositive {
        /// Parameter name.
        name: &'static str,
        /// Offending value.
        value: f64,
    },
    /// A parameter is outside its physical range.
    #[error("model parameter `{name}` = {} is outside {range}", limbfuse_core::ShownNumber(*value))]
    OutOfRange {
        /// Parameter name.
        name: &'static str,
        /// Offending value.
        value: f64,
        /// The accepted range, in words.
        range: &'static str,
    },
}

impl ModelError {
    /// The parameter's name.
    pub fn name(&self) -> &'static str {
        match self {
            ModelError::NonFinite { name, .. }
            | ModelError::NotPositive { name, .. }
            | ModelError::OutOfRange { name, .. } => name,
        }
    }
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

/// `Ok` when `value` is within `lo..=hi`, else [`ModelError::OutOfRange`]
/// with `range` (an audit: `g = 1e300`, `mass = 1e300` were accepted and
/// froze the estimate on every sample).
pub fn within(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    range: &'static str,
) -> Result<(), ModelError> {
    finite(name, value)?;
    if (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(ModelError::OutOfRange { name, value, range })
    }
}

/// A limb's physical limits, for [`within`]: gravity (m/s^2, the
/// simulators' range around Earth's 9.78-9.83), a segment mass with what it
/// carries (kg), an inertia about a joint (kg m^2), a length (m), an angle
/// parameter (rad).
pub mod limits {
    /// Gravity (m/s^2).
    pub const G: (f64, f64, &str) = (1.0, 20.0, "[1, 20] m/s^2 (Earth's: 9.78-9.83)");
    /// A segment's mass with any load it carries (kg).
    pub const MASS: (f64, f64, &str) = (1e-3, 200.0, "(0, 200] kg (a limb segment with its load)");
    /// An inertia about a joint (kg m^2).
    pub const INERTIA: (f64, f64, &str) =
        (1e-6, 50.0, "(0, 50] kg m^2 (a limb segment with its load)");
    /// A segment length or centre-of-mass distance (m).
    pub const LENGTH: (f64, f64, &str) = (1e-3, 2.0, "(0, 2] m (a human limb segment)");
    /// An angle parameter (rad).
    pub const ANGLE: (f64, f64, &str) = (-7.0, 7.0, "[-7, 7] rad (one turn either way)");
}

/// [`within`] for one of [`limits`].
pub fn within_limit(
    name: &'static str,
    value: f64,
    (lo, hi, range): (f64, f64, &'static str),
) -> Result<(), ModelError> {
    within(name, value, lo, hi, range)
}
