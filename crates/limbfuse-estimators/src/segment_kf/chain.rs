//! The error-state machinery the three segment filters share: gyro
//! integration outside the Kalman filter, the 8-state error covariance,
//! initialisation, missing-data handling, closed/open loop, diagnostics.
//!
//! Per segment `i` the filter keeps (000 eqs 5-6, 12-13):
//! * `theta_g,i`, the gyro-integrated angle: `d theta_g / dt = omega_gyro +
//!   b_hat` (000 eq 5), integrated with the trapezoidal rule on the gyro
//!   samples plus the exact integral of the decaying bias estimate;
//! * `b_hat_i`, the bias estimate in the papers' convention (000 eq 1: true
//!   rate = gyro reading + b), propagated by `d b_hat / dt = -b_hat / tau`
//!   (000 eq 6);
//! * the error state `x` = [dtheta, db] per segment and its covariance `P`.
#![allow(non_snake_case)]

use limbfuse_core::{Estimate, EstimatorError, Sample, TimeStep};
use nalgebra::{SMatrix, SVector, Vector3};

use super::criteria::reliability;
use super::model::{angle_state, bias_state, Discretizer, Mat8};
use super::params::{CommonParams, LoopMode};
use super::structured::{self, all_finite, ChainRow, Gain};
use crate::inclination::accel_inclination;

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
}

impl Inputs {
    /// Accelerometer inclination `atan2(acc_x, acc_y)` of segment `i`
    /// (computed on demand: most samples use few of the four).
    #[inline]
    pub fn theta_a(&self, i: usize) -> Option<f64> {
        self.acc[i].as_ref().map(accel_inclination)
    }
}

/// How a measurement row relates to the segments (for the gain breakdown
/// of 001 Fig. 6).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowKind {
    /// An accelerometer-inclination row of segment `i`.
    Imu(usize),
    /// A joint row: encoder (MJLS) or accelerometer difference (global).
    Joint,
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
    init: [bool; 4],
    disc: Discretizer,
    /// Encoder standard deviations when the filter starts the whole chain
    /// from one accelerometer and the encoders ([`Chain::with_encoder_start`]).
    encoder_start: Option<[f64; 3]>,
}

fn finite(v: f64) -> Option<f64> {
    if v.is_finite() {
        Some(v)
    } else {
        None
    }
}

