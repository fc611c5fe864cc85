//! Parameters of [`super::KneeSelfAlign`] and their defaults (paper 002).

use core::fmt;

use super::param_ekf::ParamEkfNoise;
use super::upright::UprightPrior;

/// Which direction in each joint plane is the zero of the accelerometer
/// angle (the `x_i` of eq 6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AngleZero {
    /// `x_T` along the joint-to-thigh-sensor direction `o_T`, `x_S` along the
    /// sensor-to-joint direction `-o_S` (both projected into the joint
    /// plane): the angle is zero when the two joint-to-sensor lines are
    /// aligned, i.e. the anatomical zero when each sensor sits on its
    /// segment's long-axis line seen from the side. Default.
    #[default]
    SensorPositions,
    /// The paper's `x_i = j_i x c` with `c = [1, 0, 0]` in each sensor
    /// frame: the zero depends on how the sensors are mounted.
    PaperC,
}

impl AngleZero {
    /// Name used in parameter listings.
    pub const fn name(self) -> &'static str {
        match self {
            AngleZero::SensorPositions => "sensor-positions",
            AngleZero::PaperC => "paper-c",
        }
    }
}

/// How the gyro and accelerometer angles are fused.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Fusion {
    /// Algorithm 1 of paper 002: one state (default, reproduces the paper).
    #[default]
    Paper,
    /// Algorithm 1 plus a rate-bias state ([`super::angle::RateBiasKf`], a
    /// limbfuse extension): removes the lag a gyro-bias difference leaves.
    RateBias {
        /// Bias random walk per sample ((rad/s)^2). Suggested 1e-10: over a
        /// minute at 100 Hz the bias may wander by sqrt(6000 x 1e-10) =
        /// 0.04 deg/s, the in-run instability of the modelled gyro.
        q_bias: f64,
        /// Initial bias variance ((rad/s)^2). Suggested (1 deg/s)^2 =
        /// 3.05e-4, above the 0.7 deg/s (1 sigma) turn-on bias difference of
        /// two BMI270-class gyros.
        p_bias0: f64,
    },
}

impl Fusion {
    /// Name in parameter files: `paper` or `rate-bias`.
    pub const fn name(self) -> &'static str {
        match self {
            Fusion::Paper => "paper",
            Fusion::RateBias { .. } => "rate-bias",
        }
    }

    /// The rate-bias variant with the suggested values.
    pub const RATE_BIAS: Fusion = Fusion::RateBias {
        q_bias: 1e-10,
        p_bias0: 3.05e-4,
    };
}

/// A parameter value outside its allowed range.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("parameter {name} = {} is outside {range}", limbfuse_core::ShownNumber(*value))]
pub struct KneeParamError {
    /// Parameter name.
    pub name: &'static str,
    /// Offending value.
    pub value: f64,
    /// Allowed range.
    pub range: &'static str,
}

