//! An ideal 3D hinge knee whose sensor signals are computed independently of
//! the estimator (orientation and position differentiated numerically), with
//! optional consumer-MEMS sensor errors and an optional still period. Shared
//! by `knee_selfalign_hinge.rs` (noise free) and `knee_real_conditions.rs`
//! (issue 15 item 3).
#![allow(dead_code)] // each test file uses a part

use limbfuse_core::{ImuSample, Record, Sample, Segment};
use nalgebra::{Matrix3, Rotation3, Vector3};

/// Rotation by `angle` (rad) about `axis`.
pub fn rot(axis: Vector3<f64>, angle: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle).into_inner()
}

const G: f64 = 9.81;

/// What the thigh does around the knee.
#[derive(Clone, Copy, PartialEq)]
pub enum HingeMotion {
    /// Walking-like: the thigh swings mainly in the sagittal plane at 0.9 Hz
    /// with small ab/adduction and axial rotation, the knee moves forward at
    /// 1.1 m/s (the noise-free test of `knee_selfalign_hinge.rs`).
    WalkLike,
    /// Free 3D motion, not walking: thigh flexion, ab/adduction and axial
    /// rotation of 20-30 deg each at incommensurate frequencies, knee
    /// flexion from 3 to 80 deg with no period, the knee centre wandering by
    /// about 10 cm with no forward progression.
    Free3d,
}

/// A still period: the motion slows to rest over 1 s at `start_s`, stays at
/// rest for `still_s` and starts again over 1 s (smooth in the first
/// derivative of the motion's time, so every reading stays bounded).
#[derive(Clone, Copy, PartialEq)]
pub struct Still {
    /// Start of the slow-down (s).
    pub start_s: f64,
    /// Duration of the rest (s).
    pub still_s: f64,
}

impl Still {
    /// The motion's own time at trial time `t` (s).
    pub fn motion_time(&self, t: f64) -> f64 {
        let (a, b) = (self.start_s, self.start_s + 1.0 + self.still_s);
        // integral of the smoothstep 3u^2 - 2u^3 from 0 to u
        let ramp = |u: f64| u * u * u - 0.5 * u * u * u * u;
        if t < a {
            t
        } else if t < a + 1.0 {
            let u = t - a;
            a + u - ramp(u)
        } else if t < b {
            a + 0.5
        } else if t < b + 1.0 {
            a + 0.5 + ramp(t - b)
        } else {
            t - (b - a)
        }
    }
}

/// A leg with a hinge knee at flexion `kappa` and two sensors at arbitrary
/// orientations and positions.
pub struct Hinge {
    /// Sensor-to-segment rotations of the thigh and shank sensors.
    pub mount: [Matrix3<f64>; 2],
    /// Sensor positions relative to the knee centre, segment frames (m).
    pub point: [Vector3<f64>; 2],
    /// What the thigh does.
    pub motion: HingeMotion,
    /// Optional still period.
    pub still: Option<Still>,
}

impl Hinge {
    fn motion_time(&self, t: f64) -> f64 {
        self.still.map_or(t, |s| s.motion_time(t))
    }

    /// Knee flexion (rad) at trial time `t`.
    pub fn kappa(&self, t: f64) -> f64 {
        let t = self.motion_time(t);
        match self.motion {
            HingeMotion::WalkLike => {
                0.55 - 0.5 * (2.0 * std::f64::consts::PI * 0.9 * t).cos() + 0.1 * (5.1 * t).sin()
            }
            HingeMotion::Free3d => {
                0.72 + 0.4 * (1.9 * t).sin() + 0.25 * (4.3 * t + 1.0).sin()
                    - 0.02 * (0.37 * t).cos()
            }
        }
    }

    /// Segment-to-world rotations of thigh and shank at motion time `t`.
    fn frames(&self, t: f64) -> [Matrix3<f64>; 2] {
        let (theta, alpha, beta, kappa) = match self.motion {
            HingeMotion::WalkLike => (
                0.4 * (5.65 * t).sin() + 0.1 * (1.3 * t).cos(),
                0.15 * (2.1 * t + 0.3).sin(),
                0.2 * (3.7 * t).sin(),
                0.55 - 0.5 * (2.0 * std::f64::consts::PI * 0.9 * t).cos() + 0.1 * (5.1 * t).sin(),
            ),
            HingeMotion::Free3d => (
                0.45 * (2.3 * t).sin() + 0.2 * (0.7 * t).cos(),
                0.35 * (1.7 * t + 0.3).sin() + 0.1 * (4.9 * t).sin(),
                0.5 * (3.1 * t).sin() + 0.15 * (0.9 * t + 2.0).cos(),
                0.72 + 0.4 * (1.9 * t).sin() + 0.25 * (4.3 * t + 1.0).sin()
                    - 0.02 * (0.37 * t).cos(),
            ),
        };
        let r_t = rot(Vector3::z(), theta) * rot(Vector3::x(), alpha) * rot(Vector3::y(), beta);
        [r_t, r_t * rot(Vector3::z(), -kappa)]
    }