/// Wraps an angle difference to [-pi, pi].
#[inline]
pub(crate) fn wrap(a: f64) -> f64 {
    libm::remainder(a, core::f64::consts::TAU)
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
            init: [false; 4],
            disc: Discretizer::new(&common.segments, common.discretization),
            common,
            encoder_start: None,
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
        let start = self.encoder_start;
        *self = Chain::new(self.common);
        self.encoder_start = start;
    }

    /// Advances time, integrates the gyros, predicts the covariance,
    /// initialises new segments and returns the cleaned measurements.
    pub fn begin(&mut self, sample: &Sample) -> Result<Inputs, EstimatorError> {
        let dt = self.time.advance(sample.t)?;
        let g = self.common.gravity;
        let mut accs = [None; 4];
        let mut rho = [None; 4];
        let mut rate = [None; 4];
        for (i, imu) in sample.imu.iter().enumerate() {
            if let Some(acc) = imu.acc {
                if acc.iter().all(|v| v.is_finite()) {
                    accs[i] = Some(acc);
                    rho[i] = Some(reliability(&acc, g));
                }
            }
            rate[i] = imu.gyr.and_then(|w| finite(w.z));
        }
        let mut encoder = [None; 3];
        for (e, s) in encoder.iter_mut().zip(sample.encoder.iter()) {
            *e = s.and_then(finite);
        }
        if let Some(dt) = dt {
            self.predict(dt, &rate);
        }
        let usable = self.init;
        if let (Some(sigma), [false, false, false, false], [Some(h), Some(k), Some(a)]) =
            (self.encoder_start, self.init, encoder)
        {
            let best = (0..4)
                .filter_map(|i| Some((i, rho[i]?, accel_inclination(&accs[i]?))))
                .min_by(|x, y| x.1.total_cmp(&y.1));
            if let Some((i, r, th)) = best {
                self.initialise_from_encoders(i, th, r, [h, k, a], sigma);
            }
        }
        for i in 0..4 {
            if !self.init[i] {
                if let (Some(a), Some(r)) = (accs[i], rho[i]) {
                    self.initialise(i, accel_inclination(&a), r);
                }
            }
            if rate[i].is_some() {
                self.last_rate[i] = rate[i];
            }
        }
        Ok(Inputs {
            acc: accs,
            rho,
            encoder,
            rate_missing: rate.iter().filter(|r| r.is_none()).count() as u8,
            usable,
        })
    }

    /// Starts segment `i` at the accelerometer inclination `theta`. The
    /// initial angle variance is `p0_angle_sigma^2` plus the dynamic-tilt
    /// allowance for the reliability `rho` of that very sample, `2 rho / (3
    /// g)` (the tilt admitted by `| ||a|| - g | = rho`, taken uniform, see
    /// `SegmentNoise::consumer_mems`), capped at `(pi/2)^2`: a filter started
    /// while the limb moves knows its first angle is poor.
    fn initialise(&mut self, i: usize, theta: f64, rho: f64) {
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
        let dynamic = (2.0 * rho / (3.0 * self.common.gravity))
            .min(core::f64::consts::FRAC_PI_2 * core::f64::consts::FRAC_PI_2);
        self.P[(a, a)] = self.common.p0_angle_sigma * self.common.p0_angle_sigma + dynamic;
        self.P[(b, b)] = self.common.p0_bias_sigma * self.common.p0_bias_sigma;
        self.init[i] = true;
    }

    /// Starts all four segments at once: segment `k` at its accelerometer
    /// inclination `theta` (initial variance as in [`Chain::initialise`]),
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
    fn initialise_from_encoders(
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

    fn predict(&mut self, dt: f64, rate: &[Option<f64>; 4]) {
        let blocks = self.disc.blocks(dt);
        for (i, rate) in rate.iter().enumerate() {
            if !self.init[i] {
                continue;
            }
            // Zero-order hold over a gyro dropout; zero if none was ever seen.
            let r1 = rate.or(self.last_rate[i]).unwrap_or(0.0);
            let r0 = self.last_rate[i].unwrap_or(r1);
            let phi = &blocks.phi[i];
            // theta_g += int omega dt + int b_hat dt, b_hat(t) = b_hat e^(-t/tau):
            // the second integral is Phi[a, b] * b_hat (exact or Euler, as Phi).
            self.angle_g[i] += 0.5 * (r0 + r1) * dt + phi[(0, 1)] * self.bias_hat[i];
            self.bias_hat[i] *= phi[(1, 1)];
        }
        structured::predict_blocks(&mut self.x, &mut self.P, &blocks.phi, &blocks.qd);
        if !(all_finite(self.x.as_slice()) && all_finite(self.P.as_slice())) {
            // Only reachable with absurd steps or parameters: restart the
            // uncertainty instead of propagating non-finite values.
            self.fold_error_state();
            self.P = Self::p0(&self.common);
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
    /// active `rows`, measurement variances `r` (diagonal `R`). Returns the
    /// update (gain, innovation) when one was made.
    pub fn update<const M: usize>(
        &mut self,
        innov: &SVector<f64, M>,
        rows: &[ChainRow; M],
        r: &[f64; M],
        active: &[bool; M],
    ) -> Option<Gain<M>> {
        if !active.iter().any(|&a| a) {
            return None;
        }
        let u = structured::update_rows(
            &mut self.x,
            &mut self.P,
            innov,
            rows,
            r,
            active,
            self.common.covariance_update,
        )
        .ok()?;
        if self.common.loop_mode == LoopMode::Closed {
            self.fold_error_state();
        }
        Some(u)
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

    /// An estimate with the segment angles (initialised segments only) and
    /// the joint angles as their differences.
    pub fn estimate(&self, t: f64) -> Estimate {
        let mut est = Estimate::empty(t);
        for i in 0..4 {
            if self.init[i] {
                est.segment[i] = Some(self.angle(i));
            }
        }
        est.fill_joints_from_segments();
        est
    }
}

/// Breakdown of each segment's angle correction by source, as in 001
/// Fig. 6: the correction of segment `s` is `sum_j K[2s, j] e_j`; the share
/// of row `j` is `|K[2s, j] e_j| / sum_j |K[2s, j] e_j|`, summed over the
/// segment's own accelerometer row, the other segments' accelerometer rows
/// and the joint rows (encoders or accelerometer differences). `None` for a
/// segment whose correction is exactly zero.
#[inline]
pub fn gain_shares<const M: usize>(
    K: &SMatrix<f64, 8, M>,
    innovation: &SVector<f64, M>,
    kinds: &[RowKind; M],
) -> [[Option<f64>; 3]; 4] {
    let mut out = [[None; 3]; 4];
    for (s, o) in out.iter_mut().enumerate() {
        let mut parts = [0.0; 3];
        for j in 0..M {
            let c = libm::fabs(K[(angle_state(s), j)] * innovation[j]);
            let k = match kinds[j] {
                RowKind::Imu(i) if i == s => 0,
                RowKind::Imu(_) => 1,
                RowKind::Joint => 2,
            };
            parts[k] += c;
        }
        let total = parts[0] + parts[1] + parts[2];
        if total > 0.0 && total.is_finite() {
            *o = [
                Some(parts[0] / total),
                Some(parts[1] / total),
                Some(parts[2] / total),
            ];
        }
    }
    out
}

#[cfg(test)]
mod gain_share_tests {
    use super::*;

    /// 001 Fig. 6 breakdown on a hand-built gain: rows = [IMU trunk,
    /// IMU thigh, joint]. Trunk correction parts: |0.5 * 0.2| = 0.1 (own),
    /// |0.1 * -0.5| = 0.05 (other), |0.25 * 0.2| = 0.05 (joint) -> 0.5 /
    /// 0.25 / 0.25. Thigh: |0.2 * 0.2| = 0.04 (other), |0.4 * -0.5| = 0.2
    /// (own), 0 (joint) -> own 0.2/0.24, other 0.04/0.24. Shank and foot have
    /// no gain: `None`.
    #[test]
    fn shares_match_a_hand_computed_breakdown() {
        let mut K = SMatrix::<f64, 8, 3>::zeros();
        K[(angle_state(0), 0)] = 0.5;
        K[(angle_state(0), 1)] = 0.1;
        K[(angle_state(0), 2)] = 0.25;
        K[(angle_state(1), 0)] = 0.2;
        K[(angle_state(1), 1)] = 0.4;
        // bias rows never count
        K[(bias_state(0), 0)] = 9.0;
        let e = SVector::<f64, 3>::new(0.2, -0.5, 0.2);
        let kinds = [RowKind::Imu(0), RowKind::Imu(1), RowKind::Joint];
        let s = gain_shares(&K, &e, &kinds);
        let close = |a: Option<f64>, b: f64| (a.unwrap() - b).abs() < 1e-15;
        assert!(close(s[0][0], 0.5) && close(s[0][1], 0.25) && close(s[0][2], 0.25));
        assert!(close(s[1][0], 0.2 / 0.24) && close(s[1][1], 0.04 / 0.24));
        assert!(close(s[1][2], 0.0));
        assert_eq!(s[2], [None; 3]);
        assert_eq!(s[3], [None; 3]);
    }
}
