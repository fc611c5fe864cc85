//! `tune`: the noise parameters of `local`, `mjls` or `global` tuned on a
//! window of a trial with reference angles (`limbfuse tune`, paper 001's
//! protocol: particle swarm, multi-start scoring, a held-out validation
//! window; `limbfuse_workflows::tune_validate`).

use std::path::{Path, PathBuf};

use limbfuse_eval::TimeWindow;
use limbfuse_methods::segment_params::{
    load_params, parse_params, to_toml, FilterMethod, FilterParams, Preset,
};
use limbfuse_methods::MethodName;
use limbfuse_workflows::protocol::{StartPlan, MAX_STARTS};
use limbfuse_workflows::tune_validate::{span, tune_and_validate, TuneValidateConfig, Validation};
use limbfuse_workflows::tuning::TuneConfig;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::interrupt::detach;
use crate::options::toml_text;
use crate::trial::TrialArgs;
use crate::workflows::polled;
use crate::{chain_message, guarded, user_error, user_msg};

/// The start parameters: a preset, or `params` (a file path, a file's
/// text, or a dict), as `estimate` takes them.
fn start_params(
    method: FilterMethod,
    params: Option<&Bound<'_, PyAny>>,
    preset: &str,
) -> PyResult<FilterParams> {
    let parsed = match params.filter(|p| !p.is_none()) {
        None => {
            let preset = Preset::from_name(preset).ok_or_else(|| {
                user_msg(format!(
                    "tune: preset: expected \"default\" or \"paper-2014\", found {preset:?}"
                ))
            })?;
            return Ok(FilterParams::preset(method, preset));
        }
        Some(p) if p.is_instance_of::<PyDict>() => {
            let text = toml_text(p.downcast::<PyDict>()?)?;
            parse_params(&text, Path::new("<params dict>"), method)
        }
        Some(p) if p.is_instance_of::<PyString>() && p.extract::<String>()?.contains('\n') => {
            parse_params(&p.extract::<String>()?, Path::new("<params text>"), method)
        }
        Some(p) => {
            let path: PathBuf = p.extract().map_err(|_| {
                user_msg(
                    "tune: params: expected None, a parameter file path, a parameter file's text \
                     or a dict of parameters",
                )
            })?;
            load_params(&path, method)
        }
    };
    parsed.map_err(|e| user_error(&e))
}

/// The options of the swarm given for `sdre` / `ekf`, which have none.
fn optimiser_options_message(name: MethodName, ignored: &[&str]) -> String {
    format!(
        "tune: method `{name}`: {} {} to local, mjls and global only; sdre and ekf choose the \
         torque error among fixed candidates by leave-one-pulse-out cross-validation within the \
         window (docs/FES_ESTIMATION.md)",
        ignored.join(", "),
        if ignored.len() == 1 {
            "applies"
        } else {
            "apply"
        }
    )
}