/// Parameters of the self-aligning knee estimator.
///
/// Defaults are paper 002's: window `s_w = 500`, `order = 6` (section 3.5),
/// Algorithm 2 noise `Q = R = 1e-3`, `P0 = I` (after eq 13), Algorithm 1
/// noise `Q = 5e-6`, `R = 0.2` (section 2.3.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KneeSelfAlignParams {
    /// Window length `s_w` in samples (Algorithm 3); 20..=100000.
    pub window: usize,
    /// Iterations of Algorithm 2 per window (`ordem`); 1..=100.
    pub order: usize,
    /// Algorithm 2 noise for the axes `j`.
    pub axis_noise: ParamEkfNoise,
    /// Algorithm 2 noise for the positions `o`.
    pub position_noise: ParamEkfNoise,
    /// Algorithm 1 process noise `Q` (rad^2 per sample).
    pub kf_q: f64,
    /// Algorithm 1 measurement noise `R` (rad^2).
    pub kf_r: f64,
    /// Zero of the accelerometer angle.
    pub zero: AngleZero,
    /// Angle fusion (paper's Algorithm 1 by default).
    pub fusion: Fusion,
    /// Gyroscope full-scale range (rad/s): a reading with any axis at or
    /// beyond 99.9 % of it is treated as saturated and kept out of the
    /// identification. Default 2000 deg/s, the largest range of the BMI270 /
    /// ICM-42688-P class the simulator models.
    pub gyro_range: f64,
    /// A window is used only when at least this fraction of its samples has
    /// both IMUs complete and unsaturated; 0..=1, default 0.5.
    pub min_valid_fraction: f64,
    /// Smallest eigenvalue of `H_j^T H_j / N` ((rad/s)^2 per rad^2 of axis
    /// turn) below which the axes are declared unobservable (e.g. a
    /// motionless recording) and the window's estimate is discarded.
    /// Default 1e-3: measured on simulated 30 s trials (400-sample windows,
    /// 8 random mountings, default sensors) it is 8e-6 to 9e-5 when standing
    /// still (gyro noise and bias only) and 0.29 to 0.48 when walking
    /// (`docs/KNEE_SELFALIGN.md`).
    pub min_information: f64,
    /// Noise floor of the sign evidence ([`super::sign::confidence`]): the
    /// circular spread of `alpha_acc - integral(alpha_gyro')` that noise
    /// alone gives. Default `1 - cos(2 deg)` = 6.1e-4, the spread of a
    /// difference wobbling by +-2 deg (a limbfuse extension).
    pub sign_floor: f64,
    /// The relative axis sign is committed (kept by continuity from then on)
    /// after the first window with a trusted accelerometer angle whose sign
    /// confidence reaches this value; until then a window switches the pair
    /// only on such evidence, and `diag_sign_confidence` says how sure it
    /// is. Default 0.9: the wrong pair's spread at least ten times the right
    /// one's, above the floor. With joint accelerations the wrong pair's
    /// spread follows the turning of the joint-centre acceleration (tens of
    /// degrees: 0.1-0.7 measured on the shared walks) and the right one's
    /// the sensor noise (1e-4 to 2e-4): confidence 0.99-1.00. With gravity
    /// alone the pairs are indistinguishable and the confidence is noise:
    /// up to 0.73 measured on knee-rig windows (issue 15; 0.5 before, which
    /// such windows passed). A limbfuse extension.
    pub sign_commit: f64,
    /// The accelerometer angle of a window is trusted (as sign evidence,
    /// for the zero and in Algorithm 1) only when the circular spread of
    /// `alpha_acc - integral(alpha_gyro')` over the window is at most this.
    /// Default `1 - cos(10 deg)` = 0.0152, the spread of a difference that
    /// scatters by about 14 deg RMS (`1 - cos(x)` ~ `x^2 / 2`). Measured
    /// (issue 15): 0.0001-0.0002 on the shared independent-simulator walks
    /// and on limbfuse's simulator, 0.1-0.8 on the gaittoolbox trial and the
    /// knee rig, where the accelerometer angle is meaningless (a limbfuse
    /// extension).
    pub acc_max_spread: f64,
    /// A window's agreement is evidence only when the knee moved: the
    /// circular spread of the gyro angle over the window must be at least
    /// this (a still window agrees trivially). Default `1 - cos(10 deg)`, the
    /// same scale as `acc_max_spread` (a limbfuse extension).
    pub acc_min_motion: f64,
    /// The accelerometer angle is not trusted from the first rest of a
    /// segment (gyro and specific force quiet for 0.2 s,
    /// [`super::rest_gravity`]) whose accelerometer norm is off g by more
    /// than this fraction, for the rest of the run: such a sensor does not
    /// measure gravity (a limbfuse extension, issue knee31b). Default
    /// [`super::rest_gravity::ACC_REST_TOLERANCE_G`] = 0.10, the data-sheet
    /// errors' worst-case sum; (0, 1].
    pub acc_rest_tolerance: f64,
    /// Corner frequency (Hz) of the first-order high-pass that removes the
    /// gyro angle's drift while the accelerometer angle is not trusted
    /// (instead of Algorithm 1's correction). Default 0.02 Hz (time constant
    /// 8 s): a 0.5 deg/s relative gyro bias then leaves 4 deg, and a 1 Hz
    /// gait cycle keeps 99.98 % of its amplitude (a limbfuse extension).
    pub highpass_hz: f64,
    /// Axis criterion: `None` is paper 002's eq 2 alone (Algorithm 2);
    /// `Some` (default) replaces eq 2's axes by the upright-leg prior
    /// ([`super::upright`]) in windows where the hinge does not explain the
    /// gyros and the legs are upright (a limbfuse extension, issue 15).
    pub axis_prior: Option<UprightPrior>,
    /// Largest time offset (samples) between the thigh and shank streams
    /// that the delay search considers, either way ([`super::delay`], a
    /// limbfuse extension); 0 turns the search off. At most a quarter of
    /// the window.
    pub max_delay: usize,
}

impl Default for KneeSelfAlignParams {
    fn default() -> Self {
        KneeSelfAlignParams {
            window: 500,
            order: 6,
            axis_noise: ParamEkfNoise::default(),
            position_noise: ParamEkfNoise::default(),
            kf_q: 5e-6,
            kf_r: 0.2,
            zero: AngleZero::SensorPositions,
            fusion: Fusion::Paper,
            gyro_range: 2000f64.to_radians(),
            min_valid_fraction: 0.5,
            min_information: 1e-3,
            sign_floor: 1.0 - libm::cos(2f64.to_radians()),
            sign_commit: 0.9,
            acc_max_spread: 1.0 - libm::cos(10f64.to_radians()),
            acc_min_motion: 1.0 - libm::cos(10f64.to_radians()),
            acc_rest_tolerance: super::rest_gravity::ACC_REST_TOLERANCE_G,
            highpass_hz: 0.02,
            axis_prior: Some(UprightPrior::default()),
            max_delay: 0,
        }
    }
}

