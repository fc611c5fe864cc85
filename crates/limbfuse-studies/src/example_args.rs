//! The command-line arguments of every study example, parsed here (with
//! clap) rather than in the examples, so that a command written in
//! `docs/RESULTS.md` can be checked without running the study: [`check`]
//! parses the arguments exactly as the example's `main` does.

use clap::{Parser, Subcommand};
use limbfuse_estimators::imm_bslip::{ImmWeights, TouchdownRule};
use limbfuse_estimators::segment_kf::AccelGate;

pub use crate::recorded_trial_args::{
    ChainGeometrySensitivityArgs, FinalContactFloorArgs, GyroShapeFloorArgs, RecordingVariantArgs,
};

/// Every example of this crate, by name (the file `examples/NAME.rs`).
pub const EXAMPLES: [&str; 32] = [
    "accel_accept_stats",
    "accel_gate_study",
    "attitude_floor",
    "baseline_study",
    "calibration_study",
    "chain_geometry_sensitivity",
    "chain_study",
    "fes_error_sources",
    "fes_figures",
    "fes_model_study",
    "fes_studies",
    "fes_thesis_protocol",
    "fes_tune_cv",
    "final_contact_floor",
    "foot_floor_study",
    "gait_library_without",
    "gait_pelvis",
    "gyro_shape_floor",
    "imm_bslip_study",
    "imm_continuous_study",
    "imm_gap_study",
    "imm_offgrid_study",
    "imm_start_study",
    "knee_study",
    "recording_variant",
    "robust_input_study",
    "segment_error_budget",
    "segment_start_study",
    "segment_study",
    "segment_validation",
    "soak",
    "time_base_study",
];

/// Why the arguments of an example command are not runnable.
#[derive(Debug, thiserror::Error)]
pub enum ExampleArgsError {
    /// No example of that name exists in this crate.
    #[error("no study example named `{0}` (examples: {list})", list = EXAMPLES.join(", "))]
    UnknownExample(String),
    /// The example's parser rejects the arguments.
    #[error("example `{example}` rejects its arguments: {message}")]
    Rejected {
        /// The example.
        example: String,
        /// clap's message.
        message: String,
    },
}

/// Parses `args` (without the program name) as example `example` would;
/// `Ok` when the example would start its work with them.
pub fn check(example: &str, args: &[String]) -> Result<(), ExampleArgsError> {
    fn parse<P: Parser>(example: &str, args: &[String]) -> Result<(), ExampleArgsError> {
        let argv = std::iter::once(example.to_string()).chain(args.iter().cloned());
        P::try_parse_from(argv)
            .map(|_| ())
            .map_err(|e| ExampleArgsError::Rejected {
                example: example.into(),
                message: e.to_string(),
            })
    }
    match example {
        "accel_accept_stats" => parse::<AccelAcceptStatsArgs>(example, args),
        "accel_gate_study" => parse::<AccelGateStudyArgs>(example, args),
        "baseline_study"
        | "fes_error_sources"
        | "fes_figures"
        | "fes_model_study"
        | "fes_thesis_protocol"
        | "fes_tune_cv"
        | "foot_floor_study" => parse::<NoArgs>(example, args),
        "chain_geometry_sensitivity" => parse::<ChainGeometrySensitivityArgs>(example, args),
        "chain_study" => parse::<ChainStudyArgs>(example, args),
        "fes_studies" => parse::<FesStudiesArgs>(example, args),
        "final_contact_floor" => parse::<FinalContactFloorArgs>(example, args),
        "gait_library_without" => parse::<GaitLibraryWithoutArgs>(example, args),
        "gait_pelvis" => parse::<GaitPelvisArgs>(example, args),
        "imm_bslip_study" => parse::<ImmBslipStudyArgs>(example, args),
        "imm_continuous_study" => parse::<ImmContinuousStudyArgs>(example, args),
        "imm_gap_study" => parse::<ImmGapStudyArgs>(example, args),
        "imm_offgrid_study" => parse::<ImmOffgridStudyArgs>(example, args),
        "imm_start_study" => parse::<ImmStartStudyArgs>(example, args),
        "knee_study" => parse::<KneeStudyArgs>(example, args),
        "recording_variant" => parse::<RecordingVariantArgs>(example, args),
        "robust_input_study" => parse::<RobustInputStudyArgs>(example, args),
        "segment_error_budget" => parse::<SegmentErrorBudgetArgs>(example, args),
        "calibration_study" => parse::<CalibrationStudyArgs>(example, args),
        "segment_start_study" => parse::<SegmentStartStudyArgs>(example, args),
        "segment_study" => parse::<SegmentStudyArgs>(example, args),
        "segment_validation" => parse::<SegmentValidationArgs>(example, args),
        "time_base_study" => parse::<TimeBaseStudyArgs>(example, args),
        "gyro_shape_floor" | "attitude_floor" => parse::<GyroShapeFloorArgs>(example, args),
        "soak" => parse::<SoakArgs>(example, args),
        _ => Err(ExampleArgsError::UnknownExample(example.into())),
    }
}

