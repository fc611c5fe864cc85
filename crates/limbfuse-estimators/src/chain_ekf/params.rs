//! Parameters of the chain EKF, their defaults and where they come from
//! (docs/CHAIN.md, "Defaults").

use limbfuse_models::DEFAULT_BODY_HEIGHT_M;

use super::kinematics::ChainGeometry;
use crate::segment_kf::robust::INNOVATION_GATE_CHI2;

/// Mean segment angle over a walking stride (deg; trunk, thigh, shank,
/// foot), from the normative curves limbfuse's walking simulator is built on
/// (J. Perry & J. M. Burnfield, *Gait Analysis*, 2nd ed., 2010; M. P. Kadaba
/// et al., J. Orthop. Res. 8:383-392, 1990; Winter 2009; docs/SIMULATOR.md),
/// measured there at 0.6-1.5 m/s: trunk -1.6..-2.5, thigh +7.0..+7.8, shank
/// -15.5..-16.5, foot -14.8..-16.6 (docs/ALIGNMENT.md, "mean segment
/// angles over walking"). `align`'s mean-inclination zero sets these means
/// to its target instead, which turns each sensor frame away from its
/// segment's anatomical frame by `target - mean`
/// ([`ChainGeometry::frame_offset`]).
pub const WALKING_MEAN_ANGLE_DEG: [f64; 4] = [-2.0, 7.0, -16.0, -16.0];

impl ChainGeometry {
    /// Segment lengths from body height `h` with Winter's ratios (D. A.
    /// Winter, *Biomechanics and Motor Control of Human Movement*, 4th ed.,
    /// Wiley 2009, Fig. 4.1: thigh 0.245 H, shank 0.246 H) and typical IMU
    /// placements scaled by `h / 1.75`: trunk on the lower back over the
    /// sacrum (0.10 m behind and 0.08 m above the hip joint centre), thigh
    /// and shank at mid-segment on the segment axis, foot on the dorsum
    /// (0.07 m in front of and 0.005 m below the ankle). Lateral offsets are
    /// unknown and set to 0.
    pub fn from_height(h: f64) -> Self {
        let thigh = 0.245 * h;
        let shank = 0.246 * h;
        let s = h / 1.75;
        ChainGeometry {
            thigh_length: thigh,
            shank_length: shank,
            imu_position: [
                [-0.10 * s, 0.08 * s, 0.0],
                [0.0, -0.5 * thigh, 0.0],
                [0.0, -0.5 * shank, 0.0],
                [0.07 * s, -0.005 * s, 0.0],
            ],
            frame_offset: [0.0; 4],
        }
    }

    /// Checks lengths (0.1-1.5 m) and positions (within 1 m of the origin).
    pub fn validate(&self) -> Result<(), ChainParamsError> {
        for (name, v) in [
            ("thigh_length", self.thigh_length),
            ("shank_length", self.shank_length),
        ] {
            if !(v.is_finite() && (0.1..=1.5).contains(&v)) {
                return Err(ChainParamsError::OutOfRange {
                    name,
                    value: v,
                    range: "0.1 to 1.5 m",
                });
            }
        }
        for (i, r) in self.imu_position.iter().enumerate() {
            if r.iter().any(|c| !(c.is_finite() && c.abs() <= 1.0)) {
                return Err(ChainParamsError::OutOfRange {
                    name: ["trunk imu", "thigh imu", "shank imu", "foot imu"][i],
                    value: r.iter().fold(0.0, |m: f64, c| m.max(c.abs())),
                    range: "-1 to 1 m per axis",
                });
            }
        }
        for (i, &psi) in self.frame_offset.iter().enumerate() {
            if !(psi.is_finite() && psi.abs() <= core::f64::consts::PI) {
                return Err(ChainParamsError::OutOfRange {
                    name: [
                        "trunk frame offset",
                        "thigh frame offset",
                        "shank frame offset",
                        "foot frame offset",
                    ][i],
                    value: psi,
                    range: "-pi to pi rad",
                });
            }
        }
        Ok(())
    }
}

