//! The knee section of `limbfuse demo` (paper 002): a short simulated trial
//! with every IMU at a random orientation and the thigh and shank IMUs at
//! random positions, run through `knee-selfalign`.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};
use limbfuse_core::{Estimator, Joint};
use limbfuse_estimators::knee_selfalign::{KneeSelfAlign, KneeSelfAlignParams};
use limbfuse_eval::knee_errors::KneeRun;
use limbfuse_sim::{KneeScenario, KneeSimulator, WalkingConfig};

/// Duration of the demo's knee trial (s): six windows of 500 samples.
const DURATION_S: f64 = 30.0;

/// Runs the knee demo; returns the text printed (also for the report).
pub fn run(seed: u64, speed: f64, out: &Path) -> Result<String> {
    let d = KneeScenario::default();
    let sim = KneeSimulator::new(KneeScenario {
        walking: WalkingConfig {
            seed,
            speed_mps: speed,
            duration_s: DURATION_S,
            ..d.walking
        },
        ..d
    })
    .context("simulate the knee demo trial")?;
    let (true_axes, _) = sim.sensor_frame_geometry();
    let records: Vec<_> = sim.collect();
    let mut est = KneeSelfAlign::new(KneeSelfAlignParams::default()).map_err(anyhow::Error::msg)?;
    let knee = Joint::Knee.index();
    let start = Instant::now();
    let mut knee_estimates = Vec::with_capacity(records.len());
    for r in &records {
        knee_estimates.push(est.step(&r.sample).map_err(anyhow::Error::msg)?.joint[knee]);
    }
    let seconds = start.elapsed().as_secs_f64();
    let run = KneeRun::from_estimates(&records, &knee_estimates, &[(0, records.len())], seconds);
    let mut s = String::new();
    writeln!(
        s,
        "knee-selfalign (paper 002): {DURATION_S:.0} s of walking, thigh and shank IMUs at random orientations and positions"
    )?;
    if let Some(g) = est.geometry() {
        for (i, seg) in ["thigh", "shank"].iter().enumerate() {
            writeln!(
                s,
                "  {seg} joint axis (sensor frame): [{:+.3}, {:+.3}, {:+.3}], {:.2} deg from the truth",
                g.axis[i].x,
                g.axis[i].y,
                g.axis[i].z,
                g.axis[i].angle(&true_axes[i]).to_degrees()
            )?;
        }
    }
    write_summary(&mut s, &run)?;
    let path = out.join("knee-selfalign.txt");
    super::write_file(&path, &s)?;
    Ok(s)
}

fn write_summary(s: &mut String, r: &KneeRun) -> std::fmt::Result {
    writeln!(
        s,
        "  knee from sample 500 on: RMSE {:.2} deg, mean error {:+.2} deg (zero from the sensor positions), offset-free RMSE {:.2} deg, corr {:.4} ({} samples)",
        r.rmse.to_degrees(),
        r.mean.to_degrees(),
        r.rmse_offset_free.to_degrees(),
        r.corr,
        r.errors.len()
    )?;
    Ok(())
}
