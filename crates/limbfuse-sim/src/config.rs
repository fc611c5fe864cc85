//! Configuration of the walking simulator, its defaults and their sources.

/// Why a configuration was rejected. Each variant names the parameter and
/// the allowed range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    /// A parameter is outside its allowed range (or not a finite number).
    #[error("{name} = {} is outside the allowed range {range}", limbfuse_core::ShownNumber(*value))]
    OutOfRange {
        /// Parameter name, as in the config struct (e.g. `speed_mps`).
        name: &'static str,
        /// The offending value.
        value: f64,
        /// Allowed range, human readable.
        range: &'static str,
    },
    /// The gait could not be calibrated to the requested speed.
    #[error(
        "could not reach stride length {wanted:.3} m (got {reached:.3} m) for the requested speed"
    )]
    Calibration {
        /// Stride length reached (m).
        reached: f64,
        /// Stride length wanted (m).
        wanted: f64,
    },
}

/// What the body does.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Motion {
    /// Walk at `speed_mps`.
    #[default]
    Walk,
    /// Upright quiet standing: every angle 0, every sensor static.
    Stand,
    /// Hold the walking posture of gait phase `phase` (rad, 0 = heel strike) still.
    Pose {
        /// Gait phase (rad).
        phase: f64,
    },
}

/// How each IMU is oriented on its segment (before the small random misalignment).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Mounting {
    /// Sensor axes along the segment axes (SPEC "aligned" frame).
    #[default]
    Aligned,
    /// A uniformly random rotation per sensor (for alignment work).
    Random,
}

/// How the 1 kHz encoder stream is brought onto the IMU time base.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EncoderResample {
    /// The latest encoder sample at or before the IMU sample time (zero-order
    /// hold, what a controller reading the encoder register gets).
    #[default]
    Latest,
    /// Mean of the encoder samples in the IMU period `(t - T, t]` (causal
    /// box filter: lag T/2, noise reduced by sqrt of the samples averaged).
    Mean,
}

/// Error figures of one sensor triad (gyroscope or accelerometer).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriadSpec {
    /// White-noise density (unit/s... per sqrt(Hz): rad/s/sqrt(Hz) or m/s^2/sqrt(Hz)).
    pub noise_density: f64,
    /// Standard deviation of the turn-on bias, constant over a trial (unit).
    pub turn_on_bias: f64,
    /// Stationary standard deviation of the in-run Gauss-Markov bias (unit).
    pub bias_instability: f64,
    /// Correlation time of the Gauss-Markov bias (s).
    pub bias_tau_s: f64,
    /// Standard deviation of the per-axis scale-factor error (fraction).
    pub scale_error: f64,
    /// Standard deviation of each cross-axis sensitivity term (fraction).
    pub cross_axis: f64,
}

/// IMU error model (paper 000 eqs 1-4, in three axes).
///
/// Defaults are those of a typical consumer MEMS IMU of today, from the
/// Bosch Sensortec BMI270 data sheet (BST-BMI270-DS000) and the TDK
/// InvenSense ICM-42688-P data sheet (DS-000347):
/// * gyro noise density 0.007 deg/s/sqrt(Hz) (BMI270 performance mode;
///   ICM-42688-P: 0.0028), accelerometer 160 ug/sqrt(Hz) (BMI270;
///   ICM-42688-P: 70 ug/sqrt(Hz));
/// * turn-on bias (1 sigma): gyro 0.5 deg/s (zero-rate offset, both parts),
///   accelerometer 20 mg (zero-g offset, both parts);
/// * scale-factor error 0.5 % (ICM-42688-P sensitivity tolerance +-0.5 %,
///   BMI270 +-0.4 %); cross-axis sensitivity 1 % (+-1 % class figure of both
///   data sheets);
/// * in-run bias drift: not a data-sheet figure. We model it as a first-order
///   Gauss-Markov process with sigma 0.03 deg/s (gyro), 1 mg (accelerometer)
///   and tau = 200 s: about the offset temperature drift (~0.02 deg/s/K,
///   ~0.2 mg/K) over the 1-5 K of warming of a body-worn sensor.
///
/// Paper 000's Table 2 holds tuned filter weights, not sensor noise (SPEC
/// section 6), and is not used here.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuSpec {
    /// Gyroscope (rad/s).
    pub gyro: TriadSpec,
    /// Accelerometer (m/s^2).
    pub acc: TriadSpec,
    /// Standard deviation of the small mounting misalignment, per axis (rad).
    pub misalignment_rad: f64,
}

