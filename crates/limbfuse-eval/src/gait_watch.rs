//! Whether a gait method found any gait (`gait-events`, `lowback-speed`):
//! a recording in which it finds none is an error for `limbfuse estimate`
//! and Python's `limbfuse.estimate`, not an empty estimate (issue 19).

use limbfuse_core::estimator::Outputs;
use limbfuse_core::runner::{self, Observer};
use limbfuse_core::{Estimate, Record};
use limbfuse_estimators::lowback_speed::{LowbackParams, WALKING_RMS_TIME_CONSTANT_S};

/// Whether an estimator with these outputs is a gait method: contacts, or
/// a walking speed without a CoM model (`imm-bslip` estimates a CoM).
pub fn is_gait_method(outputs: &Outputs) -> bool {
    outputs.contact || (outputs.speed && !outputs.com)
}

/// Name of `lowback-speed`'s vertical-acceleration diagnostic (without the
/// `diag_` prefix of estimate-file columns).
pub const VERTICAL_ACC_DIAGNOSTIC: &str = "vertical_acc";

/// Watches whether any estimate carried a contact state or a walking speed,
/// and, for an estimator with a `vertical_acc` diagnostic (`lowback-speed`),
/// the largest 2 s RMS of it: what its walking test compares with
/// `walking_rms` (docs/GAIT_EVENTS.md), said when no gait was found.
#[derive(Debug, Default)]
pub struct GaitWatch {
    /// Some estimate carried one.
    pub found: bool,
    vertical: Option<usize>,
    rms_sq: f64,
    last_t: Option<f64>,
    peak_sq: Option<f64>,
}

impl GaitWatch {
    /// A watch over estimates whose diagnostics are named `names` (as an
    /// estimator gives them, or as estimate-file columns with `diag_`).
    pub fn for_diagnostics<S: AsRef<str>>(names: impl IntoIterator<Item = S>) -> Self {
        let vertical = names.into_iter().position(|n| {
            let n = n.as_ref();
            n.strip_prefix("diag_").unwrap_or(n) == VERTICAL_ACC_DIAGNOSTIC
        });
        GaitWatch {
            vertical,
            ..GaitWatch::default()
        }
    }

    /// Adds one estimate.
    pub fn push(&mut self, e: &Estimate) {
        self.found |= e.speed.is_some() || e.contact.iter().any(Option::is_some);
        let Some(a) = self.vertical.and_then(|c| e.diag.get(c).copied().flatten()) else {
            return;
        };
        // the estimator's own mean: exponential, its time constant
        let alpha = match self.last_t {
            Some(t0) if e.t > t0 => ((e.t - t0) / WALKING_RMS_TIME_CONSTANT_S).min(1.0),
            _ => 0.0,
        };
        self.last_t = Some(e.t);
        self.rms_sq += (a * a - self.rms_sq) * alpha;
        // (the mean square's peak: the root once, when asked)
        if self.rms_sq.is_finite() && self.peak_sq.is_none_or(|p| self.rms_sq > p) {
            self.peak_sq = Some(self.rms_sq);
        }
    }

    /// The largest 2 s RMS of the vertical acceleration seen (m/s^2).
    pub fn peak_vertical_rms(&self) -> Option<f64> {
        self.peak_sq.map(libm::sqrt)
    }

    /// [`no_gait_message`], with the vertical acceleration's largest 2 s
    /// RMS when the estimator reports it.
    pub fn no_gait_message(&self, trial: &str, method: &str, n_samples: u64, kept: &str) -> String {
        let mut text = no_gait_message(trial, method, n_samples, kept);
        if let Some(rms) = self.peak_vertical_rms() {
            let default = LowbackParams::default().walking_rms;
            text.push_str(&format!(
                "; its vertical acceleration's 2 s RMS peaked at {rms:.3} m/s^2, and a step counts \
                 only while that RMS is above the method's `walking_rms` ({default} m/s^2 by default: quiet \
                 standing stays below 0.1, walking is 1-3; a very slow walker's can stay near or below \
                 it, docs/GAIT_EVENTS.md)"
            ));
        }
        text
    }
}

impl Observer for GaitWatch {
    fn start(&mut self, estimator: &dyn limbfuse_core::Estimator) -> Result<(), runner::BoxError> {
        *self = GaitWatch::for_diagnostics(estimator.diagnostic_names().iter());
        Ok(())
    }

    fn observe(&mut self, _record: &Record, e: &Estimate) -> Result<(), runner::BoxError> {
        self.push(e);
        Ok(())
    }
}

/// The error for `trial`, on which `method` found no gait in `n_samples`;
/// `kept` says what became of the output ("no estimate written").
pub fn no_gait_message(trial: &str, method: &str, n_samples: u64, kept: &str) -> String {
    format!(
        "no gait found in {trial}: `{method}` detected no foot contact and no walking speed in \
         {n_samples} samples (the recording has no walking, or the IMU is not where the method \
         expects it); {kept}"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The watch's RMS is the estimator's: an exponential mean of `a_v^2`
    /// with a 2 s time constant, here of a 1 m/s^2 sinusoid at 100 Hz
    /// (RMS 0.707) after 20 s; without the column, no hint.
    #[test]
    fn the_peak_vertical_rms_follows_the_estimators_mean() {
        let mut w = GaitWatch::for_diagnostics(["diag_ic", "diag_vertical_acc"]);
        let mut plain = GaitWatch::for_diagnostics(["diag_ic"]);
        for k in 0..2000 {
            let t = k as f64 * 0.01;
            let mut e = Estimate::empty(t);
            e.diag[1] = Some(libm::sin(2.0 * core::f64::consts::PI * 1.7 * t));
            w.push(&e);
            plain.push(&e);
        }
        let peak = w.peak_vertical_rms().unwrap();
        assert!(
            (peak - core::f64::consts::FRAC_1_SQRT_2).abs() < 0.03,
            "{peak}"
        );
        let m = w.no_gait_message("t.csv", "lowback-speed", 2000, "no estimate written");
        assert!(
            m.contains("peaked at 0.7") && m.contains("walking_rms"),
            "{m}"
        );
        assert_eq!(plain.peak_vertical_rms(), None);
        assert!(!plain
            .no_gait_message("t.csv", "gait-events", 2000, "x")
            .contains("walking_rms"));
    }
}
