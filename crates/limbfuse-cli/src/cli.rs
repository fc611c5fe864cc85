//! Command-line flags (clap). Validated once into the commands' settings.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

/// Estimate lower-limb segment and joint angles from wearable IMUs and exoskeleton encoders.
#[derive(Debug, Parser)]
#[command(name = "limbfuse", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands (SPEC section 4).
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate a walking trial, run every segment-angle estimator, print an RMSE table and write a report.
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
    /// Monte Carlo of the segment filters under parametric uncertainty (paper 000 Fig. 9).
    Montecarlo(MonteCarloArgs),
    /// Rotate raw (arbitrarily mounted) sensor channels into their segment frames, from walking data.
    Align(AlignArgs),
    /// Resample a trial onto a uniform time base (e.g. 50 Hz, the rate of paper 001).
    Resample(ResampleArgs),
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
    #[arg(long)]
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

/// Options of `simulate bslip`.
#[derive(Debug, Args)]
pub struct BslipArgs {
    /// Gait speed (m/s): the gait of --library at this speed, or searched now.
    #[arg(long, default_value_t = 0.7)]
    pub speed: f64,
    /// Gait library to take the gait from.
    #[arg(long)]
    pub library: Option<PathBuf>,
    /// Duration (s); at most 86400 (24 h) without --force.
    #[arg(long, default_value_t = 4.0)]
    pub duration: f64,
    /// Sample rate (Hz).
    #[arg(long, default_value_t = 100.0)]
    pub rate: f64,
    /// Random seed of the measurement noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Measure CoM position only (paper sec IV-B) instead of position + sagittal velocity.
    #[arg(long)]
    pub position_only: bool,
    /// Body mass (kg) when searching the gait.
    #[arg(long, default_value_t = 80.0)]
    pub mass: f64,
    /// Leg rest length (m) when searching the gait.
    #[arg(long, default_value_t = 1.0)]
    pub leg_length: f64,
    /// Output trial file.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Lift the cap on the simulated length.
    #[command(flatten)]
    pub cap: LengthCap,
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
    /// static-rotation: calibration recording (quiet standing + rotations) of the same sensors;
    /// default: the calibration segment at the start of TRIAL.
    #[arg(long)]
    pub calibration: Option<PathBuf>,
    /// IMU calibration file (`limbfuse calibrate`, TOML) applied to the raw channels (and to a
    /// static-rotation --calibration recording) before alignment.
    #[arg(long, conflicts_with = "joint_axis")]
    pub imu_calibration: Option<PathBuf>,
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
    /// Base seed (run r simulates with seed + r).
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
    /// Directory for the trial, the estimates and the report.
    #[arg(long, default_value = "limbfuse-demo")]
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

/// Simulation scenarios.
#[derive(Debug, Subcommand)]
pub enum SimulateCommand {
    /// Level walking: trunk, thigh, shank and foot IMUs plus hip, knee and ankle encoders.
    Walking(WalkingArgs),
    /// Walking with every IMU at a random orientation, the thigh and shank IMUs at random
    /// positions, optionally a thigh-sensor re-mounting (paper 002).
    Knee(KneeSimArgs),
    /// Leg-extension machine with FES of the quadriceps (paper 004): thigh and shank IMUs, knee encoder, u_ke.
    KneeFes(KneeFesArgs),
    /// 2-DOF fixed-hip swing with FES and motors (paper 004): thigh and shank IMUs, encoders, u_*, tau_*_motor.
    FixedHip(FixedHipArgs),
    /// B-SLIP walking on a periodic gait: CoM measurements (eq 15 noise) and phase_ref (paper 003).
    Bslip(BslipArgs),
    /// A calibration recording (static poses and turns) of the four IMUs of `simulate walking` with the same seed.
    Calibration(crate::cli_calibration::CalibrationSimArgs),
}

/// Options of `simulate knee`.
#[derive(Debug, Args)]
pub struct KneeSimArgs {
    /// Output trial file.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Walking speed (m/s), 0.4 to 1.8.
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
    /// Duration (s); at most 86400 (24 h) without --force.
    #[arg(long, default_value_t = 60.0)]
    pub duration: f64,
    /// IMU sample rate (Hz).
    #[arg(long, default_value_t = 100.0)]
    pub imu_rate: f64,
    /// Random seed: same seed, same file, bit for bit.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Standard deviation (cm) of each sensor's forward/backward offset from its segment line.
    #[arg(long, default_value_t = 0.0)]
    pub ap_offset_sd_cm: f64,
    /// Re-mount the thigh sensor at this time (s): turned about the thigh's long axis.
    #[arg(long, value_name = "SECONDS")]
    pub remount_at: Option<f64>,
    /// Angle of the re-mounting (deg); paper 002: 50.
    #[arg(long, default_value_t = 50.0, requires = "remount_at")]
    pub remount_deg: f64,
    /// Ideal sensors: no noise, bias, scale-factor error or misalignment.
    #[arg(long)]
    pub no_noise: bool,
    /// Keep every segment in the sagittal plane.
    #[arg(long)]
    pub no_out_of_plane: bool,
    /// Lift the cap on the simulated length.
    #[command(flatten)]
    pub cap: LengthCap,
}

/// Options of `simulate knee-fes`.
#[derive(Debug, Args)]
pub struct KneeFesArgs {
    /// Output trial file.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Leg of Table 1 (P1-L, P1-R, P2-L, P2-R, P3-L, P3-R or 1-6).
    #[arg(long, default_value = "P1-L")]
    pub subject: String,
    /// Duration (s); at most 86400 (24 h) without --force.
    #[arg(long, default_value_t = 30.0)]
    pub duration: f64,
    /// IMU sample rate (Hz).
    #[arg(long, default_value_t = 100.0)]
    pub rate: f64,
    /// Random seed: same seed, same file, bit for bit.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Ideal sensors.
    #[arg(long)]
    pub no_noise: bool,
    /// Extra constant gyro drift on both gyros (deg/s).
    #[arg(long, default_value_t = 0.0)]
    pub gyro_drift: f64,
    /// Truth without muscle activation dynamics (a = u, as the estimators assume).
    #[arg(long)]
    pub no_activation_dynamics: bool,
    /// Sensor mounting (random: raw sensor frames, align with `align --procedure static-rotation`).
    #[arg(long, value_enum, default_value_t = MountingArg::Aligned)]
    pub mounting: MountingArg,
    /// Also write the calibration recording (quiet standing + 4 hip rotations) of the same sensors.
    #[arg(long)]
    pub calibration: Option<PathBuf>,
    /// Lift the cap on the simulated length.
    #[command(flatten)]
    pub cap: LengthCap,
}

/// Options of `simulate fixed-hip`.
#[derive(Debug, Args)]
pub struct FixedHipArgs {
    /// Output trial file.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Duration (s); at most 86400 (24 h) without --force.
    #[arg(long, default_value_t = 20.0)]
    pub duration: f64,
    /// IMU sample rate (Hz).
    #[arg(long, default_value_t = 100.0)]
    pub rate: f64,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Ideal sensors.
    #[arg(long)]
    pub no_noise: bool,
    /// Extra constant gyro drift on both gyros (deg/s).
    #[arg(long, default_value_t = 0.0)]
    pub gyro_drift: f64,
    /// Lift the cap on the simulated length.
    #[command(flatten)]
    pub cap: LengthCap,
}

/// How simulated IMUs sit on their segments.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MountingArg {
    /// Aligned with the segment up to a small (~1 deg) misalignment.
    Aligned,
    /// Arbitrary random orientation (for alignment work).
    Random,
}

