//! Sensor-to-segment alignment from walking data (`limbfuse align`).
//!
//! Raw IMUs are strapped on arbitrarily. [`estimate_alignment`] finds, for
//! each sensor, the rotation that turns its raw readings into the aligned
//! frame of SPEC section 1 (z medio-lateral to the right, x/y sagittal,
//! `(0, +g, 0)` in quiet standing), from the walking data alone:
//! 1. **Axis.** Thigh, shank and foot: the principal gyro axis, refined by a
//!    joint fit of the knee and ankle hinge constraints (Seel et al., paper
//!    002 eq 2). Trunk: normal to gravity and to the walking direction, found
//!    through the hip joint it shares with the (aligned) thigh.
//! 2. **Sign** (z to the right) from the gait: fast forward swing and
//!    adjacent segments swinging together (see [`AxisMethod`], `sign.rs`).
//! 3. **In-plane zero** from a quiet-standing period when there is one,
//!    else so that the (gyro-aided) mean segment angle over the walking data
//!    equals [`AlignOptions::mean_angle_rad`] (0 by default, a biased zero).
//!
//! [`apply_alignment`] rotates a record's readings. The method, its choices
//! and measured accuracy are in `docs/ALIGNMENT.md`.

use limbfuse_core::Segment;
use nalgebra::Rotation3;

mod apply;
mod axis;
mod estimate;
mod gait_window;
mod leg_side;
mod legs;
pub mod mirror;
pub mod mirror_trial;
pub mod mirror_truth;
mod series;
mod sign;
pub mod static_rotation;
mod trunk;
mod zero;

pub use apply::{apply_alignment, apply_rotations, rotations_from_metadata};
pub use estimate::estimate_alignment;
pub use leg_side::LegDetection;

/// Parameters of [`estimate_alignment`]. `Default` gives the documented values.
#[derive(Debug, Clone, Copy)]
pub struct AlignOptions {
    /// Look for a quiet-standing period and take the in-plane zero from it.
    pub use_quiet: bool,
    /// Quiet: gyro norm below this (rad/s) for every sensor.
    pub quiet_gyro_max: f64,
    /// Quiet: accelerometer norm within this (m/s^2) of the sensor's median
    /// norm at low rates (robust to scale errors).
    pub quiet_acc_dev: f64,
    /// Quiet: minimum duration (s).
    pub quiet_min_s: f64,
    /// A quiet period is taken as *upright standing* for a segment only if
    /// its angle there differs from its walking mean by less than this (rad)
    /// (rejects sitting); otherwise that segment uses the walking mean.
    pub max_standing_offset_rad: f64,
    /// Target mean angle (rad) of each segment over the walking data, used
    /// when there is no quiet standing (trunk, thigh, shank, foot).
    pub mean_angle_rad: [f64; 4],
    /// Leave out turns: samples where the (median over the sensors) rate
    /// about the vertical, averaged over `turn_window_s`, exceeds this (rad/s).
    pub turn_max_rate: f64,
    /// Averaging window (s) of the turn detection (also its widening).
    pub turn_window_s: f64,
    /// Minimum gyro RMS (rad/s) of a leg sensor to identify its axis.
    pub min_gyro_rms: f64,
    /// Principal axis of the *horizontal* part of the leg gyro signals (the
    /// rate about the tracked vertical removed) instead of the full signal.
    pub horizontal: bool,
    /// Largest axis tilt (rad) an accelerometer bias can cause through the
    /// tracked vertical: the gyro-only principal axis is used when it is
    /// within this of the horizontal one, blended out up to twice this
    /// (`docs/ALIGNMENT.md`). Default `atan(60 mg / 1 g)` = 3.43 deg: three
    /// times the 20 mg typical zero-g offset of consumer MEMS accelerometers
    /// (BMI270 data sheet BST-BMI270-DS000; ICM-42688-P DS-000347). 0: the
    /// horizontal axis alone (the behaviour before).
    pub gyro_axis_max_tilt_rad: f64,
    /// Time constant (s) of the accelerometer correction of the tracked
    /// vertical (complementary filter).
    pub up_tau_s: f64,
    /// Refine the leg axes with the knee/ankle hinge fit (off by default:
    /// better on the simulator, worse on the real trial, see
    /// `docs/ALIGNMENT.md`).
    pub hinge: bool,
    /// Fall back to the principal axis when the hinge axis is further than
    /// this (rad) from it (a fit that wandered off).
    pub max_hinge_deviation_rad: f64,
    /// At most this many samples per hinge pair enter the fit (strided).
    pub hinge_max_samples: usize,
    /// Window (s) of the gyro-aided mean-angle fit.
    pub zero_window_s: f64,
    /// Minimum correlation of the hip forward acceleration seen from the
    /// thigh and from the pelvis for the trunk walking direction.
    pub trunk_min_corr: f64,
    /// Report segments that cannot be aligned in [`Alignment::skipped`]
    /// instead of failing.
    pub partial: bool,
    /// Window (s) of the walking (stride periodicity) detection.
    pub walk_window_s: f64,
    /// Minimum stride-lag autocorrelation of the gyro norm for walking.
    pub walk_min_autocorr: f64,
    /// Minimum duration (s) of walking data (outside turns and quiet standing).
    pub min_walking_s: f64,
    /// Largest accepted ratio of the second to the largest eigenvalue of the
    /// horizontal gyro energy of a leg sensor (above: axis undetermined).
    pub max_axis_ratio: f64,
    /// Smallest accepted sign margin of a leg sensor (below: sign undetermined).
    pub min_sign_margin: f64,
    /// Smallest |score| for which the leg (left/right) is reported as detected.
    pub leg_min_score: f64,
    /// A cancellation hook (Python's Ctrl-C), polled per window of the
    /// walking detection (the long step: seconds per hour of data) and
    /// between the steps; once it returns true the estimate ends with
    /// [`AlignError::Cancelled`]. `None` (the CLI): never.
    pub cancel: Option<fn() -> bool>,
}

