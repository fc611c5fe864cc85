//! Knee angle from the relative gyro rate about the identified joint axes
//! (`knee-gyro-axis`, issue 15 item 4; beyond the papers): a second,
//! independent estimate to cross-check `knee-selfalign` (paper 002).
//!
//! The axes `j_T`, `j_S` and their signs are those `knee-selfalign`
//! identifies (an inner [`KneeSelfAlign`]: Algorithm 2 on `e_j`, the sign
//! rules of [`crate::knee_selfalign::sign`]). The angle is *not* paper 002's:
//!
//! - `alpha_gyro = integral(g_T . j_T - g_S . j_S) dt` (eq 4, trapezoidal);
//! - drift removal by a first-order complementary filter with corner
//!   `f_c` (default 0.02 Hz, time constant `1 / (2 pi f_c)` = 8 s), towards
//!   the **inclination angle** `alpha_inc = atan2(u_T x u_S, u_T . u_S)` of
//!   the raw specific forces projected into each sensor's joint plane (eq 5
//!   with `Gamma` left out: at low frequency the specific force is gravity,
//!   so `alpha_inc` is the difference of the segments' inclinations about the
//!   joint axis), or, where that inclination is not observable, towards 0,
//!   which makes the output the gyro angle high-passed at `f_c`:
//!   `x <- x + k (wrap(alpha_inc - alpha_gyro) - x)` or `x <- x + k (-alpha_gyro
//!   - x)`, `k = 1 - exp(-2 pi f_c dt)`, output `wrap(alpha_gyro + x)`.
//!
//! Observability is judged per window of the inner estimator (`s_w`
//! samples): the inclination is used in the next window when over the last
//! one `alpha_inc - alpha_gyro` had a circular spread of at most
//! `acc_max_spread` while `alpha_gyro` itself spread at least
//! `acc_min_motion` (the same test as `knee-selfalign`'s, without the
//! sensor positions) and `knee-selfalign`'s own test passed on that window
//! (its accelerometer angle, with the joint acceleration, is trusted; never
//! after a rest whose accelerometer norm was off g, `knee_selfalign::rest_gravity`).
//! It fails when the joint axis is near vertical (no gravity in the joint
//! plane), when the accelerometers are far off (the knee rig: 1.1-1.24 g at
//! rest, a ~1 g offset along its joint axis, which is not vertical), or when
//! the knee is not a hinge (the gaittoolbox trial). With
//! the high-pass the zero is the mean angle: compare offset-free.
//! Details and measured figures: `docs/KNEE_SELFALIGN.md`.

use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{diagnostic_set, Estimate, Estimator, EstimatorError, Joint, Sample, TimeStep};
use nalgebra::Vector3;

use crate::knee_selfalign::angle::{gyro_angle_rate, wrap};
use crate::knee_selfalign::sign::{SegmentedCircular, GAP_SPLIT_PERIODS, GAP_SPLIT_S};
use crate::knee_selfalign::{KneeParamError, KneeSelfAlign, KneeSelfAlignParams};
use crate::segment_kf::robust::HELD_RATE_CORRELATION_S;

diagnostic_set! {
    /// Diagnostics of [`KneeGyroAxis`].
    pub enum KneeGyroDiag {
        /// 1 once the axes are identified (the knee angle is output), else 0.
        Identified = "identified",
        /// 1 while the inclination angle removes the drift, 0 while the
        /// high-pass does.
        InclinationUsed = "inclination_used",
        /// Integrated relative gyro rate about the axes (rad).
        AlphaGyro = "alpha_gyro",
        /// Inclination angle of this sample (rad).
        AlphaInc = "alpha_inc",
        /// Correction added to `alpha_gyro` (rad).
        Correction = "correction",
        /// Circular spread of `alpha_inc - alpha_gyro` over the last window.
        IncGyroSpread = "inc_gyro_spread",
        /// Sign confidence of the axes (from the inner `knee-selfalign`).
        SignConfidence = "sign_confidence",
        /// Windows completed.
        Windows = "windows",
        /// Thigh joint axis `j_1` in use, x (sensor frame; the inner
        /// `knee-selfalign`'s, sides as used; review 27: the report's
        /// knee-axis panel).
        JThighX = "j_thigh_x",
        /// Thigh joint axis `j_1`, y.
        JThighY = "j_thigh_y",
        /// Thigh joint axis `j_1`, z.
        JThighZ = "j_thigh_z",
        /// Shank joint axis `j_2` in use, x (sensor frame).
        JShankX = "j_shank_x",
        /// Shank joint axis `j_2`, y.
        JShankY = "j_shank_y",
        /// Shank joint axis `j_2`, z.
        JShankZ = "j_shank_z",
        /// Thigh-shank time offset in use (s; the inner `knee-selfalign`'s
        /// delay search, positive: the shank lags).
        SensorDelay = "sensor_delay_s",
        /// Samples the inner `knee-selfalign`'s windows left out of their
        /// position fits so far as gross eq-3 outliers (a gyroscope spike;
        /// `knee_selfalign::position_outliers`).
        PositionOutliers = "position_outliers",
    }
}

