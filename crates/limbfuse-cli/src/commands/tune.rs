//! `limbfuse tune --method local|mjls|global TRIAL --window 0:20 -o params.toml`.

use anyhow::{anyhow, bail, Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Estimator, Record, Segment};
use limbfuse_eval::protocol::{multi_start, plan_intervals, MultiStartResult, StartPlan};
use limbfuse_eval::tuning::{tune, SearchSpace, TuneConfig};
use limbfuse_eval::TimeWindow;
use limbfuse_methods::segment_params::{
    load_params, save_params, FilterMethod, FilterParams, Preset,
};
use limbfuse_methods::MethodName;

use crate::cli::TuneArgs;

fn evaluate(p: &FilterParams, records: &[Record], iv: &[(f64, f64)]) -> Result<MultiStartResult> {
    let make = || {
        p.build()
            .map(|f| f as Box<dyn Estimator>)
            .map_err(|e| e.to_string())
    };
    Ok(multi_start(&make, records, iv, false)?)
}

/// The validation window: `--validate`, or the block of the tuning window's
/// length right after it (shortened to the trial's end; skipped when less
/// than 1 s is left).
fn validation_window(
    a: &TuneArgs,
    tuning: &[(f64, f64)],
    t_last: f64,
) -> Result<Option<TimeWindow>> {
    match a.validate.as_deref() {
        Some("none") => Ok(None),
        Some(w) => Ok(Some(
            TimeWindow::parse(w).map_err(|m| anyhow!("--validate: {m}"))?,
        )),
        None => {
            let start = tuning.iter().map(|i| i.0).fold(f64::INFINITY, f64::min);
            let end = tuning.iter().map(|i| i.1).fold(f64::NEG_INFINITY, f64::max);
            let vend = (end + (end - start)).min(t_last);
            Ok((vend - end >= 1.0).then_some(TimeWindow {
                start: Some(end),
                end: Some(vend),
            }))
        }
    }
}

fn segment_row(name: &str, r: [Option<&MultiStartResult>; 4]) -> String {
    let f = |m: Option<&MultiStartResult>, c: Option<AngleChannel>| {
        let v = match c {
            Some(c) => m.and_then(|m| m.rmse(c)),
            None => m.and_then(MultiStartResult::mean_rmse),
        };
        v.map_or("-".to_string(), |v| format!("{:.3}", v.to_degrees()))
    };
    let c = Segment::ALL
        .iter()
        .find(|s| s.name() == name)
        .map(|s| AngleChannel::Segment(*s));
    format!(
        "{name:<10}{:>12}{:>12}{:>14}{:>14}\n",
        f(r[0], c),
        f(r[1], c),
        f(r[2], c),
        f(r[3], c)
    )
}

/// Tunes the noise parameters and writes them as a parameter file.
pub fn run(a: &TuneArgs) -> Result<()> {
    let name = MethodName::parse(&a.method)?;
    let Some(method) = FilterMethod::from_method(name) else {
        bail!(
            "tune: method `{name}` has no tunable noise parameters; tune supports local, mjls and global"
        );
    };
    let start = match &a.params {
        Some(p) => load_params(p, method)?,
        None => {
            let preset = Preset::from_name(&a.preset).ok_or_else(|| {
                anyhow!(
                    "--preset: expected `default` or `paper-2014`, found `{}`",
                    a.preset
                )
            })?;
            FilterParams::preset(method, preset)
        }
    };
    let window = TimeWindow::parse(&a.window).map_err(|m| anyhow!("--window: {m}"))?;
    let records = super::protocol::read_trial(&a.trial, name)?.records;
    let plan = StartPlan {
        window,
        starts: a.starts,
        length_s: a.length,
    };
    let tuning_iv = plan_intervals(&records, &plan)
        .with_context(|| format!("{}: tuning window", a.trial.display()))?;
    let t_last = records.last().map_or(0.0, |r| r.sample.t);
    let validation_iv = match validation_window(a, &tuning_iv, t_last)? {
        Some(w) => Some(
            plan_intervals(&records, &StartPlan { window: w, ..plan })
                .with_context(|| format!("{}: validation window", a.trial.display()))?,
        ),
        None => None,
    };
    let cfg = TuneConfig {
        seed: a.seed,
        budget: a.budget,
        particles: a.particles,
    };
    let n_eval = if a.particles > 0 {
        a.particles * (a.budget / a.particles)
    } else {
        0
    };
    let bar = ProgressBar::new(n_eval as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "tune {prefix} {bar:30} {pos}/{len} evaluations [{elapsed} < {eta}]",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_prefix(method.name());
    let dims = SearchSpace::around(&start).knobs.len();
    let result = tune(&start, &records, &tuning_iv, &cfg, &|| bar.inc(1))
        .with_context(|| format!("tuning {} on {}", method.name(), a.trial.display()))?;
    bar.finish_and_clear();

    let tun_before = evaluate(&start, &records, &tuning_iv)?;
    let tun_after = evaluate(&result.params, &records, &tuning_iv)?;
    let (val_before, val_after) = match &validation_iv {
        Some(iv) => (
            Some(evaluate(&start, &records, iv)?),
            Some(evaluate(&result.params, &records, iv)?),
        ),
        None => (None, None),
    };
    let span = |iv: &[(f64, f64)]| {
        format!(
            "{:.3}:{:.3} s, {} starting points x {:.3} s",
            iv[0].0,
            iv[iv.len() - 1].1,
            iv.len(),
            iv[0].1 - iv[0].0
        )
    };
    let deg = |m: Option<&MultiStartResult>| {
        m.and_then(MultiStartResult::mean_rmse)
            .map_or("-".to_string(), |v| format!("{:.3}", v.to_degrees()))
    };
    let mut header = vec![
        format!(
            "tuned by: limbfuse tune --method {} {} --window {} --seed {} --budget {} --particles {} --starts {}",
            method.name(),
            a.trial.display(),
            a.window,
            a.seed,
            a.budget,
            a.particles,
            a.starts
        ),
        format!(
            "optimiser: particle swarm (argmin), {} log10 coordinates, {} evaluations",
            dims, result.evaluations
        ),
        format!(
            "tuning window {}: mean segment RMSE {} -> {} deg",
            span(&tuning_iv),
            deg(Some(&tun_before)),
            deg(Some(&tun_after))
        ),
    ];
    if let Some(iv) = &validation_iv {
        header.push(format!(
            "validation window {}: mean segment RMSE {} -> {} deg",
            span(iv),
            deg(val_before.as_ref()),
            deg(val_after.as_ref())
        ));
    }
    save_params(&a.output, &result.params, &header)?;

    println!(
        "tune {}: {} coordinates, {} evaluations, seed {}",
        method.name(),
        dims,
        result.evaluations,
        a.seed
    );
    println!("tuning window     {}", span(&tuning_iv));
    match &validation_iv {
        Some(iv) => println!("validation window {}", span(iv)),
        None => println!("validation window: none (the trial ends too early; see --validate)"),
    }
    println!("RMSE deg (mean over starting points)");
    println!(
        "{:<10}{:>12}{:>12}{:>14}{:>14}",
        "segment", "tune start", "tune tuned", "valid. start", "valid. tuned"
    );
    let cols = [
        Some(&tun_before),
        Some(&tun_after),
        val_before.as_ref(),
        val_after.as_ref(),
    ];
    for s in Segment::ALL {
        print!("{}", segment_row(s.name(), cols));
    }
    print!("{}", segment_row("mean", cols));
    eprintln!("wrote {}", a.output.display());
    Ok(())
}
