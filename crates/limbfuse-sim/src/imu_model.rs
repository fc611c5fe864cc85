//! Triaxial gyroscope and accelerometer error model (paper 000 eqs 1-4,
//! applied per axis, plus scale-factor, cross-axis and mounting errors).
//!
//! Per triad, with `q` the true quantity in the sensor frame:
//! `y_k = M q_k + b0 + b_k + sigma_w w_k`, where
//! * `M = I + diag(s) + C`: scale-factor errors `s_i ~ N(0, scale_error^2)`
//!   and cross-axis terms `C_ij ~ N(0, cross_axis^2)` (i != j);
//! * `b0 ~ N(0, turn_on_bias^2)`: turn-on bias, constant over the trial;
//! * `b_k`: first-order Gauss-Markov bias (paper 000 eqs 2 and 4) with
//!   stationary sigma `sigma_b` and correlation time `tau`, discretised
//!   exactly: `b_{k+1} = e^{-dt/tau} b_k + sigma_b sqrt(1 - e^{-2 dt/tau}) n_k`,
//!   `b_0` drawn from the stationary distribution;
//! * white noise (paper 000 eqs 1 and 3) with `sigma_w = density *
//!   sqrt(rate / 2)` (the noise density integrated over the Nyquist band).
//!
//! The true sensor-frame quantities are `R_m^T R_seg^T w` (angular rate) and
//! `R_m^T R_seg^T (a - g_world)` (specific force, `g_world = (0, -g, 0)`),
//! with `R_m` the sensor-to-segment mounting rotation.

use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};
use rand::Rng;
use rand_distr::StandardNormal;

use crate::config::{ImuSpec, Mounting, TriadSpec};

fn normal3<R: Rng>(rng: &mut R) -> Vector3<f64> {
    Vector3::new(
        rng.sample(StandardNormal),
        rng.sample(StandardNormal),
        rng.sample(StandardNormal),
    )
}

/// The drawn errors and the running bias state of one triad.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Triad {
    /// Scale-factor and cross-axis matrix `M`.
    pub m: Matrix3<f64>,
    /// Turn-on bias.
    pub turn_on: Vector3<f64>,
    /// Current Gauss-Markov bias.
    pub gm: Vector3<f64>,
    gm_phi: f64,
    gm_q: f64,
    white: f64,
    on: bool,
}

impl Triad {
    /// Draws the constant errors (always the same 15 draws, so switching the
    /// noise off does not shift later draws).
    pub fn draw<R: Rng>(rng: &mut R, spec: &TriadSpec, rate_hz: f64, on: bool) -> Self {
        let s = normal3(rng) * spec.scale_error;
        let mut c = [0.0; 6];
        for ci in c.iter_mut() {
            *ci = rng.sample::<f64, _>(StandardNormal) * spec.cross_axis;
        }
        let m = Matrix3::new(
            1.0 + s.x,
            c[0],
            c[1],
            c[2],
            1.0 + s.y,
            c[3],
            c[4],
            c[5],
            1.0 + s.z,
        );
        let turn_on = normal3(rng) * spec.turn_on_bias;
        let gm = normal3(rng) * spec.bias_instability;
        let dt = 1.0 / rate_hz;
        let gm_phi = (-dt / spec.bias_tau_s).exp();
        let gm_q = spec.bias_instability * (1.0 - gm_phi * gm_phi).sqrt();
        let white = spec.noise_density * (rate_hz / 2.0).sqrt();
        if on {
            Triad {
                m,
                turn_on,
                gm,
                gm_phi,
                gm_q,
                white,
                on,
            }
        } else {
            Triad {
                m: Matrix3::identity(),
                turn_on: Vector3::zeros(),
                gm: Vector3::zeros(),
                gm_phi: 1.0,
                gm_q: 0.0,
                white: 0.0,
                on,
            }
        }
    }

    /// One reading of the sensor-frame truth `q`; advances the bias.
    /// Draws 6 normals when the noise is on, none otherwise.
    #[inline]
    pub fn measure<R: Rng>(&mut self, q: &Vector3<f64>, rng: &mut R) -> Vector3<f64> {
        if !self.on {
            return *q;
        }
        let y = self.m * q + self.turn_on + self.gm + normal3(rng) * self.white;
        self.gm = self.gm * self.gm_phi + normal3(rng) * self.gm_q;
        y
    }

    /// White-noise standard deviation per sample.
    pub fn white_sigma(&self) -> f64 {
        self.white
    }
}

/// One IMU: mounting and the two triads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Imu {
    /// Sensor-to-segment rotation (nominal mounting x misalignment).
    pub mount: Matrix3<f64>,
    /// Gyroscope errors.
    pub gyro: Triad,
    /// Accelerometer errors.
    pub acc: Triad,
}

