//! Building the paper 004 estimators (`sdre`, `ekf`, `rmx`) for a trial:
//! the model comes from the trial's metadata (`# model: knee-fes` with
//! `# subject: P1-L`, or `# model: fixed-hip`, then any `# param.NAME:
//! value` overrides, as the simulators write them), optionally overridden
//! by a TOML file:
//!
//! ```toml
//! [model]          # same names as the param.* metadata keys
//! inertia = 0.45
//! [tuning]         # sdre / ekf: diagonals of Q, S, P0; gain a; RK4 sub-step
//! q = [1e-4, 5.0]
//! s = [1e-4, 1.0]
//! a = 1.0
//! p0 = [0.01, 0.01]
//! max_substep = 0.002
//! [rmx]            # Mahony gains
//! kp = 0.5
//! ki = 0.0
//! ```
//!
//! A model that needs a stimulation or motor channel the trial lacks, an
//! unphysical parameter, an unknown key: typed errors naming the problem.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use limbfuse_core::Estimator;
use limbfuse_estimators::fes::continuous::ContinuousTuning;
use limbfuse_estimators::fes::knee::knee_default_tuning;
use limbfuse_estimators::fes::mahony::MahonyGains;
use limbfuse_estimators::fes::{FesFilter, KneePlant, Linearisation, RotationMatrixKnee};
use limbfuse_io::{TrialLayout, TrialMeta};
use limbfuse_models::{
    FixedHipModel, FixedHipParams, KneeFesModel, KneeFesParams, KneeSubject, ModelError,
    FIXED_HIP_T_A,
};
use nalgebra::SVector;
use serde::Deserialize;

use crate::fes_extended::{
    build_extended_knee, build_kinematic, knee_model_from_file, MeasurementFile, StatesFile,
};
use crate::fes_fixed_hip::{build_fixed_hip, set_hip_param};
use crate::segment_params::ParamsFileError;
use crate::MethodName;

