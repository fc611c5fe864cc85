//! A simulated accelerometer-calibration recording (`limbfuse simulate
//! calibration`): the four IMUs of [`crate::WalkingSimulator`] (same seed,
//! same drawn errors: scale, cross-axis, turn-on and Gauss-Markov biases,
//! noise), taken off the body, fixed on one rigid board and turned through a
//! sequence of static poses, with real rotations in between.
//!
//! * **Poses.** Pose `k` holds the board so that gravity points along the
//!   unit vector `d_k` of every sensor frame: the six faces `+-x, +-y, +-z`,
//!   then the eight corners `(+-1, +-1, +-1)/sqrt(3)` (14 directions, the
//!   first `n` used). The board orientation is `R_k = R_y(psi_k) R(d_k -> y)`
//!   (sensor to world, world `y` up): the shortest rotation taking `d_k` to
//!   up, then a yaw `psi_k = 0.9 k` rad that a static accelerometer cannot
//!   see. An ideal static sensor then reads `f = R_k^T (0, g, 0) = g d_k`.
//! * **Transitions.** From `R_k` to `R_{k+1}` about the fixed world axis `n`
//!   of `R_{k+1} R_k^T` (angle `Theta`), along the minimum-jerk profile
//!   `s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5`, `tau = (t - t_0) / T`:
//!   `R(t) = exp(s Theta [n]x) R_k`, world angular rate `omega = n Theta
//!   s'` and acceleration `alpha = n Theta s''` (both zero at the ends).
//! * **Lever arm.** Each sensor sits `l_i` (sensor frame, 5 cm from the
//!   board's centre of rotation by default) off the rotation centre, so a
//!   turning board accelerates it: `a = alpha x r + omega x (omega x r)`,
//!   `r = R l_i`; specific force `f = a + (0, g, 0)` (world).
//! * **Wobble** (for the bad-input tests): one pose can be held with a 1 Hz,
//!   1.5 deg rocking about the world `x` axis, a hand that does not hold
//!   still; a calibration must reject that pose, naming its time span.
//!
//! Every sample reads `Imu::read_unmounted`, i.e. the sensor error model of
//! [`crate::imu_model`] on the true sensor-frame rate and specific force; the
//! per-sample noise comes from the walking simulator's IMU noise stream of
//! the same seed.

use core::f64::consts::PI;

use limbfuse_core::{ImuSample, Record, Reference, Sample, Segment};
use nalgebra::{Matrix3, Unit, UnitQuaternion, Vector3};
use rand_chacha::ChaCha8Rng;

use crate::config::{SimError, WalkingConfig};
use crate::imu_model::Imu;
use crate::walking::{imu_noise_rng, walking_sensors};

/// Gravity directions (sensor frame, unit) of the poses, in recording order.
pub fn pose_directions() -> [Vector3<f64>; 14] {
    let c = 1.0 / 3f64.sqrt();
    [
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(0.0, -1.0, 0.0),
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(-1.0, 0.0, 0.0),
        Vector3::new(0.0, 0.0, 1.0),
        Vector3::new(0.0, 0.0, -1.0),
        Vector3::new(c, c, c),
        Vector3::new(-c, c, -c),
        Vector3::new(c, -c, -c),
        Vector3::new(-c, -c, c),
        Vector3::new(c, c, -c),
        Vector3::new(-c, c, c),
        Vector3::new(c, -c, c),
        Vector3::new(-c, -c, -c),
    ]
}

/// Largest number of poses.
pub const MAX_POSES: usize = 14;

/// What to record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseRecordingConfig {
    /// The sensors: those `simulate walking` draws with this configuration
    /// (`seed`, `imu`, `imu_rate_hz`, `noise`, `g`; the motion is unused).
    pub sensors: WalkingConfig,
    /// Number of poses, 1..=14 (the first `n` of [`pose_directions`]).
    pub poses: usize,
    /// Time each pose is held still (s), (0, 600].
    pub hold_s: f64,
    /// Time of each turn from one pose to the next (s), (0, 60].
    pub transition_s: f64,
    /// Distance of each sensor from the board's centre of rotation (m), [0, 1].
    pub lever_arm_m: f64,
    /// Hold this pose (0-based) with a 1 Hz, 1.5 deg rocking instead of still.
    pub wobble_pose: Option<usize>,
}

