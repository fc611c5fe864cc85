//! From `--method NAME [--params FILE] [flags]` to a running estimator,
//! through the method layer (`limbfuse-methods`): the CLI only maps flags.

use std::path::Path;

use anyhow::{Context, Result};
use limbfuse_core::Estimator;
use limbfuse_io::TrialReader;
use limbfuse_methods::{build, MethodFlags, MethodName, MethodSpec};

use crate::cli::EstimateArgs;

/// The help of a `--method` flag: `what`, then every method name of the
/// registry, so `--help` lists them all (not "e.g.").
pub fn method_flag_help(what: &str) -> String {
    let names: Vec<&str> = MethodName::ALL.iter().map(|m| m.info().name).collect();
    format!(
        "{what}: one of {} (`limbfuse methods` describes each)",
        names.join(", ")
    )
}

/// The method-specific flags of `estimate`.
pub fn flags(a: &EstimateArgs) -> MethodFlags {
    MethodFlags {
        window: a.window,
        order: a.order,
        library: a.library.clone(),
        kappa: a.kappa,
        rescale_height: a.rescale_height,
        imm_weights: a.imm_weights.clone(),
        imm_touchdown: a.imm_touchdown.clone(),
        imm_config: a.imm_config.clone(),
        imm_extend_library: a.imm_extend_library.clone(),
        leg_length: a.leg_length,
        mass: a.mass,
    }
}

/// Parses `--method` and resolves its settings (parameter file, flags).
pub fn resolve(name: &str, params: Option<&Path>, flags: &MethodFlags) -> Result<MethodSpec> {
    let method = MethodName::parse(name)?;
    Ok(MethodSpec::resolve(method, params, flags)?)
}

/// Builds `spec` for the trial `reader` is reading; errors name the trial.
pub fn build_for(spec: &MethodSpec, reader: &TrialReader) -> Result<Box<dyn Estimator + Send>> {
    build(spec, reader.meta(), reader.layout()).map_err(|e| {
        let path = reader.path().display();
        match model_file_beside(&e, reader.path()) {
            Some(hint) => anyhow::anyhow!("{path}: {e}; {hint}"),
            None => match methods_that_run(&e, reader) {
                Some(list) => anyhow::anyhow!("{path}: {e}; {list}"),
                None => anyhow::Error::new(e).context(path.to_string()),
            },
        }
    })
}

/// A method refused for missing columns, with no hint of its own: the
/// methods that run on the trial with their defaults, as `inspect` lists
/// them (`limbfuse_methods::availability`; a fresh-user audit, session 28:
/// `mjls` on a foot-only trial was sent to `local` or `global`, which fail
/// too).
fn methods_that_run(e: &limbfuse_methods::MethodError, reader: &TrialReader) -> Option<String> {
    use limbfuse_methods::availability::{availability, Availability};
    let limbfuse_methods::MethodError::MissingChannels { hint: "", .. } = e else {
        return None;
    };
    let runs: Vec<&str> = availability(reader.meta(), reader.layout())
        .into_iter()
        .filter(|(_, a)| matches!(a, Availability::Runs { .. }))
        .map(|(m, _)| m.name())
        .collect();
    let inspect = format!(
        "`limbfuse inspect {}`",
        crate::commands::shell_word(&reader.path().display().to_string())
    );
    Some(if runs.is_empty() {
        format!("no method runs on it with its defaults ({inspect} says why)")
    } else {
        format!(
            "methods that run on it: {} ({inspect} says more)",
            runs.join(", ")
        )
    })
}

/// `sdre` / `ekf` refused for want of a model: when a parameter file with
/// the trial's name and a `[model]` table lies beside the trial (the shared
/// independent-simulator FES trials ship one), a hint naming it.
fn model_file_beside(e: &limbfuse_methods::MethodError, trial: &std::path::Path) -> Option<String> {
    use limbfuse_methods::fes_params::FesBuildError;
    let limbfuse_methods::MethodError::Fes { source, .. } = e else {
        return None;
    };
    if !matches!(
        source,
        FesBuildError::UnknownModel { .. }
            | FesBuildError::NoModel { .. }
            | FesBuildError::NoModelInFile { .. }
    ) {
        return None;
    }
    limbfuse_methods::availability::model_file_hint(trial)
}

