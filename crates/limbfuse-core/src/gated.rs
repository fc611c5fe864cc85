//! An estimator behind the sensor gate, as `limbfuse estimate` runs every
//! method (issue 18 item 1), without `std` or allocation: what a controller
//! puts in its sample loop to get the command-line tool's estimates bit for
//! bit.
//!
//! [`EstimatorGate`] is the part in front of the estimator; [`Gated`] puts
//! it in front of an owned estimator (`no_std`, no allocation), or a boxed
//! one (the method layer's `limbfuse_methods::gated::GatedEstimator`). Per
//! sample it
//!
//! 1. refuses a sample whose time is not finite or not after the last
//!    accepted sample's ([`EstimatorError::NonFinite`] for channel `t`,
//!    [`EstimatorError::NonIncreasingTime`]) before the gate sees it, so a
//!    refused sample leaves no trace and the loop may go on with the next;
//! 2. screens the sample with its [`SampleGate`]: readings out of the
//!    sensor's range, not finite, clipped at the gyroscope's full scale,
//!    jumping faster than a human segment can accelerate, or stuck, become
//!    missing ([`crate::sample_gate`], docs/ROBUST_INPUT.md);
//! 3. steps the estimator (which predicts without the missing readings);
//! 4. makes any non-finite output missing and resets the estimator, so that
//!    it starts afresh from the next sample ("finite or missing");
//! 5. writes the cumulative rejection counts (the gate's and the
//!    estimator's own innovation gates', [`Estimator::rejected_readings`])
//!    as the diagnostics [`REJECTION_DIAGNOSTICS`] after the estimator's
//!    own, when they fit in [`MAX_DIAG`].

use core::fmt;

use crate::estimate::{Estimate, MAX_DIAG};
use crate::estimator::{Estimator, EstimatorError, Outputs, TimeStep};
use crate::sample::Sample;
use crate::sample_gate::{Rejections, SampleGate, SensorRanges};

/// Names of the gate's diagnostics, in the order they follow the
/// estimator's own (`diag_rejected_gyro`, ... columns): cumulative counts of
/// rejected gyroscope vectors, accelerometer vectors and encoder readings.
pub const REJECTION_DIAGNOSTICS: [&str; 3] = ["rejected_gyro", "rejected_acc", "rejected_encoder"];

/// The sensor gate and time check in front of one estimator (module
/// documentation); it does not own the estimator, which each call is given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EstimatorGate {
    gate: SampleGate,
    /// The times of the samples stepped without error.
    time: TimeStep,
    /// Index of `rejected_gyro` in [`Estimate::diag`], if written.
    first: Option<usize>,
}

impl EstimatorGate {
    /// A gate with `ranges` in front of an estimator with
    /// `inner_diagnostics` diagnostic values of its own.
    pub fn new(ranges: SensorRanges, inner_diagnostics: usize) -> Self {
        EstimatorGate {
            gate: SampleGate::new(ranges),
            time: TimeStep::new(),
            first: (inner_diagnostics + REJECTION_DIAGNOSTICS.len() <= MAX_DIAG)
                .then_some(inner_diagnostics),
        }
    }

    /// The sample gate (its ranges, limits and what it rejected).
    pub fn sample_gate(&self) -> &SampleGate {
        &self.gate
    }

    /// Index of `rejected_gyro` in [`Estimate::diag`] (`rejected_acc` and
    /// `rejected_encoder` follow); `None` when they do not fit.
    pub fn rejections_at(&self) -> Option<usize> {
        self.first
    }

    /// Readings rejected so far, `[gyroscope, accelerometer, encoder]`: the
    /// gate's and `inner`'s own.
    pub fn rejected_readings<E: Estimator + ?Sized>(&self, inner: &E) -> [u64; 3] {
        let r = self.gate.rejections();
        let [g, a, n] = inner.rejected_readings();
        [r.gyro + g, r.acc + a, r.encoder + n]
    }

    /// Forgets the gate's counts and history and the last time (the caller
    /// resets its estimator).
    pub fn reset(&mut self) {
        self.gate.reset();
        self.time.reset();
    }

