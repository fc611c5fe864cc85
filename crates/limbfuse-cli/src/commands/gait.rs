//! Paper 003 commands: `gait-library build`, `simulate bslip`, the
//! `imm-bslip` estimator builder, gait evaluation and the demo section.

use std::path::Path;

use anyhow::{bail, Context, Result};
use indicatif::ProgressBar;
use limbfuse_estimators::imm_bslip::{ImmBslip, ImmBslipParams};
use limbfuse_io::TrialReader;
use limbfuse_models::bslip::{BslipParams, GaitTemplate};
use limbfuse_sim::bslip::library::{build_library, LibraryGait};
use limbfuse_sim::bslip::search::SearchSettings;
use limbfuse_sim::bslip::trial::{BslipTrialConfig, ComChannels};
use limbfuse_workflows::bslip_gait::{bslip_gait, BslipGaitError, GaitSource, MAX_GAIT_SPEED};
use limbfuse_workflows::gait_library::gait_library_file;
use limbfuse_workflows::simulated_trials;

use crate::cli::{BslipArgs, GaitLibraryBuildArgs};

/// Parses `START:END:STEP` (inclusive) into speeds.
pub fn parse_speeds(text: &str) -> Result<Vec<f64>> {
    let parts: Vec<&str> = text.split(':').collect();
    let nums: Vec<f64> = parts
        .iter()
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| {
            anyhow::anyhow!(
                "--speeds: expected START:END:STEP in m/s (e.g. 0.4:0.9:0.1), found `{text}`"
            )
        })?;
    let [a, b, s] = nums[..] else {
        bail!("--speeds: expected START:END:STEP in m/s (e.g. 0.4:0.9:0.1), found `{text}`");
    };
    if !(a > 0.0 && b >= a && s > 0.0 && b <= MAX_GAIT_SPEED) {
        bail!("--speeds {text}: need 0 < START <= END <= {MAX_GAIT_SPEED} m/s and STEP > 0");
    }
    let n = ((b - a) / s + 1e-9).floor() as usize + 1;
    let last = a + (n - 1) as f64 * s;
    if (b - last).abs() > 1e-6 * s.max(1e-3) {
        // (an audit: 0.4:0.65:0.1 stopped at 0.6 without a word)
        bail!(
            "--speeds {text}: END is not START + k STEP (the last speed would be {}); give an END \
             on that grid, e.g. {} or {}",
            (last * 1e6).round() / 1e6,
            (last * 1e6).round() / 1e6,
            ((last + s) * 1e6).round() / 1e6
        );
    }
    if n > limbfuse_estimators::imm_bslip::MAX_GAITS {
        bail!(
            "--speeds {text}: {n} gaits; at most {} are supported",
            limbfuse_estimators::imm_bslip::MAX_GAITS
        );
    }
    Ok((0..n)
        .map(|k| ((a + k as f64 * s) * 1e6).round() / 1e6)
        .collect())
}

fn body(mass: f64, leg: f64) -> Result<BslipParams> {
    use limbfuse_methods::body_ranges::{leg_length_m, mass_kg};
    // A human's (an audit: `--leg-length 0.01` or `--mass 1e9` failed with
    // "no periodic gait at 1 m/s", a speed that was not asked for).
    let mass = mass_kg("--mass", mass).map_err(anyhow::Error::msg)?;
    let leg = leg_length_m("--leg-length", leg).map_err(anyhow::Error::msg)?;
    Ok(BslipParams {
        mass,
        rest_length: leg,
        ..BslipParams::default()
    })
}

/// Builds a library with a progress bar.
pub fn build(body: &BslipParams, speeds: &[f64], show_progress: bool) -> Result<Vec<LibraryGait>> {
    let bar = if show_progress {
        let bar = crate::progress::bar(
            speeds.len() as u64,
            "{prefix} [{bar:30}] {pos}/{len} gaits [{elapsed}]",
        );
        bar.set_prefix("gait library");
        bar
    } else {
        ProgressBar::hidden()
    };
    let lib = build_library(body, speeds, &SearchSettings::default(), |done, _| {
        bar.set_position(done as u64)
    })
    .context("gait library search")?;
    bar.finish_and_clear();
    Ok(lib)
}

/// `limbfuse gait-library build`.
pub fn library_build(a: &GaitLibraryBuildArgs) -> Result<()> {
    let speeds = parse_speeds(&a.speeds)?;
    let body = body(a.mass, a.leg_length)?;
    // The output's folder is tried before the search (an audit: `-o
    // /proc/x.json` failed only after it); the probe leaves nothing behind.
    drop(super::create_file(&a.output)?);
    let t0 = std::time::Instant::now();
    let lib = build(&body, &speeds, true)?;
    let file = gait_library_file(&body, &lib);
    file.write(&a.output)?;
    eprintln!(
        "gait library: {} gaits ({} m/s) in {:.1} s -> {}",
        lib.len(),
        a.speeds,
        t0.elapsed().as_secs_f64(),
        a.output.display()
    );
    eprintln!("speed  step L   step W   T step  DS      k (N/m)  vert exc  lat exc  residual");
    for g in &file.gaits {
        eprintln!(
            "{:.2}   {:.3} m  {:.3} m  {:.3} s {:>4.0} %  {:>7.0}  {:.1} cm    {:.1} cm   {:.0e}",
            g.speed,
            g.step_length,
            g.step_width,
            g.step_time,
            100.0 * (g.t_lift_off - g.t_touchdown) / g.step_time,
            g.xi.stiffness,
            100.0 * g.vertical_excursion,
            100.0 * g.lateral_excursion,
            g.periodicity_residual
        );
    }
    Ok(())
}

