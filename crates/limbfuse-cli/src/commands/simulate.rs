//! `limbfuse simulate walking ... -o trial.csv`.

use anyhow::Result;
use limbfuse_core::Leg;
use limbfuse_sim::config::{Mounting, SimError, WalkingConfig};
use limbfuse_sim::Turns;
use limbfuse_workflows::simulated_trials;

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
    let Err(e) = cfg.validate() else {
        return Ok(());
    };
    let SimError::OutOfRange { name, value, range } = e else {
        return Err(e.into());
    };
    let (flag, value, range) = match name {
        "speed_mps" => ("--speed", value, range),
        "duration_s" => ("--duration", value, range),
        "imu_rate_hz" => ("--imu-rate", value, range),
        "turns.duration_s" => ("--turn-s", value, "> 0 s"),
        "turns.every_s" => ("--turn-every", value, "(--turn-s, 1e9] s"),
        "turns.angle_rad" => ("--turn-deg", value.to_degrees(), "[-1800, 1800] deg"),
        _ => return Err(SimError::OutOfRange { name, value, range }.into()),
    };
    anyhow::bail!(
        "{flag} {}: outside the allowed range {range}",
        limbfuse_methods::shown(value)
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
    check_walking(&cfg)?;
    let trial = simulated_trials::walking(cfg)?;
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