impl Default for PoseRecordingConfig {
    fn default() -> Self {
        PoseRecordingConfig {
            sensors: WalkingConfig::default(),
            poses: MAX_POSES,
            hold_s: 4.0,
            transition_s: 2.0,
            lever_arm_m: 0.05,
            wobble_pose: None,
        }
    }
}

/// Rocking of a wobbling pose: amplitude (rad) and frequency (Hz).
const WOBBLE: (f64, f64) = (0.026, 1.0);

fn range(name: &'static str, v: f64, lo: f64, hi: f64, text: &'static str) -> Result<(), SimError> {
    if v.is_finite() && v > lo && v <= hi {
        Ok(())
    } else {
        Err(SimError::OutOfRange {
            name,
            value: v,
            range: text,
        })
    }
}

impl PoseRecordingConfig {
    /// Checks every parameter; the error names the first bad one.
    pub fn validate(&self) -> Result<(), SimError> {
        self.sensors.validate()?;
        range("poses", self.poses as f64, 0.5, MAX_POSES as f64, "1..=14")?;
        range("hold_s", self.hold_s, 0.0, 600.0, "(0, 600] s")?;
        range("transition_s", self.transition_s, 0.0, 60.0, "(0, 60] s")?;
        if !(self.lever_arm_m.is_finite() && (0.0..=1.0).contains(&self.lever_arm_m)) {
            return Err(SimError::OutOfRange {
                name: "lever_arm_m",
                value: self.lever_arm_m,
                range: "[0, 1] m",
            });
        }
        if let Some(k) = self.wobble_pose {
            range(
                "wobble_pose",
                k as f64 + 1.0,
                0.5,
                self.poses as f64,
                "0..poses (0-based)",
            )?;
        }
        Ok(())
    }

    /// Length of the recording (s).
    pub fn duration_s(&self) -> f64 {
        self.poses as f64 * self.hold_s + (self.poses.saturating_sub(1)) as f64 * self.transition_s
    }

    /// The held span `[start, end]` (s) of pose `k`.
    pub fn hold_span(&self, k: usize) -> (f64, f64) {
        let t0 = k as f64 * (self.hold_s + self.transition_s);
        (t0, t0 + self.hold_s)
    }
}

/// Sensor-to-world orientation of pose `k` (see the module docs).
fn pose_orientation(k: usize) -> UnitQuaternion<f64> {
    let d = pose_directions()[k];
    let up = Vector3::y();
    let tilt = UnitQuaternion::rotation_between(&d, &up)
        .unwrap_or_else(|| UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI));
    UnitQuaternion::from_axis_angle(&Vector3::y_axis(), 0.9 * k as f64) * tilt
}

/// Orientation, world angular rate and angular acceleration of the board.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoardState {
    /// Sensor-to-world rotation.
    pub r: Matrix3<f64>,
    /// World angular rate (rad/s).
    pub w: Vector3<f64>,
    /// World angular acceleration (rad/s^2).
    pub alpha: Vector3<f64>,
}

/// The seeded calibration recording; iterate it for one [`Record`] per sample.
#[derive(Debug, Clone)]
pub struct PoseRecording {
    cfg: PoseRecordingConfig,
    imus: [Imu; 4],
    rng: ChaCha8Rng,
    orientations: Vec<UnitQuaternion<f64>>,
    n_samples: u64,
    next_sample: u64,
}

