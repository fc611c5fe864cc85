//! The gait a simulated B-SLIP trial walks on (`limbfuse simulate bslip`,
//! Python `simulate("bslip")`, paper 003): a gait library's gait at the
//! asked speed, or one searched for now for a given body.

use std::path::{Path, PathBuf};

use limbfuse_methods::MethodError;
use limbfuse_models::bslip::{BslipParams, GaitTemplate};
use limbfuse_sim::bslip::library::build_library;
use limbfuse_sim::bslip::search::{SearchError, SearchSettings};

/// Fastest gait speed searched or simulated (m/s): B-SLIP walking beyond it
/// runs into Froude numbers where walking gives way to running.
pub const MAX_GAIT_SPEED: f64 = 2.0;

/// Where the gait comes from.
#[derive(Debug, Clone, Copy)]
pub enum GaitSource<'a> {
    /// A gait-library file: its gait at the speed (within 1e-6 m/s).
    Library(&'a Path),
    /// A periodic gait searched now for this body (`SearchSettings::default()`).
    Search(&'a BslipParams),
}

/// Why no gait was found.
#[derive(Debug, thiserror::Error)]
pub enum BslipGaitError {
    /// The speed is not a walking speed.
    #[error("expected a walking speed in (0, {MAX_GAIT_SPEED}] m/s, found {0}")]
    Speed(f64),
    /// The library could not be read.
    #[error(transparent)]
    Library(#[from] MethodError),
    /// The library has no gait at the speed.
    #[error("{}: no gait at {speed} m/s", path.display())]
    NotInLibrary {
        /// The library file.
        path: PathBuf,
        /// The speed asked for (m/s).
        speed: f64,
    },
    /// The search found no periodic gait.
    #[error("no periodic B-SLIP gait found at {speed} m/s for a {mass} kg body with {leg_length} m legs: {source}")]
    Search {
        /// The speed asked for (m/s).
        speed: f64,
        /// Body mass (kg).
        mass: f64,
        /// Leg rest length (m).
        leg_length: f64,
        /// The search's error.
        source: SearchError,
    },
}

/// The gait at `speed` (m/s) from `source`.
pub fn bslip_gait(speed: f64, source: GaitSource<'_>) -> Result<GaitTemplate, BslipGaitError> {
    bslip_gait_with(speed, source, &SearchSettings::default())
}

/// [`bslip_gait`], a searched gait searched with `settings` (Python's
/// `simulate("bslip")` hands in its Ctrl-C hook, `SearchSettings::cancel`).
pub fn bslip_gait_with(
    speed: f64,
    source: GaitSource<'_>,
    settings: &SearchSettings,
) -> Result<GaitTemplate, BslipGaitError> {
    if !(speed.is_finite() && speed > 0.0 && speed <= MAX_GAIT_SPEED) {
        return Err(BslipGaitError::Speed(speed));
    }
    match source {
        GaitSource::Library(path) => limbfuse_methods::imm_params::load_templates(path, None)?
            .into_iter()
            .find(|g| (g.speed - speed).abs() < 1e-6)
            .ok_or_else(|| BslipGaitError::NotInLibrary {
                path: path.to_path_buf(),
                speed,
            }),
        GaitSource::Search(body) => {
            let lib = build_library(body, &[speed], settings, |_, _| {}).map_err(|source| {
                BslipGaitError::Search {
                    speed,
                    mass: body.mass,
                    leg_length: body.rest_length,
                    source,
                }
            })?;
            Ok(lib[0].template(body))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_speed_outside_walking_is_refused_before_any_search() {
        let body = BslipParams::default();
        for s in [0.0, -0.5, 2.5, f64::NAN] {
            assert!(matches!(
                bslip_gait(s, GaitSource::Search(&body)),
                Err(BslipGaitError::Speed(_))
            ));
        }
    }

    #[test]
    fn a_missing_library_names_its_file() {
        let e = bslip_gait(0.7, GaitSource::Library(Path::new("/nonexistent/lib.json")))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/nonexistent/lib.json"), "{e}");
    }
}
