//! Command-line flags (clap). Validated once into the commands' settings.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

pub use crate::cli_simulate::*;

/// Estimate lower-limb segment and joint angles from wearable IMUs and exoskeleton encoders.
#[derive(Debug, Parser)]
#[command(name = "limbfuse", version, about, long_about = None)]
pub struct Cli {
    /// No progress bars (they are also hidden when stderr is not a terminal).
    #[arg(long, short, global = true)]
    pub quiet: bool,
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands (SPEC section 4).
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate and estimate every scenario (walking segment angles, self-aligning knee, knee-FES,
    /// B-SLIP gait): print the results, write report.md and HTML reports.
    Demo(DemoArgs),
    /// Write a simulated trial file.
    #[command(subcommand)]
    Simulate(SimulateCommand),
    /// Convert a real recording into a trial file.
    Import(ImportArgs),
    /// Accelerometer bias/scale/cross-axis and gyro bias from a recording of static poses (docs/CALIBRATION.md).
    Calibrate(crate::cli_calibration::CalibrateArgs),
    /// Run one estimator over a trial file.
    Estimate(EstimateArgs),
    /// Compare an estimate file with its trial's reference.
    Evaluate(EvaluateArgs),
    /// What a trial file holds (time base, gaps, inputs, unit checks) and which methods can run on it.
    Inspect(InspectArgs),
    /// Write one self-contained HTML report (plots, error tables, method panels) of a trial and its estimates.
    Report(ReportArgs),
    /// Monte Carlo of the segment filters under parametric uncertainty (paper 000 Fig. 9).
    Montecarlo(MonteCarloArgs),
    /// Rotate raw (arbitrarily mounted) sensor channels into their segment frames, from walking data.
    Align(AlignArgs),
    /// Mirror a trial's raw sensor data across the sagittal plane: the same recording as the other leg
    /// would give it (for checking alignment on both legs), optionally re-mounting every sensor at random.
    Mirror(MirrorArgs),
    /// Resample a trial onto a uniform time base (e.g. 50 Hz, the rate of paper 001).
    Resample(ResampleArgs),
    /// Write a copy of a trial whose time increases: drop a row repeating the row before (or its time), and rows whose time stamp goes back (or sort them)
    RepairTime(RepairTimeArgs),
    /// Tune a segment filter's noise parameters on a time window; writes a parameter file.
    Tune(TuneArgs),
    /// List every estimation method: what it estimates, the columns it reads, its settings.
    Methods,
    /// Write a method's parameter file with every default, commented (for `--params`).
    Params(ParamsArgs),
    /// B-SLIP gait libraries for `imm-bslip` (paper 003).
    #[command(subcommand, name = "gait-library")]
    GaitLibrary(GaitLibraryCommand),
}

/// `--force` of the commands that simulate trials (caps in `crate::bounds`).
#[derive(Debug, Clone, Copy, Default, Args)]
pub struct LengthCap {
    /// Allow a --duration beyond 24 h of simulated time (or 86.4 M samples):
    /// the cap keeps a typo from filling the disk (24 h of walking at 100 Hz is ~6 GB).
    #[arg(long)]
    pub force: bool,
}

/// Options of `params`.
#[derive(Debug, Args)]
pub struct ParamsArgs {
    /// The method (see `limbfuse methods`).
    #[arg(long, help = crate::methods::method_flag_help("The method"))]
    pub method: String,
    /// Output file (default: standard output).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

/// `gait-library` subcommands.
#[derive(Debug, Subcommand)]
pub enum GaitLibraryCommand {
    /// Search periodic B-SLIP gaits at the given speeds and write a library file (JSON).
    Build(GaitLibraryBuildArgs),
}

/// Options of `gait-library build`.
#[derive(Debug, Args)]
pub struct GaitLibraryBuildArgs {
    /// Speeds START:END:STEP in m/s (inclusive), e.g. 0.4:0.9:0.1.
    #[arg(long)]
    pub speeds: String,
    /// Output library file.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Body mass (kg).
    #[arg(long, default_value_t = 80.0)]
    pub mass: f64,
    /// Leg rest length l0 (m).
    #[arg(long, default_value_t = 1.0)]
    pub leg_length: f64,
}

/// Options of `align`.
#[derive(Debug, Args)]
pub struct AlignArgs {
    /// Trial with raw sensor channels (walking, optionally with quiet standing).
    pub trial: PathBuf,
    /// Output trial with aligned channels (rotations recorded in its metadata).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Refine the leg axes by the knee/ankle hinge fit (better on ideal hinges, see docs/ALIGNMENT.md).
    #[arg(long)]
    pub hinge: bool,
    /// Skip (and report) sensors that cannot be aligned instead of failing.
    #[arg(long)]
    pub partial: bool,
    /// Known mean angle over the walking data, SEGMENT=DEGREES (repeatable), used when
    /// there is no quiet standing (default 0 for every segment).
    #[arg(long = "mean-angle", value_name = "SEGMENT=DEG")]
    pub mean_angle: Vec<String>,
    /// Instead: identify the knee joint axis and joint position in the raw thigh and shank
    /// sensor frames (paper 002, over the whole trial) and write them to OUTPUT (TOML).
    #[arg(long, conflicts_with_all = ["hinge", "partial", "mean_angle"])]
    pub joint_axis: bool,
    /// With --joint-axis: parameter-EKF iterations (paper 002 default 6).
    #[arg(long, default_value_t = 6, requires = "joint_axis")]
    pub order: usize,
    /// Alignment procedure: from walking data, or paper 004's quiet standing + flexion/extension rotations.
    #[arg(long, value_enum, default_value_t = AlignProcedure::Walking)]
    pub procedure: AlignProcedure,
    /// --procedure static-rotation only (refused otherwise): the calibration recording (quiet
    /// standing + rotations) of the same sensors; default: the calibration segment at the start
    /// of TRIAL. An IMU calibration file (`limbfuse calibrate`) is --imu-calibration.
    #[arg(long)]
    pub calibration: Option<PathBuf>,
    /// IMU calibration file (`limbfuse calibrate`, TOML) applied to the raw channels (and to a
    /// static-rotation --calibration recording) before alignment.
    #[arg(long, conflicts_with = "joint_axis")]
    pub imu_calibration: Option<PathBuf>,
}

/// Options of `mirror`.
#[derive(Debug, Args)]
pub struct MirrorArgs {
    /// Trial with raw (unaligned) sensor channels.
    pub trial: PathBuf,
    /// Output trial (the other leg; `# leg:` flipped).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also turn every mirrored sensor by a uniformly random rotation drawn from this seed.
    #[arg(long, value_name = "SEED")]
    pub remount_seed: Option<u64>,
}

/// Alignment procedures of `align`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum AlignProcedure {
    /// Sensor-to-segment rotations from walking data (docs/ALIGNMENT.md).
    Walking,
    /// Paper 004 section 3.3: quiet standing (gravity) + 3-5 hip flexion/extension rotations (gyro axis).
    StaticRotation,
}

/// Options of `montecarlo`.
#[derive(Debug, Args)]
pub struct MonteCarloArgs {
    /// Runs per uncertainty level.
    #[arg(long, default_value_t = 100)]
    pub runs: usize,
    /// Uncertainty levels in percent as START:END:STEP.
    #[arg(long, default_value = "0:20:2")]
    pub levels: String,
    /// Base seed: run r simulates its trial with seed + r; its parameter
    /// errors come from a stream keyed by (seed, r, level).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Walking speed of the simulated trials (m/s).
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
    /// Duration of each simulated trial (s); at most 86400 (24 h) without --force.
    #[arg(long, default_value_t = 30.0)]
    pub duration: f64,
    /// Output CSV (method, level, mean and std of the mean segment RMSE).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also draw an SVG plot here.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Lift the cap on the simulated length.
    #[command(flatten)]
    pub cap: LengthCap,
}

/// Options of `demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Directory for the trial, the estimates and the report (`-o` / `--output` are accepted too).
    #[arg(
        long,
        short = 'o',
        visible_alias = "output",
        default_value = "limbfuse-demo"
    )]
    pub out: PathBuf,
    /// Random seed of the simulated trial.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Walking speed (m/s), 0.4 to 1.8.
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
    /// Trial duration (s); at most 86400 (24 h) without --force.
    #[arg(long, default_value_t = 60.0)]
    pub duration: f64,
    /// Lift the cap on the simulated length.
    #[command(flatten)]
    pub cap: LengthCap,
}

