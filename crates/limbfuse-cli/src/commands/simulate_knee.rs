//! `limbfuse simulate knee ... -o trial.csv` (paper 002 scenario).

use anyhow::Result;
use limbfuse_sim::{KneeScenario, Remount, WalkingConfig};
use limbfuse_workflows::simulated_trials;

use crate::cli::KneeSimArgs;

/// Resolves the flags into a scenario (validated by the simulator).
pub fn scenario(a: &KneeSimArgs) -> KneeScenario {
    let d = KneeScenario::default();
    KneeScenario {
        walking: WalkingConfig {
            speed_mps: a.speed,
            duration_s: a.duration,
            imu_rate_hz: a.imu_rate,
            seed: a.seed,
            noise: !a.no_noise,
            out_of_plane: !a.no_out_of_plane,
            ..d.walking
        },
        ap_offset_sd_m: a.ap_offset_sd_cm / 100.0,
        remount: a.remount_at.map(|t_s| Remount {
            t_s,
            angle_rad: a.remount_deg.to_radians(),
        }),
        ..d
    }
}

/// `simulate knee`.
pub fn run(a: &KneeSimArgs) -> Result<()> {
    let summary = write(a)?;
    eprintln!("simulated {summary} -> {}", a.output.display());
    Ok(())
}

/// Simulates and writes the trial; returns a one-line summary.
pub fn write(a: &KneeSimArgs) -> Result<String> {
    crate::bounds::simulated_trial(a.duration, "--imu-rate", a.imu_rate, a.cap.force)?;
    // (an audit: `--remount-at 1000 --duration 5` said "re-mounted at 1000 s")
    if let Some(t) = a
        .remount_at
        .filter(|t| !(t.is_finite() && *t > 0.0 && *t < a.duration))
    {
        anyhow::bail!(
            "--remount-at {}: expected a time within the trial, after 0 and before --duration {} s",
            limbfuse_methods::shown(t),
            a.duration
        );
    }
    let sc = scenario(a);
    let trial = simulated_trials::knee(sc).map_err(super::simulate::simulation_error)?;
    let summary = format!(
        "{:.0} s of walking at {} m/s (seed {}, random IMU orientations and positions{})",
        a.duration,
        a.speed,
        a.seed,
        match a.remount_at {
            Some(t) => format!(
                ", thigh sensor re-mounted by {} deg at {t} s",
                a.remount_deg
            ),
            None => String::new(),
        }
    );
    let mut out = super::create_file(&a.output)?;
    simulated_trials::write_trial(&mut out, trial, &a.output)?;
    super::commit(out)?;
    Ok(summary)
}