impl Default for AlignOptions {
    fn default() -> Self {
        AlignOptions {
            use_quiet: true,
            quiet_gyro_max: 0.1,
            quiet_acc_dev: 0.3,
            quiet_min_s: 1.0,
            max_standing_offset_rad: 30f64.to_radians(),
            mean_angle_rad: [0.0; 4],
            turn_max_rate: 0.6,
            turn_window_s: 1.0,
            min_gyro_rms: 0.2,
            horizontal: true,
            gyro_axis_max_tilt_rad: 0.06f64.atan(),
            up_tau_s: 1.0,
            hinge: false,
            max_hinge_deviation_rad: 20f64.to_radians(),
            hinge_max_samples: 20_000,
            zero_window_s: 10.0,
            trunk_min_corr: 0.3,
            partial: false,
            walk_window_s: 4.0,
            walk_min_autocorr: 0.5,
            min_walking_s: 3.0,
            max_axis_ratio: 0.5,
            min_sign_margin: 0.1,
            leg_min_score: 0.2,
            cancel: None,
        }
    }
}

/// How a sensor's medio-lateral axis was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisMethod {
    /// Joint hinge fit (paper 002 eq 2) with the knee and/or ankle partner.
    Hinge {
        /// The knee pair (thigh-shank) took part.
        knee: bool,
        /// The ankle pair (shank-foot) took part.
        ankle: bool,
    },
    /// Principal axis of the gyro signal.
    Principal,
    /// Trunk: normal to gravity and to the walking direction, found from the
    /// hip acceleration shared with the aligned thigh.
    GravityHipLink,
}

impl AxisMethod {
    /// Short name for metadata (`hinge-knee+ankle`, `principal`, ...).
    pub fn label(&self) -> String {
        match self {
            AxisMethod::Hinge { knee, ankle } => match (knee, ankle) {
                (true, true) => "hinge-knee+ankle".into(),
                (true, false) => "hinge-knee".into(),
                _ => "hinge-ankle".into(),
            },
            AxisMethod::Principal => "principal".into(),
            AxisMethod::GravityHipLink => "gravity+hip-link".into(),
        }
    }
}