/// Examples that take no arguments (`baseline_study`, `fes_figures`,
/// `fes_model_study`, `fes_thesis_protocol`).
#[derive(Debug, Parser)]
pub struct NoArgs {}

/// `segment_study [SEEDS]`.
#[derive(Debug, Parser)]
pub struct SegmentStudyArgs {
    /// Seeds 1..=SEEDS per speed.
    #[arg(default_value_t = 30)]
    pub seeds: u64,
}

/// `segment_start_study [--every S] [--seed N] [--data DIR] [--first-sample-start]`.
#[derive(Debug, Parser)]
pub struct SegmentStartStudyArgs {
    /// Spacing of the starts (s), over two strides.
    #[arg(long, default_value_t = 0.1)]
    pub every: f64,
    /// Seed of our simulator's walks.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// The shared data directory (its independent walks are skipped when absent).
    #[arg(long, default_value = "../shared/data")]
    pub data: String,
    /// The start before 2026-12-06 (`first_sample_start`: each segment at
    /// its first accelerometer sample), for the "before" figures.
    #[arg(long)]
    pub first_sample_start: bool,
}

/// `segment_error_budget [SEEDS]`.
#[derive(Debug, Parser)]
pub struct SegmentErrorBudgetArgs {
    /// Seeds 1..=SEEDS per speed.
    #[arg(default_value_t = 10)]
    pub seeds: u64,
}

/// `calibration_study [SEEDS] [--speed S ...] [--tune] [--budget N] [--startup S]`.
#[derive(Debug, Parser)]
pub struct CalibrationStudyArgs {
    /// Seeds 1..=SEEDS per speed.
    #[arg(default_value_t = 10)]
    pub seeds: u64,
    /// Walking speeds (m/s); default 0.4 (paper 001's speed).
    #[arg(long = "speed", default_values_t = vec![0.4])]
    pub speeds: Vec<f64>,
    /// Tune each filter on 10-30 s first (PSO, as `limbfuse tune`), then validate on 30-50 s.
    #[arg(long)]
    pub tune: bool,
    /// Objective evaluations of the tuning (with --tune).
    #[arg(long, default_value_t = 400)]
    pub budget: usize,
    /// The filters' run-in `startup_s` (s): no estimate for this long after
    /// each start; 0 (default) = the papers' filters.
    #[arg(long, default_value_t = 0.0)]
    pub startup: f64,
}

/// `accel_accept_stats [FIRST] [LAST] [ideal]`.
#[derive(Debug, Parser)]
pub struct AccelAcceptStatsArgs {
    /// First seed.
    #[arg(default_value_t = 1)]
    pub first: u64,
    /// Last seed (inclusive).
    #[arg(default_value_t = 10)]
    pub last: u64,
    /// `ideal` switches every sensor error off.
    #[arg(value_parser = ["ideal"])]
    pub ideal: Option<String>,
}

