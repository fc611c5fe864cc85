//! The error-state machinery the three segment filters share: gyro
//! integration outside the Kalman filter, the 8-state error covariance,
//! initialisation (when and from what a segment starts: [`start`], ours),
//! missing-data handling, closed/open loop, diagnostics.
//!
//! Per segment `i` the filter keeps (000 eqs 5-6, 12-13):
//! * `theta_g,i`, the gyro-integrated angle: `d theta_g / dt = omega_gyro +
//!   b_hat` (000 eq 5), integrated with the trapezoidal rule on the gyro
//!   samples plus the exact integral of the decaying bias estimate;
//! * `b_hat_i`, the bias estimate in the papers' convention (000 eq 1: true
//!   rate = gyro reading + b), propagated by `d b_hat / dt = -b_hat / tau`
//!   (000 eq 6);
//! * the error state `x` = [dtheta, db] per segment and its covariance `P`.
//!
//! Robustness beyond the papers (issue 18, docs/ROBUST_INPUT.md; the
//! constants and their sources are in [`super::robust`]): a chi-square
//! innovation gate on the encoder rows, a held gyro rate that decays and
//! grows uncertain over a dropout, rates borrowed through the encoders
//! (filters with encoder rows), a restart after a long time gap, after
//! encoder rows refused for [`GATE_LOCKOUT_S`], and a per-segment restart
//! after a divergence (non-finite state or an angle variance beyond
//! `pi^2`); restarts are counted (`resets`).
#![allow(non_snake_case)]

use limbfuse_core::kalman::CovarianceUpdate;
use limbfuse_core::{Estimate, EstimatorError, Sample, TimeStep};
use nalgebra::{SVector, Vector3};

use super::criteria::reliability;
use super::model::{angle_state, bias_state, Discretizer, Mat8};
use super::params::{CommonParams, LoopMode};
use super::rate_spikes::RateSpikeTest;
use super::robust::{
    predicted_rate, predicted_rate_variance, rate_slope, FillContext, RateDropouts, GATE_LOCKOUT_S,
    HELD_RATE_VARIANCE_CAP, INNOVATION_GATE_CHI2, LONG_GAP_S,
};
use super::sequential;
use super::structured::{self, all_finite, ChainRow, Gain};
use crate::inclination::{accel_inclination, sagittal_specific_force};

mod start;
use start::StartWindow;

/// What the filters read from one sample, after cleaning.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Inputs {
    /// Finite accelerometer reading per segment (its inclination is
    /// [`Inputs::theta_a`]).
    pub acc: [Option<Vector3<f64>>; 4],
    /// `| ||a|| - g |` per segment.
    pub rho: [Option<f64>; 4],
    /// Encoders (hip, knee, ankle).
    pub encoder: [Option<f64>; 3],
    /// Gyro rates that were missing (empty or non-finite) in this sample.
    pub rate_missing: u8,
    /// Segment was initialised before this sample, so rows may use it.
    pub usable: [bool; 4],
}

impl Inputs {
    /// How many of this sample's inputs are missing (empty or non-finite):
    /// the four accelerometers and four gyro rates, plus the three encoders
    /// when `with_encoders`. Missing inputs drop their rows (gyros: the last
    /// rate is held); the count is the `missing_inputs` diagnostic.
    pub fn missing(&self, rate_missing: u8, with_encoders: bool) -> u8 {
        let acc = self.acc.iter().filter(|a| a.is_none()).count() as u8;
        let enc = if with_encoders {
            self.encoder.iter().filter(|e| e.is_none()).count() as u8
        } else {
            0
        };
        acc + rate_missing + enc
    }

    /// Accelerometer inclination `atan2(acc_x, acc_y)` of segment `i`
    /// (computed on demand: most samples use few of the four).
    #[inline]
    pub fn theta_a(&self, i: usize) -> Option<f64> {
        self.acc[i].as_ref().map(accel_inclination)
    }
}