/// Supported import formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ImportFormat {
    /// gait-tech/gaittoolbox sample folder (Xsens `imu-*.csv` + `vicon-right.csv`, `vicon-left.csv` or `vicon.csv`; either leg).
    Gaittoolbox,
    /// KneeAngleAlgorithmComparison rig log (`Trial_NN.csv`, 250 Hz, MPU6050).
    KneeRig,
}

/// Options of `import`.
#[derive(Debug, Args)]
pub struct ImportArgs {
    /// Recording format.
    #[arg(long, value_enum)]
    pub format: ImportFormat,
    /// Input folder (gaittoolbox) or file (knee-rig).
    pub input: PathBuf,
    /// Output trial file.
    #[arg(short, long)]
    pub output: PathBuf,
    /// IMU calibration (`limbfuse calibrate`) applied to the raw sensor channels.
    #[arg(long, visible_alias = "imu-calibration")]
    pub calibration: Option<PathBuf>,
    /// gaittoolbox: the leg to import (default: the one the folder holds, the right when it holds both).
    #[arg(long, value_enum)]
    pub leg: Option<crate::cli::LegArg>,
}

/// Options of `estimate`.
#[derive(Debug, Args)]
pub struct EstimateArgs {
    /// Estimation method (`limbfuse methods` describes each).
    #[arg(long, help = crate::methods::method_flag_help("Estimation method"))]
    pub method: String,
    /// Trial file (`-`: standard input, read as rows arrive).
    pub trial: PathBuf,
    /// Output estimate file (`-`: standard output, each estimate written as
    /// soon as its row is read; the header then says `# trial_hash: streamed`).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Parameter overrides (TOML).
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// knee-selfalign / knee-gyro-axis: identification window length s_w in samples (a whole
    /// number such as 500), used as given (default: 5 s at the trial's rate, i.e. paper 002's 500
    /// samples at 100 Hz); in seconds: `window_s` in a --params file. Not a time span (that is
    /// `evaluate --window START:END`).
    #[arg(long, value_name = "SAMPLES", value_parser = knee_window_samples)]
    pub window: Option<usize>,
    /// knee-selfalign / knee-gyro-axis: parameter-EKF iterations per window (paper 002 default 6).
    #[arg(long)]
    pub order: Option<usize>,
    /// imm-bslip: gait library file (`limbfuse gait-library build`).
    #[arg(long)]
    pub library: Option<PathBuf>,
    /// imm-bslip: physical-likelihood gain kappa (1/m^2; eq 14), 0 disables it.
    #[arg(long)]
    pub kappa: Option<f64>,
    /// imm-bslip: rescale every library gait to this CoM height at mid-stance (m; sec IV-B).
    #[arg(long)]
    pub rescale_height: Option<f64>,
    /// imm-bslip: weight rule, `paper` (eq 8, per-sample likelihoods; default) or
    /// `recursive` (the standard IMM mode probability, with memory).
    #[arg(long, value_name = "RULE")]
    pub imm_weights: Option<String>,
    /// imm-bslip: when a library gait's leading foot lands, `height` (the CoM
    /// falling to the gait's touchdown height; default), `step-clock` (the
    /// gait's touchdown time after its last mid-stance) or `mixed` (foot
    /// placement mixed by the IMM from the phase weights).
    #[arg(long, value_name = "RULE")]
    pub imm_touchdown: Option<String>,
    /// imm-bslip: `paper` (paper 003's estimator over the library's gaits;
    /// default) or `continuous` (one gait of the continuous family
    /// re-targeted to the measured speed, phase from the leg lengths).
    #[arg(long, value_name = "CONFIG")]
    pub imm_config: Option<String>,
    /// imm-bslip, continuous configuration: `on` (default) or `off`. When
    /// most estimated speeds lie more than 0.03 m/s outside the library's
    /// range, search the missing gaits for the trial's body (the
    /// `gait-library build` search, from the library's end gait on its speed
    /// step out to the trial's mean speed), add them to the family and
    /// estimate again; stderr says which speeds were added and how long the
    /// search took. `off`: keep the library (stderr then names the library to
    /// build). Files only (a trial or estimate streamed through `-` gets that
    /// note instead).
    #[arg(long, value_name = "ON_OFF")]
    pub imm_extend_library: Option<String>,
    /// imm-bslip: the trial body's leg rest length (m), over its metadata
    /// (`# leg_length_m:`); a library built for another body is rescaled.
    #[arg(long, value_name = "M")]
    pub leg_length: Option<f64>,
    /// imm-bslip: the trial body's mass (kg), over its metadata (`# body_mass_kg:`).
    #[arg(long, value_name = "KG")]
    pub mass: Option<f64>,
    /// IMU calibration (`limbfuse calibrate`) applied to the trial's IMU channels before
    /// estimation (rotated into the aligned frame for a trial `align` wrote).
    #[arg(long, visible_alias = "imu-calibration")]
    pub calibration: Option<PathBuf>,
    /// chain: smooth offline (Rauch-Tung-Striebel over 10 s blocks with 2 s
    /// look-ahead; every estimate uses the samples after it too; docs/CHAIN.md).
    #[arg(long)]
    pub smooth: bool,
    /// knee-selfalign, knee-gyro-axis: fill the knee angle before the first
    /// identified window offline (the relative gyro angle about the first
    /// axes, integrated backwards from the first estimate; docs/KNEE_SELFALIGN.md).
    #[arg(long, conflicts_with = "smooth")]
    pub backfill: bool,
    /// Diagnostic columns to write: `all` (default), `none`, or names
    /// separated by commas, for example `sd_thigh,sd_shank` (the `diag_` columns
    /// of an estimate with `all`; a name the method lacks is refused with the
    /// list of its diagnostics).
    #[arg(long, value_name = "all|none|NAMES")]
    pub diagnostics: Option<String>,
    /// Rows whose time does not follow the row before (SPEC asks `t` to increase strictly):
    /// `refuse` stops there (default); `drop` drops them and says how many at the end: a row
    /// not after the last one passed, or one whose time jumps ahead of the rows after it (for a
    /// live stream, `-`; a file is better repaired first with `limbfuse repair-time`;
    /// docs/STREAMING.md).
    #[arg(long, value_enum, default_value_t = LateRowsArg::Refuse)]
    pub late_rows: LateRowsArg,
}