/// `limbfuse simulate bslip`.
pub fn simulate(a: &BslipArgs) -> Result<()> {
    super::refuse_overwrites(
        &[("--library", a.library.as_deref())],
        &[("-o", Some(&a.output))],
    )?;
    // (an audit: `--rate 1e-300` wrote a one-row trial, exit 0; the other
    // simulators take at least 1 Hz; checked before the length, which would
    // say "less than one sample")
    if a.rate < 1.0 {
        bail!(
            "--rate {}: expected a sample rate of at least 1 Hz (as the other simulators)",
            limbfuse_methods::shown(a.rate)
        );
    }
    crate::bounds::simulated_trial(a.duration, "--rate", a.rate, a.cap.force)?;
    if !(a.speed.is_finite() && a.speed > 0.0 && a.speed <= MAX_GAIT_SPEED) {
        bail!(
            "--speed {}: expected a walking speed in (0, {MAX_GAIT_SPEED}] m/s (the range `gait-library build --speeds` accepts)",
            limbfuse_methods::shown(a.speed)
        );
    }
    let searched_body;
    let source = match &a.library {
        Some(p) => GaitSource::Library(p),
        None => {
            searched_body = body(a.mass, a.leg_length)?;
            GaitSource::Search(&searched_body)
        }
    };
    let template = bslip_gait(a.speed, source).map_err(|e| match e {
        BslipGaitError::Search { source, .. } => anyhow::Error::new(source)
            .context("gait library search")
            .context(format!(
                "--speed {}: no periodic B-SLIP gait found at this speed for a {} kg body with {} m legs",
                a.speed, a.mass, a.leg_length
            )),
        other => anyhow::Error::new(other),
    })?;
    let cfg = BslipTrialConfig {
        duration: a.duration,
        sample_rate: a.rate,
        channels: if a.position_only {
            ComChannels::Position
        } else {
            ComChannels::Full
        },
        seed: a.seed,
        ..Default::default()
    };
    let trial = simulated_trials::bslip(&template, &cfg, "limbfuse simulate bslip");
    let mut out = super::create_file(&a.output)?;
    simulated_trials::write_trial(&mut out, trial, &a.output)?;
    super::commit(out)?;
    eprintln!(
        "simulated {:.1} s of B-SLIP walking at {} m/s ({} Hz, {} channels, seed {}) -> {}",
        a.duration,
        template.speed,
        a.rate,
        if a.position_only {
            "position"
        } else {
            "full CoM"
        },
        a.seed,
        a.output.display()
    );
    Ok(())
}

/// The demo section: gait speed and phase on a simulated B-SLIP trial with a
/// small built-in library (0.6, 0.7, 0.8 m/s, the 0.7 m/s gait simulated);
/// writes `report-bslip.html`, returns the lines printed (for report.md).
pub fn demo(dir: &Path) -> Result<String> {
    let t0 = std::time::Instant::now();
    let body = BslipParams::default();
    let lib = build(&body, &[0.6, 0.7, 0.8], false)?;
    let templates: Vec<GaitTemplate> = lib.iter().map(|g| g.template(&body)).collect();
    let trial = dir.join("bslip_trial.csv");
    let estimate = dir.join("bslip_imm.csv");
    let sim = simulated_trials::bslip(
        &templates[1],
        &BslipTrialConfig::default(),
        "limbfuse demo (B-SLIP 0.7 m/s)",
    );
    let mut out = super::create_file(&trial)?;
    simulated_trials::write_trial(&mut out, sim, &trial)?;
    super::commit(out)?;
    let mut imm = ImmBslip::new(&templates, ImmBslipParams::full_com())?;
    super::estimate::run_to_file(
        &mut imm,
        TrialReader::open(&trial)?,
        &estimate,
        limbfuse_methods::MethodName::ImmBslip.name(),
        "limbfuse demo (imm-bslip, full CoM, over a gait library of 0.6, 0.7 and 0.8 m/s searched in memory)",
        &mut [],
    )?;
    let ev = limbfuse_eval::gait_evaluation::evaluate_gait_files(&trial, &estimate, false)?;
    let text = format!(
        "Gait phase and speed (paper 003, imm-bslip): B-SLIP trial at 0.7 m/s, library 0.6/0.7/0.8 m/s\n  \
         phase accuracy {:.1} %, CoM position RMS {:.2} cm, mean speed estimate {:.3} m/s (true 0.700)  [{:.1} s]\n",
        ev.phase_accuracy_pct.unwrap_or(f64::NAN),
        100.0 * ev.com_pos_rmse_m.unwrap_or(f64::NAN),
        ev.speed_mean_mps.unwrap_or(f64::NAN),
        t0.elapsed().as_secs_f64()
    );
    print!("\n{text}");
    super::demo::html_report(
        &trial,
        &[estimate],
        &dir.join("report-bslip.html"),
        "B-SLIP trial and imm-bslip",
    )?;
    Ok(text)
}