const MG: f64 = 9.81e-3;

impl Default for ImuSpec {
    fn default() -> Self {
        let d = |x: f64| x.to_radians();
        ImuSpec {
            gyro: TriadSpec {
                noise_density: d(0.007),
                turn_on_bias: d(0.5),
                bias_instability: d(0.03),
                bias_tau_s: 200.0,
                scale_error: 0.005,
                cross_axis: 0.01,
            },
            acc: TriadSpec {
                noise_density: 0.160 * MG,
                turn_on_bias: 20.0 * MG,
                bias_instability: 1.0 * MG,
                bias_tau_s: 200.0,
                scale_error: 0.005,
                cross_axis: 0.01,
            },
            misalignment_rad: d(1.0),
        }
    }
}

/// Joint encoder error model.
///
/// Defaults: a 14-bit absolute magnetic encoder (e.g. ams AS5047P: 14-bit
/// resolution, 2 pi / 16384 rad = 0.022 deg), noise of one LSB (1 sigma),
/// and a zeroing offset of 0.5 deg (1 sigma) from mounting the exoskeleton
/// on the limb.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EncoderSpec {
    /// Resolution in bits per turn (0 = no quantisation).
    pub bits: u32,
    /// White-noise standard deviation (rad).
    pub noise_rad: f64,
    /// Standard deviation of the constant offset (rad).
    pub offset_rad: f64,
}

impl Default for EncoderSpec {
    fn default() -> Self {
        EncoderSpec {
            bits: 14,
            noise_rad: core::f64::consts::TAU / 16384.0,
            offset_rad: 0.5_f64.to_radians(),
        }
    }
}

/// Stride-to-stride variability (see [`crate::variability`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Variability {
    /// Standard deviation of the relative stride-frequency modulation
    /// (~ stride-time CV; healthy adults 1-3 %).
    pub stride_time_cv: f64,
    /// Standard deviation of the relative amplitude modulation.
    pub amplitude_cv: f64,
}

impl Default for Variability {
    fn default() -> Self {
        Variability {
            stride_time_cv: 0.02,
            amplitude_cv: 0.03,
        }
    }
}

/// Everything the walking simulator needs. Every random draw derives from `seed`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkingConfig {
    /// Walking speed (m/s), 0.4..=1.8.
    pub speed_mps: f64,
    /// Trial duration (s), > 0 (the trial holds `round(duration * imu_rate)` samples).
    pub duration_s: f64,
    /// IMU sample rate (Hz), 1..=10000.
    pub imu_rate_hz: f64,
    /// Encoder sample rate (Hz), 1..=100000.
    pub encoder_rate_hz: f64,
    /// The one seed of every random draw.
    pub seed: u64,
    /// Body height (m), 1.4..=2.1.
    pub height_m: f64,
    /// Gravity (m/s^2).
    pub g: f64,
    /// Walk, stand, or hold a pose.
    pub motion: Motion,
    /// Gait phase at t = 0 (rad, 0 = heel strike of the simulated right leg).
    pub start_phase: f64,
    /// IMU error figures.
    pub imu: ImuSpec,
    /// Encoder error figures.
    pub encoder: EncoderSpec,
    /// Nominal IMU mounting.
    pub mounting: Mounting,
    /// Encoder resampling.
    pub encoder_resample: EncoderResample,
    /// Small ab/adduction and axial rotations of every segment.
    pub out_of_plane: bool,
    /// Stride-to-stride variability; `None` = every stride identical.
    pub variability: Option<Variability>,
    /// `false` = ideal sensors (no noise, bias, scale, cross-axis,
    /// misalignment, encoder offset or quantisation). Mounting rotations
    /// still apply.
    pub noise: bool,
    /// The leg the sensors are on (the left leg is the mirror image of the
    /// right, see [`crate::body_path`]).
    pub leg: limbfuse_core::Leg,
    /// Turns of the walking path; `None` = straight.
    pub turns: Option<crate::body_path::Turns>,
}

impl Default for WalkingConfig {
    fn default() -> Self {
        WalkingConfig {
            speed_mps: 1.0,
            duration_s: 60.0,
            imu_rate_hz: 100.0,
            encoder_rate_hz: 1000.0,
            seed: 0,
            height_m: limbfuse_models::DEFAULT_BODY_HEIGHT_M,
            g: limbfuse_core::STANDARD_GRAVITY,
            motion: Motion::Walk,
            start_phase: 0.0,
            imu: ImuSpec::default(),
            encoder: EncoderSpec::default(),
            mounting: Mounting::Aligned,
            encoder_resample: EncoderResample::Latest,
            out_of_plane: true,
            variability: Some(Variability::default()),
            noise: true,
            leg: limbfuse_core::Leg::Right,
            turns: None,
        }
    }
}

