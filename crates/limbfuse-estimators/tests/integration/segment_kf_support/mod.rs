//! Shared helpers of the segment_kf integration tests: a seeded Gaussian
//! generator and a static-limb sample generator (no simulator dependency).
#![allow(dead_code)]

use limbfuse_core::Sample;
use nalgebra::{SMatrix, Vector3};

pub const G: f64 = 9.81;

/// SplitMix64 + Box-Muller: deterministic, dependency-free normals.
pub struct Rng {
    state: u64,
    spare: Option<f64>,
}

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng {
            state: seed ^ 0x9E37_79B9_7F4A_7C15,
            spare: None,
        }
    }

    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in (0, 1).
    pub fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    pub fn normal(&mut self) -> f64 {
        if let Some(s) = self.spare.take() {
            return s;
        }
        let (u1, u2) = (self.uniform(), self.uniform());
        let r = (-2.0 * u1.ln()).sqrt();
        let a = core::f64::consts::TAU * u2;
        self.spare = Some(r * a.sin());
        r * a.cos()
    }
}

/// A limb held still at `theta` (rad per segment) with biased, noisy gyros.
pub struct StaticLimb {
    pub theta: [f64; 4],
    /// Gyro bias per segment, sensor convention (gyro = true rate + bias), rad/s.
    pub gyro_bias: [f64; 4],
    /// Gyro white-noise density (rad/s/sqrt(Hz)); per-sample sigma = density / sqrt(dt).
    pub gyro_density: f64,
    /// Accelerometer white noise per axis (m/s^2).
    pub acc_sigma: f64,
    /// Encoder white noise (rad).
    pub enc_sigma: f64,
    pub dt: f64,
    pub rng: Rng,
}

impl StaticLimb {
    pub fn sample(&mut self, k: usize) -> Sample {
        let mut s = Sample::empty(k as f64 * self.dt);
        for i in 0..4 {
            let th = self.theta[i];
            let n = Vector3::new(self.rng.normal(), self.rng.normal(), self.rng.normal());
            s.imu[i].acc = Some(Vector3::new(G * th.sin(), G * th.cos(), 0.0) + n * self.acc_sigma);
            let w = self.gyro_bias[i] + self.gyro_density / self.dt.sqrt() * self.rng.normal();
            s.imu[i].gyr = Some(Vector3::new(0.0, 0.0, w));
        }
        for j in 0..3 {
            s.encoder[j] =
                Some(self.theta[j] - self.theta[j + 1] + self.enc_sigma * self.rng.normal());
        }
        s
    }
}

/// True when `p` is exactly symmetric and its Cholesky factorisation exists
/// with every pivot above `min_pivot`.
pub fn is_spd<const N: usize>(p: &SMatrix<f64, N, N>, min_pivot: f64) -> bool {
    if p.iter().any(|v| !v.is_finite()) {
        return false;
    }
    if *p != p.transpose() {
        return false;
    }
    match p.cholesky() {
        Some(c) => c.l().diagonal().iter().all(|&d| d * d > min_pivot),
        None => false,
    }
}