    /// The estimate-file header line of the ranges
    /// (`sensor_range: gyro ... rad/s, ...`).
    pub fn describe(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        let r = self.gate.ranges();
        writeln!(
            out,
            "sensor_range: gyro {} rad/s, acc {} m/s2, encoder {} rad (readings beyond are treated as missing)",
            r.gyro_rad_s, r.acc_m_s2, r.encoder_rad
        )
    }

    /// Steps `inner` on `sample` through the gate into `e` (module
    /// documentation); `seen`, when given, becomes the sample as `inner`
    /// saw it (the rejected readings missing). On an error `e` holds no
    /// meaningful value and nothing is remembered of `sample`.
    #[inline]
    pub fn step_into<E: Estimator + ?Sized>(
        &mut self,
        inner: &mut E,
        sample: &Sample,
        e: &mut Estimate,
        seen: Option<&mut Sample>,
    ) -> Result<(), EstimatorError> {
        // A sample the estimator would refuse for its time is refused
        // before the gate sees it: a refused sample leaves no trace in the
        // gate's counts and tests (Python's `Filter` goes on after an error).
        self.time.check(sample.t)?;
        // Most samples pass the gate unchanged: no copy of the sample then.
        let screening = self.gate.check(sample);
        if screening.is_clean() {
            inner.step_into(sample, e)?;
            if let Some(s) = seen {
                *s = *sample;
            }
        } else {
            let mut screened = *sample;
            screening.apply(&mut screened);
            inner.step_into(&screened, e)?;
            if let Some(s) = seen {
                *s = screened;
            }
        }
        if !outputs_finite(e) {
            blank_non_finite(e);
            inner.reset();
        }
        // (checked above)
        let _ = self.time.advance(sample.t);
        if let Some(i) = self.first {
            let [g, a, n] = self.rejected_readings(inner);
            e.diag[i] = Some(g as f64);
            e.diag[i + 1] = Some(a as f64);
            e.diag[i + 2] = Some(n as f64);
        }
        Ok(())
    }
}

/// An estimator behind an [`EstimatorGate`], owned: what `limbfuse
/// estimate` runs, for a controller's loop (`no_std`, no allocation; the
/// estimate is the command-line tool's bit for bit).
///
/// ```
/// use limbfuse_core::gated::Gated;
/// use limbfuse_core::{Estimate, Estimator, Sample, SensorRanges};
/// # use limbfuse_core::{Outputs, EstimatorError};
/// # struct Hold;
/// # impl Estimator for Hold {
/// #     fn name(&self) -> &'static str { "hold" }
/// #     fn outputs(&self) -> Outputs { Outputs::default() }
/// #     fn describe_parameters(&self, _: &mut dyn core::fmt::Write) -> core::fmt::Result { Ok(()) }
/// #     fn reset(&mut self) {}
/// #     fn step(&mut self, s: &Sample) -> Result<Estimate, EstimatorError> { Ok(Estimate::empty(s.t)) }
/// # }
/// let mut filter = Gated::new(Hold, SensorRanges::default());
/// let mut out = Estimate::empty(0.0);
/// let mut s = Sample::empty(0.0);
/// s.encoder[1] = Some(f64::NAN); // a driver's NaN: made missing and counted
/// filter.step_into(&s, &mut out).unwrap();
/// assert_eq!(filter.rejected_readings(), [0, 0, 1]);
/// ```
#[derive(Debug, Clone)]
pub struct Gated<E> {
    gate: EstimatorGate,
    /// The estimator's diagnostic names, then [`REJECTION_DIAGNOSTICS`]
    /// (when they fit), in the first `n_names` entries.
    names: [&'static str; MAX_DIAG],
    n_names: usize,
    inner: E,
}

impl<E: Estimator> Gated<E> {
    /// `inner` behind a gate with `ranges` ([`SensorRanges::default`]: the
    /// datasheet full scales of gait IMUs, 2000 deg/s and 16 g), without
    /// the clipping test of the gyroscopes or accelerometers when `inner`
    /// keeps such clipped readings ([`Estimator::keeps_clipped_gyro`],
    /// [`Estimator::keeps_clipped_acc`]).
    pub fn new(inner: E, mut ranges: SensorRanges) -> Self {
        if inner.keeps_clipped_gyro() {
            ranges.gyro_full_scale_rad_s = None;
        }
        if inner.keeps_clipped_acc() {
            ranges.acc_full_scale_m_s2 = None;
        }
        let own = inner.diagnostic_names();
        let n_own = own.len().min(MAX_DIAG);
        let gate = EstimatorGate::new(ranges, n_own);
        let mut names = [""; MAX_DIAG];
        names[..n_own].copy_from_slice(&own[..n_own]);
        let mut n_names = n_own;
        if let Some(i) = gate.rejections_at() {
            names[i..i + REJECTION_DIAGNOSTICS.len()].copy_from_slice(&REJECTION_DIAGNOSTICS);
            n_names += REJECTION_DIAGNOSTICS.len();
        }
        Gated {
            gate,
            names,
            n_names,
            inner,
        }
    }