fn check(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    range: &'static str,
) -> Result<(), SimError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(SimError::OutOfRange { name, value, range })
    }
}

fn positive(name: &'static str, value: f64) -> Result<(), SimError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(SimError::OutOfRange {
            name,
            value,
            range: "(0, inf)",
        })
    }
}

fn non_negative(name: &'static str, value: f64) -> Result<(), SimError> {
    check(name, value, 0.0, f64::MAX, "[0, inf)")
}

fn triad(prefix: [&'static str; 6], t: &TriadSpec) -> Result<(), SimError> {
    non_negative(prefix[0], t.noise_density)?;
    non_negative(prefix[1], t.turn_on_bias)?;
    non_negative(prefix[2], t.bias_instability)?;
    positive(prefix[3], t.bias_tau_s)?;
    check(prefix[4], t.scale_error, 0.0, 0.1, "[0, 0.1]")?;
    check(prefix[5], t.cross_axis, 0.0, 0.1, "[0, 0.1]")
}

impl WalkingConfig {
    /// Checks every parameter; the error names the first bad one and its range.
    pub fn validate(&self) -> Result<(), SimError> {
        check("speed_mps", self.speed_mps, 0.4, 1.8, "[0.4, 1.8] m/s")?;
        positive("duration_s", self.duration_s)?;
        check(
            "imu_rate_hz",
            self.imu_rate_hz,
            1.0,
            10_000.0,
            "[1, 10000] Hz",
        )?;
        check(
            "encoder_rate_hz",
            self.encoder_rate_hz,
            1.0,
            100_000.0,
            "[1, 100000] Hz",
        )?;
        let n = (self.duration_s * self.imu_rate_hz).round();
        check(
            "duration_s * imu_rate_hz",
            n,
            1.0,
            1e12,
            "[1, 1e12] samples",
        )?;
        check("height_m", self.height_m, 1.4, 2.1, "[1.4, 2.1] m")?;
        check("g", self.g, 1.0, 20.0, "[1, 20] m/s^2")?;
        check(
            "start_phase",
            self.start_phase,
            -1e3,
            1e3,
            "[-1000, 1000] rad",
        )?;
        if let Some(t) = self.turns {
            positive("turns.duration_s", t.duration_s)?;
            check(
                "turns.every_s",
                t.every_s,
                t.duration_s * (1.0 + 1e-9),
                1e9,
                "(turns.duration_s, 1e9] s",
            )?;
            check(
                "turns.angle_rad",
                t.angle_rad,
                -10.0 * core::f64::consts::PI,
                10.0 * core::f64::consts::PI,
                "[-10 pi, 10 pi] rad",
            )?;
        }
        if let Motion::Pose { phase } = self.motion {
            check("motion.phase", phase, -1e3, 1e3, "[-1000, 1000] rad")?;
        }
        triad(
            [
                "imu.gyro.noise_density",
                "imu.gyro.turn_on_bias",
                "imu.gyro.bias_instability",
                "imu.gyro.bias_tau_s",
                "imu.gyro.scale_error",
                "imu.gyro.cross_axis",
            ],
            &self.imu.gyro,
        )?;
        triad(
            [
                "imu.acc.noise_density",
                "imu.acc.turn_on_bias",
                "imu.acc.bias_instability",
                "imu.acc.bias_tau_s",
                "imu.acc.scale_error",
                "imu.acc.cross_axis",
            ],
            &self.imu.acc,
        )?;
        check(
            "imu.misalignment_rad",
            self.imu.misalignment_rad,
            0.0,
            0.2,
            "[0, 0.2] rad",
        )?;
        check(
            "encoder.bits",
            self.encoder.bits as f64,
            0.0,
            32.0,
            "0..=32",
        )?;
        non_negative("encoder.noise_rad", self.encoder.noise_rad)?;
        non_negative("encoder.offset_rad", self.encoder.offset_rad)?;
        if let Some(v) = self.variability {
            check(
                "variability.stride_time_cv",
                v.stride_time_cv,
                0.0,
                0.1,
                "[0, 0.1]",
            )?;
            check(
                "variability.amplitude_cv",
                v.amplitude_cv,
                0.0,
                0.1,
                "[0, 0.1]",
            )?;
        }
        Ok(())
    }
}