/// Options of `simulate walking`.
#[derive(Debug, Args)]
pub struct WalkingArgs {
    /// Output trial file.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Walking speed (m/s), 0.4 to 1.8.
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
    /// Duration (s); at most 86400 (24 h) without --force.
    #[arg(long, default_value_t = 60.0)]
    pub duration: f64,
    /// IMU sample rate (Hz).
    #[arg(long, default_value_t = 100.0)]
    pub imu_rate: f64,
    /// Random seed: same seed, same file, bit for bit.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Sensor mounting.
    #[arg(long, value_enum, default_value_t = MountingArg::Aligned)]
    pub mounting: MountingArg,
    /// Ideal sensors: no noise, bias, scale-factor error or misalignment.
    #[arg(long)]
    pub no_noise: bool,
    /// Keep every segment in the sagittal plane.
    #[arg(long)]
    pub no_out_of_plane: bool,
    /// Identical strides (no stride-to-stride variability).
    #[arg(long)]
    pub no_variability: bool,
    /// No mounting misalignment (the ~1 deg no calibration can observe); every other sensor error unchanged.
    #[arg(long)]
    pub no_misalignment: bool,
    /// Lift the cap on the simulated length.
    #[command(flatten)]
    pub cap: LengthCap,
}

/// Supported import formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ImportFormat {
    /// gait-tech/gaittoolbox sample folder (Xsens `imu-*.csv` + `vicon-right.csv`).
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
}

/// Options of `estimate`.
#[derive(Debug, Args)]
pub struct EstimateArgs {
    /// Estimation method (`limbfuse methods` lists them).
    #[arg(long)]
    pub method: String,
    /// Trial file.
    pub trial: PathBuf,
    /// Output estimate file.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Parameter overrides (TOML).
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// knee-selfalign: window length s_w in samples (paper 002 default 500).
    #[arg(long, value_name = "SAMPLES")]
    pub window: Option<usize>,
    /// knee-selfalign: parameter-EKF iterations per window (paper 002 default 6).
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
    /// IMU calibration (`limbfuse calibrate`) applied to the trial's IMU channels before
    /// estimation (rotated into the aligned frame for a trial `align` wrote).
    #[arg(long, visible_alias = "imu-calibration")]
    pub calibration: Option<PathBuf>,
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
    /// Remove the mean error of each channel before computing the RMSE.
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

/// Options of `tune`.
#[derive(Debug, Args)]
pub struct TuneArgs {
    /// Segment filter to tune: local, mjls or global.
    #[arg(long)]
    pub method: String,
    /// Trial file with segment reference angles.
    pub trial: PathBuf,
    /// Tuning window START:END (s).
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
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Number of objective evaluations.
    #[arg(long, default_value_t = 400)]
    pub budget: usize,
    /// Swarm size of the particle swarm optimiser.
    #[arg(long, default_value_t = 20)]
    pub particles: usize,
    /// Starting points per window (paper 001: 50).
    #[arg(long, default_value_t = 50)]
    pub starts: usize,
    /// Length (s) of each run from a starting point (default: half the window).
    #[arg(long, value_name = "SECONDS")]
    pub length: Option<f64>,
    /// Start from this parameter file instead of a preset.
    #[arg(long, conflicts_with = "preset")]
    pub params: Option<PathBuf>,
    /// Start from this preset: default or paper-2014.
    #[arg(long, default_value = "default")]
    pub preset: String,
}
