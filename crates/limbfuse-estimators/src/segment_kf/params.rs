//! Parameters shared by the three segment-angle filters, their physical
//! defaults and the paper-2014 preset.
//!
//! Units are SI (SPEC section 1). Each segment has its own noise model
//! ([`SegmentNoise`]); [`CommonParams`] holds the four of them plus the
//! numerical choices (loop form, discretisation, covariance form) and the
//! initial covariance. The filter-specific parameter structs
//! ([`crate::segment_kf::LocalKfParams`], [`crate::segment_kf::MarkovJumpKfParams`],
//! [`crate::segment_kf::GlobalKfParams`]) embed a [`CommonParams`].
//!
//! # Where the defaults come from
//!
//! The defaults describe a consumer MEMS IMU of the Bosch BMI160/BMI270
//! class (datasheet BST-BMI270-DS000; values in [`imu_spec`]) and a 14-bit
//! absolute joint encoder. Nothing is fitted to a data set. The derivation
//! of every number is in `docs/SEGMENT_FILTERS.md` and on the constants
//! below.

use core::fmt;

use limbfuse_core::discretize::Discretization;
use limbfuse_core::kalman::CovarianceUpdate;
use limbfuse_core::{Segment, STANDARD_GRAVITY};

/// Datasheet values the defaults are derived from.
pub mod imu_spec {
    /// Gyroscope output noise density, deg/s/sqrt(Hz): 0.007 (typ.), Bosch
    /// BMI270 datasheet BST-BMI270-DS000 (performance mode); the BMI160
    /// datasheet gives the same 0.007.
    pub const GYRO_NOISE_DENSITY_DPS: f64 = 0.007;
    /// Gyroscope zero-rate offset, deg/s: +-0.5 (typ.), BMI270 datasheet;
    /// Bosch states its "typical" values are one standard deviation. Used as
    /// the stationary standard deviation of the Gauss-Markov gyro bias and as
    /// the initial bias uncertainty.
    pub const GYRO_ZERO_RATE_OFFSET_DPS: f64 = 0.5;
    /// Correlation time of the gyro bias (s). Not a datasheet number: the
    /// in-run variation of a MEMS gyro offset is dominated by temperature,
    /// and a body-worn sensor settles to skin temperature over minutes; 600 s
    /// is that thermal time scale. With [`GYRO_ZERO_RATE_OFFSET_DPS`] it gives
    /// a bias random walk of 0.5 deg/s * sqrt(2/600 s) = 0.029 deg/s/sqrt(s).
    pub const GYRO_BIAS_TAU_S: f64 = 600.0;
    /// Accelerometer output noise density, micro-g/sqrt(Hz): 160 (typ.),
    /// BMI270 datasheet (BMI160: 180).
    pub const ACCEL_NOISE_DENSITY_UG: f64 = 160.0;
    /// Accelerometer noise bandwidth (Hz) assumed for the angle noise: the
    /// BMI270's normal-mode filter at 100 Hz ODR has a -3 dB bandwidth of
    /// about 40 Hz.
    pub const ACCEL_BANDWIDTH_HZ: f64 = 40.0;
    /// Reliability threshold zeta (m/s^2) on `| ||a|| - g |`: the value of
    /// paper 000's worked example (section 3, zeta = 0.2) read in m/s^2. It is
    /// 20 times the accelerometer's rms noise at 40 Hz bandwidth (0.0099
    /// m/s^2), so a still, calibrated sensor always passes, and it bounds the
    /// accepted dynamic acceleration to about 2 % of g.
    pub const ZETA_MPS2: f64 = 0.2;
    /// Resolution of the joint encoders (bits per revolution).
    pub const ENCODER_BITS: u32 = 14;
}

/// Noise model and reliability threshold of one segment's IMU.
///
/// Paper 000 eqs 1-2 and 9; the continuous intensities are the diagonal of
/// `Q` (000 eq 26) and the accelerometer-angle variance is `R` (000 eq 27,
/// 001 eq 22).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentNoise {
    /// Gyro white-noise density (rad/s/sqrt(Hz)), `eta_g` of 000 eq 1. The
    /// continuous intensity of the angle-error noise is its square (rad^2/s).
    pub gyro_noise: f64,
    /// Density of the white noise driving the bias (rad/s/sqrt(s)),
    /// `eta_bg` of 000 eq 2. Continuous intensity is its square. For a
    /// Gauss-Markov bias of stationary standard deviation `s` and correlation
    /// time `tau` use [`gauss_markov_drive`]`(s, tau)`.
    pub bias_drive: f64,
    /// Bias correlation time `tau_g` (s), 000 eq 2. `f64::INFINITY` makes the
    /// bias a random walk.
    pub bias_tau: f64,
    /// Standard deviation (rad) of the accelerometer inclination when the
    /// accelerometer is deemed reliable, `eta_a` of 000 eq 9 / 001 eq 2.
    pub accel_angle_sigma: f64,
    /// Reliability threshold zeta (m/s^2) on `rho = | ||a|| - g |`
    /// (000 eq 30, 001 eqs 13-18, 26-28).
    pub zeta: f64,
}

