//! `limbfuse tune --method local|mjls|global TRIAL --window 0:20 -o params.toml`
//! (`sdre`/`ekf`: `tune_fes`).

use anyhow::{anyhow, bail, Context, Result};
use limbfuse_eval::TimeWindow;
use limbfuse_methods::segment_params::{
    load_params, save_params, FilterMethod, FilterParams, Preset,
};
use limbfuse_methods::MethodName;
use limbfuse_workflows::protocol::StartPlan;
use limbfuse_workflows::tune_validate::{span, tune_and_validate, TuneValidateConfig, Validation};
use limbfuse_workflows::tuning::TuneConfig;

use crate::cli::TuneArgs;

/// Tunes the noise parameters and writes them as a parameter file.
pub fn run(a: &TuneArgs) -> Result<()> {
    let name = MethodName::parse(&a.method)?;
    super::refuse_stdout(&a.output)?;
    // (`--params p.toml -o p.toml` refines a file in place: allowed)
    super::refuse_input_as_output(&a.trial, &a.output)?;
    super::refuse_missing_folder("-o", &a.output)?;
    if matches!(name, MethodName::Sdre | MethodName::Ekf) {
        return super::tune_fes::run(a, name);
    }
    let Some(method) = FilterMethod::from_method(name) else {
        bail!(
            "tune: method `{name}` has no tunable noise parameters; tune supports local, mjls, global, sdre and ekf"
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
    super::protocol::check_starts(a.starts)?;
    // (an audit: `--particles 0` was reported as "particles: ...", naming no
    // flag; the bounds are the tuner's)
    if !(2..=10_000).contains(&a.particles) {
        bail!(
            "--particles {}: expected a swarm of 2 to 10000 particles",
            a.particles
        );
    }
    // (the same audit for `--budget 5`: "budget: expected at least two
    // generations ...", the tuner's field; its bounds)
    if a.budget < 2 * a.particles || a.budget > 10_000_000 {
        bail!(
            "--budget {}: expected at least two generations of the swarm (2 x --particles {} = {} \
             evaluations) and at most 10000000 evaluations",
            a.budget,
            a.particles,
            2 * a.particles
        );
    }
    let validation = match a.validate.as_deref() {
        Some("none") => Validation::None,
        Some(w) => {
            Validation::Window(TimeWindow::parse(w).map_err(|m| anyhow!("--validate: {m}"))?)
        }
        None => Validation::FollowingBlock,
    };
    let records = super::protocol::read_trial(&a.trial, name)?.records;
    let cfg = TuneValidateConfig {
        start,
        plan: StartPlan {
            window,
            starts: a.starts,
            length_s: a.length,
        },
        validation,
        tune: TuneConfig {
            seed: a.seed,
            budget: a.budget,
            particles: a.particles,
            cancel: None,
        },
    };
    let n_eval = if a.particles > 0 {
        a.particles * (a.budget / a.particles)
    } else {
        0
    };
    let bar = crate::progress::bar(
        n_eval as u64,
        "tune {prefix} {bar:30} {pos}/{len} evaluations [{elapsed} < {eta}]",
    );
    bar.set_prefix(method.name());
    let r = tune_and_validate(&records, &cfg, &|| bar.inc(1))
        .with_context(|| format!("tuning {} on {}", method.name(), a.trial.display()))?;
    bar.finish_and_clear();
    // Every flag that shaped the result (an audit: --preset, --params,
    // --length and --validate were left out).
    let mut command = format!(
        "tuned by: limbfuse tune --method {} {} --window {} --seed {} --budget {} --particles {} --starts {}",
        method.name(),
        a.trial.display(),
        a.window,
        a.seed,
        a.budget,
        a.particles,
        a.starts
    );
    match &a.params {
        Some(p) => command += &format!(" --params {}", p.display()),
        None => command += &format!(" --preset {}", a.preset),
    }
    if let Some(l) = a.length {
        command += &format!(" --length {l}");
    }
    if let Some(v) = &a.validate {
        command += &format!(" --validate {v}");
    }
    let mut header = vec![command];
    header.extend(r.provenance());
    save_params(&a.output, &r.params, &header)?;

    println!(
        "tune {}: {} coordinates, {} evaluations, seed {}",
        method.name(),
        r.dims,
        r.evaluations,
        a.seed
    );
    println!("tuning window     {}", span(&r.tuning));
    match &r.validation {
        Some(iv) => println!("validation window {}", span(iv)),
        None if a.validate.as_deref() == Some("none") => {
            println!("validation window: none (--validate none)")
        }
        None => println!("validation window: none (the trial ends too early; see --validate)"),
    }
    println!("RMSE deg (mean over starting points)");
    print!("{}", r.table());
    warn_about_validation(a, &r);
    eprintln!("wrote {}", a.output.display());
    Ok(())
}

/// The validation warnings of [`limbfuse_workflows::tune_validate::TuneValidateReport::validation_warnings`].
fn warn_about_validation(a: &TuneArgs, r: &limbfuse_workflows::tune_validate::TuneValidateReport) {
    let written = format!("{} is written as asked", a.output.display());
    for w in r.validation_warnings(&written, "--window") {
        eprintln!("warning: {w}");
    }
}