    fn knee_position(&self, t: f64) -> Vector3<f64> {
        match self.motion {
            HingeMotion::WalkLike => Vector3::new(
                1.1 * t + 0.05 * (5.65 * t).sin(),
                0.5 + 0.03 * (11.3 * t).cos(),
                0.02 * (2.8 * t).sin(),
            ),
            HingeMotion::Free3d => Vector3::new(
                0.08 * (1.1 * t).sin() + 0.03 * (3.3 * t).cos(),
                0.5 + 0.05 * (2.6 * t + 0.5).sin(),
                0.06 * (1.5 * t).cos(),
            ),
        }
    }

    /// Ideal gyro and specific force of sensor `i` in its own frame at trial
    /// time `t`, by central differences of the orientation and position.
    pub fn reading(&self, i: usize, t: f64) -> (Vector3<f64>, Vector3<f64>) {
        let h = 1e-5;
        let r = |t: f64| self.frames(self.motion_time(t))[i] * self.mount[i];
        let rd = (r(t + h) - r(t - h)) / (2.0 * h);
        let wx = r(t).transpose() * rd; // body-frame [w]x
        let w = Vector3::new(wx[(2, 1)], wx[(0, 2)], wx[(1, 0)]);
        let p = |t: f64| {
            let m = self.motion_time(t);
            self.knee_position(m) + self.frames(m)[i] * self.point[i]
        };
        let hp = 1e-3;
        let a = (p(t + hp) - 2.0 * p(t) + p(t - hp)) / (hp * hp);
        let f = a + Vector3::new(0.0, G, 0.0);
        (w, r(t).transpose() * f)
    }
}

/// A small deterministic generator (SplitMix64) with Gaussian draws.
pub struct Draws(u64);

impl Draws {
    /// Seeded.
    pub fn new(seed: u64) -> Self {
        Draws(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0xD1B5_4A32_D192_ED03)
    }

    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Standard normal (Box-Muller).
    pub fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }

    /// Three standard normals.
    pub fn normal3(&mut self) -> Vector3<f64> {
        Vector3::new(self.normal(), self.normal(), self.normal())
    }
}

/// Consumer-MEMS sensor errors, the walking simulator's defaults
/// (`limbfuse-sim` `ImuSpec::default`, docs/SIMULATOR.md): gyro noise
/// density 0.007 deg/s/sqrt(Hz), turn-on bias 0.5 deg/s (1 sigma per axis);
/// accelerometer noise density 160 ug/sqrt(Hz), turn-on bias 20 mg. Plus an
/// accelerometer scale factor per sensor (1 = none).
#[derive(Clone, Copy)]
pub struct SensorErrors {
    /// Draw seed of the biases and the noise.
    pub seed: u64,
    /// Accelerometer scale factor of the thigh and shank sensor (all axes).
    pub acc_scale: [f64; 2],
    /// Multiplies the gyro and the accelerometer turn-on biases (1 = the
    /// figures above, 0 = none).
    pub bias: [f64; 2],
}

/// The hinge's records at `rate_hz` for `duration_s`, with `errors` if given
/// (`None`: ideal sensors). The knee reference is `kappa`.
pub fn records(
    hinge: &Hinge,
    rate_hz: f64,
    duration_s: f64,
    errors: Option<SensorErrors>,
) -> Vec<Record> {
    let n = (duration_s * rate_hz).round() as usize;
    let mut draws = errors.map(|e| Draws::new(e.seed));
    let deg = 1f64.to_radians();
    let mg = 9.80665e-3;
    let biases: Option<[[Vector3<f64>; 2]; 2]> = draws.as_mut().map(|d| {
        let (kg, ka) = (
            errors.map_or(1.0, |e| e.bias[0]),
            errors.map_or(1.0, |e| e.bias[1]),
        );
        let gb = [d.normal3() * 0.5 * deg * kg, d.normal3() * 0.5 * deg * kg];
        let ab = [d.normal3() * 20.0 * mg * ka, d.normal3() * 20.0 * mg * ka];
        [gb, ab]
    });
    let (gyro_sd, acc_sd) = (0.007 * deg * rate_hz.sqrt(), 0.160 * mg * rate_hz.sqrt());
    (0..n)
        .map(|k| {
            let t = k as f64 / rate_hz;
            let mut sample = Sample::empty(t);
            for (i, seg) in [Segment::Thigh, Segment::Shank].into_iter().enumerate() {
                let (mut w, mut f) = hinge.reading(i, t);
                if let (Some(d), Some(b), Some(e)) = (draws.as_mut(), biases, errors) {
                    w += b[0][i] + d.normal3() * gyro_sd;
                    f = f * e.acc_scale[i] + b[1][i] + d.normal3() * acc_sd;
                }
                sample.imu[seg.index()] = ImuSample {
                    acc: Some(f),
                    gyr: Some(w),
                    quat: None,
                    ..Default::default()
                };
            }
            let mut record = Record {
                sample,
                ..Default::default()
            };
            record.reference.joint[limbfuse_core::Joint::Knee.index()] = Some(hinge.kappa(t));
            record
        })
        .collect()
}