#[derive(Debug, Clone)]
pub(crate) struct Chain {
    pub common: CommonParams,
    time: TimeStep,
    x: SVector<f64, 8>,
    P: Mat8,
    angle_g: [f64; 4],
    bias_hat: [f64; 4],
    last_rate: [Option<f64>; 4],
    /// Time of each rate's last reading (s; 0 before the first).
    last_rate_t: [f64; 4],
    /// Each rate's reading before the last and its time: the derivative
    /// for [`predicted_rate`] ([`rate_slope`]) is formed from them only
    /// when a dropout needs it, not at every reading.
    prev_rate: [(Option<f64>, f64); 4],
    init: [bool; 4],
    disc: Discretizer,
    /// Encoder standard deviations when the filter starts the whole chain
    /// from one accelerometer and the encoders ([`Chain::with_encoder_start`]).
    encoder_start: Option<[f64; 3]>,
    /// How long each gyro rate has been missing (s).
    rate_gap: [f64; 4],
    /// Own-gyro dropouts and rate power (rates held or borrowed).
    dropouts: RateDropouts,
    /// Encoders of the previous sample (for rates borrowed through them).
    last_encoder: [Option<f64>; 3],
    /// Time of the current sample (s).
    now: f64,
    /// Since when each joint's encoder row has been refused every time it
    /// was offered (s).
    encoders_gated_since: [Option<f64>; 3],
    /// Encoder rows the innovation gate rejected.
    gated_encoder: u64,
    /// Restarts after a long time gap or a divergence.
    resets: u64,
    /// Time of the first sample since the (re)start (for `startup_s`).
    first_t: Option<f64>,
    /// The segments' wait for a start ([`start`]).
    start: StartWindow,
    /// Gyroscope spikes told from the encoders (kept over restarts: it
    /// tests the sensors, not the filter).
    spikes: RateSpikeTest,
    /// The filter has encoder rows, so the spike test may use the
    /// encoders ([`Chain::with_spike_test`]; `local` has none).
    encoder_rows: bool,
}

fn finite(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}

/// Wraps an angle difference to [-pi, pi]: `remainder(a, 2 pi)`, which is
/// `a` itself for `|a| <= pi` (quotient 0, ties to even), so called only beyond.
#[inline]
pub(crate) fn wrap(a: f64) -> f64 {
    let inside = libm::fabs(a) <= core::f64::consts::PI;
    if inside {
        a
    } else {
        libm::remainder(a, core::f64::consts::TAU)
    }
}

impl Chain {
    pub fn new(common: CommonParams) -> Self {
        Chain {
            time: TimeStep::new(),
            x: SVector::zeros(),
            P: Self::p0(&common),
            angle_g: [0.0; 4],
            bias_hat: Self::bias0(&common),
            last_rate: [None; 4],
            last_rate_t: [0.0; 4],
            prev_rate: [(None, 0.0); 4],
            init: [false; 4],
            disc: Discretizer::new(&common.segments, common.discretization),
            common,
            encoder_start: None,
            rate_gap: [0.0; 4],
            dropouts: RateDropouts::default(),
            last_encoder: [None; 3],
            now: 0.0,
            encoders_gated_since: [None; 3],
            gated_encoder: 0,
            resets: 0,
            first_t: None,
            start: StartWindow::default(),
            spikes: RateSpikeTest::default(),
            encoder_rows: false,
        }
    }

    /// The chain of a filter with encoder rows (`mjls`, `global`): when
    /// `common.rate_spike_test` is on, a gyroscope reading the encoders show
    /// to be a spike is replaced by the rate they imply or held
    /// ([`RateSpikeTest`]).
    pub fn with_spike_test(self) -> Self {
        Chain {
            encoder_rows: true,
            ..self
        }
    }

    /// A chain that, when its first sample has all three encoders, starts
    /// every segment from the most reliable accelerometer (argmin rho) and the
    /// encoders instead of each segment from its own accelerometer (see
    /// [`Chain::initialise_from_encoders`]). For filters with encoder rows.
    pub fn with_encoder_start(common: CommonParams, encoder_sigma: [f64; 3]) -> Self {
        Chain {
            encoder_start: Some(encoder_sigma),
            ..Chain::new(common)
        }
    }

    fn p0(common: &CommonParams) -> Mat8 {
        let mut p = Mat8::zeros();
        for i in 0..4 {
            p[(angle_state(i), angle_state(i))] = common.p0_angle_sigma * common.p0_angle_sigma;
            p[(bias_state(i), bias_state(i))] = common.p0_bias_sigma * common.p0_bias_sigma;
        }
        p
    }

    fn bias0(common: &CommonParams) -> [f64; 4] {
        // Sensor convention (gyro = true + beta) -> papers' b = -beta.
        let mut b = [0.0; 4];
        for (bi, beta) in b.iter_mut().zip(common.initial_gyro_bias.iter()) {
            *bi = -*beta;
        }
        b
    }