/// `estimate --late-rows`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum LateRowsArg {
    /// Stop at the first such row with its line.
    Refuse,
    /// Drop such rows and count them.
    Drop,
}

impl LateRowsArg {
    /// The reader's rule.
    pub fn rule(self) -> limbfuse_io::LateRows {
        match self {
            LateRowsArg::Refuse => limbfuse_io::LateRows::Refuse,
            LateRowsArg::Drop => limbfuse_io::LateRows::Drop,
        }
    }
}

/// `estimate --window`: the knee methods' identification window in samples.
/// A time span or a duration (`0:20`, `5s`: what `evaluate --window` and
/// `tune --window` take) was clap's "invalid digit found in string" (a
/// fresh-user audit, session 28); now the message says what it is.
fn knee_window_samples(text: &str) -> Result<usize, String> {
    text.trim().parse().map_err(|_| {
        "expected the knee methods' (knee-selfalign, knee-gyro-axis) identification window in \
         samples, a whole number such as 500 (5 s at 100 Hz); for seconds give `window_s = 5.0` in \
         a --params file (`limbfuse params --method knee-selfalign`); a time span START:END is \
         `evaluate --window`"
            .to_string()
    })
}

/// Options of `evaluate`.
#[derive(Debug, Args)]
pub struct EvaluateArgs {
    /// Trial file with reference columns.
    pub trial: PathBuf,
    /// Estimate file made from that trial (not with --method).
    pub estimate: Option<PathBuf>,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Evaluate only START:END seconds (either side may be empty).
    #[arg(long)]
    pub window: Option<String>,
    /// Remove the mean error of each channel before computing the RMSE (max|e| and mean e,
    /// `max_abs_err_deg` and `mean_err_deg` in --json, stay as measured, before the mean is removed).
    #[arg(long)]
    pub offset_free: bool,
    /// Synchronise: per channel, shift the estimate by the lag within +-N samples
    /// that minimises its RMSE, and report the lags (IMU and motion-capture clocks differ).
    /// At most half the trial's samples.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub max_lag: usize,
    /// Evaluate an estimate whose header records another trial (`# trial_hash:`)
    /// instead of refusing it.
    #[arg(long)]
    pub allow_trial_mismatch: bool,
    /// Also print the mean of each estimator diagnostic (`diag_*` columns) over the trial (over
    /// --window when given).
    #[arg(long)]
    pub diagnostics: bool,
    /// Also write the estimate's strides (gait-events, lowback-speed) as CSV, one row per
    /// stride with the reference evaluate pairs with it (docs/GAIT_EVENTS.md "Stride table").
    #[arg(long, value_name = "FILE")]
    pub strides: Option<PathBuf>,
    /// Run this method on the trial instead of reading an estimate file
    /// (paper 001 protocol: see --starts, docs/TUNING.md).
    #[arg(long)]
    pub method: Option<String>,
    /// Parameter file of --method (TOML).
    #[arg(long, requires = "method")]
    pub params: Option<PathBuf>,
    /// Start --method afresh at N instants evenly spread over --window and
    /// average the errors (paper 001: 50).
    #[arg(long, value_name = "N")]
    pub starts: Option<usize>,
    /// Length (s) of each run with --starts (default: half the window; the
    /// whole window for one start).
    #[arg(long, value_name = "SECONDS", requires = "starts")]
    pub length: Option<f64>,
}