/// Why an FES estimator could not be built for a trial.
#[derive(Debug, thiserror::Error)]
pub enum FesBuildError {
    /// The trial does not say which model it follows.
    #[error("the trial has no `# model:` metadata line; `{method}` needs a model: `# model: knee-fes` (with `# subject: P1-L` ... `P3-R`) or `# model: fixed-hip` (`limbfuse simulate knee-fes|fixed-hip` writes them)")]
    NoModel {
        /// Method name.
        method: MethodName,
    },
    /// `# model:` names no limbfuse model and the parameter file does not
    /// give a whole knee model in its place.
    #[error("the trial's `# model:` line is `{found}`, which is not a limbfuse model (knee-fes, fixed-hip); to run it, give the whole knee-fes model in the parameter file's [model] table (--params), which then stands for it (missing keys: {missing})")]
    UnknownModel {
        /// The metadata value.
        found: String,
        /// `[model]` keys the parameter file lacks for the rule.
        missing: String,
    },
    /// No `# model:` line and the parameter file's `[model]` is incomplete.
    #[error("the trial has no `# model:` metadata line and the parameter file's [model] does not give the whole knee-fes model (missing keys: {missing})")]
    NoModelInFile {
        /// `[model]` keys the parameter file lacks.
        missing: String,
    },
    /// The extended knee model cannot be built.
    #[error(transparent)]
    Extended(#[from] limbfuse_models::ExtendedKneeError),
    /// An option that applies to another model or method.
    #[error("{path}: {what}")]
    NotApplicable {
        /// The parameter file.
        path: String,
        /// What does not apply, and to what it does.
        what: String,
    },
    /// `# subject:` names an unknown leg.
    #[error("unknown subject `{0}`; known: P1-L, P1-R, P2-L, P2-R, P3-L, P3-R")]
    UnknownSubject(String),
    /// A parameter value is not a number.
    #[error("{source_name}: parameter `{key}` = `{value}` is not a number")]
    NotANumber {
        /// Where the value came from (metadata or the TOML file).
        source_name: String,
        /// Key.
        key: String,
        /// Offending text.
        value: String,
    },
    /// An unknown parameter key.
    #[error("{source_name}: unknown parameter `{key}` for model {model}")]
    UnknownKey {
        /// Where the key came from.
        source_name: String,
        /// Key.
        key: String,
        /// Model name.
        model: &'static str,
    },
    /// A channel the model needs is not in the trial.
    #[error("the {model} model needs the column `{column}`, which the trial does not have")]
    MissingChannel {
        /// Model name.
        model: &'static str,
        /// Column name.
        column: &'static str,
    },
    /// The parameters are unphysical.
    #[error("unphysical model parameters: {0}")]
    Model(#[from] ModelError),
    /// An unphysical parameter and where its value came from (the parameter
    /// file or the trial's metadata line; an audit: the message named only
    /// the trial when the file's value was wrong).
    #[error("{source_name}: unphysical model parameters: {error}")]
    ModelFrom {
        /// The file, or the trial's metadata line, that gave the value.
        source_name: String,
        /// What is wrong.
        error: ModelError,
    },
    /// A value of the parameter file is out of range.
    #[error("{}: {message}", path.display())]
    File {
        /// File path.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

/// The model a trial follows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FesModel {
    /// Leg-extension machine (2 states); thigh angle of the seat (rad).
    Knee(KneeFesParams, f64),
    /// Fixed hip (4 states) and its activation time constant `T_a` (s;
    /// used when the activation states are on, issue 16).
    FixedHip(FixedHipParams, f64),
}

/// `v` as a finite number, or the error naming `source` and `key`.
pub(crate) fn number(source: &str, key: &str, v: &str) -> Result<f64, FesBuildError> {
    v.trim()
        .parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| FesBuildError::NotANumber {
            source_name: source.to_string(),
            key: key.to_string(),
            value: v.to_string(),
        })
}

/// Sets one knee parameter by name; `false` for an unknown name.
pub fn set_knee_param(p: &mut KneeFesParams, key: &str, v: f64) -> bool {
    match key {
        "inertia" => p.inertia = v,
        "mass" => p.mass = v,
        "l_c" => p.l_c = v,
        "g" => p.g = v,
        "phi0" => p.phi0 = v,
        "theta_eq" => p.theta_eq = v,
        "t_a" => p.t_a = v,
        "i_threshold_ma" => p.i_threshold_ma = v,
        "i_saturation_ma" => p.i_saturation_ma = v,
        "d1" | "d2" | "d3" | "d4" | "d5" | "d6" => {
            p.d[(key.as_bytes()[1] - b'1') as usize] = v;
        }
        "c0" | "c1" | "c2" | "c3" => p.c[(key.as_bytes()[1] - b'0') as usize] = v,
        _ => return false,
    }
    true
}

impl FesModel {
    /// The model of a trial's metadata (preset + `param.*` overrides).
    pub fn from_meta(meta: &TrialMeta, method: MethodName) -> Result<Self, FesBuildError> {
        let name = meta.get("model").ok_or(FesBuildError::NoModel { method })?;
        let mut m = match name.trim() {
            "knee-fes" => {
                let subject = meta.get("subject").unwrap_or("P1-L").trim();
                let s = KneeSubject::parse(subject)
                    .ok_or_else(|| FesBuildError::UnknownSubject(subject.to_string()))?;
                let thigh = match meta.get("thigh_angle_rad") {
                    Some(v) => number("metadata", "thigh_angle_rad", v)?,
                    None => core::f64::consts::FRAC_PI_2,
                };
                FesModel::Knee(KneeFesParams::subject(s), thigh)
            }
            "fixed-hip" => FesModel::FixedHip(FixedHipParams::default(), FIXED_HIP_T_A),
            other => {
                return Err(FesBuildError::UnknownModel {
                    found: other.to_string(),
                    missing: "all".to_string(),
                })
            }
        };
        for (k, v) in meta.entries() {
            if let Some(key) = k.strip_prefix("param.") {
                m.set("metadata", key, number("metadata", k, v)?)?;
            }
        }
        Ok(m)
    }

    /// Sets a parameter by name.
    pub fn set(&mut self, source: &str, key: &str, v: f64) -> Result<(), FesBuildError> {
        let (ok, model) = match self {
            FesModel::Knee(p, _) => (set_knee_param(p, key, v), "knee-fes"),
            FesModel::FixedHip(p, t_a) => (set_hip_param(p, t_a, key, v), "fixed-hip"),
        };
        if ok {
            Ok(())
        } else {
            Err(FesBuildError::UnknownKey {
                source_name: source.to_string(),
                key: key.to_string(),
                model,
            })
        }
    }

    /// Model name.
    pub fn name(&self) -> &'static str {
        match self {
            FesModel::Knee(..) => "knee-fes",
            FesModel::FixedHip(..) => "fixed-hip",
        }
    }

    /// Checks that the trial has every input column the model needs.
    pub fn check_layout(&self, layout: &TrialLayout) -> Result<(), FesBuildError> {
        let model = self.name();
        let need: &[(bool, &'static str)] = match self {
            FesModel::Knee(..) => &[(layout.stim[0], "u_ke")],
            FesModel::FixedHip(..) => &[
                (layout.stim[3], "u_hf"),
                (layout.stim[2], "u_he"),
                (layout.stim[1], "u_kf"),
                (layout.stim[0], "u_ke"),
                (layout.motor_torque[0], "tau_hip_motor"),
                (layout.motor_torque[1], "tau_knee_motor"),
            ],
        };
        for (present, column) in need {
            if !present {
                return Err(FesBuildError::MissingChannel { model, column });
            }
        }
        Ok(())
    }
}

/// Which paper-004 estimator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FesMethod {
    /// `sdre`: SDC linearisation (eqs 4.14-4.16).
    Sdre,
    /// `ekf`: Jacobian linearisation.
    Ekf,
    /// `rmx`: relative orientation of two Mahony filters.
    Rmx,
    /// `knee-kinematic`: model-free EKF with sensor-bias states (issue 16).
    KneeKinematic,
}

impl FesMethod {
    /// The method this is.
    pub const fn method(self) -> MethodName {
        match self {
            FesMethod::Sdre => MethodName::Sdre,
            FesMethod::Ekf => MethodName::Ekf,
            FesMethod::Rmx => MethodName::Rmx,
            FesMethod::KneeKinematic => MethodName::KneeKinematic,
        }
    }

