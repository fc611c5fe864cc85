//! The one error type of the method layer: resolving a method's settings
//! (name, parameter file, flags) and building it for a trial.

use std::path::PathBuf;

use limbfuse_estimators::knee_selfalign::KneeParamError;
use limbfuse_estimators::segment_kf::ParamError;
use limbfuse_io::gait_library::LibraryFileError;

use crate::fes_params::FesBuildError;
use crate::name::UnknownMethod;
use crate::segment_params::ParamsFileError;
use crate::MethodName;

/// Why a method could not be configured or built.
#[derive(Debug, thiserror::Error)]
pub enum MethodError {
    /// The name is not a method.
    #[error(transparent)]
    Unknown(#[from] UnknownMethod),
    /// The parameter file cannot be read, is not valid, or has a key that
    /// does not belong to the method (file, line, column, key).
    #[error(transparent)]
    ParamsFile(#[from] ParamsFileError),
    /// A command-line flag that the method does not take.
    #[error("{flags} apply to method {owner} only, not to `{method}`")]
    FlagNotForMethod {
        /// The flags, as typed.
        flags: &'static str,
        /// The method they belong to.
        owner: MethodName,
        /// The method being configured.
        method: MethodName,
    },
    /// A flag's value is not one of the accepted ones.
    #[error("{flag}: expected {expected}, found `{found}`")]
    BadFlagValue {
        /// The flag.
        flag: &'static str,
        /// The accepted values.
        expected: &'static str,
        /// What was given.
        found: String,
    },
    /// A setting the method cannot run without.
    #[error("method `{method}` needs {what}")]
    Missing {
        /// The method.
        method: MethodName,
        /// What is missing and how to get it.
        what: &'static str,
    },
    /// A segment-filter parameter out of range.
    #[error(transparent)]
    SegmentParams(#[from] ParamError),
    /// A knee-selfalign setting out of range.
    #[error("method `{method}`: {source}{}", window_hint(source.name))]
    KneeParams {
        /// The method (`knee-selfalign` or `knee-gyro-axis`).
        method: crate::MethodName,
        /// The setting out of range.
        source: KneeParamError,
    },
    /// The knee methods' identification window cannot be resolved (both
    /// file keys, a duration out of range, a trial rate that is not one).
    #[error("method `{method}`: {message}")]
    KneeWindow {
        /// The method.
        method: MethodName,
        /// What is wrong (names the key and what was expected).
        message: String,
    },
    /// An imm-bslip setting out of range.
    #[error("method `imm-bslip`: {0}")]
    ImmParams(String),
    /// A `gait-events` or `lowback-speed` setting out of range (from the
    /// trial's metadata; a parameter file's value is a
    /// [`ParamsFileError::Invalid`] naming the file).
    #[error("method `{method}`: {message}")]
    GaitParams {
        /// The method's name.
        method: &'static str,
        /// What is wrong (names the key and what was expected).
        message: String,
    },
    /// The gait library file cannot be used.
    #[error(transparent)]
    Library(#[from] LibraryFileError),
    /// `rescale_height` is not a positive height.
    #[error("--rescale-height {0}: expected a positive height in metres")]
    RescaleHeight(f64),
    /// The paper-004 estimator cannot be built for this trial.
    #[error("cannot run `{method}`: {source}")]
    Fes {
        /// The method.
        method: MethodName,
        /// Why.
        source: FesBuildError,
    },
    /// A sensor range in the trial metadata that is not a positive number.
    #[error("trial metadata `# {key}: {found}`: expected the sensor's full-scale range as a positive number")]
    SensorRange {
        /// The metadata key.
        key: &'static str,
        /// Its value.
        found: String,
    },
    /// The trial lacks columns the method needs.
    #[error("method `{method}` {why}, but the trial has no {} column(s){hint}", missing.join(", "))]
    MissingChannels {
        /// The method.
        method: &'static str,
        /// What the method does with them.
        why: &'static str,
        /// The missing column groups.
        missing: Vec<String>,
        /// What to do instead ("" or "; use ...").
        hint: &'static str,
    },
    /// The `chain` method cannot be built for this trial (its geometry).
    #[error("method `chain`: {0}")]
    Chain(String),
    /// `--smooth` asked of a method without an offline smoother.
    #[error("method `{0}` has no offline smoother (`--smooth` applies to `chain`)")]
    NoSmoother(&'static str),
    /// `--backfill` asked of a method without a first identification window.
    #[error("method `{0}` has nothing to backfill (`--backfill` applies to `knee-selfalign` and `knee-gyro-axis`)")]
    NoBackfill(&'static str),
    /// A trial metadata entry the method reads is not valid.
    #[error("{0}")]
    Metadata(String),
    /// A library path in a parameter file that is not valid UTF-8 or empty.
    #[error("{}: `library` must name a gait library file", .0.display())]
    BadLibraryPath(PathBuf),
}

/// What `--window` and `--order` count, after an error about them only (an
/// audit: it followed every knee setting's error).
fn window_hint(name: &str) -> &'static str {
    match name {
        "window" | "order" => " (--window counts samples: 20 to 100000; --order: 1 to 100)",
        _ => "",
    }
}

/// `v` as an error message shows it: as Rust prints it, but a huge or tiny
/// magnitude in exponent form (`1e300`, not 301 digits).
pub fn shown(v: f64) -> String {
    limbfuse_core::ShownNumber(v).to_string()
}

#[cfg(test)]
mod tests {
    /// Huge and tiny magnitudes in exponent form, the rest as Rust prints.
    #[test]
    fn shown_numbers_stay_short() {
        assert_eq!(super::shown(1e300), "1e300");
        assert_eq!(super::shown(-2.5e-7), "-2.5e-7");
        assert_eq!(super::shown(0.964), "0.964");
        assert_eq!(super::shown(5000.0), "5000");
        assert_eq!(super::shown(0.0), "0");
    }
}