fn check(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    range: &'static str,
) -> Result<(), KneeParamError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(KneeParamError { name, value, range })
    }
}

fn positive(name: &'static str, value: f64) -> Result<(), KneeParamError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(KneeParamError {
            name,
            value,
            range: "(0, inf)",
        })
    }
}

/// The window lengths `s_w` allowed (samples), shared with
/// `knee-gyro-axis`.
pub const WINDOW_SAMPLES: (usize, usize) = (20, 100_000);

/// Paper 002's window, `s_w = 500` samples at its exoskeleton's 100 Hz
/// (section 3.5), as a duration (s): the window must span enough motion to
/// identify the axes, and motion is measured in seconds (docs/RESULTS.md
/// "knee-selfalign: the window in seconds"). `limbfuse estimate` uses it at
/// the trial's `# sample_rate_hz:` unless a window in samples is given.
pub const DEFAULT_WINDOW_S: f64 = 5.0;

impl KneeSelfAlignParams {
    /// The defaults at a sample rate of `rate_hz` (Hz): the window is
    /// [`DEFAULT_WINDOW_S`] at that rate ([`Self::window_samples`]), as
    /// `limbfuse estimate` sets it from a trial's rate. The default
    /// [`KneeSelfAlignParams::window`] is 500 *samples*: 0.5 s at 1 kHz.
    pub fn at_rate(rate_hz: f64) -> Result<Self, KneeParamError> {
        Ok(KneeSelfAlignParams {
            window: Self::window_samples(DEFAULT_WINDOW_S, rate_hz)?,
            ..KneeSelfAlignParams::default()
        })
    }

    /// A window of `seconds` at `rate_hz` in samples, `round(seconds *
    /// rate_hz)` (what `limbfuse estimate` computes); an error names the
    /// window when it falls outside [`WINDOW_SAMPLES`] (or either value is
    /// not a positive finite number).
    pub fn window_samples(seconds: f64, rate_hz: f64) -> Result<usize, KneeParamError> {
        positive("rate_hz", rate_hz)?;
        positive("window_s", seconds)?;
        let n = libm::round(seconds * rate_hz);
        check(
            "window",
            n,
            WINDOW_SAMPLES.0 as f64,
            WINDOW_SAMPLES.1 as f64,
            "20..=100000 samples",
        )?;
        Ok(n as usize)
    }

    /// Checks every value; the error names the first bad one.
    pub fn validate(&self) -> Result<(), KneeParamError> {
        check(
            "window",
            self.window as f64,
            WINDOW_SAMPLES.0 as f64,
            WINDOW_SAMPLES.1 as f64,
            "20..=100000 samples",
        )?;
        check("order", self.order as f64, 1.0, 100.0, "1..=100")?;
        for (names, n) in [
            (["axis_q", "axis_r", "axis_p0"], &self.axis_noise),
            (
                ["position_q", "position_r", "position_p0"],
                &self.position_noise,
            ),
        ] {
            check(names[0], n.q, 0.0, 1e6, "[0, 1e6]")?;
            positive(names[1], n.r)?;
            positive(names[2], n.p0)?;
        }
        check("kf_q", self.kf_q, 0.0, 1e6, "[0, 1e6]")?;
        positive("kf_r", self.kf_r)?;
        positive("gyro_range", self.gyro_range)?;
        if let Fusion::RateBias { q_bias, p_bias0 } = self.fusion {
            check("q_bias", q_bias, 0.0, 1.0, "[0, 1]")?;
            positive("p_bias0", p_bias0)?;
        }
        check(
            "min_valid_fraction",
            self.min_valid_fraction,
            0.0,
            1.0,
            "[0, 1]",
        )?;
        check(
            "min_information",
            self.min_information,
            0.0,
            1e6,
            "[0, 1e6]",
        )?;
        check("sign_floor", self.sign_floor, 0.0, 1.0, "[0, 1]")?;
        check("sign_commit", self.sign_commit, 0.0, 1.0, "[0, 1]")?;
        check("acc_max_spread", self.acc_max_spread, 0.0, 1.0, "[0, 1]")?;
        check("acc_min_motion", self.acc_min_motion, 0.0, 1.0, "[0, 1]")?;
        if !(self.acc_rest_tolerance > 0.0 && self.acc_rest_tolerance <= 1.0) {
            return Err(KneeParamError {
                name: "acc_rest_tolerance",
                value: self.acc_rest_tolerance,
                range: "(0, 1]",
            });
        }
        if let Some(u) = self.axis_prior {
            check(
                "upright_min_hinge_ratio",
                u.min_hinge_ratio,
                0.0,
                1e6,
                "[0, 1e6]",
            )?;
            check(
                "upright_min_perpendicular_fraction",
                u.min_perpendicular_fraction,
                0.0,
                1.0,
                "[0, 1]",
            )?;
        }
        if self.max_delay > self.window / 4 {
            return Err(KneeParamError {
                name: "max_delay",
                value: self.max_delay as f64,
                range: "0..=window/4 samples",
            });
        }
        // (as `knee-gyro-axis`'s `corner_hz`; an audit: 1e300 was accepted)
        if !(self.highpass_hz > 0.0 && self.highpass_hz <= 10.0) {
            return Err(KneeParamError {
                name: "highpass_hz",
                value: self.highpass_hz,
                range: "(0, 10] Hz",
            });
        }
        Ok(())
    }