    /// The paper-004 estimator `method` is, if it is one.
    pub const fn from_method(method: MethodName) -> Option<Self> {
        match method {
            MethodName::Sdre => Some(FesMethod::Sdre),
            MethodName::Ekf => Some(FesMethod::Ekf),
            MethodName::Rmx => Some(FesMethod::Rmx),
            MethodName::KneeKinematic => Some(FesMethod::KneeKinematic),
            _ => None,
        }
    }
}

/// A number or a list of numbers (`q = 1e-4` or `q = [1e-4, 5.0]`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(untagged)]
enum Numbers {
    One(f64),
    Many(Vec<f64>),
}

impl Numbers {
    fn values(&self) -> Vec<f64> {
        match self {
            Numbers::One(x) => vec![*x],
            Numbers::Many(v) => v.clone(),
        }
    }
}

/// `[tuning]` of an FES parameter file: diagonals of Q, S, P0, the gain a
/// and the RK4 sub-step (docs/FES_ESTIMATION.md).
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FesTuningFile {
    q: Option<Numbers>,
    s: Option<Numbers>,
    a: Option<Numbers>,
    p0: Option<Numbers>,
    max_substep: Option<Numbers>,
    /// Relative torque error `e` of the extended knee model's default
    /// tuning (the filter admits a torque error of `e m g l_c`;
    /// docs/FES_ESTIMATION.md): what `limbfuse tune --method sdre|ekf`
    /// chooses. Extended knee model only.
    pub(crate) torque_error: Option<f64>,
}

/// `[rmx]` of an FES parameter file: the Mahony gains.
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RmxFile {
    /// Proportional gain (1/s).
    pub kp: Option<f64>,
    /// Integral gain (1/s^2).
    pub ki: Option<f64>,
}

/// A parameter file of `sdre`, `ekf` or `rmx` (typed, unknown keys are
/// errors with line and column; model keys are checked against the trial's
/// model when the estimator is built).
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FesParamsFile {
    /// Optional; must match `--method` when present.
    pub method: Option<MethodName>,
    /// Model parameter overrides, same names as the `param.*` metadata keys.
    #[serde(default)]
    pub model: BTreeMap<String, f64>,
    /// Filter tuning of `sdre` / `ekf`.
    #[serde(default)]
    pub tuning: FesTuningFile,
    /// Gains of `rmx`.
    #[serde(default)]
    pub rmx: RmxFile,
    /// Optional states of the knee model (issue 16; `sdre` / `ekf`);
    /// `None` when the file has no `[states]` table (then `[model] t_a`
    /// decides: [`FesParamsFile::state_options`]).
    #[serde(default)]
    pub states: Option<StatesFile>,
    /// Shank accelerometer lever arm (`sdre` / `ekf` / `knee-kinematic`).
    #[serde(default)]
    pub measurement: MeasurementFile,
    /// The file the values came from (`-` for none), for messages.
    #[serde(skip)]
    pub path: PathBuf,
}

impl FesParamsFile {
    /// No overrides.
    pub fn none() -> Self {
        FesParamsFile {
            path: PathBuf::from("-"),
            ..Default::default()
        }
    }