impl KneeGyroDiag {
    /// `j_thigh_*`, `j_shank_*` (`[sensor][component]`).
    pub const AXIS: [[KneeGyroDiag; 3]; 2] = [
        [
            KneeGyroDiag::JThighX,
            KneeGyroDiag::JThighY,
            KneeGyroDiag::JThighZ,
        ],
        [
            KneeGyroDiag::JShankX,
            KneeGyroDiag::JShankY,
            KneeGyroDiag::JShankZ,
        ],
    ];
}

/// Time constant (s) of the smoothing of `alpha_inc - alpha_gyro` before
/// the observability test: one stride of walking at a normal cadence
/// (~1.1 s, Perry, *Gait Analysis*, 1992, ch. 1), over which the segments'
/// own accelerations in the specific force largely average out while a
/// meaningless inclination keeps its slow errors.
const STRIDE_S: f64 = 1.0;

/// Samples by which the accelerometer angle trails (the five-point rate
/// derivative of `Gamma`).
const LAG: usize = crate::knee_selfalign::position::DERIVATIVE_LATENCY;

/// Parameters of [`KneeGyroAxis`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KneeGyroAxisParams {
    /// The axis identification (window, order, sign rules; the fusion
    /// settings of `knee-selfalign` are not used for the angle).
    pub axes: KneeSelfAlignParams,
    /// Corner frequency `f_c` of the drift removal (Hz). Default 0.02 Hz:
    /// time constant 8 s; a 1 Hz gait cycle keeps 99.98 % of its amplitude
    /// and a 0.5 deg/s relative gyro bias leaves 4 deg.
    pub corner_hz: f64,
}

impl Default for KneeGyroAxisParams {
    fn default() -> Self {
        KneeGyroAxisParams {
            axes: KneeSelfAlignParams::default(),
            corner_hz: 0.02,
        }
    }
}

impl KneeGyroAxisParams {
    /// Checks every value; the error names the first bad one.
    pub fn validate(&self) -> Result<(), KneeParamError> {
        self.axes.validate()?;
        if self.corner_hz.is_finite() && self.corner_hz > 0.0 && self.corner_hz <= 10.0 {
            Ok(())
        } else {
            Err(KneeParamError {
                name: "corner_hz",
                value: self.corner_hz,
                range: "(0, 10] Hz",
            })
        }
    }
}

/// The knee angle from the relative gyro rate about the identified axes.
#[derive(Debug, Clone)]
pub struct KneeGyroAxis {
    params: KneeGyroAxisParams,
    inner: KneeSelfAlign,
    time: TimeStep,
    axes: Option<[Vector3<f64>; 2]>,
    alpha: f64,
    last_rate: Option<f64>,
    x: f64,
    use_inclination: bool,
    windows: usize,
    diff: SegmentedCircular,
    motion: SegmentedCircular,
    last_spread: f64,
    smoothed: Option<(f64, f64)>,
    recent_alpha: [Option<f64>; LAG + 1],
    z: f64,
    start_pending: bool,
    /// Time (s) since the last knee rate.
    gyro_gap: f64,
    /// The gyro angle at the last knee rate (rad): a short gap is bridged
    /// from it (up to [`GAP_SPLIT_S`]).
    alpha_at_rate: f64,
    /// Time (s) since the last accelerometer angle the correction used.
    since_inclination: f64,
    /// Samples until the correction restarts after a gap.
    reanchor_in: Option<usize>,
    /// Shortest time step of the recording so far (s): the sampling period.
    period: f64,
}

