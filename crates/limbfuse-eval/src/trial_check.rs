//! Whether an estimate file was made from the trial it is evaluated against.
//!
//! `limbfuse estimate` writes the trial's file name and content hash into the
//! estimate file's header (`# trial:`, `# trial_hash:`, see
//! `limbfuse_io::content_hash`). An estimate of another trial with the same
//! time base would otherwise be evaluated silently against the wrong
//! reference; [`check_trial`] refuses it unless the caller allows it.

use std::fmt;
use std::path::Path;

use limbfuse_io::content_hash::STREAMED_HASH;
use limbfuse_io::{ContentHash, EstimateReader};

use crate::evaluation::EvalError;

/// The outcome of [`check_trial`].
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum TrialCheck {
    /// Not checked (an evaluation of an in-memory run).
    #[default]
    NotChecked,
    /// The estimate records this trial's hash.
    Matches,
    /// The estimate does not record its trial (written before limbfuse did):
    /// accepted, with a warning.
    NotRecorded {
        /// The estimate file.
        estimate: String,
    },
    /// The estimate was streamed as it was made (`# trial_hash: streamed`:
    /// its header was written before its trial had been read to the end):
    /// accepted, with a warning.
    Streamed {
        /// The estimate file.
        estimate: String,
        /// Its `# trial:` entry.
        recorded_trial: String,
    },
    /// The estimate records another trial; evaluated because the caller
    /// allowed it.
    MismatchAllowed(TrialMismatch),
}

impl TrialCheck {
    /// What to tell the user, if anything.
    pub fn warning(&self) -> Option<String> {
        match self {
            TrialCheck::NotChecked | TrialCheck::Matches => None,
            TrialCheck::NotRecorded { estimate } => Some(format!(
                "{estimate}: the estimate file does not record the trial it was made from \
                 (no `# trial_hash:` line; written by an older limbfuse), so it cannot be \
                 checked against the trial"
            )),
            TrialCheck::Streamed {
                estimate,
                recorded_trial,
            } => Some(format!(
                "{estimate}: the estimate was streamed from `{recorded_trial}` as it was made \
                 (`# trial_hash: streamed`: its header was written before the trial ended), \
                 so it cannot be checked against the trial"
            )),
            TrialCheck::MismatchAllowed(m) => Some(format!("{m} (evaluated anyway, as asked)")),
        }
    }
}

/// An estimate made from another trial than the one it is evaluated against.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TrialMismatch {
    /// The trial evaluated against.
    pub trial: String,
    /// Its content hash.
    pub trial_hash: ContentHash,
    /// The estimate file.
    pub estimate: String,
    /// The `# trial:` entry of the estimate file.
    pub recorded_trial: String,
    /// The `# trial_hash:` entry of the estimate file, as written.
    pub recorded_hash: String,
}

impl fmt::Display for TrialMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} was made from the trial `{}` ({}), but {} has the content hash {}: \
             it is another trial (or the trial file changed since)",
            self.estimate, self.recorded_trial, self.recorded_hash, self.trial, self.trial_hash
        )
    }
}

/// Compares the trial hash recorded in the estimate `er` with `trial_hash`,
/// the hash of `trial`; a mismatch is an error unless `allow_mismatch`.
pub fn check_trial(
    trial: &Path,
    trial_hash: ContentHash,
    er: &EstimateReader,
    allow_mismatch: bool,
) -> Result<TrialCheck, EvalError> {
    let estimate = er.path().display().to_string();
    let Some(recorded) = er.recorded_trial_hash() else {
        return Ok(TrialCheck::NotRecorded { estimate });
    };
    if recorded.trim() == STREAMED_HASH {
        return Ok(TrialCheck::Streamed {
            estimate,
            recorded_trial: er.recorded_trial().unwrap_or("?").to_string(),
        });
    }
    if ContentHash::parse(recorded) == Some(trial_hash) {
        return Ok(TrialCheck::Matches);
    }
    let mismatch = TrialMismatch {
        trial: trial.display().to_string(),
        trial_hash,
        estimate,
        recorded_trial: er.recorded_trial().unwrap_or("?").to_string(),
        recorded_hash: recorded.to_string(),
    };
    if allow_mismatch {
        Ok(TrialCheck::MismatchAllowed(mismatch))
    } else {
        Err(EvalError::TrialMismatch(mismatch))
    }
}