/// `accel_gate_study [FIRST] [LAST] [VARIANT ...] [--ideal] [--rate HZ]`.
#[derive(Debug, Parser)]
pub struct AccelGateStudyArgs {
    /// First seed.
    #[arg(default_value_t = 1)]
    pub first: u64,
    /// Last seed (inclusive).
    #[arg(default_value_t = 10)]
    pub last: u64,
    /// Acceptance variants (see [`accel_gate`]); default: the study's list.
    #[arg(value_parser = accel_gate_variant)]
    pub variants: Vec<String>,
    /// Switch every sensor error off.
    #[arg(long)]
    pub ideal: bool,
    /// IMU sample rate (Hz).
    #[arg(long, default_value_t = 100.0)]
    pub rate: f64,
}

/// The accelerometer gate of an `accel_gate_study` variant: `base` or
/// `+`-joined parts `holdMS` (`AccelGate::hold_s`, milliseconds) and
/// `gyroW` (`AccelGate::max_rate`, rad/s), optionally suffixed `@mjls`.
pub fn accel_gate(name: &str) -> Result<AccelGate, String> {
    let mut g = AccelGate::OFF;
    for part in name.trim_end_matches("@mjls").split('+') {
        if let Some(v) = part.strip_prefix("hold") {
            g.hold_s = v
                .parse::<f64>()
                .map_err(|e| format!("hold ms `{v}`: {e}"))?
                * 1e-3;
        } else if let Some(v) = part.strip_prefix("gyro") {
            g.max_rate = v.parse().map_err(|e| format!("gyro rad/s `{v}`: {e}"))?;
        } else if part != "base" {
            return Err(format!("unknown variant part `{part}`"));
        }
    }
    Ok(g)
}

fn accel_gate_variant(name: &str) -> Result<String, String> {
    accel_gate(name).map(|_| name.to_string())
}

/// `knee_study MODE [...]`.
#[derive(Debug, Parser)]
pub struct KneeStudyArgs {
    /// The study to run.
    #[command(subcommand)]
    pub mode: KneeStudyMode,
}

/// The modes of `knee_study`.
#[derive(Debug, Subcommand)]
pub enum KneeStudyMode {
    /// Accuracy over seeds 1..=N (s_w = 500, order 6).
    Seeds {
        /// Seeds 1..=N.
        #[arg(default_value_t = 30)]
        n: u64,
        /// Anterior-posterior sensor offset from the segment line, sd (cm).
        #[arg(default_value_t = 0.0)]
        ap_sd_cm: f64,
        /// Fusion filter: `paper` (Algorithm 1) or `rate-bias`.
        #[arg(default_value = "paper", value_parser = ["paper", "rate-bias"])]
        fusion: String,
    },
    /// The order x window grid of 002 Table 1, seeds 1..=N.
    Table1 {
        /// Seeds 1..=N.
        #[arg(default_value_t = 10)]
        n: u64,
    },
    /// Thigh-sensor re-mounting at t = 30 s, seeds 1..=N.
    Remount {
        /// Seeds 1..=N.
        #[arg(default_value_t = 10)]
        n: u64,
    },
    /// The shared gaittoolbox and knee-rig recordings.
    Real {
        /// Directory of the shared data.
        #[arg(default_value = "../shared/data")]
        data_dir: String,
    },
    /// The error left with the true geometry fixed, seeds 1..=N.
    Floor {
        /// Seeds 1..=N.
        #[arg(default_value_t = 30)]
        n: u64,
    },
}

/// `fes_studies [--hip-only]`.
#[derive(Debug, Parser)]
pub struct FesStudiesArgs {
    /// Skip the single-joint study (a): run the fixed-hip studies (b)-(e).
    #[arg(long)]
    pub hip_only: bool,
}

/// `gait_pelvis [DATA_DIR] [--touchdown RULE] [--continuous]`.
#[derive(Debug, Parser)]
pub struct GaitPelvisArgs {
    /// The gaittoolbox trial directory.
    #[arg(default_value = "../shared/data/gaittoolbox-s02-walk")]
    pub data_dir: String,
    /// Touchdown rule: `height` (default), `step-clock` or `mixed`.
    #[arg(long, default_value = "height", value_parser = touchdown_rule)]
    pub touchdown: TouchdownRule,
    /// Run the `continuous` configuration (issue 19) instead of the paper's.
    #[arg(long)]
    pub continuous: bool,
}

