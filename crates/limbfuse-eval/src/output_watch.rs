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
}

impl AnyOutputWatch {
    /// Adds one estimate.
    #[inline]
    pub fn push(&mut self, e: &Estimate) {
        if self.found {
            return;
        }
        self.found = e.segment.iter().any(Option::is_some)
            || e.joint.iter().any(Option::is_some)
            || e.phase.is_some()
            || e.speed.is_some()
            || e.contact.iter().any(Option::is_some)
            || e.com_pos.is_some()
            || e.com_vel.is_some();
    }
}

impl Observer for AnyOutputWatch {
    fn observe(&mut self, _record: &Record, e: &Estimate) -> Result<(), runner::BoxError> {
        self.push(e);
        Ok(())
    }
}

/// The error for `trial`, on which `method` gave no value in `n_samples`;
/// `kept` says what became of the output ("no estimate written").
pub fn no_output_message(trial: &str, method: &str, n_samples: u64, kept: &str) -> String {
    format!(
        "{trial}: `{method}` gave no estimate on any of its {n_samples} samples (the inputs it \
         reads are missing on every row, or rejected as out of range or implausible: `limbfuse \
         inspect` shows the rows each input misses, a warning the readings rejected); {kept}"
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
            no_output_message("t.csv", "imm-bslip", 3, "no estimate written")
                .starts_with("t.csv: `imm-bslip` gave no estimate on any of its 3 samples")
        );
    }
}
