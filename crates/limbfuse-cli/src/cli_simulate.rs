//! Flags of `simulate` and its scenarios (split from `cli.rs` to keep each
//! file readable in one sitting).

use std::path::PathBuf;

use clap::{Args, Subcommand, ValueEnum};

use crate::cli::LengthCap;
use limbfuse_workflows::simulator_options;

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
    /// IMU sample rate (Hz); `--rate` is accepted as an alias.
    #[arg(long, alias = "rate", default_value_t = 100.0)]
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
    #[arg(long, default_value_t = simulator_options::DEFAULT_REMOUNT_DEG, requires = "remount_at")]
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
    /// IMU sample rate (Hz); `--rate` is accepted as an alias.
    #[arg(long, alias = "rate", default_value_t = 100.0)]
    pub imu_rate: f64,
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
    /// Leg extensions, 6 s each after 2 s of rest (paper 004's 30 s trials hold five); the leg rests
    /// after the last one.
    #[arg(long, default_value_t = 5)]
    pub cycles: u32,
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
    /// IMU sample rate (Hz); `--rate` is accepted as an alias.
    #[arg(long, alias = "rate", default_value_t = 100.0)]
    pub imu_rate: f64,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Ideal sensors.
    #[arg(long)]
    pub no_noise: bool,
    /// Extra constant gyro drift on both gyros (deg/s).
    #[arg(long, default_value_t = 0.0)]
    pub gyro_drift: f64,
    /// Muscle activation dynamics in the truth, `a' = (u - a) / T_a` for the
    /// four muscles, with this T_a (s; issue 16); default: none (activation
    /// equals stimulation, the thesis model).
    #[arg(long, value_name = "T_A")]
    pub activation_t_a: Option<f64>,
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
    /// IMU sample rate (Hz); `--rate` is accepted as an alias.
    #[arg(long, alias = "rate", default_value_t = 100.0)]
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
    /// Leg the sensors are on (the left leg moves as the mirror image of the right).
    #[arg(long, value_enum, default_value_t = LegArg::Right)]
    pub leg: LegArg,
    /// Turn the walking path every this many seconds (step turns: the leg changes heading in its
    /// swings, the stance foot stays planted, the trunk turns step by step); default: walk straight.
    #[arg(long, value_name = "SECONDS")]
    pub turn_every: Option<f64>,
    /// Heading change of each turn (deg; positive = to the left).
    #[arg(long, default_value_t = simulator_options::DEFAULT_TURN_DEG, requires = "turn_every")]
    pub turn_deg: f64,
    /// Duration of each turn (s): the swings whose toe off falls within it take the turn (at least
    /// one, and enough that none turns by more than 90 deg).
    #[arg(long, default_value_t = simulator_options::DEFAULT_TURN_S, requires = "turn_every")]
    pub turn_s: f64,
    /// No mounting misalignment (the ~1 deg no calibration can observe); every other sensor error unchanged.
    #[arg(long)]
    pub no_misalignment: bool,
    /// Also write the gait truth: `contact_left_ref` and `contact_right_ref` (each foot on the
    /// ground from heel strike to toe off at 60 % of its stride; the foot without sensors half a
    /// stride after the simulated one) and `speed_ref` (per stride), so that `gait-events` and
    /// `lowback-speed` estimates can be evaluated.
    #[arg(long)]
    pub gait_reference: bool,
    /// Lift the cap on the simulated length.
    #[command(flatten)]
    pub cap: LengthCap,
}

/// Which leg a simulated trial records.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum LegArg {
    /// The right leg.
    Right,
    /// The left leg.
    Left,
}