    /// Parses a file's text; `path` names it in errors.
    pub fn parse(text: &str, path: &Path) -> Result<Self, ParamsFileError> {
        let mut f: FesParamsFile = crate::params_toml::from_str(text, path)?;
        f.path = path.to_path_buf();
        if let Some((k, v)) = f.model.iter().find(|(_, v)| !v.is_finite()) {
            return Err(ParamsFileError::Invalid {
                path: path.to_path_buf(),
                message: format!("[model] `{k}` must be a finite number, found {v}"),
            });
        }
        if let Some(e) = f
            .tuning
            .torque_error
            .filter(|e| !(e.is_finite() && *e > 0.0))
        {
            return Err(ParamsFileError::Invalid {
                path: path.to_path_buf(),
                message: format!("[tuning] `torque_error` must be a finite number > 0, found {e}"),
            });
        }
        // Mahony gains (issue 18 fuzzing: `kp = nan` gave a NaN knee angle).
        for (k, v) in [("kp", f.rmx.kp), ("ki", f.rmx.ki)] {
            if let Some(v) = v.filter(|v| !(v.is_finite() && *v >= 0.0)) {
                return Err(ParamsFileError::Invalid {
                    path: path.to_path_buf(),
                    message: format!("[rmx] `{k}` must be a finite number >= 0, found {v}"),
                });
            }
        }
        Ok(f)
    }

