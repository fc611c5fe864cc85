//! How the segment filters start and restart (ours: papers 000 and 001 do
//! not say how their filters start; docs/SEGMENT_FILTERS.md,
//! "Initialisation").
//!
//! One accelerometer sample cannot tell the inclination of a moving limb: a
//! dynamic acceleration of about `g` turns the specific force by up to 60
//! deg without changing its norm, so even `rho < zeta` (the papers' own
//! test) admits tens of degrees mid-stride (measured: docs/RESULTS.md, "The
//! paper filters started mid-walk"). A segment therefore starts:
//!
//! * at the first sample at which it is **quasi-static**: `rho_i < zeta_i`
//!   (the papers' reliability test, SPEC section 6) and `|omega_i| <
//!   sqrt(zeta_i / SEGMENT_REACH_M)` (the rotation's own centripetal
//!   acceleration below `zeta_i`), both held for [`START_HOLD_S`]: the
//!   stationary-phase test of zero-velocity detectors (Skog et al., IEEE
//!   TBME 57(11), 2010). Standing, and the flat foot of every stance, pass
//!   at once; or
//! * when none came within [`START_WINDOW_S`] of its (re)start, at the
//!   gravity direction of that window: the mean of its specific force
//!   rotated back to the window's first sample by the integrated gyro rate.
//!   The mean dynamic acceleration of a body point over a window of length
//!   `T` is its velocity change over `T` divided by `T`: zero over whole
//!   strides of steady walking (periodic velocity), and over a window of a
//!   stride or more a fraction of `g` only as large as the point's
//!   velocity swing over `g T` (as `chain`'s start-up window,
//!   docs/CHAIN.md).
//!
//! Until then the segment has no estimate (`None`) and no row uses it. The
//! Markov-jump filter starts the whole chain at once from one segment and
//! the encoders ([`Chain::initialise_from_encoders`]): from the quasi-static
//! segment of smallest `rho`, else after the window from the trunk's
//! window (the segment whose velocity swings least in walking).

use limbfuse_core::Segment;
use nalgebra::{SVector, Vector3};

use super::{wrap, Chain};
use crate::inclination::accel_inclination;
use crate::segment_kf::model::{angle_state, bias_state, Mat8};

/// Distance (m) from a segment's rotation centre to its sensor bounding the
/// centripetal acceleration `omega^2 r` of a quasi-static start: the length
/// of the longest leg segment (thigh 0.245 H = 0.43 m for a 1.75 m body,
/// Winter's anthropometric table), rounded up.
pub(crate) const SEGMENT_REACH_M: f64 = 0.5;

/// How long (s) a segment must have been quasi-static to start from its
/// accelerometer: five samples at 100 Hz, the window of the stationary
/// detectors of Skog et al. (2010), short against a stance's flat-foot
/// phase (0.2-0.4 s).
pub(crate) const START_HOLD_S: f64 = 0.05;

/// The longest wait (s) for a quasi-static sample before a segment starts
/// from its window's gravity direction: one stride at the slowest walking
/// cadence (stride frequency 0.5 Hz), so the window spans at least one
/// stride of walking at any speed.
pub(crate) const START_WINDOW_S: f64 = 2.0;

/// Tolerance (s) on those durations, for timestamps that are not exact
/// multiples of the sample period or are large (at t = 1.7e9 s one unit in
/// the last place is 2.4e-7 s), as the accelerometer gate's hold.
const START_EPS_S: f64 = 1e-6;

/// Largest velocity change (m/s) of a leg segment's sensor between the
/// two ends of a start window: the swing-phase speed of a shank or thigh
/// point, up to twice a brisk walking speed (1 m/s).
pub(crate) const VELOCITY_SWING_MPS: f64 = 2.0;

/// The window start's tilt error is at most `VELOCITY_SWING_MPS / (g T)`
/// over a window of `T` = [`START_WINDOW_S`]; taken uniform, its variance
/// `(dv / (g T))^2 / 3` written as the `rho` whose dynamic-tilt allowance
/// `2 rho / (3 g)` equals it: `dv^2 / (2 g T^2)` (with g = 9.81).
const WINDOW_RHO: f64 =
    VELOCITY_SWING_MPS * VELOCITY_SWING_MPS / (2.0 * 9.81 * START_WINDOW_S * START_WINDOW_S);

/// The start-up state of the four segments: per segment since when it
/// waits, since when it has been quasi-static, its gyro angle since the
/// window's first sample and the derotated specific-force sum. Fixed size.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct StartWindow {
    since: [Option<f64>; 4],
    still_since: [Option<f64>; 4],
    still_acc: [Vector3<f64>; 4],
    phi: [f64; 4],
    rate: [Option<f64>; 4],
    last_t: [f64; 4],
    sum: [(f64, f64); 4],
}