    /// The estimator behind the gate.
    pub fn inner(&self) -> &E {
        &self.inner
    }

    /// As [`Estimator::step_into`]; `seen` becomes the sample as the
    /// estimator saw it (the readings the gate rejected missing), for an
    /// offline pass that reuses the readings (the method layer's knee
    /// backfill).
    pub fn step_seen(
        &mut self,
        sample: &Sample,
        e: &mut Estimate,
        seen: &mut Sample,
    ) -> Result<(), EstimatorError> {
        self.gate.step_into(&mut self.inner, sample, e, Some(seen))
    }

    /// What the gate rejected since construction or the last reset, by
    /// kind and reason (the estimator's own rejections are in
    /// [`Estimator::rejected_readings`]).
    pub fn rejections(&self) -> &Rejections {
        self.gate.sample_gate().rejections()
    }
}

impl<E: Estimator> Estimator for Gated<E> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn outputs(&self) -> Outputs {
        self.inner.outputs()
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        self.inner.describe_parameters(out)?;
        self.gate.describe(out)
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        &self.names[..self.n_names]
    }

    fn rejected_readings(&self) -> [u64; 3] {
        self.gate.rejected_readings(&self.inner)
    }

    fn keeps_clipped_gyro(&self) -> bool {
        self.inner.keeps_clipped_gyro()
    }

    fn keeps_clipped_acc(&self) -> bool {
        self.inner.keeps_clipped_acc()
    }

    fn reset(&mut self) {
        self.inner.reset();
        self.gate.reset();
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let mut e = Estimate::empty(sample.t);
        self.step_into(sample, &mut e)?;
        Ok(e)
    }

    fn step_into(&mut self, sample: &Sample, e: &mut Estimate) -> Result<(), EstimatorError> {
        self.gate.step_into(&mut self.inner, sample, e, None)
    }
}

/// Whether every angle, speed and centre-of-mass output is finite or missing.
fn outputs_finite(e: &Estimate) -> bool {
    let ok = |v: &Option<f64>| v.is_none_or(|x| x.is_finite());
    let ok3 =
        |v: &Option<nalgebra::Vector3<f64>>| v.is_none_or(|v| v.iter().all(|x| x.is_finite()));
    e.segment.iter().all(ok)
        && e.joint.iter().all(ok)
        && ok(&e.speed)
        && ok3(&e.com_pos)
        && ok3(&e.com_vel)
}

