//! Pairing a trial file with an estimate file and evaluating the estimate.

use std::fmt;
use std::path::Path;

use limbfuse_core::ShownNumber;
use limbfuse_io::{EstimateReader, FileError, TrialFingerprint, TrialReader};

use crate::metrics::{AngleMetrics, Evaluation};
use crate::trial_check::{check_trial, TrialMismatch};

/// A closed time interval `[start, end]` in seconds; open ends mean unbounded.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TimeWindow {
    /// First time included (s).
    pub start: Option<f64>,
    /// Last time included (s).
    pub end: Option<f64>,
}

impl TimeWindow {
    /// Whether `t` lies inside the window.
    pub fn contains(&self, t: f64) -> bool {
        self.start.is_none_or(|s| t >= s) && self.end.is_none_or(|e| t <= e)
    }

    /// Parses `START:END` (seconds; either side may be empty).
    pub fn parse(text: &str) -> Result<Self, String> {
        let (a, b) = text.split_once(':').ok_or_else(|| {
            format!("expected START:END in seconds (e.g. 10:40 or 5:), found `{text}`")
        })?;
        let num = |s: &str| -> Result<Option<f64>, String> {
            let s = s.trim();
            if s.is_empty() {
                return Ok(None);
            }
            match s.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(Some(v)),
                _ => Err(format!(
                    "expected a time in seconds, found `{s}` in `{text}`"
                )),
            }
        };
        let w = TimeWindow {
            start: num(a)?,
            end: num(b)?,
        };
        if let (Some(s), Some(e)) = (w.start, w.end) {
            if e <= s {
                return Err(format!(
                    "window end {} s is not after its start {} s",
                    ShownNumber(e),
                    ShownNumber(s)
                ));
            }
        }
        Ok(w)
    }
}

impl fmt::Display for TimeWindow {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = self
            .start
            .map_or(String::new(), |v| ShownNumber(v).to_string());
        let e = self
            .end
            .map_or(String::new(), |v| ShownNumber(v).to_string());
        write!(f, "{s}:{e} s")
    }
}

/// How to evaluate.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EvalOptions {
    /// Only samples inside this window count.
    pub window: TimeWindow,
    /// Remove the mean error of each channel before the RMSE.
    pub offset_free: bool,
    /// Synchronise each channel by the lag within `-max_lag..=max_lag`
    /// samples that minimises its RMSE ([`crate::sync_lag`]); 0 = off. At
    /// most [`max_lag_bound`] of the trial's samples.
    pub max_lag: usize,
    /// Evaluate an estimate whose header records another trial
    /// ([`crate::trial_check`]) instead of refusing it.
    pub allow_trial_mismatch: bool,
}

/// The largest synchronisation lag allowed on a trial of `samples` samples:
/// half of it, so that every lag searched still compares at least half the
/// trial (a longer lag compares a handful of samples and its "best" RMSE
/// means nothing).
pub fn max_lag_bound(samples: u64) -> u64 {
    samples / 2
}

/// Why an evaluation failed.
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// A file could not be read.
    #[error(transparent)]
    File(#[from] FileError),
    /// The two files do not share their time base.
    #[error("{estimate}:{line}: estimate time {t_estimate} s does not match the trial's sample {index} time {t_trial} s (an estimate file must have its trial's time base)")]
    TimeMismatch {
        /// Estimate file.
        estimate: String,
        /// Line in the estimate file.
        line: u64,
        /// 0-based sample index.
        index: u64,
        /// Time in the estimate.
        t_estimate: f64,
        /// Time in the trial.
        t_trial: f64,
    },
    /// One file has more samples than the other.
    #[error("{0}")]
    LengthMismatch(String),
    /// The estimate file records another trial than the one given.
    #[error("{0}")]
    TrialMismatch(TrialMismatch),
    /// The synchronisation lag is too long for the trial.
    #[error("a maximum lag of {max_lag} samples is longer than half the trial {trial} ({samples} samples): at most {bound}, so that every lag searched compares at least half the trial")]
    MaxLagTooLong {
        /// The lag asked for (samples).
        max_lag: usize,
        /// [`max_lag_bound`] of the trial.
        bound: u64,
        /// The trial file.
        trial: String,
        /// Its samples.
        samples: u64,
    },
    /// The trial has no reference angle to compare with.
    #[error("{0}: the trial has no reference angle column (`thigh_ref`, `knee_ref`, ...), so there is nothing to evaluate against")]
    NoReference(String),
    /// No sample of the window has both an estimate and a reference of
    /// any angle: nothing was scored (the message says why).
    #[error("{0}")]
    NothingScored(String),
    /// The estimate has no strides to tabulate (a method without strides,
    /// or written without its stride diagnostics): the message says which.
    #[error("{0}")]
    NoStrides(String),
}