impl Imu {
    /// Draws mounting and errors: 4 normals (random mounting quaternion), 3
    /// (misalignment), 15 + 15 (triads), whatever the options.
    pub fn draw<R: Rng>(
        rng: &mut R,
        spec: &ImuSpec,
        mounting: Mounting,
        rate_hz: f64,
        noise: bool,
    ) -> Self {
        let q4 = normal3(rng);
        let qv = Quaternion::new(rng.sample::<f64, _>(StandardNormal), q4.x, q4.y, q4.z);
        let nominal: Matrix3<f64> = match mounting {
            Mounting::Aligned => Matrix3::identity(),
            Mounting::Random if qv.norm() > 1e-9 => UnitQuaternion::from_quaternion(qv)
                .to_rotation_matrix()
                .into_inner(),
            Mounting::Random => Matrix3::identity(),
        };
        let mis = normal3(rng) * spec.misalignment_rad;
        let mis = if noise {
            Rotation3::new(mis).into_inner()
        } else {
            Matrix3::identity()
        };
        Imu {
            mount: nominal * mis,
            gyro: Triad::draw(rng, &spec.gyro, rate_hz, noise),
            acc: Triad::draw(rng, &spec.acc, rate_hz, noise),
        }
    }

    /// Error-free sensor-frame angular rate and specific force for segment
    /// rotation `r_seg`, world angular rate `w` and world specific force `f`.
    #[inline]
    pub fn ideal(
        &self,
        r_seg: &Matrix3<f64>,
        w: &Vector3<f64>,
        f: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let r = (r_seg * self.mount).transpose();
        (r * w, r * f)
    }

    /// Measured (gyro, acc); draws 12 normals when the noise is on.
    #[inline]
    pub fn read<R: Rng>(
        &mut self,
        r_seg: &Matrix3<f64>,
        w: &Vector3<f64>,
        f: &Vector3<f64>,
        rng: &mut R,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let (wi, fi) = self.ideal(r_seg, w, f);
        self.measure(&wi, &fi, rng)
    }

    /// Measured (gyro, acc) of the sensor on its own, off any segment:
    /// `r_sensor` is the sensor-to-world rotation (the mounting plays no
    /// part), `w` and `f` world angular rate and specific force. Draws 12
    /// normals when the noise is on.
    #[inline]
    pub fn read_unmounted<R: Rng>(
        &mut self,
        r_sensor: &Matrix3<f64>,
        w: &Vector3<f64>,
        f: &Vector3<f64>,
        rng: &mut R,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let rt = r_sensor.transpose();
        self.measure(&(rt * w), &(rt * f), rng)
    }

    #[inline]
    fn measure<R: Rng>(
        &mut self,
        wi: &Vector3<f64>,
        fi: &Vector3<f64>,
        rng: &mut R,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let g = self.gyro.measure(wi, rng);
        let a = self.acc.measure(fi, rng);
        (g, a)
    }

    /// Mounting rotation as a unit quaternion `[w, x, y, z]` (sensor to segment).
    pub fn mount_quaternion(&self) -> [f64; 4] {
        let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(self.mount));
        [q.w, q.i, q.j, q.k]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn gauss_markov_keeps_its_stationary_sigma_and_white_noise_scales() {
        let spec = TriadSpec {
            noise_density: 0.01,
            turn_on_bias: 0.0,
            bias_instability: 0.2,
            bias_tau_s: 0.5,
            scale_error: 0.0,
            cross_axis: 0.0,
        };
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let mut t = Triad::draw(&mut rng, &spec, 200.0, true);
        assert!((t.white_sigma() - 0.1).abs() < 1e-12);
        let n = 200_000;
        let mut s2 = 0.0;
        for _ in 0..n {
            let _ = t.measure(&Vector3::zeros(), &mut rng);
            s2 += t.gm.x * t.gm.x;
        }
        let sd = (s2 / n as f64).sqrt();
        assert!((sd - 0.2).abs() < 0.01, "{sd}");
    }

    #[test]
    fn ideal_imu_reads_the_truth_in_its_frame() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let imu = Imu::draw(
            &mut rng,
            &ImuSpec::default(),
            Mounting::Random,
            100.0,
            false,
        );
        let (w, f) = imu.ideal(&Matrix3::identity(), &Vector3::z(), &Vector3::y());
        assert!((imu.mount * w - Vector3::z()).norm() < 1e-12);
        assert!((imu.mount * f - Vector3::y()).norm() < 1e-12);
        let q = imu.mount_quaternion();
        assert!(((q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) - 1.0).abs() < 1e-12);
    }
}