impl PoseRecording {
    /// Validates `cfg` and draws the sensors of `simulate walking` with
    /// `cfg.sensors` (same seed: same sensors).
    pub fn new(cfg: PoseRecordingConfig) -> Result<Self, SimError> {
        cfg.validate()?;
        let imus = walking_sensors(&cfg.sensors)?;
        let n_samples = (cfg.duration_s() * cfg.sensors.imu_rate_hz).round() as u64;
        Ok(PoseRecording {
            cfg,
            imus,
            rng: imu_noise_rng(cfg.sensors.seed),
            orientations: (0..cfg.poses).map(pose_orientation).collect(),
            n_samples,
            next_sample: 0,
        })
    }

    /// The configuration in use.
    pub fn config(&self) -> &PoseRecordingConfig {
        &self.cfg
    }

    /// The IMUs (error state as of the last record), trunk..foot.
    pub fn imus(&self) -> &[Imu; 4] {
        &self.imus
    }

    /// Number of records the recording holds.
    pub fn sample_count(&self) -> u64 {
        self.n_samples
    }

    /// Board state at time `t` (s).
    pub fn board(&self, t: f64) -> BoardState {
        let c = &self.cfg;
        let period = c.hold_s + c.transition_s;
        let k = ((t / period).floor().max(0.0) as usize).min(c.poses - 1);
        let local = t - k as f64 * period;
        let rk = self.orientations[k];
        if local <= c.hold_s || k + 1 >= c.poses {
            if c.wobble_pose == Some(k) {
                let (amp, f) = WOBBLE;
                let wt = 2.0 * PI * f * local;
                let x = Vector3::x();
                let r = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), amp * wt.sin()) * rk;
                return BoardState {
                    r: r.to_rotation_matrix().into_inner(),
                    w: x * (amp * 2.0 * PI * f * wt.cos()),
                    alpha: x * (-amp * (2.0 * PI * f).powi(2) * wt.sin()),
                };
            }
            return BoardState {
                r: rk.to_rotation_matrix().into_inner(),
                w: Vector3::zeros(),
                alpha: Vector3::zeros(),
            };
        }
        let mut dq = self.orientations[k + 1] * rk.inverse();
        if dq.w < 0.0 {
            dq = UnitQuaternion::new_unchecked(-dq.into_inner());
        }
        let v = dq.imag();
        let theta = 2.0 * v.norm().atan2(dq.w);
        let n = if v.norm() > 1e-12 {
            v / v.norm()
        } else {
            Vector3::x()
        };
        let big_t = c.transition_s;
        let tau = (local - c.hold_s) / big_t;
        let s = tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau);
        let ds = 30.0 * tau * tau * (1.0 - tau) * (1.0 - tau) / big_t;
        let dds = 60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau) / (big_t * big_t);
        let r = UnitQuaternion::from_axis_angle(&Unit::new_unchecked(n), s * theta) * rk;
        BoardState {
            r: r.to_rotation_matrix().into_inner(),
            w: n * (theta * ds),
            alpha: n * (theta * dds),
        }
    }

    /// Offset of sensor `i` from the board's centre of rotation, sensor frame (m).
    pub fn lever_arm(&self, i: usize) -> Vector3<f64> {
        let dirs = [
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.0, 0.0, 1.0),
            Vector3::new(1.0, 1.0, 1.0) / 3f64.sqrt(),
        ];
        dirs[i] * self.cfg.lever_arm_m
    }

    /// True world specific force (m/s^2) at sensor `i` for board state `b`.
    pub fn specific_force(&self, b: &BoardState, i: usize) -> Vector3<f64> {
        let r = b.r * self.lever_arm(i);
        let a = b.alpha.cross(&r) + b.w.cross(&b.w.cross(&r));
        a + Vector3::new(0.0, self.cfg.sensors.g, 0.0)
    }

    /// Run metadata as `key: value` pairs (for a trial file header).
    pub fn metadata(&self) -> Vec<(String, String)> {
        let c = &self.cfg;
        let s = &c.sensors;
        let mut out: Vec<(String, String)> = Vec::new();
        let mut put = |k: &str, v: String| out.push((k.to_string(), v));
        put("source", "limbfuse-sim calibration poses".into());
        put("seed", s.seed.to_string());
        put("g", s.g.to_string());
        put("sample_rate_hz", s.imu_rate_hz.to_string());
        put("noise", s.noise.to_string());
        put("poses", c.poses.to_string());
        put("hold_s", c.hold_s.to_string());
        put("transition_s", c.transition_s.to_string());
        put("lever_arm_m", c.lever_arm_m.to_string());
        let spans: Vec<String> = (0..c.poses)
            .map(|k| {
                let (a, b) = c.hold_span(k);
                format!("{a}..{b}")
            })
            .collect();
        put("pose_spans_s", spans.join(" "));
        if let Some(k) = c.wobble_pose {
            let (a, b) = c.hold_span(k);
            put("wobble_pose_s", format!("{a}..{b}"));
        }
        put(
            "sensors",
            "the IMUs of `limbfuse simulate walking` with the same seed (raw sensor frames)".into(),
        );
        for seg in Segment::ALL {
            let imu = &self.imus[seg.index()];
            let a = imu.acc.turn_on;
            put(
                &format!("{}_acc_turn_on_bias", seg.name()),
                format!("{:e} {:e} {:e}", a.x, a.y, a.z),
            );
            let m = imu.acc.m;
            put(
                &format!("{}_acc_matrix", seg.name()),
                format!(
                    "{:e} {:e} {:e}; {:e} {:e} {:e}; {:e} {:e} {:e}",
                    m[(0, 0)],
                    m[(0, 1)],
                    m[(0, 2)],
                    m[(1, 0)],
                    m[(1, 1)],
                    m[(1, 2)],
                    m[(2, 0)],
                    m[(2, 1)],
                    m[(2, 2)]
                ),
            );
            let g = imu.gyro.turn_on;
            put(
                &format!("{}_gyro_turn_on_bias", seg.name()),
                format!("{:e} {:e} {:e}", g.x, g.y, g.z),
            );
        }
        out
    }
}