/// `imm_bslip_study [SEEDS] [--truth SPEED] [--weights W] [--touchdown R]
/// [--p-next P] [--p-gait P] [--rate HZ] [--kappa K] [--ms-guard L | --ms-past-foot]`.
#[derive(Debug, Parser)]
pub struct ImmBslipStudyArgs {
    /// Noise seeds 1..=SEEDS.
    #[arg(default_value_t = 10)]
    pub seeds: u64,
    /// The library gait (m/s, one of 0.4-0.9 by 0.1) simulated and held out.
    #[arg(long, default_value_t = 0.7, value_parser = library_speed)]
    pub truth: f64,
    /// IMM weights: `paper` (eq 8, default) or `recursive`.
    #[arg(long, default_value = "paper", value_parser = imm_weights)]
    pub weights: ImmWeights,
    /// Touchdown rule: `height` (default), `step-clock` or `mixed`.
    #[arg(long, default_value = "height", value_parser = touchdown_rule)]
    pub touchdown: TouchdownRule,
    /// Markov probability of the next phase (default: the estimator's).
    #[arg(long)]
    pub p_next: Option<f64>,
    /// Markov probability of another gait (default: the estimator's).
    #[arg(long)]
    pub p_gait: Option<f64>,
    /// Measurement rate (Hz).
    #[arg(long, default_value_t = 100.0)]
    pub rate: f64,
    /// Only this kappa (default: 1e5, 1e4, 1e3 and 0).
    #[arg(long, value_parser = non_negative)]
    pub kappa: Option<f64>,
    /// MS event at the CoM's apex within this many leg lengths of the leading
    /// foot (default: the estimator's, 0.1).
    #[arg(long, conflicts_with = "ms_past_foot", value_parser = non_negative)]
    pub ms_guard: Option<f64>,
    /// MS event when the CoM is past the leading foot and past its apex.
    #[arg(long)]
    pub ms_past_foot: bool,
}

/// `imm_continuous_study [SEEDS] [--truth SPEED] [--rate HZ] [--data DIR] [--long SEEDS] [--long-duration S]`.
#[derive(Debug, Parser)]
pub struct ImmContinuousStudyArgs {
    /// Noise seeds 1..=SEEDS.
    #[arg(default_value_t = 10)]
    pub seeds: u64,
    /// The library gait (m/s, one of 0.4-0.9 by 0.1) simulated and held out.
    #[arg(long, default_value_t = 0.7, value_parser = library_speed)]
    pub truth: f64,
    /// Measurement rate (Hz).
    #[arg(long, default_value_t = 100.0)]
    pub rate: f64,
    /// The shared data directory.
    #[arg(long, default_value = "../shared/data")]
    pub data: String,
    /// Also 10 s trials of every 0.4-1.0 m/s library gait of both bodies
    /// (80 kg / 1 m, 70 kg / 0.95 m), noise seeds 1..=LONG (0: skipped).
    #[arg(long, default_value_t = 0)]
    pub long: u64,
    /// Duration of the `--long` trials (s).
    #[arg(long, default_value_t = 10.0)]
    pub long_duration: f64,
}

/// `imm_gap_study [--gap S] [--data DIR]`.
#[derive(Debug, Parser)]
pub struct ImmGapStudyArgs {
    /// Length of each gap (s).
    #[arg(long, default_value_t = 1.0, value_parser = positive_seconds)]
    pub gap: f64,
    /// The shared data directory.
    #[arg(long, default_value = "../shared/data")]
    pub data: String,
}

/// `imm_start_study [--every PCT] [--data DIR]`.
#[derive(Debug, Parser)]
pub struct ImmStartStudyArgs {
    /// Start (and end) points every PCT % of a stride over two strides.
    #[arg(long, default_value_t = 2.5, value_parser = stride_percent)]
    pub every: f64,
    /// The shared data directory.
    #[arg(long, default_value = "../shared/data")]
    pub data: String,
}