/// Makes every non-finite output and diagnostic missing.
fn blank_non_finite(e: &mut Estimate) {
    let blank = |v: &mut Option<f64>| {
        if v.is_some_and(|x| !x.is_finite()) {
            *v = None;
        }
    };
    e.segment
        .iter_mut()
        .chain(e.joint.iter_mut())
        .chain(e.diag.iter_mut())
        .for_each(blank);
    blank(&mut e.speed);
    for v in [&mut e.com_pos, &mut e.com_vel] {
        if v.is_some_and(|v| v.iter().any(|x| !x.is_finite())) {
            *v = None;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    /// Integrates the thigh gyro's z rate; outputs whatever it integrates
    /// (a non-finite angle when given one), counts one rejected encoder
    /// reading of its own per sample with a knee encoder.
    #[derive(Default)]
    struct Integrator {
        angle: f64,
        last_t: Option<f64>,
        own_rejections: u64,
        resets: u32,
    }

    impl Estimator for Integrator {
        fn name(&self) -> &'static str {
            "integrator"
        }
        fn outputs(&self) -> Outputs {
            Outputs::default()
        }
        fn describe_parameters(&self, _: &mut dyn fmt::Write) -> fmt::Result {
            Ok(())
        }
        fn diagnostic_names(&self) -> &[&'static str] {
            &["own"]
        }
        fn rejected_readings(&self) -> [u64; 3] {
            [0, 0, self.own_rejections]
        }
        fn reset(&mut self) {
            self.angle = 0.0;
            self.last_t = None;
            self.resets += 1;
        }
        fn step(&mut self, s: &Sample) -> Result<Estimate, EstimatorError> {
            let mut e = Estimate::empty(s.t);
            if let (Some(t0), Some(g)) = (self.last_t, s.imu[1].gyr) {
                self.angle += g.z * (s.t - t0);
            }
            self.last_t = Some(s.t);
            self.own_rejections += u64::from(s.encoder[1].is_some());
            e.segment[1] = Some(self.angle);
            e.diag[0] = Some(1.0);
            Ok(e)
        }
    }

    fn sample(t: f64, rate: f64) -> Sample {
        let mut s = Sample::empty(t);
        s.imu[1].gyr = Some(Vector3::new(0.0, 0.0, rate));
        s
    }

    /// What a controller needs without `std`: the gate in front of an owned
    /// estimator, with the method layer's diagnostics, refusals and
    /// "finite or missing" rule (before, the gated estimator lived only in
    /// `limbfuse-methods`, which needs `std` and allocates).
    #[test]
    fn gated_screens_counts_refuses_and_keeps_outputs_finite_without_std() {
        let mut f = Gated::new(Integrator::default(), SensorRanges::default());
        assert_eq!(
            f.diagnostic_names(),
            &["own", "rejected_gyro", "rejected_acc", "rejected_encoder"]
        );
        let mut e = Estimate::empty(0.0);
        f.step_into(&sample(0.0, 1.0), &mut e).unwrap();
        // a driver's NaN: made missing (the angle holds) and counted
        f.step_into(&sample(0.01, f64::NAN), &mut e).unwrap();
        assert_eq!(e.segment[1], Some(0.0));
        assert_eq!(e.diag[1..4], [Some(1.0), Some(0.0), Some(0.0)]);
        // a repeated time is refused and leaves no trace in the gate
        let refused = f.step_into(&sample(0.01, 1e9), &mut e);
        assert!(matches!(
            refused,
            Err(EstimatorError::NonIncreasingTime { .. })
        ));
        assert_eq!(f.rejections().gyro, 1);
        f.step_into(&sample(0.02, 1.0), &mut e).unwrap();
        assert!((e.segment[1].unwrap() - 0.01).abs() < 1e-12);
        // the estimator's own rejections are added to the gate's
        let mut s = sample(0.03, 1.0);
        s.encoder[1] = Some(0.2);
        f.step_into(&s, &mut e).unwrap();
        assert_eq!(e.diag[3], Some(1.0));
        assert_eq!(f.rejected_readings(), [1, 0, 1]);
        // a reset starts a new recording: any time is accepted again
        f.reset();
        assert_eq!(f.rejections().total(), 0);
        f.step_into(&sample(0.0, 1.0), &mut e).unwrap();
        assert_eq!(f.inner().resets, 1);
    }

    #[test]
    fn a_non_finite_output_is_made_missing_and_the_estimator_reset() {
        // within range (40 rad/s) but integrating to infinity: the
        // estimator's own divergence, not the gate's
        let mut f = Gated::new(Integrator::default(), SensorRanges::default());
        let mut e = Estimate::empty(0.0);
        f.step_into(&sample(0.0, 1.0), &mut e).unwrap();
        f.step_into(&sample(1e308, 30.0), &mut e).unwrap();
        assert_eq!(e.segment[1], None);
        assert_eq!(f.inner().resets, 1);
        f.step_into(&sample(1e308 * 1.5, 1.0), &mut e).unwrap();
        assert_eq!(e.segment[1], Some(0.0));
    }
}