/// Options of `report` (docs/REPORT.md).
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// Trial file.
    pub trial: PathBuf,
    /// Estimate files made from that trial (one or more).
    #[arg(required = true)]
    pub estimates: Vec<PathBuf>,
    /// Output HTML file.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Display resolution: each line is drawn with at most 2 x N points (min and max of N runs).
    #[arg(long, value_name = "N", default_value_t = limbfuse_report::DEFAULT_BUCKETS)]
    pub buckets: usize,
    /// Include estimates whose header records another trial (as `evaluate --allow-trial-mismatch`).
    #[arg(long)]
    pub allow_trial_mismatch: bool,
    /// Score only START:END seconds of the trial's `t` (either side may be empty), as
    /// `evaluate --window`: the error tables and the error over the gait cycle.
    #[arg(long)]
    pub window: Option<String>,
    /// Remove the mean error of each channel before the RMSE, as `evaluate --offset-free`
    /// (tables and the error over the gait cycle; max|e| and mean e stay as measured).
    #[arg(long)]
    pub offset_free: bool,
    /// Synchronise each channel by the lag within +-N samples that minimises its RMSE, as
    /// `evaluate --max-lag` (tables and the error over the gait cycle). At most half the trial's samples.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub max_lag: usize,
}

/// Low-pass of the IMU channels in `resample`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum AntiAliasArg {
    /// Blackman-windowed sinc, cut-off 0.35 x the new rate (default).
    Sinc,
    /// Mean over one output period.
    Boxcar,
    /// None: linear interpolation (aliases).
    None,
}

