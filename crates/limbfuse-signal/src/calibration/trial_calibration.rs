//! A calibration file applied to a trial (`--calibration` of `estimate`,
//! `import`, `align --imu-calibration`; the Python `calibration=`): refused
//! for a trial calibrated already or one with an IMU the file does not
//! cover, rotated into the aligned frames of a trial `align` wrote, and the
//! notes a user should read (sensors the file calibrates that the trial
//! lacks; the rotation). One implementation for the CLI and Python, so both
//! say the same (session 45: Python said nothing).

use std::path::{Path, PathBuf};

use limbfuse_io::{Calibration, CalibrationFileError, TrialLayout, TrialMeta};

use crate::align::{rotations_from_metadata, AlignError};

/// The calibration to apply to one trial.
#[derive(Debug, Clone)]
pub struct TrialCalibration {
    /// The calibration, in the trial's frames.
    pub calibration: Calibration,
    /// The frame it acts in, for the metadata (`Calibration::annotate`).
    pub frame: &'static str,
    /// What the user should know (the CLI prints each as `note: ...`,
    /// Python gives each as a `LimbfuseWarning`).
    pub notes: Vec<String>,
}

/// Why a calibration cannot be applied to a trial.
#[derive(Debug, thiserror::Error)]
pub enum TrialCalibrationError {
    /// Calibrated already, or an IMU not covered.
    #[error(transparent)]
    File(#[from] CalibrationFileError),
    /// The trial's alignment rotations cannot be read.
    #[error("{}: reading the alignment rotations", trial.display())]
    Rotations {
        /// The trial.
        trial: PathBuf,
        /// What was wrong.
        #[source]
        source: AlignError,
    },
}

/// `cal` (read from `path`) for the trial `trial` with this metadata and
/// layout.
pub fn for_trial(
    cal: Calibration,
    path: &Path,
    trial: &Path,
    meta: &TrialMeta,
    layout: &TrialLayout,
) -> Result<TrialCalibration, TrialCalibrationError> {
    Calibration::check_not_calibrated(meta, trial)?;
    let unused = cal.check_covers(layout, path, trial)?;
    let mut notes = Vec::new();
    if !unused.is_empty() {
        let names: Vec<&str> = unused.iter().map(|s| s.name()).collect();
        notes.push(format!(
            "{} also calibrates {}, which {} does not have",
            path.display(),
            names.join(", "),
            trial.display()
        ));
    }
    let rotations =
        rotations_from_metadata(meta).map_err(|source| TrialCalibrationError::Rotations {
            trial: trial.to_path_buf(),
            source,
        })?;
    if rotations.iter().any(Option::is_some) {
        notes.push(format!(
            "{} was aligned (`<segment>_align_quat`): the raw-frame calibration is rotated into \
             the aligned frames",
            trial.display()
        ));
        return Ok(TrialCalibration {
            calibration: cal.rotated(&rotations),
            frame: "raw sensor frame, rotated with the alignment",
            notes,
        });
    }
    Ok(TrialCalibration {
        calibration: cal,
        frame: "raw sensor frame",
        notes,
    })
}