/// How the in-plane zero was found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ZeroMethod {
    /// The angle is 0 over this quiet-standing period (s).
    QuietStanding {
        /// First sample time of the period.
        start_s: f64,
        /// Last sample time of the period.
        end_s: f64,
    },
    /// The mean angle over the walking data equals `target_rad`.
    MeanInclination {
        /// Target mean angle (rad).
        target_rad: f64,
    },
}

/// One sensor's alignment and how good it looks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorAlignment {
    /// Rotation from raw sensor coordinates to the aligned frame:
    /// `v_aligned = rotation * v_raw`.
    pub rotation: Rotation3<f64>,
    /// How the axis was found.
    pub axis_method: AxisMethod,
    /// How the in-plane zero was found.
    pub zero_method: ZeroMethod,
    /// Fraction of the gyro energy (sum of squares) about the final z axis.
    pub axis_energy_fraction: f64,
    /// Leg sensors: second / largest eigenvalue of the horizontal gyro
    /// energy (0 = one clear axis, 1 = undetermined); `None` for the trunk.
    pub axis_ratio: Option<f64>,
    /// Angle (rad) between the final axis and the principal gyro axis.
    pub axis_vs_principal_rad: f64,
    /// Leg sensors: weight (0..1) of the gyro-only principal axis in the
    /// axis, against the principal axis of the horizontal gyro (see
    /// [`AlignOptions::gyro_axis_max_tilt_rad`]); 0 for the trunk.
    pub gyro_only_weight: f64,
    /// RMS hinge residual (rad/s) of the pairs this sensor took part in.
    pub hinge_residual: Option<f64>,
    /// Sign evidence: score margin of the chosen sign over the flipped one
    /// (leg segments), or the hip-link correlation (trunk).
    pub sign_margin: f64,
    /// Gyro-aided mean angle (rad) over the walking (non-quiet) samples in
    /// the aligned frame: the target for `MeanInclination`, a measurement
    /// for `QuietStanding`.
    pub walking_mean_angle_rad: f64,
}

/// Alignment of all sensors of a trial.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Alignment {
    /// Per segment (trunk, thigh, shank, foot); `None` when the trial has no
    /// IMU there (or it was skipped, see `skipped`).
    pub per_segment: [Option<SensorAlignment>; 4],
    /// Segments with data that could not be aligned (only with
    /// [`AlignOptions::partial`]).
    pub skipped: Vec<(Segment, AlignError)>,
    /// Quiet period found (first and last sample time, s), if any.
    pub quiet: Option<(f64, f64)>,
    /// Samples used as walking data (not quiet, not turning).
    pub walking_samples: usize,
    /// Samples left out as turning.
    pub turning_samples: usize,
    /// Samples left out as not walking (no stride periodicity).
    pub not_walking_samples: usize,
    /// Which leg the sensors are on, detected from the data.
    pub leg: Option<LegDetection>,
}

