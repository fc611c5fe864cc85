//! Estimator restarts in an estimate (issue 16 item 0).
//!
//! The paper-004 filters (`sdre`, `ekf`; `limbfuse-estimators::fes`)
//! restart from the accelerometer inclination when their state or Riccati
//! solution goes non-finite and count it in the cumulative diagnostic
//! `resets` (`diag_resets` in an estimate file). After a restart the
//! estimate is the restart value, not a filter output, so a non-zero count
//! must never pass unnoticed: [`ResetWatch`] finds it, while a run streams
//! (as a runner [`Observer`]) or over an estimate file
//! ([`scan_estimate_file`]); the CLI prints the warning.

use std::fmt;
use std::path::Path;

use limbfuse_core::runner::{BoxError, Observer};
use limbfuse_core::{Estimate, Estimator, Record};
use limbfuse_io::EstimateReader;

use crate::evaluation::EvalError;

/// Name of the cumulative restart-count diagnostic (without the `diag_`
/// prefix of estimate-file columns).
pub const RESETS_DIAGNOSTIC: &str = "resets";

/// Restarts found in an estimate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resets {
    /// Number of restarts.
    pub count: u64,
    /// Time of the first sample whose count rose (s).
    pub first_t: f64,
    /// Samples whose count rose.
    pub samples: u64,
    /// Samples seen.
    pub of_samples: u64,
}

impl fmt::Display for Resets {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the estimator restarted {} time{} after a non-finite or diverged state or a gap in the data \
             ({} of {} samples, first at t = {} s); the estimate after a restart starts again from the \
             next valid data (accelerometer inclination), not from the filter's past",
            self.count,
            if self.count == 1 { "" } else { "s" },
            self.samples,
            self.of_samples,
            limbfuse_core::ShownNumber(self.first_t)
        )
    }
}

/// Follows the `resets` diagnostic over a run. Without such a column it
/// never reports anything.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ResetWatch {
    column: Option<usize>,
    previous: f64,
    count: u64,
    first_t: Option<f64>,
    samples: u64,
    of_samples: u64,
}

impl ResetWatch {
    /// A watch over estimates whose diagnostics are named `names` (as an
    /// estimator gives them, or as estimate-file columns with `diag_`).
    pub fn new<S: AsRef<str>>(names: impl IntoIterator<Item = S>) -> Self {
        let column = names.into_iter().position(|n| {
            let n = n.as_ref();
            n.strip_prefix("diag_").unwrap_or(n) == RESETS_DIAGNOSTIC
        });
        ResetWatch {
            column,
            ..ResetWatch::default()
        }
    }

    /// Whether the estimates carry a restart count at all.
    pub fn has_column(&self) -> bool {
        self.column.is_some()
    }

    /// Adds one estimate. The count is cumulative; a drop (the estimator
    /// was reset) starts counting again from the new value.
    pub fn push(&mut self, e: &Estimate) {
        self.of_samples += 1;
        let Some(v) = self.column.and_then(|c| e.diag.get(c).copied().flatten()) else {
            return;
        };
        if v > self.previous {
            self.count += libm::round(v - self.previous).max(1.0) as u64;
            self.samples += 1;
            self.first_t.get_or_insert(e.t);
        }
        self.previous = v;
    }

    /// The restarts seen so far; `None` when there were none.
    pub fn resets(&self) -> Option<Resets> {
        self.first_t.map(|first_t| Resets {
            count: self.count,
            first_t,
            samples: self.samples,
            of_samples: self.of_samples,
        })
    }
}

impl Observer for ResetWatch {
    fn start(&mut self, estimator: &dyn Estimator) -> Result<(), BoxError> {
        *self = ResetWatch::new(estimator.diagnostic_names().iter());
        Ok(())
    }

    fn observe(&mut self, _record: &Record, estimate: &Estimate) -> Result<(), BoxError> {
        self.push(estimate);
        Ok(())
    }
}

/// Reads an estimate file and returns its restarts (`None` when it has no
/// `diag_resets` column or the column never rises above 0).
pub fn scan_estimate_file(path: &Path) -> Result<Option<Resets>, EvalError> {
    let mut r = EstimateReader::open(path)?;
    let mut watch = ResetWatch::new(r.diagnostic_names().collect::<Vec<_>>());
    if !watch.has_column() {
        return Ok(None);
    }
    while let Some((_, e)) = r.next_estimate()? {
        watch.push(&e);
    }
    Ok(watch.resets())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn est(t: f64, resets: f64) -> Estimate {
        let mut e = Estimate::empty(t);
        e.diag[1] = Some(resets);
        e
    }

    #[test]
    fn counts_rises_of_the_cumulative_column() {
        let mut w = ResetWatch::new(["shank_rate", "diag_resets"]);
        assert!(w.has_column());
        for (t, v) in [(0.0, 0.0), (0.1, 0.0), (0.2, 1.0), (0.3, 1.0), (0.4, 3.0)] {
            w.push(&est(t, v));
        }
        let r = w.resets().unwrap();
        assert_eq!(
            (r.count, r.first_t, r.samples, r.of_samples),
            (3, 0.2, 2, 5)
        );
        let text = r.to_string();
        assert!(
            text.contains("restarted 3 times") && text.contains("t = 0.2 s"),
            "{text}"
        );
    }

    #[test]
    fn zero_or_absent_column_reports_nothing() {
        let mut w = ResetWatch::new(["resets"]);
        let mut e = Estimate::empty(0.0);
        e.diag[0] = Some(0.0);
        w.push(&e);
        assert_eq!(w.resets(), None);
        let mut none = ResetWatch::new(["p11"]);
        none.push(&est(0.0, 5.0));
        assert!(!none.has_column());
        assert_eq!(none.resets(), None);
    }

    #[test]
    fn a_reset_estimator_counts_again_from_zero() {
        let mut w = ResetWatch::new(["x", "resets"]);
        for (t, v) in [(0.0, 2.0), (0.1, 0.0), (0.2, 1.0)] {
            w.push(&est(t, v));
        }
        assert_eq!(w.resets().unwrap().count, 3);
    }
}