impl Default for ChainGeometry {
    fn default() -> Self {
        Self::from_height(DEFAULT_BODY_HEIGHT_M)
    }
}

/// A parameter outside its range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ChainParamsError {
    /// `name` = `value` is outside `range`.
    #[error("chain parameter `{name}` = {} is outside {range}", limbfuse_core::ShownNumber(*value))]
    OutOfRange {
        /// Parameter name (the parameter-file key).
        name: &'static str,
        /// The value given.
        value: f64,
        /// The accepted range, in words.
        range: &'static str,
    },
}

/// Noise levels, anchors and switches of the chain EKF. The measurement
/// and anchor sigmas are per sample at 100 Hz; at another rate their
/// variances scale with the sample period so that the information per
/// second stays the same ([`super::sample_period`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChainParams {
    /// Gyro z white noise + model error per sample at 100 Hz, 1 sigma (rad/s).
    pub gyro_noise: f64,
    /// Accelerometer x/y noise + model error per sample at 100 Hz, 1 sigma
    /// (m/s^2).
    pub acc_noise: f64,
    /// Encoder noise + quantisation, 1 sigma (rad).
    pub encoder_noise: f64,
    /// Angular jerk intensity of the trunk, rad^2/s^5.
    pub trunk_jerk: f64,
    /// Angular jerk intensity of thigh, shank and foot, rad^2/s^5.
    pub leg_jerk: f64,
    /// Hip acceleration per axis: stationary 1 sigma (m/s^2) of its
    /// Gauss-Markov model.
    pub hip_acc_sd: f64,
    /// Hip acceleration: correlation time (s) of its Gauss-Markov model.
    pub hip_acc_tau: f64,
    /// Gyro bias random walk intensity, rad^2/s^3.
    pub gyro_bias_walk: f64,
    /// Initial gyro bias, 1 sigma (rad/s).
    pub gyro_bias_initial: f64,
    /// Vertical hip velocity about 0, 1 sigma (m/s) (anchor).
    pub hip_vertical_velocity: f64,
    /// Forward hip velocity about the mean speed, 1 sigma (m/s) (anchor).
    pub hip_forward_velocity: f64,
    /// Mean forward speed random walk intensity, m^2/s^3.
    pub mean_speed_walk: f64,
    /// Ankle velocity while the foot is still, 1 sigma (m/s) (anchor).
    pub stance_velocity: f64,
    /// Ankle acceleration while the foot is still, 1 sigma (m/s^2) (anchor).
    pub stance_acceleration: f64,
    /// Foot still: |gyro| below this (rad/s) ...
    pub stance_gyro: f64,
    /// ... and | |acc| - g | below this (m/s^2).
    pub stance_acc: f64,
    /// ... for at least this long (s) before the ankle anchor applies.
    pub stance_min_s: f64,
    /// Start-up window (s).
    pub startup_s: f64,
    /// Accelerometer rows with |innovation| above this many sigmas are
    /// skipped (infinity: none).
    pub acc_gate: f64,
    /// Encoder rows with |innovation| above this many sigmas are refused
    /// (infinity: none); a joint refused for `GATE_LOCKOUT_S` is re-adopted
    /// ([`super::encoder_gate`]). Default `sqrt(INNOVATION_GATE_CHI2)` =
    /// 4.89, the segment filters' encoder gate: the `1 - 1e-6` quantile of
    /// the chi-square distribution with one degree of freedom, so that a
    /// consistent filter refuses one good row in a million
    /// ([`crate::segment_kf::robust::INNOVATION_GATE_CHI2`]).
    pub encoder_gate: f64,
    /// A segment's gyroscope row with |innovation| above this many sigmas
    /// is refused (infinity: none), but only while an encoder of one of the
    /// segment's joints has a reading in the same sample, which observes
    /// the segment's motion relative to its neighbour; without one the row
    /// is always applied, and so is the row after a refused one (a glitch
    /// is one sample; [`super::encoder_gate`], "Gyroscope rows beside an
    /// encoder"). Default `sqrt(INNOVATION_GATE_CHI2)` = 4.89, as
    /// `encoder_gate`.
    pub gyro_gate: f64,
    /// Use the joint encoders when the trial has them.
    pub use_encoders: bool,
    /// Correct for the non-sagittal gyro components (eq C5).
    pub out_of_plane: bool,
    /// Turning: time constant (s) of the low-pass of the rate about the
    /// vertical (mean over the sensors), `Omega`.
    pub turn_tau_s: f64,
    /// Turning: `|Omega|` above this (rad/s) is a turn.
    pub turn_rate_min: f64,
    /// Turning: angle variance added per radian turned beyond
    /// `turn_rate_min`, as a 1-sigma per sqrt(rad) (rad): the planar model
    /// does not hold in a turn (0: off).
    pub turn_angle_noise: f64,
    /// Use the device's own orientation (`<seg>_quat_*`) when the trial has
    /// it, as an angle row per segment (docs/CHAIN.md, "Device orientation").
    pub device_orientation: bool,
    /// 1-sigma of that angle per sample at 100 Hz (rad).
    pub device_angle_noise: f64,
}