    pub fn reset(&mut self) {
        let (start, encoder_rows) = (self.encoder_start, self.encoder_rows);
        *self = Chain::new(self.common);
        self.encoder_start = start;
        self.encoder_rows = encoder_rows;
    }

    /// Starts every segment afresh from the next data, keeping the time and
    /// the counts (a restart, counted in `resets`).
    fn restart(&mut self) {
        let (time, now, gated, resets) = (self.time, self.now, self.gated_encoder, self.resets);
        let spikes = self.spikes;
        self.reset();
        self.time = time;
        self.now = now;
        self.gated_encoder = gated;
        self.resets = resets + 1;
        self.spikes = spikes;
    }

    /// Encoder rows rejected by the innovation gate so far.
    pub fn gated_encoders(&self) -> u64 {
        self.gated_encoder
    }

    /// Gyroscope readings refused as spikes so far ([`RateSpikeTest`]).
    pub fn refused_rates(&self) -> u64 {
        self.spikes.refused()
    }

    /// Restarts so far (long gaps, divergences).
    pub fn resets(&self) -> u64 {
        self.resets
    }

    /// Restarts segment `i` from its next accelerometer reading when its
    /// state is no longer a usable estimate: a non-finite angle, bias or
    /// variance, or an angle variance beyond `pi^2` (the angle is unknown to
    /// more than half a turn). The other segments keep their state.
    fn restart_diverged(&mut self) {
        for i in 0..4 {
            let (a, b) = (angle_state(i), bias_state(i));
            let ok = self.angle_g[i].is_finite()
                && self.bias_hat[i].is_finite()
                && self.P[(a, a)].is_finite()
                && self.P[(b, b)].is_finite()
                && self.P[(a, a)] <= core::f64::consts::PI * core::f64::consts::PI;
            if self.init[i] && !ok {
                self.restart_segment(i);
            }
        }
    }

    /// Forgets segment `i` (its next accelerometer reading restarts it) and counts a restart.
    fn restart_segment(&mut self, i: usize) {
        let (a, b) = (angle_state(i), bias_state(i));
        self.init[i] = false;
        self.clear_segment(i, 0.0);
        self.P[(a, a)] = self.common.p0_angle_sigma * self.common.p0_angle_sigma;
        self.P[(b, b)] = self.common.p0_bias_sigma * self.common.p0_bias_sigma;
        self.rate_gap[i] = 0.0;
        self.start.forget(i);
        self.resets += 1;
    }

    /// Advances time, integrates the gyros, predicts the covariance,
    /// initialises new segments and returns the cleaned measurements.
    pub fn begin(&mut self, sample: &Sample) -> Result<Inputs, EstimatorError> {
        let dt = self.time.advance(sample.t)?;
        self.now = sample.t;
        let g = self.common.gravity;
        let mut accs = [None; 4];
        let mut rho = [None; 4];
        let mut rate = [None; 4];
        for (i, imu) in sample.imu.iter().enumerate() {
            if let Some(acc) = sagittal_specific_force(imu) {
                // (a norm that overflows, e.g. 1e300 on an axis, is no reading:
                // found by tests/integration/issue_18_fuzz.rs as an infinite `rho` diagnostic)
                // (a finite norm, the square root of the sum of the squares,
                // implies finite axes: no test per axis)
                let r = reliability(&acc, g);
                if r.is_finite() {
                    accs[i] = Some(acc);
                    rho[i] = Some(r);
                }
            }
            // the sagittal rate, also from an incomplete vector (issue 18)
            rate[i] = imu.gyr_axis(2).and_then(finite);
        }
        let mut encoder = [None; 3];
        for (e, s) in encoder.iter_mut().zip(sample.encoder.iter()) {
            // A joint angle beyond a full turn is no reading (found by
            // tests/integration/issue_18_fuzz.rs: -1e308 started the chain at infinity).
            // (NaN and infinity fail the comparison too)
            *e = s.filter(|v| v.abs() <= core::f64::consts::TAU);
        }
        if self.encoder_rows && self.common.rate_spike_test {
            self.spikes.check(&mut rate, &encoder, dt);
        }
        let rate_missing = rate.iter().filter(|r| r.is_none()).count() as u8;
        let own_gap_before = self.dropouts.observe(&rate, dt);
        // `fill` only replaces missing rates: nothing to do without one
        // (and then the held rates it would be given are not computed).
        if let (Some(sigma), Some(dt), true) = (self.encoder_start, dt, rate_missing > 0) {
            // (only a missing rate is replaced by its held value: no `exp` else)
            let held: [Option<f64>; 4] = core::array::from_fn(|i| {
                (self.init[i] && rate[i].is_none())
                    .then(|| self.held_rate(i, self.rate_gap[i] + dt))
                    .flatten()
            });
            let sigma_e = sigma.iter().fold(0.0f64, |m, s| m.max(*s));
            let ctx = FillContext {
                held: &held,
                own_gap_before: &own_gap_before,
                encoder: &encoder,
                last_encoder: &self.last_encoder,
                sigma_e,
                dt,
            };
            self.dropouts.fill(&mut rate, &ctx);
        }
        self.last_encoder = encoder;
        match dt {
            Some(dt) if dt > LONG_GAP_S && self.init.iter().any(|&i| i) => self.restart(),
            Some(dt) => self.predict(dt, &rate),
            None => {}
        }
        self.restart_diverged();
        let usable = self.init;
        self.first_t.get_or_insert(sample.t);
        self.start_segments(sample.t, &accs, &rho, &rate, &encoder);
        for (i, rate) in rate.iter().enumerate() {
            if let Some(r) = *rate {
                self.prev_rate[i] = (self.last_rate[i], self.last_rate_t[i]);
                self.last_rate[i] = Some(r);
                self.last_rate_t[i] = sample.t;
            }
        }
        Ok(Inputs {
            acc: accs,
            rho,
            encoder,
            rate_missing,
            usable,
        })
    }

