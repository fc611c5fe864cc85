//! The streaming estimator interface.
//!
//! An estimator receives one timestamped [`Sample`] at a time and returns one
//! [`Estimate`]. It never does I/O and never fixes `dt` at construction: the
//! step length is always the difference of successive timestamps
//! (see [`TimeStep`]).

use core::fmt;

use crate::estimate::Estimate;
use crate::sample::Sample;

/// Why an estimator could not process a sample.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum EstimatorError {
    /// The sample's time is not after the previous sample's.
    #[error("time {t} s is not after the previous sample's time {previous} s")]
    NonIncreasingTime {
        /// Previous sample time (s).
        previous: f64,
        /// Offending sample time (s).
        t: f64,
    },
    /// A timestamp or a reading is not a finite number.
    #[error("non-finite value in channel {channel}")]
    NonFinite {
        /// Channel name.
        channel: &'static str,
    },
    /// A channel the estimator needs is absent from the trial altogether.
    #[error("this method needs channel {channel}, which the trial does not have")]
    MissingChannel {
        /// Channel name.
        channel: &'static str,
    },
    /// A numerical failure (e.g. a singular innovation covariance).
    #[error("numerical failure: {0}")]
    Numerical(&'static str),
}

/// Which quantities an estimator produces (the columns of its estimate file).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Outputs {
    /// Absolute segment angles, indexed by [`crate::Segment::index`].
    pub segment: [bool; 4],
    /// Joint angles, indexed by [`crate::Joint::index`].
    pub joint: [bool; 3],
    /// Gait phase.
    pub phase: bool,
    /// Walking speed.
    pub speed: bool,
    /// Centre-of-mass position and velocity (`com_x`..`com_vz`).
    pub com: bool,
    /// Foot contact per side (`contact_left`, `contact_right`).
    pub contact: bool,
}

impl Outputs {
    /// All four segment angles and the three joint angles.
    pub const ALL_ANGLES: Outputs = Outputs {
        segment: [true; 4],
        joint: [true; 3],
        phase: false,
        speed: false,
        com: false,
        contact: false,
    };
}

/// A streaming estimator: one sample in, one estimate out.
pub trait Estimator {
    /// Method name as used by `limbfuse estimate --method` (e.g. `mjls`).
    fn name(&self) -> &'static str;

    /// The quantities this estimator fills in its estimates.
    fn outputs(&self) -> Outputs;

    /// Writes the parameters in use as `key: value` lines (for the estimate file header).
    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result;

    /// Names of the diagnostic values in [`Estimate::diag`] (without the `diag_` prefix):
    /// the `NAMES` of the estimator's declared [`crate::DiagnosticSet`]
    /// (see [`crate::diagnostics`]).
    fn diagnostic_names(&self) -> &[&'static str] {
        &[]
    }

    /// Readings this estimator's own checks rejected so far (cumulative),
    /// as `[gyroscope, accelerometer, encoder]`: rows refused by an
    /// innovation gate (issue 18). The method layer adds them to its
    /// `rejected_*` diagnostics. Default: none.
    fn rejected_readings(&self) -> [u64; 3] {
        [0; 3]
    }

    /// Whether a gyroscope reading clipped at the full scale is to be passed
    /// on rather than rejected by the sensor gate ([`crate::Gated`] then
    /// turns off the gate's clipping test, `SensorRanges::
    /// gyro_full_scale_rad_s`). Default: `false` (a clipped rate is wrong
    /// for any estimator that integrates it); `gait-events` keeps them (a
    /// rate at least the full scale still says the foot swings).
    fn keeps_clipped_gyro(&self) -> bool {
        false
    }

    /// Whether an accelerometer reading clipped at the full scale is to be
    /// passed on rather than rejected by the sensor gate ([`crate::Gated`]
    /// then turns off the gate's accelerometer clipping test,
    /// `SensorRanges::acc_full_scale_m_s2`). Default: `false` (a clipped
    /// specific force points the wrong way for an inclination or a
    /// kinematic chain); estimators that integrate the specific force keep
    /// them (`gait-events`, `lowback-speed`: a clipped impact loses part of
    /// its velocity change, a missing one all of it).
    fn keeps_clipped_acc(&self) -> bool {
        false
    }

    /// Forgets all state; the next sample starts a new recording.
    fn reset(&mut self);

    /// Processes one sample. Missing channels are `None` in the sample; the
    /// estimator degrades (e.g. predicts only) instead of failing.
    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError>;