/// What segment `i` can start from at this sample.
#[derive(Debug, Clone, Copy)]
struct Ready {
    quasi_static: Option<(f64, f64)>,
    window: Option<f64>,
}

impl StartWindow {
    /// Segment `i` waits afresh from its next sample.
    pub fn forget(&mut self, i: usize) {
        self.since[i] = None;
        self.still_since[i] = None;
    }

    /// Adds one sample of segment `i` (not started): its specific force
    /// `acc` with reliability `rho`, its rate (`None`: held) plus the bias
    /// estimate `b0`.
    #[allow(clippy::too_many_arguments)]
    fn observe(
        &mut self,
        i: usize,
        t: f64,
        acc: Option<Vector3<f64>>,
        rho: Option<f64>,
        rate: Option<f64>,
        b0: f64,
        zeta: f64,
    ) -> Ready {
        match self.since[i] {
            None => {
                self.since[i] = Some(t);
                self.phi[i] = 0.0;
                self.sum[i] = (0.0, 0.0);
                self.rate[i] = rate;
            }
            Some(_) => {
                let dt = t - self.last_t[i];
                let r1 = rate.or(self.rate[i]).unwrap_or(0.0);
                let r0 = self.rate[i].unwrap_or(r1);
                self.phi[i] += (0.5 * (r0 + r1) + b0) * dt;
                if rate.is_some() {
                    self.rate[i] = rate;
                }
            }
        }
        self.last_t[i] = t;
        if let Some(a) = acc {
            let (s, c) = (libm::sin(self.phi[i]), libm::cos(self.phi[i]));
            self.sum[i].0 += a.x * c - a.y * s;
            self.sum[i].1 += a.y * c + a.x * s;
        }
        let (sx, sy) = self.sum[i];
        if !(self.phi[i].is_finite() && sx.is_finite() && sy.is_finite()) {
            // absurd readings (a rate or a force beyond any sensor, found by
            // tests/integration/issue_18_fuzz.rs): the window begins again
            self.since[i] = Some(t);
            self.phi[i] = 0.0;
            self.sum[i] = (0.0, 0.0);
        }
        let max_rate = libm::sqrt(zeta / SEGMENT_REACH_M);
        // (a missing gyro sample holds the last rate, as the filter does)
        let slow = rate.or(self.rate[i]).map(|w| libm::fabs(w) < max_rate);
        let still = match (acc, rho) {
            (Some(a), Some(r)) if r < zeta && slow == Some(true) => {
                // the specific force held within zeta of its value at the
                // hold's first sample (no changing acceleration)
                let first = self.still_since[i].is_none();
                if first {
                    self.still_acc[i] = a;
                }
                first || (a - self.still_acc[i]).norm() < zeta
            }
            // a sample without its accelerometer vector (an axis missing)
            // is no evidence either way: a hold goes on through it while
            // the rate stays slow, and the start waits for a sample that has
            // one (with 20 % of the cells missing, 6 complete samples in a
            // row came once in 200: the start fell back to the window)
            (None, _) | (_, None) => self.still_since[i].is_some() && slow != Some(false),
            _ => false,
        };
        if !still {
            self.still_since[i] = None;
        }
        let held = still && t - *self.still_since[i].get_or_insert(t) >= START_HOLD_S - START_EPS_S;
        let quasi_static = match (held, acc, rho) {
            (true, Some(a), Some(r)) => Some((accel_inclination(&a), r)),
            _ => None,
        };
        let waited = self.since[i].is_some_and(|t0| t - t0 >= START_WINDOW_S - START_EPS_S);
        let (sx, sy) = self.sum[i];
        let window =
            (waited && (sx != 0.0 || sy != 0.0)).then(|| wrap(libm::atan2(sx, sy) + self.phi[i]));
        Ready {
            quasi_static,
            window,
        }
    }
}