/// Tunes `method`'s noise parameters on `window` of `trial` (`limbfuse
/// tune`); returns the parameter file's text, the RMSE table, the windows
/// and the validation warnings.
#[pyfunction]
#[pyo3(signature = (trial, method, window, params=None, preset="default", validate=None, seed=1, budget=400, particles=20, starts=50, length=None))]
#[allow(clippy::too_many_arguments)]
fn tune<'py>(
    py: Python<'py>,
    trial: TrialArgs<'py>,
    method: &str,
    window: &str,
    params: Option<&Bound<'py, PyAny>>,
    preset: &str,
    validate: Option<&str>,
    seed: u64,
    budget: usize,
    particles: usize,
    starts: usize,
    length: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    guarded(|| {
        let name = MethodName::parse(method).map_err(|e| user_error(&e))?;
        if matches!(name, MethodName::Sdre | MethodName::Ekf) {
            let ignored: Vec<&str> = [
                ("preset", preset != "default"),
                ("validate", validate.is_some()),
                ("seed", seed != 1),
                ("budget", budget != 400),
                ("particles", particles != 20),
                ("starts", starts != 50),
                ("length", length.is_some()),
            ]
            .into_iter()
            .filter_map(|(k, given)| given.then_some(k))
            .collect();
            if !ignored.is_empty() {
                return Err(user_msg(optimiser_options_message(name, &ignored)));
            }
            let d = crate::tune_fes::tune_fes(py, &trial, name, window, params)?;
            d.set_item("warnings", Vec::<String>::new())?;
            return Ok(d);
        }
        let Some(fm) = FilterMethod::from_method(name) else {
            return Err(user_msg(format!(
                "tune: method `{name}` has no tunable parameters; tune supports local, mjls and \
                 global (their noise parameters) and sdre and ekf (the extended knee model's \
                 torque error)"
            )));
        };
        let start = start_params(fm, params, preset)?;
        let plan_window =
            TimeWindow::parse(window).map_err(|m| user_msg(format!("tune: window: {m}")))?;
        if starts == 0 || starts > MAX_STARTS {
            return Err(user_msg(format!(
                "tune: starts = {starts}: expected 1 to {MAX_STARTS} starting points"
            )));
        }
        if !(2..=10_000).contains(&particles) {
            return Err(user_msg(format!(
                "tune: particles = {particles}: expected a swarm of 2 to 10000 particles"
            )));
        }
        if budget < 2 * particles || budget > 10_000_000 {
            return Err(user_msg(format!(
                "tune: budget = {budget}: expected at least two generations of the swarm (2 x \
                 particles {particles} = {} evaluations) and at most 10000000 evaluations",
                2 * particles
            )));
        }
        let validation = match validate {
            Some("none") => Validation::None,
            Some(w) => Validation::Window(
                TimeWindow::parse(w).map_err(|m| user_msg(format!("tune: validate: {m}")))?,
            ),
            None => Validation::FollowingBlock,
        };
        let cols = trial.columns()?;
        let label = trial.label();
        if !cols.layout().has_angle_reference() {
            return Err(user_msg(format!(
                "{label}: the trial has no reference angle column (`thigh_ref`, `knee_ref`, ...), \
                 so there is nothing to tune against"
            )));
        }
        let records = detach(py, || polled(cols.records()))?;
        let cfg = TuneValidateConfig {
            start,
            plan: StartPlan {
                window: plan_window,
                starts,
                length_s: length,
            },
            validation,
            tune: TuneConfig {
                seed,
                budget,
                particles,
                cancel: Some(crate::interrupt::cancelled),
            },
        };
        let r = detach(py, || tune_and_validate(&records, &cfg, &|| ()))?.map_err(|e| {
            user_msg(format!(
                "tuning {} on {label}: {}",
                fm.name(),
                chain_message(&e)
            ))
        })?;
        let mut header = vec![format!(
            "tuned by: limbfuse.tune({label}, \"{}\", window=\"{window}\", seed={seed}, \
             budget={budget}, particles={particles}, starts={starts}{}{}{})",
            fm.name(),
            match params.filter(|p| !p.is_none()) {
                Some(_) => ", params=...".to_string(),
                None => format!(", preset=\"{preset}\""),
            },
            length.map_or(String::new(), |l| format!(", length={l}")),
            validate.map_or(String::new(), |v| format!(", validate=\"{v}\"")),
        )];
        header.extend(r.provenance());
        let d = PyDict::new(py);
        d.set_item("params", to_toml(&r.params, &header))?;
        d.set_item("method", fm.name())?;
        d.set_item("dims", r.dims)?;
        d.set_item("evaluations", r.evaluations)?;
        d.set_item("tuning_window", span(&r.tuning))?;
        d.set_item("validation_window", r.validation.as_deref().map(span))?;
        d.set_item("table", r.table())?;
        let mean =
            |m: &limbfuse_workflows::protocol::MultiStartResult| m.mean_rmse().map(f64::to_degrees);
        let [tb, ta] = &r.tuning_before_after;
        d.set_item("tuning_rmse_deg", (mean(tb), mean(ta)))?;
        d.set_item(
            "validation_rmse_deg",
            r.validation_before_after
                .as_ref()
                .map(|[vb, va]| (mean(vb), mean(va))),
        )?;
        d.set_item(
            "warnings",
            r.validation_warnings("they are returned as asked", "window"),
        )?;
        Ok(d)
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(tune, m)?)?;
    Ok(())
}