/// White-noise density driving a first-order Gauss-Markov process of
/// stationary standard deviation `sigma` and correlation time `tau`:
/// `sigma * sqrt(2 / tau)` (intensity `2 sigma^2 / tau`).
pub fn gauss_markov_drive(sigma: f64, tau: f64) -> f64 {
    sigma * libm::sqrt(2.0 / tau)
}

/// Standard deviation (rad) of the quantisation noise of an absolute
/// encoder of `bits` bits per revolution: `(2 pi / 2^bits) / sqrt(12)`.
pub fn encoder_quantisation_sigma(bits: u32) -> f64 {
    core::f64::consts::TAU / libm::pow(2.0, bits as f64) / libm::sqrt(12.0)
}

impl SegmentNoise {
    /// The physical default of a BMI270-class IMU (see [`imu_spec`]).
    ///
    /// * `gyro_noise` = 0.007 deg/s/sqrt(Hz) = 1.222e-4 rad/s/sqrt(Hz);
    /// * `bias_drive` = `gauss_markov_drive(0.5 deg/s, 600 s)` = 5.04e-4 rad/s/sqrt(s);
    /// * `bias_tau` = 600 s;
    /// * `accel_angle_sigma` = sqrt((sigma_acc/g)^2 + (zeta/g)^2) = 0.0204 rad
    ///   (1.17 deg), where sigma_acc = 160 ug/sqrt(Hz) * sqrt(40 Hz) = 0.0099
    ///   m/s^2 is the accelerometer noise and zeta/g the allowance for the
    ///   residual dynamic acceleration the reliability test lets through
    ///   (a dynamic acceleration of size zeta perpendicular to gravity tilts
    ///   the measured vector by zeta/g);
    /// * `zeta` = 0.2 m/s^2.
    pub fn bmi270_class(gravity: f64) -> Self {
        let deg = core::f64::consts::PI / 180.0;
        let sigma_b = imu_spec::GYRO_ZERO_RATE_OFFSET_DPS * deg;
        let sigma_acc = imu_spec::ACCEL_NOISE_DENSITY_UG
            * 1e-6
            * STANDARD_GRAVITY
            * libm::sqrt(imu_spec::ACCEL_BANDWIDTH_HZ);
        let zeta = imu_spec::ZETA_MPS2;
        let noise_angle = sigma_acc / gravity;
        let dynamic_angle = zeta / gravity;
        SegmentNoise {
            gyro_noise: imu_spec::GYRO_NOISE_DENSITY_DPS * deg,
            bias_drive: gauss_markov_drive(sigma_b, imu_spec::GYRO_BIAS_TAU_S),
            bias_tau: imu_spec::GYRO_BIAS_TAU_S,
            accel_angle_sigma: libm::sqrt(
                noise_angle * noise_angle + dynamic_angle * dynamic_angle,
            ),
            zeta,
        }
    }
}

/// Paper 000, Table 2 ("System parameters"), one row per segment: zeta,
/// sigma_g, sigma_bg, sigma_a, tau_g. These are weights tuned by a genetic
/// algorithm for that paper's data (SPEC section 6), used as they are: the
/// sigmas squared are the continuous intensities of `Q` (000 eq 26) and
/// `R = sigma_a^2` (000 eq 27).
pub const PAPER_2014_TABLE_2: [[f64; 5]; 4] = [
    // zeta, sigma_g, sigma_bg, sigma_a, tau_g
    [0.01, 0.0103, 0.0003, 46.562, 839.70], // body/trunk
    [0.01, 0.0017, 0.0005, 329.08, 2138.5], // thigh
    [0.01, 0.0008, 9.6405, 100.94, 1465.3], // shank
    [0.01, 7.7482, 18.594, 291.29, 3567.5], // foot
];

/// How the error-state estimate is used (SPEC section 6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LoopMode {
    /// After each update the angle correction is added to the integrated
    /// angle, the bias correction to the bias estimate, and the error state
    /// is reset to zero (default).
    #[default]
    Closed,
    /// The papers' form (000 eqs 12-13, 001 eq 3): the gyro is integrated
    /// without feedback and the output is `theta_g + dtheta_hat`; the error
    /// state is propagated with `Phi` and never reset.
    Open,
}