impl EvalError {
    /// `Ok` when the estimate's time `t_estimate` (line `line` of
    /// `estimate`) is the trial's sample `index` time `t_trial` (to 1e-9
    /// relative); else [`EvalError::TimeMismatch`].
    pub fn check_same_time(
        estimate: &std::path::Path,
        line: u64,
        index: u64,
        t_estimate: f64,
        t_trial: f64,
    ) -> Result<(), EvalError> {
        if (t_trial - t_estimate).abs() > 1e-9 * t_trial.abs().max(1.0) {
            return Err(EvalError::TimeMismatch {
                estimate: estimate.display().to_string(),
                line,
                index,
                t_estimate,
                t_trial,
            });
        }
        Ok(())
    }
}

/// Evaluates the estimate file against the trial's reference, streaming both.
///
/// First, one pass over the trial's bytes hashes it and counts its samples:
/// an estimate recording another trial is refused
/// ([`EvalError::TrialMismatch`], unless `options.allow_trial_mismatch`) and
/// `options.max_lag` is bounded by the trial ([`EvalError::MaxLagTooLong`])
/// before anything is sized by it.
pub fn evaluate_files(
    trial: &Path,
    estimate: &Path,
    options: EvalOptions,
) -> Result<Evaluation, EvalError> {
    let fingerprint = TrialFingerprint::of_file(trial)?;
    let mut tr = TrialReader::open(trial)?;
    if !tr.layout().has_angle_reference() {
        return Err(EvalError::NoReference(trial.display().to_string()));
    }
    let mut er = EstimateReader::open(estimate)?;
    let trial_check = check_trial(trial, fingerprint.hash, &er, options.allow_trial_mismatch)?;
    let bound = max_lag_bound(fingerprint.data_rows);
    if options.max_lag as u64 > bound {
        return Err(EvalError::MaxLagTooLong {
            max_lag: options.max_lag,
            bound,
            trial: trial.display().to_string(),
            samples: fingerprint.data_rows,
        });
    }
    let mut metrics = AngleMetrics::new(er.method(), options);
    metrics.set_carried_channels(core::array::from_fn(|k| {
        er.has_angle(limbfuse_core::sample::AngleChannel::ALL[k])
    }));
    metrics.set_diagnostic_names(
        er.diagnostic_names()
            .map(str::to_string)
            .collect::<Vec<_>>(),
    );
    let mut index = 0u64;
    loop {
        let rec = tr.next_record()?;
        let est = er.next_estimate()?;
        match (rec, est) {
            (None, None) => break,
            (Some(r), Some((line, e))) => {
                EvalError::check_same_time(estimate, line, index, e.t, r.sample.t)?;
                metrics.push(&r, &e);
            }
            (Some(_), None) => {
                return Err(length_mismatch(
                    format!(
                        "{}: the estimate ends after {index} samples but the trial {} has more",
                        estimate.display(),
                        trial.display()
                    ),
                    cut_lines(Some(&tr), &er),
                ))
            }
            (None, Some((line, _))) => {
                return Err(length_mismatch(
                    format!(
                        "{}:{line}: the estimate has more samples than the trial {} ({index})",
                        estimate.display(),
                        trial.display()
                    ),
                    cut_lines(Some(&tr), &er),
                ))
            }
        }
        index += 1;
    }
    Ok(Evaluation {
        trial_check,
        cut_lines: cut_lines(Some(&tr), &er),
        ..metrics.evaluation()
    })
}