impl KneeGyroAxis {
    /// A validated estimator (allocates the inner window once, here).
    pub fn new(params: KneeGyroAxisParams) -> Result<Self, KneeParamError> {
        params.validate()?;
        Ok(KneeGyroAxis {
            params,
            inner: KneeSelfAlign::new(params.axes)?,
            time: TimeStep::new(),
            axes: None,
            alpha: 0.0,
            last_rate: None,
            x: 0.0,
            use_inclination: false,
            windows: 0,
            diff: SegmentedCircular::default(),
            motion: SegmentedCircular::default(),
            last_spread: 1.0,
            smoothed: None,
            recent_alpha: [None; LAG + 1],
            z: 0.0,
            start_pending: false,
            gyro_gap: 0.0,
            alpha_at_rate: 0.0,
            since_inclination: 0.0,
            reanchor_in: None,
            period: f64::INFINITY,
        })
    }

    /// The parameters in use.
    pub fn params(&self) -> &KneeGyroAxisParams {
        &self.params
    }

    /// The inner axis identification.
    pub fn axes_estimator(&self) -> &KneeSelfAlign {
        &self.inner
    }

    /// Decides, at the end of an inner window, whether the next window uses
    /// the inclination (see the module documentation).
    fn end_window(&mut self) {
        let p = &self.params.axes;
        if self.diff.count() > 0 {
            let spread = self.diff.spread();
            self.last_spread = spread;
            // The inclination leaves out the joint acceleration: it is used
            // only where the full accelerometer angle (eq 5 with `Gamma`) of
            // the inner estimator follows the gyro angle too. On the
            // gaittoolbox turn window the one-stride smoothing hid a
            // difference swinging by ~100 deg per stride (issue 15).
            if spread > p.acc_max_spread || !self.inner.acc_trusted() {
                self.use_inclination = false;
            } else if self.motion.spread() >= p.acc_min_motion {
                if !self.use_inclination {
                    // From the high-pass to the inclination: start at the
                    // window's mean offset instead of converging to it
                    // with the 8 s time constant.
                    self.x = self.diff.mean();
                }
                self.use_inclination = true;
            }
        }
        self.diff = SegmentedCircular::default();
        self.motion = SegmentedCircular::default();
    }

    fn restart(&mut self) {
        self.alpha = 0.0;
        self.last_rate = None;
        self.x = 0.0;
        self.use_inclination = false;
        self.diff = SegmentedCircular::default();
        self.motion = SegmentedCircular::default();
        self.last_spread = 1.0;
        self.smoothed = None;
        self.recent_alpha = [None; LAG + 1];
        self.z = 0.0;
        self.start_pending = false;
        self.gyro_gap = 0.0;
        self.alpha_at_rate = 0.0;
        self.since_inclination = 0.0;
        self.reanchor_in = None;
    }
}