impl LoopMode {
    /// `closed` or `open`.
    pub const fn label(self) -> &'static str {
        match self {
            LoopMode::Closed => "closed",
            LoopMode::Open => "open",
        }
    }
}

/// Parameters every segment filter shares.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CommonParams {
    /// Noise model per segment, indexed by [`Segment::index`] (trunk, thigh, shank, foot).
    pub segments: [SegmentNoise; 4],
    /// Gravity g (m/s^2) in `rho = | ||a|| - g |`. Default 9.81 (SPEC section 1).
    pub gravity: f64,
    /// Initial standard deviation of each angle error (rad). Default 0.05
    /// rad (2.9 deg): the first accelerometer inclination of a subject
    /// standing still but swaying, with up to 0.5 m/s^2 of residual
    /// acceleration (0.5/9.81 = 0.051 rad).
    pub p0_angle_sigma: f64,
    /// Initial standard deviation of each gyro-bias error (rad/s). Default
    /// 0.5 deg/s, the BMI270 zero-rate offset (one sigma).
    pub p0_bias_sigma: f64,
    /// Gyro bias assumed at start (rad/s) per segment, in the sensor
    /// convention (gyro reads true rate + bias). Default zero.
    pub initial_gyro_bias: [f64; 4],
    /// Closed-loop (default) or open-loop error-state filter.
    pub loop_mode: LoopMode,
    /// `Phi`/`Qd` computation: exact (matrix exponential + Van Loan, default)
    /// or Euler (the papers' `Phi = I + A T`, `Qd = Q T`), SPEC section 6.
    pub discretization: Discretization,
    /// Posterior covariance form: Joseph (default) or the papers' `(I - K H) P`.
    pub covariance_update: CovarianceUpdate,
}

impl Default for CommonParams {
    fn default() -> Self {
        let noise = SegmentNoise::bmi270_class(STANDARD_GRAVITY);
        CommonParams {
            segments: [noise; 4],
            gravity: STANDARD_GRAVITY,
            p0_angle_sigma: 0.05,
            p0_bias_sigma: imu_spec::GYRO_ZERO_RATE_OFFSET_DPS * core::f64::consts::PI / 180.0,
            initial_gyro_bias: [0.0; 4],
            loop_mode: LoopMode::Closed,
            discretization: Discretization::Exact,
            covariance_update: CovarianceUpdate::Joseph,
        }
    }
}

impl CommonParams {
    /// Paper 000 Table 2 ([`PAPER_2014_TABLE_2`]) with the papers' numerics:
    /// Euler discretisation (000 eq 19 / 001 Algorithm 1, `F = I + A T`,
    /// `G ~ B T^(1/2)`) and `P0 = I` (001, first iteration of the worked
    /// example). The loop form and covariance form keep their defaults
    /// (closed loop and Joseph form give the same estimates as the papers'
    /// open loop and `(I - K H) P` up to round-off).
    pub fn paper_2014() -> Self {
        let mut segments = [SegmentNoise::bmi270_class(STANDARD_GRAVITY); 4];
        for (s, row) in segments.iter_mut().zip(PAPER_2014_TABLE_2.iter()) {
            *s = SegmentNoise {
                zeta: row[0],
                gyro_noise: row[1],
                bias_drive: row[2],
                accel_angle_sigma: row[3],
                bias_tau: row[4],
            };
        }
        CommonParams {
            segments,
            p0_angle_sigma: 1.0,
            p0_bias_sigma: 1.0,
            discretization: Discretization::Euler,
            ..CommonParams::default()
        }
    }

    /// The reliability thresholds zeta of the four segments.
    pub fn zetas(&self) -> [f64; 4] {
        [
            self.segments[0].zeta,
            self.segments[1].zeta,
            self.segments[2].zeta,
            self.segments[3].zeta,
        ]
    }

    /// Checks that every value is finite and in range.
    pub fn validate(&self) -> Result<(), ParamError> {
        for s in &self.segments {
            positive_or_zero("gyro_noise", s.gyro_noise)?;
            positive_or_zero("bias_drive", s.bias_drive)?;
            if !(s.bias_tau > 0.0) {
                return Err(ParamError::new("bias_tau", "must be > 0 (infinity allowed)"));
            }
            positive("accel_angle_sigma", s.accel_angle_sigma)?;
            positive("zeta", s.zeta)?;
        }
        positive("gravity", self.gravity)?;
        positive("p0_angle_sigma", self.p0_angle_sigma)?;
        positive("p0_bias_sigma", self.p0_bias_sigma)?;
        for b in self.initial_gyro_bias {
            if !b.is_finite() {
                return Err(ParamError::new("initial_gyro_bias", "must be finite"));
            }
        }
        Ok(())
    }

