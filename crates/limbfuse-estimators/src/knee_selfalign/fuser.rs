//! The angle-fusion filter in use: Algorithm 1 ([`ComplementaryKf`]) or
//! its rate-bias extension ([`RateBiasKf`]), and the high-pass used while
//! the accelerometer angle is not trusted.

use super::angle::{ComplementaryKf, RateBiasKf};
use super::params::{Fusion, KneeSelfAlignParams};

/// The angle-fusion filter in use.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Fuser {
    Paper(ComplementaryKf),
    RateBias(RateBiasKf),
}

impl Fuser {
    pub(crate) fn new(p: &KneeSelfAlignParams) -> Self {
        match p.fusion {
            Fusion::Paper => Fuser::Paper(ComplementaryKf::new(p.kf_q, p.kf_r)),
            Fusion::RateBias { q_bias, p_bias0 } => {
                Fuser::RateBias(RateBiasKf::new(p.kf_q, q_bias, p.kf_r, p_bias0))
            }
        }
    }
    pub(crate) fn predict(&mut self, dt: f64) {
        match self {
            Fuser::Paper(k) => k.predict_over(dt),
            Fuser::RateBias(k) => k.predict(dt),
        }
    }
    pub(crate) fn update(&mut self, z: f64) {
        match self {
            Fuser::Paper(k) => k.update(z),
            Fuser::RateBias(k) => k.update(z),
        }
    }
    /// The high-pass used instead of [`Fuser::update`] while the
    /// accelerometer angle is not trusted: the correction `x` relaxes towards
    /// `-alpha_gyro` with gain `k` per sample, so `alpha_gyro + x` is
    /// `alpha_gyro` high-passed (first order, `k = 1 - exp(-2 pi f_c dt)`).
    pub(crate) fn leak(&mut self, alpha_gyro: f64, k: f64) {
        match self {
            Fuser::Paper(f) => f.x += k * (-alpha_gyro - f.x),
            Fuser::RateBias(f) => f.x[0] += k * (-alpha_gyro - f.x[0]),
        }
    }
    /// Adds `dv` (rad^2) to the variance of the correction, capped at
    /// `cap` (a gyro angle that became uncertain over a dropout).
    pub(crate) fn inflate(&mut self, dv: f64, cap: f64) {
        let p = match self {
            Fuser::Paper(k) => &mut k.p,
            Fuser::RateBias(k) => &mut k.p[0][0],
        };
        *p = (*p + dv).min(cap.max(*p));
    }
    /// Correction added to the gyro angle, its variance, the rate bias.
    pub(crate) fn state(&self) -> (f64, f64, Option<f64>) {
        match self {
            Fuser::Paper(k) => (k.x, k.p, None),
            Fuser::RateBias(k) => (k.x[0], k.p[0][0], Some(k.x[1])),
        }
    }
}