    fn tuning_entries(&self) -> Vec<(&'static str, Vec<f64>)> {
        let t = &self.tuning;
        [
            ("q", &t.q),
            ("s", &t.s),
            ("a", &t.a),
            ("p0", &t.p0),
            ("max_substep", &t.max_substep),
        ]
        .into_iter()
        .filter_map(|(k, v)| v.as_ref().map(|v| (k, v.values())))
        .collect()
    }
}

/// Applies `[tuning]` overrides to `t` (lengths and ranges checked).
pub(crate) fn apply_tuning<const N: usize, const M: usize>(
    t: &mut ContinuousTuning<N, M>,
    o: &[(&'static str, Vec<f64>)],
    path: &Path,
) -> Result<(), FesBuildError> {
    let err = |message: String| FesBuildError::File {
        path: path.to_path_buf(),
        message,
    };
    let vector = |key: &str, v: &[f64], n: usize| -> Result<(), FesBuildError> {
        if v.len() != n {
            return Err(err(format!(
                "[tuning] {key} needs {n} values, found {}",
                v.len()
            )));
        }
        if v.iter().any(|x| *x < 0.0) {
            return Err(err(format!("[tuning] {key} must be >= 0")));
        }
        Ok(())
    };
    for (key, v) in o {
        if v.iter().any(|x| !x.is_finite()) {
            return Err(err(format!("[tuning] {key} must be finite")));
        }
        match *key {
            "q" => {
                vector(key, v, N)?;
                t.q = SVector::from_column_slice(v);
            }
            "s" => {
                vector(key, v, M)?;
                if v.iter().any(|x| *x <= 0.0) {
                    return Err(err("[tuning] s must be > 0 (it is inverted)".into()));
                }
                t.s = SVector::from_column_slice(v);
            }
            "p0" => {
                vector(key, v, N)?;
                t.p0 = SVector::from_column_slice(v);
            }
            "a" => {
                vector(key, v, 1)?;
                t.a = v[0];
            }
            "max_substep" => {
                vector(key, v, 1)?;
                if !(v[0] > 0.0 && v[0] <= 0.1) {
                    return Err(err("[tuning] max_substep must be in (0, 0.1] s".into()));
                }
                t.max_substep = v[0];
            }
            _ => unreachable!("FesTuningFile has exactly these keys"),
        }
    }
    Ok(())
}

/// Builds `sdre`, `ekf` or `rmx` for a trial with the given metadata and
/// layout, with the overrides of a parameter file.
pub fn build_fes_estimator(
    method: FesMethod,
    meta: &TrialMeta,
    layout: &TrialLayout,
    file: &FesParamsFile,
) -> Result<Box<dyn Estimator + Send>, FesBuildError> {
    build_unlocated(method, meta, layout, file).map_err(|e| match e {
        FesBuildError::Model(error) => FesBuildError::ModelFrom {
            source_name: model_value_source(error.name(), meta, file),
            error,
        },
        e => e,
    })
}

/// Where the model's value `key` came from: the parameter file's `[model]`,
/// else the trial's `# param.KEY:` or `# param_*:` line, else the subject's
/// preset.
fn model_value_source(key: &str, meta: &TrialMeta, file: &FesParamsFile) -> String {
    if file.model.contains_key(key) {
        return format!("{} [model] `{key}`", file.path.display());
    }
    let dotted = format!("param.{key}");
    let line = crate::fes_param_lines::PARAM_LINE_KEYS
        .iter()
        .find(|(_, k)| *k == key)
        .map(|(line, _)| *line)
        .filter(|line| meta.get(line).is_some())
        .or_else(|| meta.get(&dotted).map(|_| dotted.as_str()));
    match line {
        Some(line) => format!("the trial's `# {line}:` line"),
        None => format!("the model's preset `{key}`"),
    }
}

fn build_unlocated(
    method: FesMethod,
    meta: &TrialMeta,
    layout: &TrialLayout,
    file: &FesParamsFile,
) -> Result<Box<dyn Estimator + Send>, FesBuildError> {
    // A free-text `# model:` whose `# param_*` lines state the whole model
    // (the independent FES simulator's trials): as if given in the file.
    let file = &*file.for_trial(meta)?;
    let path = file.path.as_path();
    let lin = match method {
        FesMethod::Rmx => {
            let mut g = MahonyGains::default();
            if let Some(kp) = file.rmx.kp {
                g.kp = kp;
            }
            if let Some(ki) = file.rmx.ki {
                g.ki = ki;
            }
            return Ok(Box::new(RotationMatrixKnee::with_gains(g)));
        }
        FesMethod::KneeKinematic => {
            let r = file.kinematic_lever_arm(meta)?.radius;
            return build_kinematic(meta, r, &file.tuning_entries(), path);
        }
        FesMethod::Sdre => Linearisation::Sdc,
        FesMethod::Ekf => Linearisation::Jacobian,
    };
    let mut model = match FesModel::from_meta(meta, method.method()) {
        Ok(m) => m,
        // A free-text or absent `# model:` line: the parameter file may give
        // the whole knee model instead (docs/FES_ESTIMATION.md).
        Err(FesBuildError::NoModel { .. }) => {
            let (p, thigh) = knee_model_from_file(&file.model, meta, None)?;
            FesModel::Knee(p, thigh)
        }
        Err(FesBuildError::UnknownModel { found, .. }) => {
            let (p, thigh) = knee_model_from_file(&file.model, meta, Some(&found))?;
            FesModel::Knee(p, thigh)
        }
        Err(e) => return Err(e),
    };
    let source = path.display().to_string();
    for (k, v) in &file.model {
        model.set(&source, k, *v)?;
    }
    model.check_layout(layout)?;
    let tuning = file.tuning_entries();
    let opts = file.state_options();
    let extended = file.is_extended();
    if !extended && file.tuning.torque_error.is_some() && matches!(model, FesModel::Knee(..)) {
        return Err(FesBuildError::NotApplicable {
            path: source,
            what: "[tuning] torque_error applies to the extended knee model only (a file with [states] or [measurement])".into(),
        });
    }
    Ok(match model {
        FesModel::FixedHip(p, t_a) => {
            build_fixed_hip(FixedHipModel::new(p)?, t_a, file, lin, &tuning)?
        }
        FesModel::Knee(p, thigh) if extended => build_extended_knee(
            KneeFesModel::new(p)?,
            thigh,
            (opts, file.lever_arm(meta)?),
            (lin, file.tuning.torque_error),
            &tuning,
            path,
        )?,
        FesModel::Knee(p, thigh) => {
            let mut t = knee_default_tuning(lin);
            apply_tuning(&mut t, &tuning, path)?;
            let mut plant = KneePlant::new(KneeFesModel::new(p)?);
            plant.thigh_angle = thigh;
            Box::new(FesFilter::new(plant, lin, t))
        }
    })
}
