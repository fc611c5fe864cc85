//! `limbfuse simulate walking ... -o trial.csv`.

use anyhow::Result;
use limbfuse_core::Leg;
use limbfuse_sim::config::{Mounting, WalkingConfig};
use limbfuse_sim::Turns;
use limbfuse_workflows::simulated_trials::{self, SimulatedTrialError};
use limbfuse_workflows::simulator_options::OptionOutOfRange;

use crate::cli::{LegArg, MountingArg, WalkingArgs};

/// Resolves the flags into a validated simulator configuration.
pub fn walking_config(a: &WalkingArgs) -> WalkingConfig {
    let mut imu = WalkingConfig::default().imu;
    if a.no_misalignment {
        imu.misalignment_rad = 0.0;
    }
    WalkingConfig {
        imu,
        speed_mps: a.speed,
        duration_s: a.duration,
        imu_rate_hz: a.imu_rate,
        seed: a.seed,
        mounting: match a.mounting {
            MountingArg::Aligned => Mounting::Aligned,
            MountingArg::Random => Mounting::Random,
        },
        noise: !a.no_noise,
        out_of_plane: !a.no_out_of_plane,
        variability: if a.no_variability {
            None
        } else {
            WalkingConfig::default().variability
        },
        leg: match a.leg {
            LegArg::Right => Leg::Right,
            LegArg::Left => Leg::Left,
        },
        turns: a.turn_every.map(|every_s| Turns {
            every_s,
            duration_s: a.turn_s,
            angle_rad: a.turn_deg.to_radians(),
        }),
        ..WalkingConfig::default()
    }
}

/// Checks a walking configuration made from flags, naming the flag (an
/// audit: the simulator's own messages said `turns.angle_rad` for
/// `--turn-deg`, in radians, with 300 digits for `1e300`).
pub fn check_walking(cfg: &WalkingConfig) -> Result<()> {
    cfg.validate()
        .map_err(|e| simulation_error(simulated_trials::config_error("walking", e)))
}

/// A simulated trial's error, an out-of-range setting named by its flag.
pub fn simulation_error(e: SimulatedTrialError) -> anyhow::Error {
    match e {
        SimulatedTrialError::Option { option, .. } => option_error(option),
        e => e.into(),
    }
}

/// An out-of-range setting named by its flag, in the flag's unit.
pub fn option_error(option: OptionOutOfRange) -> anyhow::Error {
    anyhow::anyhow!(
        "{} {}: outside the allowed range {}",
        option.flag(),
        limbfuse_methods::shown(option.value),
        option.range
    )
}

/// `simulate walking`.
pub fn walking(a: &WalkingArgs) -> Result<()> {
    let summary = write_walking(a)?;
    eprintln!("simulated {summary} -> {}", a.output.display());
    Ok(())
}

/// Simulates and writes the trial; returns a one-line summary.
pub fn write_walking(a: &WalkingArgs) -> Result<String> {
    crate::bounds::simulated_trial(a.duration, "--imu-rate", a.imu_rate, a.cap.force)?;
    let cfg = walking_config(a);
    let trial = simulated_trials::walking(cfg).map_err(simulation_error)?;
    let summary = format!(
        "{:.0} s of walking at {} m/s (seed {}, {} Hz IMUs, {} mounting, noise {})",
        a.duration,
        a.speed,
        a.seed,
        a.imu_rate,
        if a.mounting == MountingArg::Aligned {
            "aligned"
        } else {
            "random"
        },
        if a.no_noise { "off" } else { "on" }
    );
    let mut out = super::create_file(&a.output)?;
    if a.gait_reference {
        let trial = simulated_trials::with_gait_reference(trial);
        simulated_trials::write_trial(&mut out, trial, &a.output)?;
    } else {
        simulated_trials::write_trial(&mut out, trial, &a.output)?;
    }
    super::commit(out)?;
    Ok(summary)
}