impl Chain {
    /// Starts the segments that are not started yet and can be (module
    /// doc): with the encoder start and all three encoders, the whole chain
    /// at once; otherwise each segment on its own.
    pub(super) fn start_segments(
        &mut self,
        t: f64,
        accs: &[Option<Vector3<f64>>; 4],
        rho: &[Option<f64>; 4],
        rate: &[Option<f64>; 4],
        encoder: &[Option<f64>; 3],
    ) {
        if self.init == [true; 4] {
            return;
        }
        if self.common.first_sample_start {
            self.start_at_first_sample(accs, rho, encoder);
            return;
        }
        let mut ready = [None; 4];
        for i in 0..4 {
            if !self.init[i] {
                let zeta = self.common.segments[i].zeta;
                let b0 = -self.common.initial_gyro_bias[i];
                ready[i] = Some(self.start.observe(i, t, accs[i], rho[i], rate[i], b0, zeta));
            }
        }
        if let (Some(sigma), [false, false, false, false], [Some(h), Some(k), Some(a)]) =
            (self.encoder_start, self.init, *encoder)
        {
            let still = (0..4)
                .filter_map(|i| Some((i, ready[i]?.quasi_static?)))
                .min_by(|x, y| x.1 .1.total_cmp(&y.1 .1));
            let trunk = Segment::Trunk.index();
            let from_window = || Some((trunk, (ready[trunk]?.window?, WINDOW_RHO)));
            if let Some((i, (th, r))) = still.or_else(from_window) {
                self.initialise_from_encoders(i, th, r, [h, k, a], sigma);
                return;
            }
        }
        for (i, ready) in ready.iter().enumerate() {
            let Some(ready) = ready else { continue };
            if let Some((th, r)) = ready
                .quasi_static
                .or(ready.window.map(|th| (th, WINDOW_RHO)))
            {
                self.initialise(i, th, r);
            }
        }
    }

    /// The start of limbfuse before 2026-12-06
    /// ([`CommonParams::first_sample_start`](crate::segment_kf::CommonParams)):
    /// each segment at its first accelerometer inclination, or with the
    /// encoder start the whole chain from the argmin `rho` segment.
    fn start_at_first_sample(
        &mut self,
        accs: &[Option<Vector3<f64>>; 4],
        rho: &[Option<f64>; 4],
        encoder: &[Option<f64>; 3],
    ) {
        if let (Some(sigma), [false, false, false, false], [Some(h), Some(k), Some(a)]) =
            (self.encoder_start, self.init, *encoder)
        {
            let best = (0..4)
                .filter_map(|i| Some((i, rho[i]?, accel_inclination(&accs[i]?))))
                .min_by(|x, y| x.1.total_cmp(&y.1));
            if let Some((i, r, th)) = best {
                self.initialise_from_encoders(i, th, r, [h, k, a], sigma);
            }
        }
        for i in 0..4 {
            if let (false, Some(a), Some(r)) = (self.init[i], accs[i], rho[i]) {
                self.initialise(i, accel_inclination(&a), r);
            }
        }
    }

    /// Segment `i` at angle `theta` with the initial bias, its error state
    /// zero and its rows and columns of `P` zero (the caller sets the
    /// diagonal).
    pub(super) fn clear_segment(&mut self, i: usize, theta: f64) {
        let (a, b) = (angle_state(i), bias_state(i));
        self.angle_g[i] = theta;
        self.bias_hat[i] = -self.common.initial_gyro_bias[i];
        self.x[a] = 0.0;
        self.x[b] = 0.0;
        for k in 0..8 {
            for s in [a, b] {
                self.P[(s, k)] = 0.0;
                self.P[(k, s)] = 0.0;
            }
        }
    }

    /// Starts segment `i` at the inclination `theta`. The
    /// initial angle variance is `p0_angle_sigma^2` plus the dynamic-tilt
    /// allowance for the reliability `rho` of that very sample, `2 rho / (3
    /// g)` (the tilt admitted by `| ||a|| - g | = rho`, taken uniform, see
    /// `SegmentNoise::consumer_mems`; a window start counts as
    /// [`WINDOW_RHO`]), capped at `(pi/2)^2`.
    pub(super) fn initialise(&mut self, i: usize, theta: f64, rho: f64) {
        let (a, b) = (angle_state(i), bias_state(i));
        self.clear_segment(i, theta);
        let dynamic = (2.0 * rho / (3.0 * self.common.gravity))
            .min(core::f64::consts::FRAC_PI_2 * core::f64::consts::FRAC_PI_2);
        self.P[(a, a)] = self.common.p0_angle_sigma * self.common.p0_angle_sigma + dynamic;
        self.P[(b, b)] = self.common.p0_bias_sigma * self.common.p0_bias_sigma;
        self.init[i] = true;
    }

