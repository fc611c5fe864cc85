//! `limbfuse simulate walking ... -o trial.csv`.

use anyhow::{Context, Result};
use limbfuse_io::{TrialLayout, TrialMeta, TrialWriter};
use limbfuse_sim::config::{Mounting, WalkingConfig};
use limbfuse_sim::WalkingSimulator;

use crate::cli::{MountingArg, WalkingArgs};

/// Resolves the flags into a validated simulator configuration.
pub fn walking_config(a: &WalkingArgs) -> WalkingConfig {
    WalkingConfig {
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
        ..WalkingConfig::default()
    }
}

/// `simulate walking`.
pub fn walking(a: &WalkingArgs) -> Result<()> {
    let summary = write_walking(a)?;
    eprintln!("simulated {summary} -> {}", a.output.display());
    Ok(())
}

/// Simulates and writes the trial; returns a one-line summary.
pub fn write_walking(a: &WalkingArgs) -> Result<String> {
    let cfg = walking_config(a);
    let sim = WalkingSimulator::new(cfg).context("simulate walking")?;
    let mut meta = TrialMeta::trial_v1();
    meta.set("source", "limbfuse simulate walking");
    meta.set("sample_rate_hz", a.imu_rate);
    meta.set("leg", "right");
    meta.set("g", cfg.g);
    for (k, v) in sim.metadata() {
        meta.set(k, v);
    }
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