impl Default for ChainParams {
    fn default() -> Self {
        ChainParams {
            gyro_noise: 0.02,
            acc_noise: 0.3,
            encoder_noise: 0.2_f64.to_radians(),
            trunk_jerk: 300.0,
            leg_jerk: 1.0e4,
            hip_acc_sd: 2.0,
            hip_acc_tau: 0.1,
            gyro_bias_walk: 1.0e-7,
            gyro_bias_initial: 0.5_f64.to_radians() * 2.0,
            hip_vertical_velocity: 0.2,
            hip_forward_velocity: 0.3,
            mean_speed_walk: 1.0e-3,
            stance_velocity: 0.05,
            stance_acceleration: 0.5,
            stance_gyro: 0.6,
            stance_acc: 1.0,
            stance_min_s: 0.08,
            startup_s: 1.0,
            acc_gate: f64::INFINITY,
            encoder_gate: libm::sqrt(INNOVATION_GATE_CHI2),
            gyro_gate: libm::sqrt(INNOVATION_GATE_CHI2),
            use_encoders: true,
            out_of_plane: true,
            turn_tau_s: 0.5,
            turn_rate_min: 0.6,
            turn_angle_noise: 0.05,
            device_orientation: true,
            device_angle_noise: 2.0_f64.to_radians(),
        }
    }
}