    /// Segment `i`'s rate predicted over a dropout of `tau` s from its last
    /// reading and slope ([`predicted_rate`]); `None` if none was seen.
    fn held_rate(&self, i: usize, tau: f64) -> Option<f64> {
        let slope = rate_slope(self.last_rate[i], self.last_rate_t[i], self.prev_rate[i]);
        self.last_rate[i].map(|r| predicted_rate(r, slope, tau))
    }

    fn predict(&mut self, dt: f64, rate: &[Option<f64>; 4]) {
        let (last_rate, last_t, prev) = (&self.last_rate, &self.last_rate_t, &self.prev_rate);
        let blocks = self.disc.blocks(dt);
        for (i, rate) in rate.iter().enumerate() {
            if !self.init[i] {
                continue;
            }
            // Over a gyro dropout the rate is predicted from the last reading
            // and its slope, tending to zero after a stride
            // (`predicted_rate`); zero if none was ever seen.
            let tau = self.rate_gap[i];
            let held = |t: f64| {
                let slope = rate_slope(last_rate[i], last_t[i], prev[i]);
                last_rate[i].map(|r| predicted_rate(r, slope, t))
            };
            // The decay is evaluated only over a dropout (`tau == 0`: the
            // held rate is the last rate itself, the same arithmetic).
            let r1 = match rate {
                Some(r) => *r,
                None => held(tau + dt).unwrap_or(0.0),
            };
            let r0 = if tau == 0.0 {
                last_rate[i].unwrap_or(r1)
            } else {
                held(tau).unwrap_or(r1)
            };
            let phi = &blocks.phi[i];
            // theta_g += int omega dt + int b_hat dt, b_hat(t) = b_hat e^(-t/tau):
            // the second integral is Phi[a, b] * b_hat (exact or Euler, as Phi).
            self.angle_g[i] += 0.5 * (r0 + r1) * dt + phi[(0, 1)] * self.bias_hat[i];
            self.bias_hat[i] *= phi[(1, 1)];
        }
        structured::predict_blocks(&mut self.x, &mut self.P, &blocks.phi, &blocks.qd);
        self.dropouts
            .grow_over_time_gap(&mut self.P, &self.init, dt);
        for (i, rate) in rate.iter().enumerate() {
            if rate.is_some() || !self.init[i] {
                self.rate_gap[i] = 0.0;
                continue;
            }
            // The held rate grows uncertain over a gyro dropout.
            let before = predicted_rate_variance(self.rate_gap[i]);
            self.rate_gap[i] += dt;
            let a = angle_state(i);
            let grown = self.P[(a, a)] + predicted_rate_variance(self.rate_gap[i]) - before;
            self.P[(a, a)] = grown.min(HELD_RATE_VARIANCE_CAP.max(self.P[(a, a)]));
        }
        if !(all_finite(self.x.as_slice()) && all_finite(self.P.as_slice())) {
            // Only reachable with absurd steps or parameters: restart the
            // uncertainty instead of propagating non-finite values.
            self.fold_error_state();
            self.P = Self::p0(&self.common);
            self.resets += 1;
        }
    }