impl Iterator for PoseRecording {
    type Item = Record;

    fn next(&mut self) -> Option<Record> {
        if self.next_sample >= self.n_samples {
            return None;
        }
        let t = self.next_sample as f64 / self.cfg.sensors.imu_rate_hz;
        self.next_sample += 1;
        let b = self.board(t);
        let mut sample = Sample::empty(t);
        for i in 0..4 {
            let f = self.specific_force(&b, i);
            let (w, a) = self.imus[i].read_unmounted(&b.r, &b.w, &f, &mut self.rng);
            sample.imu[i] = ImuSample {
                acc: Some(a),
                gyr: Some(w),
                quat: None,
                ..Default::default()
            };
        }
        Some(Record {
            sample,
            reference: Reference::default(),
        })
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = usize::try_from(self.n_samples - self.next_sample).unwrap_or(usize::MAX);
        (left, Some(left))
    }
}

impl ExactSizeIterator for PoseRecording {}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    /// `R^T (0, 1, 0)`: the unit up direction in the sensor frame.
    fn up_in_sensor_frame(r: &Rotation3<f64>) -> Vector3<f64> {
        r.transpose() * Vector3::y()
    }

    fn ideal() -> PoseRecordingConfig {
        PoseRecordingConfig {
            sensors: WalkingConfig {
                noise: false,
                ..WalkingConfig::default()
            },
            ..PoseRecordingConfig::default()
        }
    }

    #[test]
    fn each_pose_puts_gravity_along_its_direction() {
        let rec = PoseRecording::new(ideal()).unwrap();
        for (k, d) in pose_directions().iter().enumerate() {
            let (a, b) = rec.config().hold_span(k);
            let st = rec.board(0.5 * (a + b));
            let up = up_in_sensor_frame(&Rotation3::from_matrix_unchecked(st.r));
            assert!((up - d).norm() < 1e-12, "pose {k}: {up} vs {d}");
            assert_eq!(st.w, Vector3::zeros());
        }
    }

    #[test]
    fn transition_rate_and_acceleration_are_the_derivatives_of_the_orientation() {
        let rec = PoseRecording::new(ideal()).unwrap();
        let c = rec.config();
        for k in 0..c.poses - 1 {
            let t = c.hold_span(k).1 + 0.37 * c.transition_s;
            let h = 1e-5;
            let (m, p) = (rec.board(t - h), rec.board(t + h));
            // omega from R' R^T (skew), central differences.
            let dr = (p.r - m.r) / (2.0 * h);
            let skew = dr * rec.board(t).r.transpose();
            let w_fd = Vector3::new(skew[(2, 1)], skew[(0, 2)], skew[(1, 0)]);
            let b = rec.board(t);
            assert!((w_fd - b.w).norm() < 1e-6 * (1.0 + b.w.norm()), "{k}");
            let a_fd = (p.w - m.w) / (2.0 * h);
            assert!(
                (a_fd - b.alpha).norm() < 1e-5 * (1.0 + b.alpha.norm()),
                "{k}"
            );
            assert!(
                b.w.norm() > 0.1,
                "a real rotation between poses {k}, {}",
                k + 1
            );
        }
    }

    #[test]
    fn lever_arm_acceleration_is_the_second_derivative_of_the_position() {
        let rec = PoseRecording::new(ideal()).unwrap();
        let t = rec.config().hold_span(2).1 + 0.6;
        let h = 1e-4;
        let pos = |t: f64| rec.board(t).r * rec.lever_arm(3);
        let a_fd = (pos(t + h) - 2.0 * pos(t) + pos(t - h)) / (h * h);
        let f = rec.specific_force(&rec.board(t), 3) - Vector3::new(0.0, rec.cfg.sensors.g, 0.0);
        assert!((a_fd - f).norm() < 1e-5, "{a_fd} vs {f}");
    }

    #[test]
    fn same_seed_same_sensors_as_the_walking_simulator() {
        let cfg = PoseRecordingConfig {
            sensors: WalkingConfig {
                seed: 7,
                speed_mps: 0.4,
                ..WalkingConfig::default()
            },
            ..PoseRecordingConfig::default()
        };
        let walk = crate::WalkingSimulator::new(WalkingConfig {
            speed_mps: 1.3,
            ..cfg.sensors
        })
        .unwrap();
        let rec = PoseRecording::new(cfg).unwrap();
        for i in 0..4 {
            assert_eq!(rec.imus()[i].acc.m, walk.imus()[i].acc.m);
            assert_eq!(rec.imus()[i].acc.turn_on, walk.imus()[i].acc.turn_on);
            assert_eq!(rec.imus()[i].acc.gm, walk.imus()[i].acc.gm);
            assert_eq!(rec.imus()[i].gyro.turn_on, walk.imus()[i].gyro.turn_on);
        }
        let a: Vec<Record> = PoseRecording::new(cfg).unwrap().take(50).collect();
        let b: Vec<Record> = rec.take(50).collect();
        assert_eq!(a, b);
    }

    #[test]
    fn bad_configurations_name_the_parameter() {
        for (cfg, name) in [
            (
                PoseRecordingConfig {
                    poses: 0,
                    ..PoseRecordingConfig::default()
                },
                "poses",
            ),
            (
                PoseRecordingConfig {
                    poses: 15,
                    ..PoseRecordingConfig::default()
                },
                "poses",
            ),
            (
                PoseRecordingConfig {
                    hold_s: f64::NAN,
                    ..PoseRecordingConfig::default()
                },
                "hold_s",
            ),
            (
                PoseRecordingConfig {
                    wobble_pose: Some(14),
                    ..PoseRecordingConfig::default()
                },
                "wobble_pose",
            ),
        ] {
            let e = PoseRecording::new(cfg).unwrap_err().to_string();
            assert!(e.starts_with(name), "{e}");
        }
    }
}