    /// Starts all four segments at once: segment `k` at the inclination
    /// `theta` (initial variance as in [`Chain::initialise`]),
    /// the others through the joint chain `theta_{j+1} = theta_j - enc_j`
    /// (SPEC section 1). The angle covariance is the exact one of that
    /// construction: `cov(theta_i, theta_j) = v + sum of the encoder
    /// variances on the part of the path from `k` that `i` and `j` share`,
    /// so the started angles are as correlated as they really are. Not in the
    /// papers (which do not say how the filters start); without it a filter
    /// started mid-stride carries each distal segment's poor first
    /// inclination (tens of degrees for the foot in swing) until its own
    /// accelerometer is next reliable, even though the encoders pin it to its
    /// neighbours.
    pub(super) fn initialise_from_encoders(
        &mut self,
        k: usize,
        theta: f64,
        rho: f64,
        enc: [f64; 3],
        enc_sigma: [f64; 3],
    ) {
        let mut angle = [theta; 4];
        for i in k + 1..4 {
            angle[i] = angle[i - 1] - enc[i - 1];
        }
        for i in (0..k).rev() {
            angle[i] = angle[i + 1] + enc[i];
        }
        // encoder j lies on the path from k to i when it sits between them
        let on_path = |j: usize, i: usize| (i > k && j >= k && j < i) || (i < k && j >= i && j < k);
        let dynamic = (2.0 * rho / (3.0 * self.common.gravity))
            .min(core::f64::consts::FRAC_PI_2 * core::f64::consts::FRAC_PI_2);
        let v = self.common.p0_angle_sigma * self.common.p0_angle_sigma + dynamic;
        self.P = Mat8::zeros();
        for i in 0..4 {
            for m in 0..4 {
                let shared: f64 = (0..3)
                    .filter(|&j| on_path(j, i) && on_path(j, m))
                    .map(|j| enc_sigma[j] * enc_sigma[j])
                    .sum();
                self.P[(angle_state(i), angle_state(m))] = v + shared;
            }
            let b = bias_state(i);
            self.P[(b, b)] = self.common.p0_bias_sigma * self.common.p0_bias_sigma;
            self.bias_hat[i] = -self.common.initial_gyro_bias[i];
        }
        self.angle_g = angle;
        self.x = SVector::zeros();
        self.init = [true; 4];
    }
}

#[cfg(test)]
mod tests {
    use crate::segment_kf::{CommonParams, LocalKf, LocalKfParams};
    use limbfuse_core::{Estimator, Sample};
    use nalgebra::Vector3;

    /// One segment (the trunk) swinging `theta = 0.3 sin(2 pi t)` at 1 Hz
    /// while its sensor accelerates forward by `5 cos(2 pi t)` m/s^2 (zero
    /// mean over a period): at t = 0 the specific force points 27 deg off
    /// the segment's inclination, its norm only 1.2 m/s^2 above g.
    fn swinging(t: f64) -> (Sample, f64) {
        let w = core::f64::consts::TAU;
        let theta = 0.3 * libm::sin(w * t);
        let (fx, fy) = (5.0 * libm::cos(w * t), 9.80665);
        let (s, c) = (libm::sin(theta), libm::cos(theta));
        let mut sample = Sample::empty(t);
        sample.imu[0].acc = Some(Vector3::new(fx * c + fy * s, -fx * s + fy * c, 0.0));
        sample.imu[0].gyr = Some(Vector3::new(0.0, 0.0, 0.3 * w * libm::cos(w * t)));
        (sample, theta)
    }

    fn local(first_sample_start: bool) -> LocalKf {
        LocalKf::new(LocalKfParams {
            common: CommonParams {
                first_sample_start,
                ..CommonParams::default()
            },
            min_reliable: 1,
        })
        .unwrap()
    }

    #[test]
    fn a_swinging_accelerating_segment_starts_from_its_window_not_its_first_sample() {
        // first-sample start: 27 deg off at t = 0
        let (s0, th0) = swinging(0.0);
        let old = local(true).step(&s0).unwrap().segment[0].unwrap();
        assert!((old - th0).abs().to_degrees() > 20.0, "{old} vs {th0}");
        let mut f = local(false);
        for k in 0..=250 {
            let t = k as f64 * 0.01;
            let (s, th) = swinging(t);
            let e = f.step(&s).unwrap().segment[0];
            if t < 2.0 - 1e-9 {
                // never quasi-static: its specific force keeps changing
                assert_eq!(e, None, "t = {t}");
            } else if k == 200 {
                // the window spans two whole periods: the dynamic
                // acceleration averages out
                let d = (e.unwrap() - th).abs().to_degrees();
                assert!(d < 1.0, "{d} deg off at the start");
            }
        }
    }

    #[test]
    fn a_still_segment_starts_after_its_hold_at_its_inclination() {
        let mut f = local(false);
        let a = Vector3::new(libm::sin(0.2), libm::cos(0.2), 0.0) * 9.80665;
        for k in 0..10 {
            let mut s = Sample::empty(k as f64 * 0.01);
            s.imu[0].acc = Some(a);
            s.imu[0].gyr = Some(Vector3::zeros());
            let e = f.step(&s).unwrap().segment[0];
            // quasi-static for 0.05 s from the sixth sample on
            assert_eq!(e.is_some(), k >= 5, "k = {k}");
            if let Some(v) = e {
                assert!((v - 0.2).abs() < 1e-12, "{v}");
            }
        }
    }
}