    /// Writes the parameters as `key: value` lines.
    pub fn describe(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        writeln!(out, "window: {}", self.window)?;
        writeln!(out, "order: {}", self.order)?;
        writeln!(
            out,
            "axis_ekf: q={} r={} p0={}",
            self.axis_noise.q, self.axis_noise.r, self.axis_noise.p0
        )?;
        writeln!(
            out,
            "position_ekf: q={} r={} p0={}",
            self.position_noise.q, self.position_noise.r, self.position_noise.p0
        )?;
        writeln!(out, "complementary_kf: q={} r={}", self.kf_q, self.kf_r)?;
        match self.fusion {
            Fusion::Paper => writeln!(out, "fusion: paper (Algorithm 1, one state)")?,
            Fusion::RateBias { q_bias, p_bias0 } => writeln!(
                out,
                "fusion: rate-bias (Algorithm 1 + rate-bias state) q_bias={q_bias} p_bias0={p_bias0}"
            )?,
        }
        writeln!(out, "zero: {}", self.zero.name())?;
        writeln!(out, "gyro_range_rad_s: {}", self.gyro_range)?;
        writeln!(out, "min_valid_fraction: {}", self.min_valid_fraction)?;
        writeln!(out, "min_information: {}", self.min_information)?;
        writeln!(
            out,
            "sign: floor={} commit={}",
            self.sign_floor, self.sign_commit
        )?;
        writeln!(
            out,
            "accelerometer angle trusted when spread <= {} and motion >= {}, until a rest reads |norm/g - 1| > {}; else high-pass at {} Hz",
            self.acc_max_spread, self.acc_min_motion, self.acc_rest_tolerance, self.highpass_hz
        )?;
        match self.axis_prior {
            None => writeln!(out, "axis_prior: none (paper 002 eq 2 alone)")?,
            Some(u) => writeln!(
                out,
                "axis_prior: upright (min_hinge_ratio={} min_perpendicular_fraction={})",
                u.min_hinge_ratio, u.min_perpendicular_fraction
            )?,
        }
        match self.max_delay {
            0 => writeln!(out, "sensor_delay: not searched")?,
            m => writeln!(
                out,
                "sensor_delay: searched within +-{m} samples per window (hinge residual e_j)"
            )?,
        }
        writeln!(
            out,
            "gyro_derivative: five-point symmetric, latency 2 samples"
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A controller builds the estimator from its parameters and its loop
    /// rate: the default window of 500 samples is paper 002's 5 s only at
    /// 100 Hz (0.5 s at 1 kHz, where `limbfuse estimate` uses 5000).
    #[test]
    fn the_window_at_a_controller_rate_is_five_seconds() {
        assert_eq!(KneeSelfAlignParams::at_rate(100.0).unwrap().window, 500);
        assert_eq!(KneeSelfAlignParams::at_rate(500.0).unwrap().window, 2500);
        assert_eq!(KneeSelfAlignParams::at_rate(1000.0).unwrap().window, 5000);
        assert!(KneeSelfAlignParams::at_rate(1000.0)
            .unwrap()
            .validate()
            .is_ok());
        assert_eq!(KneeSelfAlignParams::window_samples(2.0, 250.0), Ok(500));
        assert_eq!(
            KneeSelfAlignParams::window_samples(0.1, 100.0)
                .unwrap_err()
                .name,
            "window"
        );
        let e = KneeSelfAlignParams::at_rate(1e308).unwrap_err();
        assert_eq!(e.name, "window");
        let e = KneeSelfAlignParams::at_rate(f64::NAN).unwrap_err();
        assert_eq!(e.name, "rate_hz");
        assert_eq!(
            KneeSelfAlignParams::window_samples(0.0, 100.0)
                .unwrap_err()
                .name,
            "window_s"
        );
    }
}