/// knee-selfalign / knee-gyro-axis: the identification window in samples
/// at the trial's rate (`limbfuse_methods::knee_window`); 0 for other methods.
pub fn knee_window(spec: &MethodSpec, reader: &TrialReader) -> Result<usize> {
    limbfuse_methods::knee_window::identification_window(spec, reader.meta())
        .with_context(|| reader.path().display().to_string())
}

/// imm-bslip: the slowest and fastest gait of the library as used on the
/// trial `reader` reads (rescaled to its body); `None` for other methods.
pub fn library_speed_range(spec: &MethodSpec, reader: &TrialReader) -> Result<Option<(f64, f64)>> {
    let MethodSpec::ImmBslip(s) = spec else {
        return Ok(None);
    };
    let range = limbfuse_methods::imm_params::library_speed_range(s, reader.meta())
        .with_context(|| reader.path().display().to_string())?;
    Ok(Some(range))
}

/// imm-bslip: says on stderr when the library was rescaled to the trial's
/// body (issue 19); lowback-speed: where the pendulum length came from; sdre / ekf: the states and the lever arm a file that
/// states `t_a` without `[states]` gets (issue 16).
pub fn report_body(spec: &MethodSpec, reader: &TrialReader) -> Result<()> {
    let label = reader.path().display().to_string();
    if let Some(note) = limbfuse_methods::raw_frame_note(spec.method(), reader.meta(), &label) {
        eprintln!("{note}");
    }
    if let Some(w) =
        limbfuse_methods::leg_length_keys::conflict_warning(spec.method(), reader.meta(), &label)
    {
        eprintln!("{w}");
    }
    if let MethodSpec::Sdre(f) | MethodSpec::Ekf(f) = spec {
        let from_lines = limbfuse_methods::fes_param_lines::model_from_param_lines(reader.meta())
            .with_context(|| reader.path().display().to_string())?;
        if from_lines.is_some_and(|m| m.keys().any(|k| !f.model.contains_key(k))) {
            eprintln!(
                "{}: the knee-fes model from the trial's `# param_*` lines (docs/FES_ESTIMATION.md, \
                 \"Trials of other simulators\"; a parameter file's [model] keys win)",
                spec.method()
            );
        }
        let note = f
            .plant_as_stated_note(spec.method(), reader.meta())
            .with_context(|| reader.path().display().to_string())?;
        if let Some(note) = note {
            eprintln!("{note}");
        }
    }
    if let MethodSpec::KneeKinematic(f) = spec {
        let note = f
            .kinematic_note(reader.meta())
            .with_context(|| reader.path().display().to_string())?;
        if let Some(note) = note {
            eprintln!("{note}");
        }
    }
    if let MethodSpec::LowbackSpeed(s) = spec {
        let note = limbfuse_methods::lowback_method::pendulum_note(s, reader.meta())
            .with_context(|| reader.path().display().to_string())?;
        if let Some(note) = note {
            eprintln!("{note}");
        }
        // (session 48: a trial without the trunk gyroscope gave no side
        // and no turn rule, and nothing said why)
        if !reader.layout().gyr[limbfuse_core::Segment::Trunk.index()] {
            eprintln!(
                "lowback-speed: {} has no trunk gyroscope (trunk_gyr_x/y/z): the gravity mean does not \
                 follow the trunk's turns, turning strides are not told apart (each gets a speed) and \
                 no contact gets its foot (docs/GAIT_EVENTS.md, lowback-speed items 1, 5 and 7)",
                reader.path().display()
            );
        }
    }
    if let MethodSpec::ImmBslip(s) = spec {
        let (_, note) = limbfuse_methods::imm_params::templates_for_trial(s, reader.meta())
            .with_context(|| reader.path().display().to_string())?;
        if let Some(note) = note {
            eprintln!("{note}");
        }
    }
    Ok(())
}