/// [`EvalError::LengthMismatch`] with `why`, and the last line the file
/// that ended first left out, if it was cut off mid-row (`cut`, from
/// [`cut_lines`]): the likely cause.
pub(crate) fn length_mismatch(why: String, cut: Vec<String>) -> EvalError {
    EvalError::LengthMismatch(
        core::iter::once(why)
            .chain(cut)
            .collect::<Vec<_>>()
            .join("; "),
    )
}

/// What was left out of a trial and an estimate file read to their ends:
/// a last line cut off mid-row (`limbfuse_io::table::CutLine`), the
/// trial's first. Every file evaluation reports them (`evaluate` said
/// nothing, where `estimate`, `inspect` and the other commands warn).
pub(crate) fn cut_lines(trial: Option<&TrialReader>, estimate: &EstimateReader) -> Vec<String> {
    let trial = trial.and_then(|r| Some(r.cut_last_line()?.message(r.path())));
    let estimate = estimate.cut_last_line().map(|c| c.message(estimate.path()));
    trial.into_iter().chain(estimate).collect()
}

/// [`evaluate_files`], refusing an evaluation that scored nothing: an
/// estimate without any angle, a window outside the trial, references
/// empty wherever the estimate has angles (an audit: `limbfuse evaluate`
/// printed an empty table with exit 0). `limbfuse evaluate` and Python's
/// `evaluate` use it; the report keeps [`evaluate_files`] (a gait-events
/// estimate has its own panel and no angle to score).
pub fn evaluate_files_scored(
    trial: &Path,
    estimate: &Path,
    options: EvalOptions,
) -> Result<Evaluation, EvalError> {
    let window = options.window;
    let ev = evaluate_files(trial, estimate, options)?;
    let angles = EstimateReader::open(estimate)?.has_any_angle();
    let (trial, estimate) = (trial.display().to_string(), estimate.display().to_string());
    match nothing_scored(&ev, angles, &window, &trial, &estimate) {
        Some(why) => Err(EvalError::NothingScored(why)),
        None => Ok(ev),
    }
}

/// Why `ev` scored nothing (no angle sample with both an estimate and a
/// reference), or `None` when it scored something; `angles`: whether the
/// estimate has any angle column. Shared with Python's `evaluate`.
pub fn nothing_scored(
    ev: &Evaluation,
    angles: bool,
    window: &TimeWindow,
    trial: &str,
    estimate: &str,
) -> Option<String> {
    if ev.channels.iter().any(|(_, c)| c.n() > 0) {
        return None;
    }
    Some(if !angles {
        format!(
            "{estimate}: the estimate has no angle column ({}), and the trial {trial} has no \
             reference of what it estimates (gait events and walking speed are scored against \
             `contact_left_ref` / `contact_right_ref` / `speed_ref`, a gait phase against \
             `phase_ref`)",
            ev.method
        )
    } else if ev.n_samples == 0 {
        format!(
            "{trial}: no sample of the trial inside the window ({window}; `limbfuse inspect` \
             gives the trial's time span)"
        )
    } else {
        format!(
            "{trial}: none of the {} samples in the window has both an angle of {estimate} and \
             its reference (the reference cells are empty, or the estimate gave no angle): \
             nothing to score",
            ev.n_samples
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn window_parsing() {
        assert_eq!(
            TimeWindow::parse("10:40").unwrap(),
            TimeWindow {
                start: Some(10.0),
                end: Some(40.0)
            }
        );
        assert_eq!(
            TimeWindow::parse("5:").unwrap(),
            TimeWindow {
                start: Some(5.0),
                end: None
            }
        );
        assert!(TimeWindow::parse("40:10").is_err());
        assert!(TimeWindow::parse("abc").is_err());
        assert!(TimeWindow::parse("1:x").unwrap_err().contains("`x`"));
        let w = TimeWindow::parse(":2").unwrap();
        assert!(w.contains(2.0) && !w.contains(2.1));
    }
}