impl Estimator for KneeGyroAxis {
    fn name(&self) -> &'static str {
        "knee-gyro-axis"
    }

    fn outputs(&self) -> Outputs {
        Outputs {
            joint: [false, true, false],
            ..Outputs::default()
        }
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        writeln!(out, "inputs: raw thigh and shank IMUs (any mounting)")?;
        writeln!(out, "corner_hz: {}", self.params.corner_hz)?;
        writeln!(out, "axes (knee-selfalign identification):")?;
        self.params.axes.describe(out)
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        &KneeGyroDiag::NAMES
    }

    fn reset(&mut self) {
        self.inner.reset();
        self.time.reset();
        self.axes = None;
        self.windows = 0;
        self.period = f64::INFINITY;
        self.restart();
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        self.inner.step(sample)?;
        let dt = self.time.advance(sample.t)?;
        let dt = dt.map(|d| self.inner.on_stamp_grid(d));
        // A time gap (rows missing: a step over `GAP_SPLIT_S` and
        // `GAP_SPLIT_PERIODS` sampling periods) is a dropout too: no
        // trapezoid across it (an audit: 0.5 s of rows removed from the
        // independent 0.7 m/s walk left the knee 10-35 deg off for 10 s).
        let time_gap = dt.is_some_and(|d| d > GAP_SPLIT_S && d > GAP_SPLIT_PERIODS * self.period);
        if let Some(d) = dt.filter(|_| !time_gap) {
            self.period = self.period.min(d);
        }
        if self.inner.windows() != self.windows {
            self.windows = self.inner.windows();
            self.end_window();
        }
        let mut est = Estimate::empty(sample.t);
        let mut alpha_inc = None;
        if let Some(g) = self.inner.geometry().copied() {
            let same_sides = self
                .axes
                .is_some_and(|a| a[0].dot(&g.axis[0]) >= 0.0 && a[1].dot(&g.axis[1]) >= 0.0);
            // The gyro angles of the last samples with the new axes (this
            // sample's 0): the accelerometer angle LAG samples back has its
            // gyro angle from the first sample on (issue 15 item 3: without
            // it the first LAG outputs were the bare integral from 0, 58 deg
            // off on the shared 1.6 m/s walk at 40 Hz).
            let mut backfill = None;
            if !same_sides {
                // New axes (or new sides): the integral starts afresh, with
                // the inner estimator's verdict on the accelerometer angle
                // of the window that identified them; the correction starts
                // at the first difference.
                self.restart();
                self.use_inclination = self.inner.acc_trusted();
                self.start_pending = true;
                backfill = Some(self.inner.recent_gyro_angles());
            }
            self.axes = Some(g.axis);
            // The readings as the inner estimator paired them (its delay
            // search; the input's own without an offset).
            let [thigh, shank] = self.inner.aligned();
            let rate = match (thigh.gyr, shank.gyr) {
                (Some(gt), Some(gs)) => Some(gyro_angle_rate(&gt, &gs, &g.axis[0], &g.axis[1])),
                _ => None,
            };
            if let Some((angles, _)) = backfill {
                self.alpha = 0.0;
                self.alpha_at_rate = 0.0;
                self.last_rate = rate;
                self.recent_alpha = core::array::from_fn(|k| angles[4 - LAG + k]);
            } else {
                // Over a dropout the last rate is held decaying towards 0
                // (`HELD_RATE_CORRELATION_S`, as knee-selfalign and the
                // segment filters; issue 18). Before, it was held constant:
                // a 1 s gap of both IMUs mid-walk left the knee 21.6 deg RMSE
                // over the next 5 s. After a gap longer than `GAP_SPLIT_S`
                // the gyro angle's error over it is unknown: the window's
                // statistics start a new part, and with the inclination in
                // use the correction restarts at the first difference.
                let step = dt.unwrap_or(0.0);
                let held = |t: f64| {
                    self.last_rate
                        .map(|r| r * libm::exp(-t / HELD_RATE_CORRELATION_S))
                };
                // (The decay is evaluated only over a dropout: with no gap
                // the held rate is the last rate itself.)
                let r1 = rate.or_else(|| held(self.gyro_gap + step));
                let r0 = if self.gyro_gap == 0.0 {
                    self.last_rate
                } else {
                    held(self.gyro_gap)
                }
                .or(r1);
                if time_gap {
                    self.gyro_gap += step;
                } else if let (Some(dt), Some(r0), Some(r1)) = (dt, r0, r1) {
                    self.alpha = match (rate, self.last_rate) {
                        // The first rate after a short gap: one trapezoid
                        // from the last rate across the whole gap replaces
                        // the held rate's extrapolation.
                        (Some(r), Some(last))
                            if self.gyro_gap > 0.0 && self.gyro_gap + dt <= GAP_SPLIT_S =>
                        {
                            self.alpha_at_rate + 0.5 * (last + r) * (self.gyro_gap + dt)
                        }
                        _ => self.alpha + 0.5 * (r0 + r1) * dt,
                    };
                }
                if rate.is_some() {
                    self.alpha_at_rate = self.alpha;
                    if self.gyro_gap > GAP_SPLIT_S {
                        self.diff.split();
                        self.motion.split();
                        self.smoothed = None;
                        self.reanchor_in = Some(LAG + 1);
                    }
                    self.last_rate = rate;
                    self.gyro_gap = 0.0;
                } else if !time_gap {
                    self.gyro_gap += step;
                }
                // The accelerometer angle is that of the sample LAG steps
                // back: compare it with the gyro angle of that sample.
                self.recent_alpha.rotate_left(1);
                self.recent_alpha[LAG] = Some(self.alpha);
            }
            alpha_inc = self.inner.lagged_accel_angle();
            let lagged = self.recent_alpha[0].zip(alpha_inc).map(|(g, a)| a - g);
            if let Some(d) = lagged {
                // The difference, smoothed over about one stride (as a unit
                // vector, so that it may cross +-pi), is what the test sees.
                let (s, c) = libm::sincos(d);
                let k1 = 1.0 - libm::exp(-dt.unwrap_or(0.0) / STRIDE_S);
                let (ls, lc) = match self.smoothed {
                    Some((ls, lc)) => (ls + k1 * (s - ls), lc + k1 * (c - lc)),
                    None => (s, c),
                };
                self.smoothed = Some((ls, lc));
                self.diff.add(libm::atan2(ls, lc));
                self.motion.add(self.alpha);
            }
            let k = 1.0
                - libm::exp(-core::f64::consts::TAU * self.params.corner_hz * dt.unwrap_or(0.0));
            if let (true, Some(d)) = (self.start_pending, lagged) {
                self.x = if self.use_inclination { d } else { 0.0 };
                self.start_pending = false;
            }
            // Back from a gap: once the lagged comparison is past it.
            // (The accelerometer angle needs a few readings after the gap:
            // the first difference may come later still.)
            match (self.reanchor_in, lagged) {
                (Some(0), Some(d)) => {
                    self.reanchor_in = None;
                    if self.use_inclination {
                        self.x = d;
                    }
                }
                (Some(0), None) => {}
                (Some(n), _) => self.reanchor_in = Some(n - 1),
                (None, _) => {}
            }
            match (self.use_inclination, lagged) {
                (true, Some(d)) => {
                    // Second-order (PI) complementary filter, critically
                    // damped at omega_n = 2 pi f_c: the integral state z
                    // takes up a relative gyro bias, which a first-order
                    // filter would leave as a lag of b tau. The error acts
                    // over the time since the last accelerometer angle (held
                    // in between; at most a stride), so that the loop keeps
                    // its corner when that angle comes on few samples
                    // (empty cells: 16 % of the samples with a twentieth of
                    // the cells empty).
                    let dt = dt.unwrap_or(0.0);
                    let h = (self.since_inclination + dt).min(STRIDE_S);
                    self.since_inclination = 0.0;
                    let w = core::f64::consts::TAU * self.params.corner_hz;
                    let e = wrap(d - self.x);
                    self.z += w * w * e * h;
                    self.x += 2.0 * w * e * h + self.z * dt;
                }
                // No accelerometer angle on this sample: the integral state
                // (the relative rate bias) still acts on the correction.
                (true, None) => {
                    let dt = dt.unwrap_or(0.0);
                    self.since_inclination += dt;
                    self.x += self.z * dt;
                }
                (false, _) => self.x += k * (-self.alpha - self.x),
            }
            // Between a gap and the re-anchoring the gyro angle misses the
            // knee's motion over the gap: no knee angle until then.
            if !(self.use_inclination && self.reanchor_in.is_some()) {
                est.joint[Joint::Knee.index()] = Some(wrap(self.alpha + self.x));
            }
        }
        let (confidence, _) = self.inner.sign_state();
        let identified = self.axes.is_some();
        let mut d = est.diagnostics_mut::<KneeGyroDiag>();
        d.flag(KneeGyroDiag::Identified, identified);
        d.value(KneeGyroDiag::Windows, self.windows as f64);
        d.value(KneeGyroDiag::SensorDelay, self.inner.sensor_delay_s());
        d.value(
            KneeGyroDiag::PositionOutliers,
            self.inner.position_outliers() as f64,
        );
        if identified {
            d.flag(KneeGyroDiag::InclinationUsed, self.use_inclination);
            d.value(KneeGyroDiag::AlphaGyro, self.alpha);
            d.set(KneeGyroDiag::AlphaInc, alpha_inc);
            d.value(KneeGyroDiag::Correction, self.x);
            d.value(KneeGyroDiag::IncGyroSpread, self.last_spread);
            d.value(KneeGyroDiag::SignConfidence, confidence);
        }
        if let Some(axes) = &self.axes {
            for (names, axis) in KneeGyroDiag::AXIS.iter().zip(axes) {
                for (name, v) in names.iter().zip(axis.iter()) {
                    d.value(*name, *v);
                }
            }
        }
        Ok(est)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn high_pass_gain_matches_the_first_order_filter() {
        // A constant rate b: the high-passed integral of a ramp settles at
        // -b tau (the step response of s / (s + 1/tau) to b / s^2).
        let mut x = 0.0;
        let (dt, fc, b) = (0.01, 0.02, 0.1);
        let tau = 1.0 / (core::f64::consts::TAU * fc);
        let k = 1.0 - libm::exp(-dt / tau);
        let mut alpha = 0.0;
        for _ in 0..(100.0 * tau / dt) as usize {
            alpha += b * dt;
            x += k * (-alpha - x);
        }
        let out = alpha + x;
        assert!(
            (out - b * tau).abs() < 0.01 * b * tau,
            "{out} vs {}",
            b * tau
        );
    }

    #[test]
    fn bad_corner_is_named() {
        let e = KneeGyroAxis::new(KneeGyroAxisParams {
            corner_hz: 0.0,
            ..Default::default()
        })
        .unwrap_err();
        assert_eq!(e.name, "corner_hz");
    }
}