/// `imm_offgrid_study [SEEDS] [--speeds V,V,...] [--duration S]`.
#[derive(Debug, Parser)]
pub struct ImmOffgridStudyArgs {
    /// Noise seeds 1..=SEEDS.
    #[arg(default_value_t = 3)]
    pub seeds: u64,
    /// Walking speeds (m/s), comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = [0.35, 0.45, 0.55, 0.65, 0.75, 1.05], value_parser = non_negative)]
    pub speeds: Vec<f64>,
    /// Trial duration (s).
    #[arg(long, default_value_t = 10.0, value_parser = non_negative)]
    pub duration: f64,
}

/// The gait speeds of the `imm_bslip_study` library (m/s).
pub const IMM_STUDY_SPEEDS: [f64; 6] = [0.4, 0.5, 0.6, 0.7, 0.8, 0.9];

/// A finite value >= 0.
fn non_negative(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|e| format!("`{s}`: {e}"))?;
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(format!("{v}: must be finite and >= 0"))
    }
}

fn positive_seconds(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|e| format!("`{s}`: {e}"))?;
    if v.is_finite() && v > 0.0 && v <= 5.0 {
        Ok(v)
    } else {
        Err(format!("{v}: must be in (0, 5] s"))
    }
}

fn stride_percent(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|e| format!("`{s}`: {e}"))?;
    if (0.5..=50.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("{v}: must be in [0.5, 50] % of a stride"))
    }
}

fn library_speed(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|e| format!("`{s}`: {e}"))?;
    if IMM_STUDY_SPEEDS.iter().any(|x| (x - v).abs() < 1e-9) {
        Ok(v)
    } else {
        Err(format!("{v} is not a library speed {IMM_STUDY_SPEEDS:?}"))
    }
}

/// Parses a touchdown rule name (`height`, `step-clock`, `mixed`; the names of
/// `limbfuse estimate --imm-touchdown`).
pub fn touchdown_rule(s: &str) -> Result<TouchdownRule, String> {
    match s {
        "height" => Ok(TouchdownRule::Height),
        "step-clock" => Ok(TouchdownRule::StepClock),
        "mixed" => Ok(TouchdownRule::Mixed),
        _ => Err(format!(
            "unknown touchdown rule `{s}` (height, step-clock, mixed)"
        )),
    }
}

/// Parses an IMM weight rule name (`paper`, `recursive`).
pub fn imm_weights(s: &str) -> Result<ImmWeights, String> {
    match s {
        "paper" => Ok(ImmWeights::Paper),
        "recursive" => Ok(ImmWeights::Recursive),
        _ => Err(format!("unknown IMM weights `{s}` (paper, recursive)")),
    }
}

/// `segment_validation [--seeds N] [DATA_DIR]`.
#[derive(Debug, Parser)]
pub struct SegmentValidationArgs {
    /// Seeds 1..=N per speed of limbfuse's simulator.
    #[arg(long, default_value_t = 10)]
    pub seeds: u64,
    /// The shared data folder (gaittoolbox-s02-walk, independent-sim).
    #[arg(default_value = "../shared/data")]
    pub data_dir: String,
}

/// `soak [--hours H] [--methods LIST]`.
#[derive(Debug, Parser)]
pub struct SoakArgs {
    /// Simulated hours per estimator.
    #[arg(long, default_value_t = 24.0)]
    pub hours: f64,
    /// Estimators, comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "local,mjls,global,chain,knee-selfalign",
        value_parser = method_name
    )]
    pub methods: Vec<limbfuse_methods::MethodName>,
    /// One glitch every this many seconds (`inf`: a clean run).
    #[arg(long, default_value_t = 30.0)]
    pub glitch_every: f64,
    /// Length of one reported chunk (s).
    #[arg(long, default_value_t = 3600.0)]
    pub chunk_s: f64,
    /// The glitches injected in turn, comma-separated (gyro-huge, acc-huge,
    /// saturated-burst, gap, encoder-huge).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "gyro-huge,acc-huge,saturated-burst,gap,encoder-huge",
        value_parser = crate::soak::Glitch::parse
    )]
    pub glitches: Vec<crate::soak::Glitch>,
}

