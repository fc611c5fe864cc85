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
//! The defaults describe a consumer MEMS IMU of the Bosch BMI270 / TDK
//! ICM-42688-P class and a 14-bit absolute joint encoder, with the figures
//! of the simulator's `ImuSpec`/`EncoderSpec` (values and sources in
//! [`imu_spec`]). Nothing is fitted to a data set. The derivation
//! of every number is in `docs/SEGMENT_FILTERS.md` and on the constants
//! below.

use core::fmt;

use limbfuse_core::discretize::Discretization;
use limbfuse_core::kalman::CovarianceUpdate;
use limbfuse_core::{Segment, STANDARD_GRAVITY};

use super::criteria::AccelGate;

/// Datasheet values the defaults are derived from.
///
/// They are the figures of `limbfuse_sim::config::ImuSpec` and
/// `EncoderSpec` (the simulator's consumer-MEMS IMU and 14-bit encoder),
/// repeated here because this `no_std` crate cannot depend on the simulator.
/// Sources: Bosch Sensortec BMI270 data sheet (BST-BMI270-DS000), TDK
/// InvenSense ICM-42688-P data sheet (DS-000347), ams AS5047P data sheet.
pub mod imu_spec {
    /// Gyroscope output noise density, deg/s/sqrt(Hz): 0.007 (typ.), BMI270
    /// performance mode (the BMI160 data sheet gives the same).
    pub const GYRO_NOISE_DENSITY_DPS: f64 = 0.007;
    /// Gyroscope turn-on bias (zero-rate offset), deg/s, one sigma: 0.5
    /// (BMI270 and ICM-42688-P; Bosch states "typical" means one sigma).
    /// Constant over a trial.
    pub const GYRO_TURN_ON_BIAS_DPS: f64 = 0.5;
    /// In-run gyro bias drift, deg/s, stationary sigma of a Gauss-Markov
    /// process: 0.03. Not a data-sheet figure: about the offset temperature
    /// drift (~0.02 deg/s/K) over the 1-5 K of warming of a body-worn sensor.
    pub const GYRO_BIAS_INSTABILITY_DPS: f64 = 0.03;
    /// Correlation time (s) of that in-run drift: 200 (thermal time scale).
    pub const GYRO_BIAS_INSTABILITY_TAU_S: f64 = 200.0;
    /// Accelerometer output noise density, micro-g/sqrt(Hz): 160 (typ.),
    /// BMI270 (BMI160: 180).
    pub const ACCEL_NOISE_DENSITY_UG: f64 = 160.0;
    /// Accelerometer noise bandwidth (Hz): the BMI270's normal-mode filter at
    /// 100 Hz output data rate has a -3 dB bandwidth of about 40 Hz.
    pub const ACCEL_BANDWIDTH_HZ: f64 = 40.0;
    /// Accelerometer turn-on bias (zero-g offset), milli-g, one sigma: 20
    /// (BMI270, ICM-42688-P). Constant over a trial.
    pub const ACCEL_TURN_ON_BIAS_MG: f64 = 20.0;
    /// Accelerometer scale-factor error, fraction, one sigma: 0.005
    /// (ICM-42688-P +-0.5 %, BMI270 +-0.4 %).
    pub const ACCEL_SCALE_ERROR: f64 = 0.005;
    /// Reliability threshold zeta (m/s^2) on `| ||a|| - g |`: twice the
    /// standard deviation of that quantity for a *still* sensor, so a still
    /// sensor passes about 95 % of the time. With the figures above the
    /// still-sensor error of `||a||` is sqrt(b^2 + (s g)^2 + n^2) =
    /// sqrt(0.196^2 + 0.049^2 + 0.0099^2) = 0.2025 m/s^2 (b the zero-g
    /// offset, s the scale error, n the noise at 40 Hz), and 2 x 0.2025 =
    /// 0.405, rounded to 0.4.
    pub const ZETA_MPS2: f64 = 0.4;
    /// Encoder resolution, bits per turn (AS5047P: 14).
    pub const ENCODER_BITS: u32 = 14;
    /// Encoder white noise, in least significant bits, one sigma: 1.
    pub const ENCODER_NOISE_LSB: f64 = 1.0;
    /// Constant zeroing offset between the exoskeleton joint and the
    /// anatomical joint, deg, one sigma: 0.5 (mounting the exoskeleton).
    pub const ENCODER_OFFSET_DEG: f64 = 0.5;
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
/// `sigma * sqrt(2 / tau)` (intensity `2 sigma^2 / tau`). Over steps much
/// shorter than `tau` the process then changes as it does in the sensor.
pub fn gauss_markov_drive(sigma: f64, tau: f64) -> f64 {
    sigma * libm::sqrt(2.0 / tau)
}

/// Standard deviation (rad) of the quantisation noise alone of an absolute
/// encoder of `bits` bits per turn: `(2 pi / 2^bits) / sqrt(12)`.
pub fn encoder_quantisation_sigma(bits: u32) -> f64 {
    encoder_lsb(bits) / libm::sqrt(12.0)
}

/// One least significant bit (rad) of an encoder of `bits` bits per turn.
pub fn encoder_lsb(bits: u32) -> f64 {
    core::f64::consts::TAU / libm::pow(2.0, bits as f64)
}

/// The default encoder-row standard deviation (rad): white noise of
/// [`imu_spec::ENCODER_NOISE_LSB`] LSB of a 14-bit encoder (3.835e-4 rad)
/// combined with the 0.5 deg zeroing offset ([`imu_spec::ENCODER_OFFSET_DEG`]),
/// which the filter cannot separate from the joint angle and so treats as
/// noise: sqrt(3.835e-4^2 + 8.727e-3^2) = 8.735e-3 rad (0.50 deg).
pub fn default_encoder_sigma() -> f64 {
    let n = imu_spec::ENCODER_NOISE_LSB * encoder_lsb(imu_spec::ENCODER_BITS);
    let o = imu_spec::ENCODER_OFFSET_DEG * core::f64::consts::PI / 180.0;
    libm::sqrt(n * n + o * o)
}

impl SegmentNoise {
    /// The physical default of a consumer MEMS IMU ([`imu_spec`]):
    ///
    /// * `gyro_noise` = 0.007 deg/s/sqrt(Hz) = 1.2217e-4 rad/s/sqrt(Hz);
    /// * `bias_drive` = `gauss_markov_drive(0.03 deg/s, 200 s)` = 0.003
    ///   deg/s/sqrt(s) = 5.236e-5 rad/s/sqrt(s): the in-run drift;
    /// * `bias_tau` = infinity: the dominant part of the bias, the 0.5 deg/s
    ///   turn-on offset, is constant over a trial, so the bias estimate must
    ///   not decay towards zero between updates (a finite `tau` in 000 eq 6
    ///   would pull it to zero); over a trial the in-run drift is then a
    ///   random walk of the same increments;
    /// * `accel_angle_sigma` = sqrt((n/g)^2 + (b/g)^2 + d^2) = 0.166 rad
    ///   (9.5 deg): accelerometer noise n = 160 ug/sqrt(Hz) * sqrt(40 Hz) =
    ///   0.0099 m/s^2; the zero-g offset b = 20 mg, whose component
    ///   perpendicular to gravity tilts the measured vector by b/g = 0.020
    ///   rad (constant per trial, treated as noise); and the allowance d for
    ///   the dynamic acceleration the reliability test lets through. The
    ///   test is only second-order sensitive to an acceleration a_perp
    ///   perpendicular to gravity: `||g + a_perp|| - g ~ a_perp^2 / (2 g)`,
    ///   so `rho < zeta` admits a_perp up to sqrt(2 g zeta) (2.8 m/s^2 for
    ///   zeta = 0.4), a tilt of up to sqrt(2 zeta / g) = 0.286 rad (16 deg).
    ///   Taking the admitted tilt as uniform within that bound gives d =
    ///   sqrt(2 zeta / g) / sqrt(3) = 0.165 rad. (The first-order figure
    ///   zeta/g = 0.041 rad holds only for accelerations along gravity and
    ///   underestimates the error: in the walking simulator at 1 m/s the
    ///   inclination error at instants passing the test has a standard
    ///   deviation of 13-22 deg.)
    /// * `zeta` = 0.4 m/s^2 ([`imu_spec::ZETA_MPS2`]).
    pub fn consumer_mems(gravity: f64) -> Self {
        let deg = core::f64::consts::PI / 180.0;
        let n = imu_spec::ACCEL_NOISE_DENSITY_UG
            * 1e-6
            * STANDARD_GRAVITY
            * libm::sqrt(imu_spec::ACCEL_BANDWIDTH_HZ);
        let b = imu_spec::ACCEL_TURN_ON_BIAS_MG * 1e-3 * STANDARD_GRAVITY;
        let zeta = imu_spec::ZETA_MPS2;
        let (n, b) = (n / gravity, b / gravity);
        let d = libm::sqrt(2.0 * zeta / gravity) / libm::sqrt(3.0);
        SegmentNoise {
            gyro_noise: imu_spec::GYRO_NOISE_DENSITY_DPS * deg,
            bias_drive: gauss_markov_drive(
                imu_spec::GYRO_BIAS_INSTABILITY_DPS * deg,
                imu_spec::GYRO_BIAS_INSTABILITY_TAU_S,
            ),
            bias_tau: f64::INFINITY,
            accel_angle_sigma: libm::sqrt(n * n + b * b + d * d),
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
    /// rad (2.9 deg): the first accelerometer inclination carries the
    /// zero-g offset (0.020 rad) and, for a subject standing still but
    /// swaying, up to about 0.45 m/s^2 of residual acceleration (0.046 rad);
    /// sqrt(0.020^2 + 0.046^2) = 0.050.
    pub p0_angle_sigma: f64,
    /// Initial standard deviation of each gyro-bias error (rad/s). Default
    /// sqrt(0.5^2 + 0.03^2) = 0.5009 deg/s: turn-on offset and in-run drift
    /// ([`imu_spec`]).
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
    /// Refinements of the accelerometer acceptance test on top of `rho_i <
    /// zeta_i` (quasi-static duration, angular rate). Off
    /// by default ([`AccelGate::OFF`]): the papers' test alone. See
    /// [`AccelGate`] and `docs/SEGMENT_FILTERS.md`.
    pub accel_gate: AccelGate,
    /// Run-in (s) after a (re)start during which the filter emits no
    /// estimate; 0 (default) = the papers' filters, which output from their
    /// first sample. The filter itself runs exactly as without it (each
    /// segment started at its first accelerometer inclination): only its
    /// convergence transient is withheld, as `chain` withholds its start-up
    /// window (ours, issue 14; papers 000/001 do not say how their filters
    /// start; docs/SEGMENT_FILTERS.md, "Run-in").
    pub startup_s: f64,
    /// `true`: every segment starts at its first accelerometer sample (the
    /// start of limbfuse before 2026-12-06; mjls: the chain from the argmin
    /// `rho` segment of its first sample). `false` (default): a segment
    /// starts from a quasi-static sample or, after a 2 s window, from its
    /// gyro-derotated mean specific force (ours, not the papers', which do
    /// not say how their filters start; docs/SEGMENT_FILTERS.md,
    /// "Initialisation").
    pub first_sample_start: bool,
    /// `true` (default): a gyroscope reading that the joint encoders show
    /// to be a single-sample spike is replaced by the rate the encoders
    /// imply (thigh, shank) or held as a missing one (trunk, foot) (ours,
    /// not the papers'; [`super::rate_spikes`],
    /// docs/ROBUST_INPUT.md "Gyroscope spikes beside the encoders"). Needs
    /// the three encoders; `false` applies every reading the sample gate
    /// passes, as the papers do.
    pub rate_spike_test: bool,
}

impl Default for CommonParams {
    fn default() -> Self {
        let noise = SegmentNoise::consumer_mems(STANDARD_GRAVITY);
        CommonParams {
            segments: [noise; 4],
            gravity: STANDARD_GRAVITY,
            p0_angle_sigma: 0.05,
            p0_bias_sigma: libm::sqrt(
                imu_spec::GYRO_TURN_ON_BIAS_DPS * imu_spec::GYRO_TURN_ON_BIAS_DPS
                    + imu_spec::GYRO_BIAS_INSTABILITY_DPS * imu_spec::GYRO_BIAS_INSTABILITY_DPS,
            ) * core::f64::consts::PI
                / 180.0,
            initial_gyro_bias: [0.0; 4],
            loop_mode: LoopMode::Closed,
            discretization: Discretization::Exact,
            covariance_update: CovarianceUpdate::Joseph,
            accel_gate: AccelGate::OFF,
            startup_s: 0.0,
            first_sample_start: false,
            rate_spike_test: true,
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
        let mut segments = [SegmentNoise::consumer_mems(STANDARD_GRAVITY); 4];
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
            density("gyro_noise", s.gyro_noise)?;
            density("bias_drive", s.bias_drive)?;
            if s.bias_tau.is_nan() || s.bias_tau <= 0.0 {
                return Err(ParamError::new(
                    "bias_tau",
                    "must be > 0 (infinity allowed)",
                ));
            }
            sigma("accel_angle_sigma", s.accel_angle_sigma)?;
            positive("zeta", s.zeta)?;
        }
        if !(GRAVITY_RANGE.contains(&self.gravity)) {
            return Err(ParamError::new(
                "gravity",
                "must be from 1 to 20 (Earth's: 9.78-9.83)",
            ));
        }
        sigma("p0_angle_sigma", self.p0_angle_sigma)?;
        sigma("p0_bias_sigma", self.p0_bias_sigma)?;
        for b in self.initial_gyro_bias {
            if !(b.is_finite() && b.abs() <= MAX_GYRO_BIAS) {
                return Err(ParamError::new(
                    "initial_gyro_bias",
                    "must be within +-1 rad/s (57 deg/s; a MEMS gyro's zero-rate offset is a few deg/s)",
                ));
            }
        }
        let g = &self.accel_gate;
        positive_or_zero("accel_gate.hold_s", g.hold_s)?;
        if g.max_rate.is_nan() || g.max_rate <= 0.0 {
            return Err(ParamError::new(
                "accel_gate.max_rate",
                "must be > 0 (infinity = off)",
            ));
        }
        if !(self.startup_s.is_finite() && (0.0..=30.0).contains(&self.startup_s)) {
            return Err(ParamError::new("startup_s", "must be 0 (off) to 30 s"));
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
        if !self.accel_gate.is_off() {
            let g = &self.accel_gate;
            writeln!(out, "accel_gate.hold_s: {}", g.hold_s)?;
            writeln!(out, "accel_gate.max_rate: {}", g.max_rate)?;
        }
        if self.startup_s > 0.0 {
            writeln!(out, "startup_s: {}", self.startup_s)?;
        }
        for seg in Segment::ALL {
            let s = &self.segments[seg.index()];
            let n = seg.name();
            writeln!(out, "{n}.gyro_noise: {}", s.gyro_noise)?;
            writeln!(out, "{n}.bias_drive: {}", s.bias_drive)?;
            writeln!(out, "{n}.bias_tau: {}", s.bias_tau)?;
            writeln!(out, "{n}.accel_angle_sigma: {}", s.accel_angle_sigma)?;
            writeln!(out, "{n}.zeta: {}", s.zeta)?;
            writeln!(
                out,
                "{n}.initial_gyro_bias: {}",
                self.initial_gyro_bias[seg.index()]
            )?;
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

/// The gravity a filter may be given (m/s^2): the simulators' range, wide
/// around Earth's 9.78-9.83 (an audit: 1e-300 and 1e300 were accepted and
/// turned every accelerometer row off).
const GRAVITY_RANGE: core::ops::RangeInclusive<f64> = 1.0..=20.0;

/// The largest initial gyro bias (rad/s): the simulators' drift bound.
const MAX_GYRO_BIAS: f64 = 1.0;

/// The range of a standard deviation (or noise density) in its SI unit:
/// squared into a covariance, a value below 1e-12 underflows towards 0 or
/// swamps nothing (an audit: `encoder_sigma = 1e-300` squared to 0 and then
/// acted exactly as `1e300`, whose square is infinite: no update ever), and
/// one above 1e12 leaves no digit of the other terms in double precision.
pub const SIGMA_RANGE: core::ops::RangeInclusive<f64> = 1e-12..=1e12;

/// A standard deviation: within [`SIGMA_RANGE`].
pub(crate) fn sigma(field: &'static str, v: f64) -> Result<(), ParamError> {
    if SIGMA_RANGE.contains(&v) {
        Ok(())
    } else {
        Err(ParamError::new(
            field,
            "must be from 1e-12 to 1e12 (squared into a covariance, a smaller value underflows and a larger one swamps every other term)",
        ))
    }
}

/// A process-noise density: 0 (none) or within [`SIGMA_RANGE`].
pub(crate) fn density(field: &'static str, v: f64) -> Result<(), ParamError> {
    if v == 0.0 || SIGMA_RANGE.contains(&v) {
        Ok(())
    } else {
        Err(ParamError::new(
            field,
            "must be 0 (none) or from 1e-12 to 1e12 (squared into a covariance, a smaller value underflows and a larger one swamps every other term)",
        ))
    }
}

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
        let s = SegmentNoise::consumer_mems(9.81);
        // 0.007 deg/s/sqrt(Hz) in rad.
        assert!((s.gyro_noise - 1.22173e-4).abs() < 1e-9);
        // 0.03 deg/s * sqrt(2/200) = 0.003 deg/s/sqrt(s) = 5.23599e-5 rad.
        assert!((s.bias_drive - 5.23599e-5).abs() < 1e-10);
        assert_eq!(s.bias_tau, f64::INFINITY);
        // n/g = 160e-6 * sqrt(40) = 1.01193e-3; b/g = 0.02;
        // d^2 = (2 * 0.4 / 9.81) / 3 = 0.0271832;
        // sqrt(1.02400e-6 + 4e-4 + 0.0271832) = sqrt(0.0275842) = 0.166085 rad.
        assert!((s.accel_angle_sigma - 0.166085).abs() < 1e-6);
        assert_eq!(s.zeta, 0.4);
        // 2 pi / 16384 = 3.8350e-4 rad; / sqrt(12) = 1.10706e-4 rad.
        assert!((encoder_quantisation_sigma(14) - 1.10706e-4).abs() < 1e-9);
        // sqrt(3.83495e-4^2 + 8.72665e-3^2) = 8.73507e-3 rad.
        assert!((default_encoder_sigma() - 8.73507e-3).abs() < 1e-8);
        // sqrt(0.5^2 + 0.03^2) deg/s = 0.500899 deg/s = 8.742340e-3 rad/s.
        assert!((CommonParams::default().p0_bias_sigma - 8.742340e-3).abs() < 1e-9);
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
        let p = CommonParams {
            gravity: f64::NAN,
            ..CommonParams::default()
        };
        assert!(p.validate().is_err());
        let mut p = CommonParams::default();
        p.segments[0].bias_tau = f64::INFINITY;
        assert!(p.validate().is_ok());
        p.accel_gate.hold_s = -0.01;
        assert_eq!(p.validate().unwrap_err().field, "accel_gate.hold_s");
        p.accel_gate.hold_s = 0.01;
        p.accel_gate.max_rate = 0.0;
        assert_eq!(p.validate().unwrap_err().field, "accel_gate.max_rate");
        p.accel_gate.max_rate = f64::NAN;
        assert!(p.validate().is_err());
        p.accel_gate.max_rate = 1.0;
        assert!(p.validate().is_ok());
    }
}