    /// Current angle estimate of segment `i` (000 eq 12): `theta_g + dtheta_hat`.
    #[inline]
    pub fn angle(&self, i: usize) -> f64 {
        self.angle_g[i] + self.x[angle_state(i)]
    }

    /// Estimated gyro bias in the sensor convention (gyro = true + bias),
    /// i.e. `-(b_hat + db_hat)` of 000 eq 13.
    #[inline]
    pub fn gyro_bias(&self, i: usize) -> f64 {
        -(self.bias_hat[i] + self.x[bias_state(i)])
    }

    #[inline]
    pub fn angle_sd(&self, i: usize) -> f64 {
        libm::sqrt(self.P[(angle_state(i), angle_state(i))].max(0.0))
    }

    #[inline]
    pub fn initialised(&self, i: usize) -> bool {
        self.init[i]
    }

    pub fn covariance(&self) -> &Mat8 {
        &self.P
    }

    pub fn error_state(&self) -> &SVector<f64, 8> {
        &self.x
    }

    /// Measurement update with innovations `innov` (already wrapped) on the
    /// active `rows`, measurement variances `r` (diagonal `R`). The rows
    /// marked in `encoder` pass the innovation gate
    /// ([`INNOVATION_GATE_CHI2`]) first: a failing row is made inactive in
    /// `active` and counted. Returns whether an update was made; its gain
    /// and innovation are then in `gain` (otherwise unspecified).
    pub fn update<const M: usize>(
        &mut self,
        innov: &SVector<f64, M>,
        rows: &[ChainRow; M],
        r: &[f64; M],
        active: &mut [bool; M],
        encoder: &[bool; M],
        gain: &mut Gain<M>,
    ) -> bool {
        let mut locked_out = false;
        for k in 0..M {
            if !(active[k] && encoder[k]) {
                continue;
            }
            let row = rows[k];
            let p = |s: usize, t: usize| self.P[(angle_state(s), angle_state(t))];
            let hph = match row.minus {
                Some(m) => p(row.plus, row.plus) + p(m, m) - 2.0 * p(row.plus, m),
                None => p(row.plus, row.plus),
            };
            let nis = innov[k] * innov[k] / (hph + r[k]);
            let since = &mut self.encoders_gated_since[row.plus.min(2)];
            if nis <= INNOVATION_GATE_CHI2 {
                *since = None;
            } else {
                active[k] = false;
                self.gated_encoder += 1;
                locked_out |= self.now - *since.get_or_insert(self.now) >= GATE_LOCKOUT_S;
            }
        }
        if locked_out {
            self.restart();
            return false;
        }
        // Joseph (default): row by row; standard: batch
        let (x, P, form) = (&mut self.x, &mut self.P, self.common.covariance_update);
        let made = active.iter().any(|&a| a)
            && if form == CovarianceUpdate::Joseph {
                sequential::update_rows_into(x, P, innov, rows, r, active, gain).is_ok()
            } else {
                structured::update_rows(x, P, innov, rows, r, active, form)
                    .map(|u| *gain = u)
                    .is_ok()
            };
        if made && self.common.loop_mode == LoopMode::Closed {
            self.fold_error_state();
        }
        made
    }

    /// Closed-loop reset (SPEC section 6): angle correction into the
    /// integrated angle, bias correction into the bias estimate, x = 0.
    fn fold_error_state(&mut self) {
        for i in 0..4 {
            let (a, b) = (angle_state(i), bias_state(i));
            if self.x[a].is_finite() && self.x[b].is_finite() {
                self.angle_g[i] += self.x[a];
                self.bias_hat[i] += self.x[b];
            }
        }
        self.x = SVector::zeros();
    }

    /// Overwrites `est` with an estimate at `t`: the segment angles
    /// (initialised segments only) and the joint angles as their
    /// differences; none during the run-in (`startup_s`) after a (re)start.
    pub fn estimate_into(&self, t: f64, est: &mut Estimate) {
        *est = Estimate::empty(t);
        let w = self.common.startup_s;
        let settled = self
            .first_t
            .is_none_or(|t0| t - t0 >= w - 1e-9 * w.max(1.0));
        for i in 0..4 {
            if self.init[i] && settled {
                est.segment[i] = Some(self.angle(i));
            }
        }
        est.fill_joints_from_segments();
    }
}
