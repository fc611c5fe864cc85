//! Strides whose foot accelerometer clipped for longer than a heel strike's
//! impact (`gait-events`' `diag_stride_clipped_left` / `_right`): the swing
//! itself reached the sensor's full scale (a 2-3 g sensor), the velocity it
//! lost is not recovered, and the stride's length and speed come out short
//! (docs/GAIT_EVENTS.md "Clipped swings"). [`ClippedSwingWatch`] follows
//! them while a run streams, so that `limbfuse estimate` and Python's
//! `limbfuse.estimate` can warn.

use std::fmt;

use limbfuse_core::runner::{BoxError, Observer};
use limbfuse_core::{Estimate, Estimator, Record, ShownNumber};
use limbfuse_estimators::gait_events::strapdown::IMPACT_CLIP_TIME;

/// The diagnostics followed (left, right).
const NAMES: [&str; 2] = ["stride_clipped_left", "stride_clipped_right"];

/// The strides of a run that clipped past an impact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClippedSwings {
    /// Strides clipped for longer than [`IMPACT_CLIP_TIME`].
    pub clipped: u64,
    /// Strides finished, both feet.
    pub strides: u64,
    /// The longest clipped time of a stride (s).
    pub longest_s: f64,
    /// Time of the first estimate that finished such a stride (s).
    pub first_t: f64,
}

impl fmt::Display for ClippedSwings {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} of {} strides had a foot accelerometer at its full scale for longer than a heel \
             strike's impact ({} ms; longest {} ms, the first finished at t = {} s): the velocity a \
             clipped swing loses is not recovered, so those strides' lengths and speeds come out \
             short (by 1-17 % on the shared walks clipped at 2-3 g; docs/GAIT_EVENTS.md \
             \"Clipped swings\"); a foot \
             sensor of 8 g or more avoids it (clipped: an axis at 97 % of the full scale, the \
             trial's `# acc_range_m_s2:` or else 16 g, or a reading repeated exactly at 1.5 g or \
             more; state the range: a calibrated sensor's rail does not repeat exactly)",
            self.clipped,
            self.strides,
            ShownNumber(IMPACT_CLIP_TIME * 1000.0),
            (self.longest_s * 1000.0).round(),
            ShownNumber(self.first_t)
        )
    }
}

/// Follows the strides' clipped time over a run; reports nothing for an
/// estimator without the columns.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ClippedSwingWatch {
    columns: Option<[usize; 2]>,
    clipped: u64,
    strides: u64,
    longest_s: f64,
    first_t: Option<f64>,
}

impl ClippedSwingWatch {
    /// A watch over estimates whose diagnostics are named `names`.
    pub fn new(names: &[&str]) -> Self {
        let find = |n: &str| names.iter().position(|x| *x == n);
        let columns = match NAMES.map(find) {
            [Some(l), Some(r)] => Some([l, r]),
            _ => None,
        };
        ClippedSwingWatch {
            columns,
            ..ClippedSwingWatch::default()
        }
    }

    /// Adds one estimate.
    pub fn push(&mut self, e: &Estimate) {
        let Some(cols) = self.columns else { return };
        for c in cols {
            let Some(clipped) = e.diag[c] else { continue };
            self.strides += 1;
            if clipped > IMPACT_CLIP_TIME {
                self.clipped += 1;
                self.longest_s = self.longest_s.max(clipped);
                self.first_t.get_or_insert(e.t);
            }
        }
    }

    /// The clipped strides; `None` when no stride clipped past an impact.
    pub fn clipped(&self) -> Option<ClippedSwings> {
        self.first_t.map(|first_t| ClippedSwings {
            clipped: self.clipped,
            strides: self.strides,
            longest_s: self.longest_s,
            first_t,
        })
    }
}

impl Observer for ClippedSwingWatch {
    fn start(&mut self, estimator: &dyn Estimator) -> Result<(), BoxError> {
        *self = ClippedSwingWatch::new(estimator.diagnostic_names());
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

    fn est(t: f64, left: Option<f64>, right: Option<f64>) -> Estimate {
        let mut e = Estimate::empty(t);
        e.diag[1] = left;
        e.diag[2] = right;
        e
    }

    const COLUMNS: [&str; 3] = ["rest_left", "stride_clipped_left", "stride_clipped_right"];

    #[test]
    fn counts_the_strides_clipped_past_an_impact() {
        let mut w = ClippedSwingWatch::new(&COLUMNS);
        w.push(&est(1.0, Some(0.0), None));
        w.push(&est(1.5, None, Some(IMPACT_CLIP_TIME)));
        assert_eq!(
            w.clipped(),
            None,
            "an impact's clipping is not a clipped swing"
        );
        w.push(&est(2.0, Some(0.12), None));
        w.push(&est(2.5, None, Some(0.3)));
        w.push(&est(2.6, None, None));
        let c = w.clipped().unwrap();
        assert_eq!((c.clipped, c.strides), (2, 4));
        assert_eq!(c.longest_s, 0.3);
        assert_eq!(c.first_t, 2.0);
        let s = c.to_string();
        assert!(s.starts_with("2 of 4 strides"), "{s}");
        assert!(s.contains("longest 300 ms"), "{s}");
    }

    #[test]
    fn an_estimator_without_the_columns_reports_nothing() {
        let mut w = ClippedSwingWatch::new(&["mode", "rest_left"]);
        w.push(&est(0.0, Some(1.0), Some(1.0)));
        assert_eq!(w.clipped(), None);
    }
}
