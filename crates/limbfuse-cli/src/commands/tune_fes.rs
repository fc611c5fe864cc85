//! `limbfuse tune --method sdre|ekf PRETRIAL --params model.toml -o tuned.toml`
//! (issue 16 item 3): how much the extended knee filter trusts its model,
//! chosen by leave-one-pulse-out cross-validation on a pre-trial with a
//! knee reference (`limbfuse_workflows::fes_torque_tuning`, which the Python
//! `tune` calls too), never on the trial the tuned file is then used on.

use std::path::Path;

use anyhow::{anyhow, bail, Context, Result};
use limbfuse_eval::TimeWindow;
use limbfuse_methods::{MethodFlags, MethodName, MethodSpec};
use limbfuse_workflows::fes_torque_tuning::{
    tune_torque_error, with_torque_error, TorqueTuningError, TORQUE_ERRORS,
};

use crate::cli::TuneArgs;

/// Tunes `[tuning] torque_error` of `sdre` / `ekf` on the pre-trial.
pub fn run(a: &TuneArgs, name: MethodName) -> Result<()> {
    let Some(params) = a.params.as_deref() else {
        bail!(
            "tune --method {name}: give the knee model's parameter file with --params, with [states] \
             (e.g. activation, gyro_bias, acc_bias) or [measurement]: the torque error tuned here \
             belongs to the extended knee model (docs/FES_ESTIMATION.md)"
        );
    };
    let ignored = a.optimiser_flags();
    if !ignored.is_empty() {
        bail!(
            "tune --method {name}: {} {} to local, mjls and global only; sdre and ekf choose the \
             torque error among fixed candidates by leave-one-pulse-out cross-validation within \
             --window (docs/FES_ESTIMATION.md)",
            ignored.join(", "),
            if ignored.len() == 1 {
                "applies"
            } else {
                "apply"
            }
        );
    }
    let spec = MethodSpec::resolve(name, Some(params), &MethodFlags::default())?;
    let file = match &spec {
        MethodSpec::Sdre(f) | MethodSpec::Ekf(f) => f.clone(),
        _ => bail!("tune --method {name}: not a knee-FES filter"),
    };
    if !file.is_extended() {
        bail!(
            "{}: {}",
            params.display(),
            TorqueTuningError::NotExtended(name)
        );
    }
    let window = TimeWindow::parse(&a.window).map_err(|m| anyhow!("--window: {m}"))?;
    let trial = super::protocol::read_trial(&a.trial, name)?;
    let records: Vec<_> = trial
        .records
        .into_iter()
        .filter(|r| window.contains(r.sample.t))
        .collect();
    let bar = crate::progress::bar(
        TORQUE_ERRORS.len() as u64,
        "tune {prefix} {bar:30} {pos}/{len} candidates [{elapsed} < {eta}]",
    );
    bar.set_prefix(name.to_string());
    let tuned = tune_torque_error(
        name,
        &file,
        (&trial.meta, &trial.layout),
        &records,
        &format!("--window {}", a.window),
        &|| bar.inc(1),
        None,
    );
    bar.finish_and_clear();
    let tuned = tuned.map_err(|e| match e {
        TorqueTuningError::Build(e) => anyhow!(e).context(a.trial.display().to_string()),
        TorqueTuningError::AllDiverged => {
            anyhow!("{}: {e} {}", a.trial.display(), params.display())
        }
        e => anyhow!("{}: {e}", a.trial.display()),
    })?;
    let text = std::fs::read_to_string(params)
        .with_context(|| format!("{}: cannot read the parameter file", params.display()))?;
    let header = format!(
        "# tuned by: limbfuse tune --method {name} {} --window {} --params {}\n{}",
        file_name(&a.trial),
        a.window,
        file_name(params),
        tuned.comment()
    );
    super::write_file(
        &a.output,
        header + &with_torque_error(&text, tuned.torque_error),
    )?;
    print!("{}", tuned.table(&a.trial.display().to_string()));
    eprintln!("wrote {}", a.output.display());
    Ok(())
}

/// The file name of `path` (its display form if it has none).
fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}