/// Options of `resample`.
#[derive(Debug, Args)]
pub struct ResampleArgs {
    /// Trial file.
    pub trial: PathBuf,
    /// Output rate (Hz).
    #[arg(long)]
    pub rate: f64,
    /// Output trial file.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Anti-alias low-pass of the accelerometer and gyro channels.
    #[arg(long, value_enum, default_value_t = AntiAliasArg::Sinc)]
    pub anti_alias: AntiAliasArg,
}

/// Options of `repair-time`.
#[derive(Debug, Args)]
pub struct RepairTimeArgs {
    /// Trial file (CSV or Arrow) whose `t` does not increase strictly.
    pub trial: PathBuf,
    /// Output trial file (CSV).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Rows whose time stamp goes back: `drop` keeps one of the longest runs of rows, in file order, whose time increases (a wrong time stamp costs its row); `sort` puts the rows in time order (packets that arrived out of order with their own time stamps).
    #[arg(long, value_enum, default_value_t = TimeOrderArg::Drop)]
    pub out_of_order: TimeOrderArg,
}

/// `repair-time --out-of-order`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TimeOrderArg {
    /// Drop them (keep a longest run whose time increases).
    Drop,
    /// Sort the rows by time.
    Sort,
}

/// Options of `inspect`.
#[derive(Debug, Args)]
pub struct InspectArgs {
    /// Trial files (CSV or Arrow).
    #[arg(required = true)]
    pub trials: Vec<PathBuf>,
    /// One JSON array, an object per trial (the keys of Python's `limbfuse.inspect`, plus `trial`).
    #[arg(long)]
    pub json: bool,
}

