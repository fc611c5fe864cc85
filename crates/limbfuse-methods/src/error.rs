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
    #[error("{flags} apply to {owners} only, not to `{method}`")]
    FlagNotForMethod {
        /// The flags, as typed.
        flags: &'static str,
        /// The methods they belong to (`method imm-bslip`, `methods
        /// knee-selfalign and knee-gyro-axis`).
        owners: &'static str,
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

/// Longest value a message echoes whole (characters): longer ones are cut
/// with `...` and their full length.
pub const MAX_ECHO_CHARS: usize = 120;

/// Longest message [`clip_echoes`] returns (characters).
const MAX_MESSAGE_CHARS: usize = 2000;

/// `message` with every value it quotes (between backticks or double
/// quotes) longer than `MAX_ECHO_CHARS` (120 characters) cut short: an array to its first
/// numbers and `... (N numbers)`, other text to its start and `... (N
/// characters)`; a message still longer than 2000 characters is cut too.
/// An audit found a 2,000,000-number `encoder_sigma` echoed as a 12 MB
/// message, a 1 MB key and a 5 MB `method` likewise.
pub fn clip_echoes(message: &str) -> String {
    let mut out = String::new();
    let mut rest = message;
    while let Some(open) = rest.find(['`', '"']) {
        let quote = rest.as_bytes()[open] as char;
        let Some(len) = rest[open + 1..].find(quote) else {
            break;
        };
        let inner = &rest[open + 1..open + 1 + len];
        out.push_str(&rest[..=open]);
        out.push_str(&clip_value(inner));
        out.push(quote);
        rest = &rest[open + len + 2..];
    }
    out.push_str(rest);
    let n = out.chars().count();
    if n > MAX_MESSAGE_CHARS {
        let cut: String = out.chars().take(MAX_MESSAGE_CHARS).collect();
        return format!("{cut}... ({n} characters)");
    }
    out
}

/// One quoted value, cut as [`clip_echoes`] says.
fn clip_value(v: &str) -> String {
    let n = v.chars().count();
    if n <= MAX_ECHO_CHARS {
        return v.to_string();
    }
    if let Some(items) = v.strip_prefix('[').and_then(|s| s.strip_suffix(']')) {
        let items: Vec<&str> = items.split(',').map(str::trim).collect();
        let numbers = items.iter().all(|s| s.parse::<f64>().is_ok());
        let head = items[..items.len().min(5)].join(", ");
        return format!(
            "[{head}, ...] ({} {})",
            items.len(),
            if numbers { "numbers" } else { "items" }
        );
    }
    let head: String = v.chars().take(MAX_ECHO_CHARS / 2).collect();
    format!("{head}... ({n} characters)")
}

#[cfg(test)]
mod tests {
    /// An audit: a 2,000,000-number array, a 1 MB key and a 5 MB method
    /// name were echoed whole (a 12 MB message). Each is cut with its
    /// full length; short values are kept.
    #[test]
    fn long_echoed_values_are_cut_with_their_length() {
        let array = format!("[{}]", vec!["0.01"; 2_000_000].join(", "));
        let m = super::clip_echoes(&format!(
            "`encoder_sigma`: expected 3 numbers, found `{array}`"
        ));
        assert_eq!(
            m,
            "`encoder_sigma`: expected 3 numbers, found `[0.01, 0.01, 0.01, 0.01, 0.01, ...] (2000000 numbers)`"
        );
        let key = "k".repeat(1_000_000);
        let m = super::clip_echoes(&format!("unknown field `{key}`, expected `a`"));
        assert!(m.starts_with("unknown field `kkk"), "{m}");
        assert!(
            m.ends_with("kkk... (1000000 characters)`, expected `a`"),
            "{m}"
        );
        assert!(m.len() < 200, "{m}");
        let name = "m".repeat(5_000_000);
        let m = super::clip_echoes(&format!("`method` = \"{name}\": unknown method `{name}`"));
        assert!(
            m.len() < 300 && m.contains("(5000000 characters)\": unknown"),
            "{m}"
        );
        let unquoted = "x".repeat(10_000);
        assert!(super::clip_echoes(&unquoted).ends_with("... (10000 characters)"));
        assert_eq!(super::clip_echoes("`a` = \"b\" `c"), "`a` = \"b\" `c");
    }

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
