//! `tune` for `sdre` and `ekf` (`limbfuse tune --method sdre|ekf`,
//! `limbfuse_workflows::fes_torque_tuning`): the extended knee model's
//! torque error chosen by leave-one-pulse-out cross-validation on a
//! pre-trial with a knee reference.

use std::path::{Path, PathBuf};

use limbfuse_eval::TimeWindow;
use limbfuse_methods::{MethodFlags, MethodName, MethodSpec};
use limbfuse_workflows::fes_torque_tuning::{
    tune_torque_error, with_torque_error, TorqueTuningError, TORQUE_ERRORS,
};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::interrupt::detach;
use crate::options::{python_spelling, toml_text};
use crate::trial::TrialArgs;
use crate::workflows::polled;
use crate::{chain_message, user_msg};

/// The knee model: its parameter file's text and the resolved spec.
fn model(name: MethodName, params: Option<&Bound<'_, PyAny>>) -> PyResult<(String, MethodSpec)> {
    let flags = MethodFlags::default();
    let (text, spec) = match params.filter(|p| !p.is_none()) {
        None => {
            return Err(user_msg(format!(
                "tune: method `{name}`: give the knee model's parameters with `params` (a file, \
                 its text or a dict), with [states] (e.g. activation, gyro_bias, acc_bias) or \
                 [measurement]: the torque error tuned here belongs to the extended knee model \
                 (docs/FES_ESTIMATION.md)"
            )))
        }
        Some(p) if p.is_instance_of::<PyDict>() => {
            let text = toml_text(p.downcast::<PyDict>()?)?;
            let spec =
                MethodSpec::from_parts(name, Some((&text, Path::new("<params dict>"))), &flags);
            (text, spec)
        }
        Some(p) if p.is_instance_of::<PyString>() && p.extract::<String>()?.contains('\n') => {
            let text: String = p.extract()?;
            let spec =
                MethodSpec::from_parts(name, Some((&text, Path::new("<params text>"))), &flags);
            (text, spec)
        }
        Some(p) => {
            let path: PathBuf = p.extract().map_err(|_| {
                user_msg(
                    "tune: params: expected a parameter file path, a parameter file's text or a \
                     dict of parameters",
                )
            })?;
            let spec = MethodSpec::resolve(name, Some(&path), &flags);
            let text = std::fs::read_to_string(&path).map_err(|e| {
                user_msg(format!(
                    "{}: cannot read the parameter file: {e}",
                    path.display()
                ))
            });
            // (the spec's error first: it names a missing file as the CLI does)
            let spec = spec.map_err(|e| user_msg(python_spelling(&chain_message(&e))))?;
            (text?, Ok(spec))
        }
    };
    let spec = spec.map_err(|e| user_msg(python_spelling(&chain_message(&e))))?;
    Ok((text, spec))
}

/// Tunes `[tuning] torque_error` of `sdre` / `ekf` on `window` of the
/// pre-trial `trial` (the dict of Python `tune`).
pub fn tune_fes<'py>(
    py: Python<'py>,
    trial: &TrialArgs<'py>,
    name: MethodName,
    window: &str,
    params: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (text, spec) = model(name, params)?;
    let file = match spec {
        MethodSpec::Sdre(f) | MethodSpec::Ekf(f) => f,
        _ => return Err(user_msg(format!("tune: `{name}` is not a knee-FES filter"))),
    };
    let label = trial.label();
    if !file.is_extended() {
        return Err(user_msg(format!(
            "tune: params: {}",
            TorqueTuningError::NotExtended(name)
        )));
    }
    let win = TimeWindow::parse(window).map_err(|m| user_msg(format!("tune: window: {m}")))?;
    let cols = trial.columns()?;
    let meta = trial.meta();
    let records: Vec<_> = detach(py, || polled(cols.records()))?
        .into_iter()
        .filter(|r| win.contains(r.sample.t))
        .collect();
    let shown = format!("window \"{window}\"");
    let r = detach(py, || {
        tune_torque_error(
            name,
            &file,
            (&meta, cols.layout()),
            &records,
            &shown,
            &|| (),
            Some(&crate::interrupt::cancelled),
        )
    })?
    .map_err(|e| user_msg(format!("{label}: {}", python_spelling(&chain_message(&e)))))?;
    let header = format!(
        "# tuned by: limbfuse.tune({label}, \"{name}\", window=\"{window}\", params=...)\n{}",
        r.comment()
    );
    let d = PyDict::new(py);
    d.set_item("params", header + &with_torque_error(&text, r.torque_error))?;
    d.set_item("method", name.to_string())?;
    d.set_item("table", r.table(&label))?;
    d.set_item("torque_errors", TORQUE_ERRORS.to_vec())?;
    d.set_item("rmse_deg", r.rmse_deg.clone())?;
    d.set_item("torque_error", r.torque_error)?;
    d.set_item("cv_rmse_deg", r.cv_rmse_deg)?;
    d.set_item("pulse_windows", r.windows)?;
    Ok(d)
}
