//! `limbfuse simulate knee ... -o trial.csv` (paper 002 scenario).

use anyhow::{Context, Result};
use limbfuse_io::{TrialLayout, TrialMeta, TrialWriter};
use limbfuse_sim::{KneeScenario, KneeSimulator, Remount, WalkingConfig};

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
    let sc = scenario(a);
    let sim = KneeSimulator::new(sc).context("simulate knee")?;
    let mut meta = TrialMeta::trial_v1();
    meta.set("source", "limbfuse simulate knee");
    meta.set("sample_rate_hz", a.imu_rate);
    meta.set("leg", "right");
    meta.set("g", sc.walking.g);
    for (k, v) in sim.metadata() {
        meta.set(k, v);
    }
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
    let out = super::create_file(&a.output)?;
    let mut w = TrialWriter::new(out, &meta, TrialLayout::walking())
        .with_context(|| format!("{}: cannot write", a.output.display()))?;
    for r in sim {
        w.write(&r)
            .with_context(|| format!("{}: cannot write", a.output.display()))?;
    }
    w.finish()
        .with_context(|| format!("{}: cannot write", a.output.display()))?;
    Ok(summary)
}
