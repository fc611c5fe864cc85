//! Sensor readings the method layer's range gate rejected during a run
//! (issue 18 item 1): the cumulative diagnostics `rejected_gyro`,
//! `rejected_acc` and `rejected_encoder` that `limbfuse_methods::gated`
//! appends to every estimator's own. [`RejectionWatch`] follows them while a
//! run streams, so the CLI can say how many readings were dropped and from
//! when.

use std::fmt;

use limbfuse_core::runner::{BoxError, Observer};
use limbfuse_core::{Estimate, Estimator, Record};

/// The diagnostics followed, in the order [`Rejected::counts`] gives them.
const NAMES: [&str; 3] = ["rejected_gyro", "rejected_acc", "rejected_encoder"];

/// Readings rejected over a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rejected {
    /// Gyroscope, accelerometer and encoder readings rejected.
    pub counts: [u64; 3],
    /// Time of the first estimate whose counts rose (s).
    pub first_t: f64,
}

impl fmt::Display for Rejected {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [g, a, e] = self.counts;
        write!(
            f,
            "{g} gyroscope, {a} accelerometer and {e} encoder reading(s) were rejected \
             (first at t = {} s): outside the sensors' range, clipped at their full scale, a \
             non-physical jump, a stuck sensor, an innovation beyond the filter's chi-square \
             gate or a single-sample gyroscope spike; they were treated as missing (a spike: \
             in `mjls` and `global` a thigh or shank reading is replaced by the rate the joint \
             encoders imply, in the FES filters by the median of the last three readings; the trial's \
             `# gyro_range_rad_s:` and `# acc_range_m_s2:` set the range; docs/ROBUST_INPUT.md)",
            limbfuse_core::ShownNumber(self.first_t)
        )
    }
}

/// Follows the rejection counts over a run; reports nothing for an
/// estimator without them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RejectionWatch {
    columns: Option<[usize; 3]>,
    last: [u64; 3],
    first_t: Option<f64>,
}

impl RejectionWatch {
    /// A watch over estimates whose diagnostics are named `names`.
    pub fn new(names: &[&str]) -> Self {
        let find = |n: &str| names.iter().position(|x| *x == n);
        let columns = match NAMES.map(find) {
            [Some(g), Some(a), Some(e)] => Some([g, a, e]),
            _ => None,
        };
        RejectionWatch {
            columns,
            ..RejectionWatch::default()
        }
    }

    /// Adds one estimate.
    pub fn push(&mut self, e: &Estimate) {
        let Some(cols) = self.columns else { return };
        let now = cols.map(|c| e.diag[c].map_or(0, |v| v as u64));
        if now.iter().zip(&self.last).any(|(n, l)| n > l) {
            self.first_t.get_or_insert(e.t);
        }
        self.last = now;
    }

    /// Continues from `counts` (the cumulative counts an earlier run of the
    /// same estimator ended at): only a rise above them is a rejection from
    /// now on (the time of an earlier one is forgotten).
    pub fn carry(&mut self, counts: [u64; 3]) {
        self.last = counts;
        self.first_t = None;
    }

    /// The cumulative counts of the last estimate.
    pub fn counts(&self) -> [u64; 3] {
        self.last
    }

    /// What was rejected; `None` when nothing was.
    pub fn rejected(&self) -> Option<Rejected> {
        self.first_t.map(|first_t| Rejected {
            counts: self.last,
            first_t,
        })
    }
}

impl Observer for RejectionWatch {
    fn start(&mut self, estimator: &dyn Estimator) -> Result<(), BoxError> {
        *self = RejectionWatch::new(estimator.diagnostic_names());
        Ok(())
    }

    fn observe(&mut self, _record: &Record, estimate: &Estimate) -> Result<(), BoxError> {
        self.push(estimate);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn est(t: f64, counts: [f64; 3]) -> Estimate {
        let mut e = Estimate::empty(t);
        e.diag[1] = Some(counts[0]);
        e.diag[2] = Some(counts[1]);
        e.diag[3] = Some(counts[2]);
        e
    }

    #[test]
    fn reports_the_last_counts_and_the_first_time_they_rose() {
        let names = ["mode", "rejected_gyro", "rejected_acc", "rejected_encoder"];
        let mut w = RejectionWatch::new(&names);
        w.push(&est(0.0, [0.0; 3]));
        assert_eq!(w.rejected(), None);
        w.push(&est(0.01, [1.0, 0.0, 0.0]));
        w.push(&est(0.02, [1.0, 2.0, 0.0]));
        let r = w.rejected().unwrap();
        assert_eq!(r.counts, [1, 2, 0]);
        assert_eq!(r.first_t, 0.01);
        assert!(r
            .to_string()
            .contains("1 gyroscope, 2 accelerometer and 0 encoder"));
    }

    #[test]
    fn an_estimator_without_the_columns_reports_nothing() {
        let mut w = RejectionWatch::new(&["mode"]);
        w.push(&est(0.0, [5.0; 3]));
        assert_eq!(w.rejected(), None);
    }
}
