//! # limbfuse-report
//!
//! `limbfuse report`: one self-contained HTML file (inline SVG, inline
//! script and style, no network access) for a trial and one or more of its
//! estimates: each angle against its reference over a zoomable time window,
//! the error over the normalised gait cycle (mean +- sd), the error tables of
//! `limbfuse evaluate` (computed by `limbfuse-eval` on every sample),
//! method-specific panels and the commands that produced the files.
//! docs/REPORT.md describes each panel and the display decimation.
#![deny(missing_docs)]

pub mod data;
pub mod decimate;
mod error_section;
pub mod events_panel;
pub mod gait_cycle;
mod header;
mod page;
pub mod panels;
pub mod scoring;
pub mod strides_table;
pub mod svg;
pub mod tables;
pub mod time_base;
pub mod y_range;

use std::path::{Path, PathBuf};

use limbfuse_eval::EvalError;
use limbfuse_io::FileError;

pub use page::render;
pub use scoring::{Scoring, ScoringOption};

/// Display buckets per series by default: at most 2 x 2000 points per line
/// (docs/REPORT.md, "Decimation").
pub const DEFAULT_BUCKETS: usize = 2000;

/// What to put in the report.
#[derive(Debug, Clone)]
pub struct ReportInput {
    /// The trial file.
    pub trial: PathBuf,
    /// The estimate files (made from that trial).
    pub estimates: Vec<PathBuf>,
    /// The command that writes the report (shown in its commands section).
    pub command: String,
    /// Display buckets per series ([`decimate::min_max`]).
    pub buckets: usize,
    /// Include estimates whose header records another trial (as
    /// `evaluate --allow-trial-mismatch`).
    pub allow_trial_mismatch: bool,
    /// `evaluate`'s scoring options, applied to the error tables and the
    /// error over the gait cycle.
    pub scoring: Scoring,
    /// A cancellation hook (Python's Ctrl-C), polled between the steps
    /// (reading the trial, each estimate's evaluation and reading, the
    /// sections): once it returns true, [`render`] ends with
    /// [`ReportError::Cancelled`]. `None` (the CLI): never.
    pub cancel: Option<fn() -> bool>,
}

impl ReportInput {
    /// A report of `estimates` over `trial` with the default settings.
    pub fn new(trial: &Path, estimates: &[PathBuf], command: impl Into<String>) -> Self {
        ReportInput {
            trial: trial.to_path_buf(),
            estimates: estimates.to_vec(),
            command: command.into(),
            buckets: DEFAULT_BUCKETS,
            allow_trial_mismatch: false,
            scoring: Scoring::default(),
            cancel: None,
        }
    }
}

/// Why a report could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A file could not be read.
    #[error(transparent)]
    File(#[from] FileError),
    /// An estimate could not be evaluated against the trial.
    #[error(transparent)]
    Eval(#[from] EvalError),
    /// No estimate file was given.
    #[error("a report needs at least one estimate file")]
    NoEstimate,
    /// One estimate file given twice (an audit: two identical columns and
    /// legends, nothing said).
    #[error(
        "{second}: the same file as the estimate {first} given before it; give each estimate once"
    )]
    RepeatedEstimate {
        /// The first time it was given.
        first: String,
        /// The repeat.
        second: String,
    },
    /// Scoring options given where no estimate of the report is scored
    /// in a way they apply to (as `evaluate` refuses them).
    #[error("{}: {} {why}", options.iter().map(|o| o.flag()).collect::<Vec<_>>().join(", "), if options.len() == 1 { "applies" } else { "apply" })]
    ScoringNotApplicable {
        /// The options that apply to nothing.
        options: Vec<ScoringOption>,
        /// To what they apply, and what the report scores instead.
        why: String,
    },
    /// The cancellation hook ([`ReportInput::cancel`]) stopped it.
    #[error("cancelled")]
    Cancelled,
    /// An estimate does not have its trial's number of samples.
    #[error("{estimate}: {n_estimate} samples, but the trial {trial} has {n_trial}")]
    Length {
        /// Estimate file.
        estimate: String,
        /// Its samples.
        n_estimate: usize,
        /// Trial file.
        trial: String,
        /// Its samples.
        n_trial: usize,
    },
}