/// Options of `tune`.
#[derive(Debug, Args)]
pub struct TuneArgs {
    /// Filter to tune: local, mjls or global (noise parameters, paper 001
    /// protocol), or sdre / ekf (the extended knee model's torque error, by
    /// leave-one-pulse-out cross-validation; needs --params).
    #[arg(long)]
    pub method: String,
    /// Trial file with reference angles (sdre/ekf: a pre-trial with
    /// `knee_ref` and stimulation pulses).
    pub trial: PathBuf,
    /// Tuning window START:END (s) (sdre/ekf: the part of the pre-trial used).
    #[arg(long, default_value = "0:20")]
    pub window: String,
    /// Validation window START:END (s), or `none`; default: the block of the
    /// tuning window's length right after it.
    #[arg(long)]
    pub validate: Option<String>,
    /// Output parameter file (TOML), usable with `estimate --params`.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Seed of the optimiser: same seed, same result.
    #[arg(long, default_value_t = TuneArgs::SEED)]
    pub seed: u64,
    /// Number of objective evaluations.
    #[arg(long, default_value_t = TuneArgs::BUDGET)]
    pub budget: usize,
    /// Swarm size of the particle swarm optimiser.
    #[arg(long, default_value_t = TuneArgs::PARTICLES)]
    pub particles: usize,
    /// Starting points per window (paper 001: 50).
    #[arg(long, default_value_t = TuneArgs::STARTS)]
    pub starts: usize,
    /// Length (s) of each run from a starting point (default: half the window).
    #[arg(long, value_name = "SECONDS")]
    pub length: Option<f64>,
    /// Start from this parameter file instead of a preset (sdre/ekf: the
    /// knee model's file with `[states]`; the tuned file is a copy of it).
    #[arg(long, conflicts_with = "preset")]
    pub params: Option<PathBuf>,
    /// Start from this preset: default or paper-2014.
    #[arg(long, default_value = TuneArgs::PRESET)]
    pub preset: String,
}

impl TuneArgs {
    /// `--seed`'s default.
    pub const SEED: u64 = 1;
    /// `--budget`'s default.
    pub const BUDGET: usize = 400;
    /// `--particles`'s default.
    pub const PARTICLES: usize = 20;
    /// `--starts`'s default.
    pub const STARTS: usize = 50;
    /// `--preset`'s default.
    pub const PRESET: &'static str = "default";

    /// The optimiser's flags given with other than their defaults (`sdre` /
    /// `ekf` tuning has no optimiser: an audit found them ignored without a
    /// word).
    pub fn optimiser_flags(&self) -> Vec<&'static str> {
        [
            ("--seed", self.seed != Self::SEED),
            ("--budget", self.budget != Self::BUDGET),
            ("--particles", self.particles != Self::PARTICLES),
            ("--starts", self.starts != Self::STARTS),
            ("--length", self.length.is_some()),
            ("--validate", self.validate.is_some()),
            ("--preset", self.preset != Self::PRESET),
        ]
        .into_iter()
        .filter_map(|(f, given)| given.then_some(f))
        .collect()
    }
}