impl ChainParams {
    /// Every value positive and finite (the gate may be infinite), the
    /// start-up window 0.1-30 s.
    pub fn validate(&self) -> Result<(), ChainParamsError> {
        let positive = [
            ("gyro_noise", self.gyro_noise),
            ("acc_noise", self.acc_noise),
            ("encoder_noise", self.encoder_noise),
            ("trunk_jerk", self.trunk_jerk),
            ("leg_jerk", self.leg_jerk),
            ("hip_acc_sd", self.hip_acc_sd),
            ("hip_acc_tau", self.hip_acc_tau),
            ("gyro_bias_walk", self.gyro_bias_walk),
            ("gyro_bias_initial", self.gyro_bias_initial),
            ("hip_vertical_velocity", self.hip_vertical_velocity),
            ("hip_forward_velocity", self.hip_forward_velocity),
            ("mean_speed_walk", self.mean_speed_walk),
            ("stance_velocity", self.stance_velocity),
            ("stance_acceleration", self.stance_acceleration),
            ("stance_gyro", self.stance_gyro),
            ("stance_acc", self.stance_acc),
            ("stance_min_s", self.stance_min_s),
            ("turn_tau_s", self.turn_tau_s),
            ("turn_rate_min", self.turn_rate_min),
        ];
        // (an audit: 1e300 and 1e-300 were accepted; squared into the
        // covariances they overflow or underflow, and the chain then gave
        // no estimate, reported as inputs missing)
        for (name, value) in positive {
            if !crate::segment_kf::params::SIGMA_RANGE.contains(&value) {
                return Err(ChainParamsError::OutOfRange {
                    name,
                    value,
                    range: "1e-12 to 1e12 (squared into a covariance, a smaller value underflows and a larger one swamps every other term)",
                });
            }
        }
        if !(self.startup_s.is_finite() && (0.1..=30.0).contains(&self.startup_s)) {
            return Err(ChainParamsError::OutOfRange {
                name: "startup_s",
                value: self.startup_s,
                range: "0.1 to 30 s",
            });
        }
        if !(self.turn_angle_noise.is_finite() && self.turn_angle_noise >= 0.0) {
            return Err(ChainParamsError::OutOfRange {
                name: "turn_angle_noise",
                value: self.turn_angle_noise,
                range: "0 or positive finite numbers",
            });
        }
        if !(self.device_angle_noise.is_finite() && self.device_angle_noise > 0.0) {
            return Err(ChainParamsError::OutOfRange {
                name: "device_angle_noise",
                value: self.device_angle_noise,
                range: "positive finite numbers",
            });
        }
        for (name, value) in [
            ("acc_gate", self.acc_gate),
            ("encoder_gate", self.encoder_gate),
            ("gyro_gate", self.gyro_gate),
        ] {
            if value.is_nan() || value <= 0.0 {
                return Err(ChainParamsError::OutOfRange {
                    name,
                    value,
                    range: "positive numbers (inf: no gate)",
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiny_and_huge_noise_levels_are_refused_in_exponent_form() {
        for (v, said) in [(1e300, "1e300"), (1e-300, "1e-300")] {
            let p = ChainParams {
                leg_jerk: v,
                ..Default::default()
            };
            let e = p.validate().unwrap_err().to_string();
            assert!(
                e.contains(&format!("`leg_jerk` = {said} is outside 1e-12 to 1e12")),
                "{e}"
            );
        }
    }

    #[test]
    fn defaults_validate_and_bad_values_are_named() {
        ChainParams::default().validate().unwrap();
        ChainGeometry::default().validate().unwrap();
        let p = ChainParams {
            acc_noise: -1.0,
            ..Default::default()
        };
        assert!(p.validate().unwrap_err().to_string().contains("acc_noise"));
        let g = ChainGeometry {
            shank_length: 3.0,
            ..Default::default()
        };
        assert!(g
            .validate()
            .unwrap_err()
            .to_string()
            .contains("shank_length"));
    }

    #[test]
    fn the_gates_take_positive_numbers_or_infinity() {
        for set in [
            |p: &mut ChainParams, v| p.acc_gate = v,
            |p: &mut ChainParams, v| p.encoder_gate = v,
            |p: &mut ChainParams, v| p.gyro_gate = v,
        ] {
            for (v, ok) in [
                (f64::INFINITY, true),
                (3.0, true),
                (0.0, false),
                (-1.0, false),
            ] {
                let mut p = ChainParams::default();
                set(&mut p, v);
                assert_eq!(p.validate().is_ok(), ok, "{v}");
            }
            let mut p = ChainParams::default();
            set(&mut p, f64::NAN);
            let e = p.validate().unwrap_err().to_string();
            assert!(e.contains("_gate"), "{e}");
        }
    }

    #[test]
    fn winter_lengths_scale_with_height() {
        let g = ChainGeometry::from_height(1.80);
        assert!((g.thigh_length - 0.441).abs() < 1e-12);
        assert!((g.shank_length - 0.4428).abs() < 1e-12);
    }
}