    /// Writes the parameters as `key: value` lines.
    pub fn describe(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        writeln!(out, "loop: {}", self.loop_mode.label())?;
        writeln!(
            out,
            "discretization: {}",
            match self.discretization {
                Discretization::Exact => "exact",
                Discretization::Euler => "euler",
            }
        )?;
        writeln!(
            out,
            "covariance_update: {}",
            match self.covariance_update {
                CovarianceUpdate::Joseph => "joseph",
                CovarianceUpdate::Standard => "standard",
            }
        )?;
        writeln!(out, "gravity: {}", self.gravity)?;
        writeln!(out, "p0_angle_sigma: {}", self.p0_angle_sigma)?;
        writeln!(out, "p0_bias_sigma: {}", self.p0_bias_sigma)?;
        for seg in Segment::ALL {
            let s = &self.segments[seg.index()];
            let n = seg.name();
            writeln!(out, "{n}.gyro_noise: {}", s.gyro_noise)?;
            writeln!(out, "{n}.bias_drive: {}", s.bias_drive)?;
            writeln!(out, "{n}.bias_tau: {}", s.bias_tau)?;
            writeln!(out, "{n}.accel_angle_sigma: {}", s.accel_angle_sigma)?;
            writeln!(out, "{n}.zeta: {}", s.zeta)?;
            writeln!(out, "{n}.initial_gyro_bias: {}", self.initial_gyro_bias[seg.index()])?;
        }
        Ok(())
    }
}

/// An invalid parameter value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ParamError {
    /// Name of the offending field.
    pub field: &'static str,
    /// What is wrong with it.
    pub reason: &'static str,
}

impl ParamError {
    pub(crate) const fn new(field: &'static str, reason: &'static str) -> Self {
        ParamError { field, reason }
    }
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "invalid parameter {}: {}", self.field, self.reason)
    }
}

#[cfg(feature = "std")]
impl std::error::Error for ParamError {}

pub(crate) fn positive(field: &'static str, v: f64) -> Result<(), ParamError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(ParamError::new(field, "must be finite and > 0"))
    }
}

pub(crate) fn positive_or_zero(field: &'static str, v: f64) -> Result<(), ParamError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(ParamError::new(field, "must be finite and >= 0"))
    }
}

/// Validates a Psi_s count: 1 to 4.
pub(crate) fn check_min_reliable(s: u8) -> Result<(), ParamError> {
    if (1..=4).contains(&s) {
        Ok(())
    } else {
        Err(ParamError::new("min_reliable", "Psi_s needs s in 1..=4"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_values_follow_from_the_datasheet_numbers() {
        let s = SegmentNoise::bmi270_class(9.81);
        // 0.007 deg/s/sqrt(Hz) in rad.
        assert!((s.gyro_noise - 1.2217e-4).abs() < 1e-8);
        // 0.5 deg/s * sqrt(2/600) = 8.7266e-3 * 0.057735 = 5.0383e-4.
        assert!((s.bias_drive - 5.0383e-4).abs() < 1e-8);
        // sigma_acc = 160e-6 * 9.81 * sqrt(40) = 9.927e-3 m/s^2;
        // sqrt((9.927e-3/9.81)^2 + (0.2/9.81)^2) = 0.020413 rad.
        assert!((s.accel_angle_sigma - 0.020413).abs() < 1e-6);
        // 2 pi / 16384 = 3.8350e-4 rad; / sqrt(12) = 1.10706e-4 rad.
        assert!((encoder_quantisation_sigma(14) - 1.10706e-4).abs() < 1e-9);
        assert!(CommonParams::default().validate().is_ok());
        assert!(CommonParams::paper_2014().validate().is_ok());
    }

    #[test]
    fn paper_preset_holds_table_2() {
        let p = CommonParams::paper_2014();
        assert_eq!(p.segments[3].gyro_noise, 7.7482);
        assert_eq!(p.segments[2].bias_drive, 9.6405);
        assert_eq!(p.segments[1].accel_angle_sigma, 329.08);
        assert_eq!(p.segments[0].bias_tau, 839.70);
        assert_eq!(p.zetas(), [0.01; 4]);
    }

    #[test]
    fn validation_rejects_nonsense() {
        let mut p = CommonParams::default();
        p.segments[2].zeta = -1.0;
        assert_eq!(p.validate().unwrap_err().field, "zeta");
        let mut p = CommonParams::default();
        p.gravity = f64::NAN;
        assert!(p.validate().is_err());
        let mut p = CommonParams::default();
        p.segments[0].bias_tau = f64::INFINITY;
        assert!(p.validate().is_ok());
    }
}