fn method_name(s: &str) -> Result<limbfuse_methods::MethodName, String> {
    limbfuse_methods::MethodName::parse(s).map_err(|e| e.to_string())
}

/// `chain_study [SEEDS] [--calibrated]`.
#[derive(Debug, Parser)]
pub struct ChainStudyArgs {
    /// Seeds 1..=SEEDS per speed.
    #[arg(default_value_t = 10)]
    pub seeds: u64,
    /// Calibrate each trial's accelerometers from the simulated pose
    /// recording of the same sensors (`limbfuse calibrate`), with the
    /// mounting misalignment set to zero (issue 14's calibrated case).
    #[arg(long)]
    pub calibrated: bool,
}

/// `robust_input_study [--seeds N] [--missing-pct P] [--data DIR]`.
#[derive(Debug, Parser)]
#[command(name = "robust_input_study")]
pub struct RobustInputStudyArgs {
    /// Masking seeds 1..=N per trial.
    #[arg(long, default_value_t = 5)]
    pub seeds: u64,
    /// Share of the IMU cells made missing (percent).
    #[arg(long, default_value_t = 20.0)]
    pub missing_pct: f64,
    /// The shared data directory.
    #[arg(long, default_value = "../shared/data")]
    pub data: String,
    /// Which IMU vectors are masked: `both` (default), `acc` or `gyr`.
    #[arg(long, value_enum, default_value_t = MaskedCells::Both)]
    pub cells: MaskedCells,
    /// Print the RMSE of each segment (trunk / thigh / shank / foot) too.
    #[arg(long)]
    pub per_segment: bool,
    /// Only these methods (default: mjls, chain, global, local).
    #[arg(long, value_delimiter = ',', value_parser = method_name)]
    pub methods: Vec<limbfuse_methods::MethodName>,
    /// A vector with a missing cell goes missing as a whole (the trial
    /// reader before issue 18 item 2); default: its present axes stay.
    #[arg(long)]
    pub whole_vectors: bool,
}

/// The IMU vectors `robust_input_study` masks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum MaskedCells {
    /// Accelerometer and gyroscope cells.
    Both,
    /// Accelerometer cells only.
    Acc,
    /// Gyroscope cells only.
    Gyr,
}

/// `time_base_study [TRIAL] [--offset S] [--methods M,...] [--from S] [-o SHIFTED]`.
#[derive(Debug, Parser)]
#[command(name = "time_base_study")]
pub struct TimeBaseStudyArgs {
    /// The trial file.
    #[arg(default_value = "../shared/data/independent-sim/walk-v1.2-s301.csv")]
    pub trial: String,
    /// Added to every time stamp (s; default a Unix time, 1.7e9).
    #[arg(long, default_value_t = 1.7e9)]
    pub offset: f64,
    /// Methods run on both clocks (default: knee-selfalign, mjls, chain).
    #[arg(long, value_delimiter = ',', value_parser = method_name)]
    pub methods: Vec<limbfuse_methods::MethodName>,
    /// Score the RMSE against the reference from this many seconds after
    /// the first sample.
    #[arg(long, default_value_t = 0.0)]
    pub from: f64,
    /// Also write the shifted trial here (for `limbfuse estimate` / `evaluate`).
    #[arg(short = 'o', long)]
    pub output: Option<String>,
}

/// `gait_library_without LIBRARY SPEED -o OUTPUT`.
#[derive(Debug, Parser)]
#[command(name = "gait_library_without")]
pub struct GaitLibraryWithoutArgs {
    /// The gait library file (`limbfuse gait-library build`).
    pub library: String,
    /// The speed of the gait left out (m/s).
    pub speed: f64,
    /// The library file written.
    #[arg(short = 'o', long)]
    pub output: String,
}