/// Why a trial (or one of its sensors) could not be aligned.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AlignError {
    /// The trial has no records.
    #[error("no samples: the trial is empty")]
    NoSamples,
    /// No segment has any IMU reading.
    #[error("no IMU data: no segment has accelerometer or gyroscope samples")]
    NoImu,
    /// No thigh, shank or foot IMU (a lower-back sensor alone): the walking
    /// and every axis are found from the leg sensors, the trunk through the
    /// thigh (an audit: a lower-back trial was told "no walking found").
    #[error("no leg IMU: walking alignment finds the walking and each sensor's axis from thigh, shank or foot IMUs (`thigh_gyr_x` ..., `shank_...`, `foot_...`; the trunk is aligned through the thigh), and the trial has a trunk IMU only")]
    NoLegImu,
    /// Sample times are not finite and increasing.
    #[error("bad time base: sample times must be finite and increasing")]
    BadTime,
    /// A sensor has no gyro samples.
    #[error("{}: no gyro samples (the axis is found from the angular rate)", .segment.name())]
    NoGyro {
        /// The segment.
        segment: Segment,
    },
    /// A sensor has no accelerometer samples.
    #[error("{}: no accelerometer samples (needed for gravity and the in-plane zero)", .segment.name())]
    NoAcc {
        /// The segment.
        segment: Segment,
    },
    /// Too little rotation to identify the axis.
    #[error("{}: not enough motion to identify the axis: gyro RMS {gyro_rms:.3} rad/s (need >= {needed} rad/s)", .segment.name())]
    TooLittleMotion {
        /// The segment.
        segment: Segment,
        /// Gyro RMS over the moving samples (rad/s).
        gyro_rms: f64,
        /// Required RMS (rad/s).
        needed: f64,
    },
    /// The trunk's walking direction needs an aligned thigh sensor.
    #[error("trunk: the walking direction is found through the hip, which needs an aligned thigh sensor{}", .thigh.as_ref().map_or(String::new(), |e| format!(" ({e})")))]
    TrunkNeedsThigh {
        /// Why the thigh is not aligned, when it has data.
        thigh: Option<Box<AlignError>>,
    },
    /// The trunk walking-direction fit failed.
    #[error("trunk: no walking direction found: the hip forward acceleration seen from the thigh and from the pelvis correlate at r = {corr:.3} (need >= {needed}) with pelvis gain {gain:.2} (need 0.33..3); is this walking?")]
    NoWalkingDirection {
        /// The correlation found (0 when undefined).
        corr: f64,
        /// Gain of the pelvis acceleration in the fit (0 when undefined).
        gain: f64,
        /// Required |correlation|.
        needed: f64,
    },
    /// Too little walking data.
    #[error("no walking found: {walking_s:.1} s of stride-periodic leg motion outside turns and quiet standing (need >= {needed_s} s); alignment needs straight walking")]
    NoWalking {
        /// Walking data found (s).
        walking_s: f64,
        /// Required (s).
        needed_s: f64,
    },
    /// The trial has a single sample: no sample interval, no walking.
    #[error("no walking found: the trial has only one sample (one row); alignment needs at least {} s of walking, i.e. many rows with increasing times in seconds (column `t`)", limbfuse_core::ShownNumber(*.needed_s))]
    OneSample {
        /// Required walking (s).
        needed_s: f64,
    },
    /// The whole trial is shorter than the walking alignment needs.
    #[error("no walking found: the trial's samples span {} s (column `t`), less than the {} s of walking alignment needs; are its times in seconds?", limbfuse_core::ShownNumber(*.span_s), limbfuse_core::ShownNumber(*.needed_s))]
    TooShort {
        /// Samples times the mean sample interval (s).
        span_s: f64,
        /// Required walking (s).
        needed_s: f64,
    },
    /// The sensor rotates about two axes about equally: no sagittal axis.
    #[error("{}: axis undetermined: the sensor rotates about two horizontal axes about equally (second/largest energy {ratio:.2}, need <= {max}); is it on a walking leg?", .segment.name())]
    AxisUndetermined {
        /// The segment.
        segment: Segment,
        /// Second / largest eigenvalue of the horizontal gyro energy.
        ratio: f64,
        /// Largest accepted ratio.
        max: f64,
    },
    /// The gait sign rules do not agree on the direction of the axis.
    #[error("{}: the direction of the axis (left/right) is undetermined: sign margin {margin:.2} (need >= {min}); is this forward walking?", .segment.name())]
    SignUndetermined {
        /// The segment.
        segment: Segment,
        /// Sign margin found.
        margin: f64,
        /// Smallest accepted margin.
        min: f64,
    },
    /// The medio-lateral axis is along gravity (the sensor cannot tell its
    /// sagittal plane).
    #[error("{}: the axis found is (nearly) vertical: no sagittal plane", .segment.name())]
    VerticalAxis {
        /// The segment.
        segment: Segment,
    },
    /// An option is outside its range.
    #[error("option {name} = {} is outside {range}", limbfuse_core::ShownNumber(*value))]
    BadOption {
        /// Field name of [`AlignOptions`].
        name: &'static str,
        /// Value given.
        value: f64,
        /// Allowed range.
        range: &'static str,
    },
    /// The cancellation hook ([`AlignOptions::cancel`]) stopped it.
    #[error("cancelled")]
    Cancelled,
    /// A metadata entry does not hold what it should.
    #[error("metadata `{key}`: expected {expected}, found `{found}`")]
    BadMetadata {
        /// Metadata key.
        key: String,
        /// What was expected.
        expected: &'static str,
        /// What was found.
        found: String,
    },
}
