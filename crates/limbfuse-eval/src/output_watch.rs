//! Whether a run gave any estimate at all: an estimate file empty on every
//! row (an audit: `imm-bslip` on a trial whose `com_meas_*` cells were all
//! empty, `knee-kinematic` on one whose IMU cells were) is an error for
//! `limbfuse estimate` and Python's `limbfuse.estimate`, not an output
//! written with exit 0. The knee-axis and gait methods have their own,
//! more specific verdicts ([`crate::knee_watch`], [`crate::gait_watch`]).

use limbfuse_core::runner::{self, Observer};
use limbfuse_core::{Estimate, Record};

/// Watches whether any estimate carried a value (an angle, a phase, a
/// speed, a contact, a CoM); diagnostics do not count.
#[derive(Debug, Default)]
pub struct AnyOutputWatch {
    /// Some estimate carried one.
    pub found: bool,
    /// Time of the first and of the last estimate seen.
    span: Option<(f64, f64)>,
}

impl AnyOutputWatch {
    /// Adds one estimate.
    #[inline]
    pub fn push(&mut self, e: &Estimate) {
        if self.found {
            return;
        }
        self.span = Some(match self.span {
            Some((first, _)) => (first, e.t),
            None => (e.t, e.t),
        });
        self.found = e.segment.iter().any(Option::is_some)
            || e.joint.iter().any(Option::is_some)
            || e.phase.is_some()
            || e.speed.is_some()
            || e.contact.iter().any(Option::is_some)
            || e.com_pos.is_some()
            || e.com_vel.is_some();
    }
}

impl AnyOutputWatch {
    /// Seconds from the first to the last estimate seen while none carried
    /// a value (`None` before two).
    pub fn span_s(&self) -> Option<f64> {
        self.span
            .map(|(a, b)| b - a)
            .filter(|d| d.is_finite() && *d > 0.0)
    }
}

impl Observer for AnyOutputWatch {
    fn observe(&mut self, _record: &Record, e: &Estimate) -> Result<(), runner::BoxError> {
        self.push(e);
        Ok(())
    }
}

/// Trials shorter than this (s) may end before a method's start-up window
/// does: the segment filters wait up to 2 s for a quasi-static moment
/// (`segment_kf::chain::start`), `chain` fills its `startup_s` (1 s by
/// default) first; with some margin.
pub const SHORT_TRIAL_S: f64 = 2.5;

/// The error for `trial`, on which `method` gave no value in `n_samples`
/// spanning `span_s` seconds; `kept` says what became of the output ("no
/// estimate written"). A trial shorter than [`SHORT_TRIAL_S`] is named as a
/// possible cause (2026-12-07: a 0.5 s clip of a walk, whose inputs are
/// complete, was told its inputs were missing or rejected).
pub fn no_output_message(
    trial: &str,
    method: &str,
    n_samples: u64,
    span_s: Option<f64>,
    kept: &str,
) -> String {
    let short = match span_s {
        Some(d) if d < SHORT_TRIAL_S => format!(
            "the trial lasts {d:.2} s, and a method that starts from a window of data gives \
             nothing until the window is full (the segment filters wait up to 2 s for a \
             quasi-static moment, docs/SEGMENT_FILTERS.md \"Initialisation\"; `chain` \
             fills its `startup_s` first); or "
        ),
        _ => String::new(),
    };
    format!(
        "{trial}: `{method}` gave no estimate on any of its {n_samples} samples ({short}the \
         inputs it reads are missing on every row, or rejected as out of range or implausible: \
         `limbfuse inspect` shows the rows each input misses, a warning the readings rejected); \
         {kept}"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn any_output_counts_and_diagnostics_do_not() {
        let mut w = AnyOutputWatch::default();
        let mut e = Estimate::empty(0.0);
        e.diag[0] = Some(1.0);
        w.push(&e);
        assert!(!w.found);
        e.com_vel = Some(nalgebra::Vector3::zeros());
        w.push(&e);
        assert!(w.found);
        assert!(
            no_output_message("t.csv", "imm-bslip", 3, None, "no estimate written").starts_with(
                "t.csv: `imm-bslip` gave no estimate on any of its 3 samples (the inputs"
            )
        );
        let short = no_output_message("t.csv", "mjls", 50, Some(0.49), "no estimate written");
        assert!(
            short.contains("(the trial lasts 0.49 s, and a method"),
            "{short}"
        );
        let long = no_output_message("t.csv", "mjls", 500, Some(4.99), "no estimate written");
        assert!(!long.contains("the trial lasts"), "{long}");
    }
}
