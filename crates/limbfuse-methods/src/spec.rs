//! [`MethodFlags`]: the method settings given on the command line.

use std::path::PathBuf;

use crate::{MethodError, MethodName};

/// Method settings given as command-line flags (`limbfuse estimate`); each
/// belongs to one method and overrides the same key of its parameter file.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MethodFlags {
    /// knee-selfalign: window length `s_w` (samples).
    pub window: Option<usize>,
    /// knee-selfalign: parameter-EKF iterations per window.
    pub order: Option<usize>,
    /// imm-bslip: gait library file.
    pub library: Option<PathBuf>,
    /// imm-bslip: eq 14 gain (1/m^2).
    pub kappa: Option<f64>,
    /// imm-bslip: CoM height to rescale every gait to (m).
    pub rescale_height: Option<f64>,
    /// imm-bslip: weight rule (`paper`, `recursive`).
    pub imm_weights: Option<String>,
    /// imm-bslip: touchdown rule (`height`, `step-clock`, `mixed`).
    pub imm_touchdown: Option<String>,
    /// imm-bslip: configuration (`paper`, `continuous`).
    pub imm_config: Option<String>,
    /// imm-bslip (continuous): extend the library to the trial's speeds
    /// (`on`, the default, or `off`).
    pub imm_extend_library: Option<String>,
    /// imm-bslip: the trial body's leg length (m), over its metadata.
    pub leg_length: Option<f64>,
    /// imm-bslip: the trial body's mass (kg), over its metadata.
    pub mass: Option<f64>,
}

impl MethodFlags {
    /// Checks that every flag given belongs to `method`.
    pub fn check_applies_to(&self, method: MethodName) -> Result<(), MethodError> {
        let knee = self.window.is_some() || self.order.is_some();
        if knee && !matches!(method, MethodName::KneeSelfAlign | MethodName::KneeGyroAxis) {
            return Err(MethodError::FlagNotForMethod {
                flags: "--window and --order",
                owners: "methods knee-selfalign and knee-gyro-axis",
                method,
            });
        }
        let imm = self.library.is_some()
            || self.kappa.is_some()
            || self.rescale_height.is_some()
            || self.imm_weights.is_some()
            || self.imm_touchdown.is_some()
            || self.imm_config.is_some()
            || self.imm_extend_library.is_some()
            || self.leg_length.is_some()
            || self.mass.is_some();
        if imm && method != MethodName::ImmBslip {
            return Err(MethodError::FlagNotForMethod {
                flags: "--library, --kappa, --rescale-height, --imm-weights, --imm-touchdown, --imm-config, --imm-extend-library, --leg-length and --mass",
                owners: "method imm-bslip",
                method,
            });
        }
        Ok(())
    }
}