    /// [`Estimator::step`] into a caller-owned estimate, which it overwrites
    /// whole (on an error `out` holds no meaningful value). The runner reuses
    /// one estimate for a run; an estimator that builds its estimate in
    /// place overrides this to spare the move of an [`Estimate`] (about
    /// 1 KB) per sample. The default moves the result of `step`.
    fn step_into(&mut self, sample: &Sample, out: &mut Estimate) -> Result<(), EstimatorError> {
        *out = self.step(sample)?;
        Ok(())
    }
}

/// A boxed estimator (a trait object: any method) is an estimator, so that
/// [`crate::Gated`] puts the method layer's boxed estimators behind the
/// gate as it puts an owned one.
impl<E: Estimator + ?Sized> Estimator for alloc::boxed::Box<E> {
    fn name(&self) -> &'static str {
        (**self).name()
    }
    fn outputs(&self) -> Outputs {
        (**self).outputs()
    }
    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        (**self).describe_parameters(out)
    }
    fn diagnostic_names(&self) -> &[&'static str] {
        (**self).diagnostic_names()
    }
    fn rejected_readings(&self) -> [u64; 3] {
        (**self).rejected_readings()
    }
    fn keeps_clipped_gyro(&self) -> bool {
        (**self).keeps_clipped_gyro()
    }
    fn keeps_clipped_acc(&self) -> bool {
        (**self).keeps_clipped_acc()
    }
    fn reset(&mut self) {
        (**self).reset()
    }
    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        (**self).step(sample)
    }
    fn step_into(&mut self, sample: &Sample, out: &mut Estimate) -> Result<(), EstimatorError> {
        (**self).step_into(sample, out)
    }
}

/// An offline estimator (e.g. a smoother): the estimate of a sample may use
/// samples after it, so estimates come out later than their samples, in
/// order, one per sample pushed ([`crate::runner::run_offline`]).
pub trait OfflineEstimator {
    /// The estimator as the estimate file's header describes it (name,
    /// outputs, parameters, diagnostic names).
    fn header(&self) -> &dyn Estimator;

    /// Takes the next sample.
    fn push(&mut self, sample: &Sample) -> Result<(), EstimatorError>;

    /// The next estimate, in sample order, once it is final.
    fn pop(&mut self) -> Option<Estimate>;

    /// No more samples: every estimate still held becomes final.
    fn finish(&mut self);
}

/// Tracks timestamps and yields the step `dt` of each new sample.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct TimeStep {
    previous: Option<f64>,
}

impl TimeStep {
    /// A tracker that has seen no sample.
    pub const fn new() -> Self {
        TimeStep { previous: None }
    }

    /// Whether sample time `t` may follow (finite, after the previous
    /// sample's), without registering it.
    pub fn check(&self, t: f64) -> Result<(), EstimatorError> {
        if !t.is_finite() {
            return Err(EstimatorError::NonFinite { channel: "t" });
        }
        match self.previous {
            Some(previous) if t <= previous => {
                Err(EstimatorError::NonIncreasingTime { previous, t })
            }
            _ => Ok(()),
        }
    }

    /// Registers sample time `t`: `Ok(None)` for the first sample, `Ok(Some(dt))` after.
    pub fn advance(&mut self, t: f64) -> Result<Option<f64>, EstimatorError> {
        self.check(t)?;
        let dt = self.previous.map(|previous| t - previous);
        self.previous = Some(t);
        Ok(dt)
    }

    /// Forgets the previous time.
    pub fn reset(&mut self) {
        self.previous = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dt_comes_from_timestamps_including_gaps() {
        let mut ts = TimeStep::new();
        assert_eq!(ts.advance(1.0).unwrap(), None);
        assert_eq!(ts.advance(1.01).unwrap(), Some(1.01 - 1.0));
        assert_eq!(ts.advance(1.5).unwrap(), Some(1.5 - 1.01));
    }

    #[test]
    fn non_increasing_time_is_an_error() {
        let mut ts = TimeStep::new();
        ts.advance(2.0).unwrap();
        assert_eq!(
            ts.advance(2.0),
            Err(EstimatorError::NonIncreasingTime {
                previous: 2.0,
                t: 2.0
            })
        );
        assert!(ts.advance(f64::NAN).is_err());
    }

    #[test]
    fn check_refuses_as_advance_does_without_registering() {
        let mut ts = TimeStep::new();
        assert_eq!(ts.check(5.0), Ok(()));
        ts.advance(1.0).unwrap();
        assert!(ts.check(1.0).is_err() && ts.check(f64::INFINITY).is_err());
        assert_eq!(ts.check(3.0), Ok(()));
        // nothing registered by `check`: 2.0 still follows 1.0
        assert_eq!(ts.advance(2.0).unwrap(), Some(1.0));
    }
}
