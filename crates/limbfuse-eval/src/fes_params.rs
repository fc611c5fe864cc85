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

use std::path::{Path, PathBuf};

use limbfuse_core::Estimator;
use limbfuse_estimators::fes::continuous::ContinuousTuning;
use limbfuse_estimators::fes::fixed_hip::fixed_hip_default_tuning;
use limbfuse_estimators::fes::knee::knee_default_tuning;
use limbfuse_estimators::fes::mahony::MahonyGains;
use limbfuse_estimators::fes::{
    FesFilter, FixedHipPlant, KneePlant, Linearisation, RotationMatrixKnee,
};
use limbfuse_io::{TrialLayout, TrialMeta};
use limbfuse_models::{
    FixedHipModel, FixedHipParams, KneeFesModel, KneeFesParams, KneeSubject, ModelError,
};
use nalgebra::SVector;

/// Why an FES estimator could not be built for a trial.
#[derive(Debug, thiserror::Error)]
pub enum FesBuildError {
    /// The trial does not say which model it follows.
    #[error("the trial has no `# model:` metadata line; `{method}` needs a model: `# model: knee-fes` (with `# subject: P1-L` ... `P3-R`) or `# model: fixed-hip` (`limbfuse simulate knee-fes|fixed-hip` writes them)")]
    NoModel {
        /// Method name.
        method: String,
    },
    /// `# model:` names an unknown model.
    #[error("unknown model `{0}` in the trial metadata; known: knee-fes, fixed-hip")]
    UnknownModel(String),
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
    /// The TOML file cannot be read or parsed.
    #[error("{path}: {message}")]
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
    /// Fixed hip (4 states).
    FixedHip(FixedHipParams),
}

fn number(source: &str, key: &str, v: &str) -> Result<f64, FesBuildError> {
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

/// Sets one fixed-hip parameter by name; `false` for an unknown name.
pub fn set_hip_param(p: &mut FixedHipParams, key: &str, v: f64) -> bool {
    match key {
        "thigh_mass" => p.thigh_mass = v,
        "thigh_length" => p.thigh_length = v,
        "thigh_com" => p.thigh_com = v,
        "thigh_inertia" => p.thigh_inertia = v,
        "leg_mass" => p.leg_mass = v,
        "leg_com" => p.leg_com = v,
        "leg_inertia" => p.leg_inertia = v,
        "g" => p.g = v,
        "hip_stiffness" => p.hip_stiffness = v,
        "hip_damping" => p.hip_damping = v,
        "knee_phi0" => p.knee_phi0 = v,
        "force_velocity" => p.force_velocity = v,
        "knee_d1" | "knee_d2" | "knee_d3" | "knee_d4" | "knee_d5" | "knee_d6" => {
            p.knee_d[(key.as_bytes()[6] - b'1') as usize] = v;
        }
        "t_hf" => p.muscle_peak[0] = v,
        "t_he" => p.muscle_peak[1] = v,
        "t_kf" => p.muscle_peak[2] = v,
        "t_ke" => p.muscle_peak[3] = v,
        _ => return false,
    }
    true
}

impl FesModel {
    /// The model of a trial's metadata (preset + `param.*` overrides).
    pub fn from_meta(meta: &TrialMeta, method: &str) -> Result<Self, FesBuildError> {
        let name = meta.get("model").ok_or_else(|| FesBuildError::NoModel {
            method: method.to_string(),
        })?;
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
            "fixed-hip" => FesModel::FixedHip(FixedHipParams::default()),
            other => return Err(FesBuildError::UnknownModel(other.to_string())),
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
            FesModel::FixedHip(p) => (set_hip_param(p, key, v), "fixed-hip"),
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
            FesModel::FixedHip(_) => "fixed-hip",
        }
    }

    /// Checks that the trial has every input column the model needs.
    pub fn check_layout(&self, layout: &TrialLayout) -> Result<(), FesBuildError> {
        let model = self.name();
        let need: &[(bool, &'static str)] = match self {
            FesModel::Knee(..) => &[(layout.stim[0], "u_ke")],
            FesModel::FixedHip(_) => &[
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

/// Overrides read from a TOML file.
#[derive(Debug, Clone, Default)]
struct Overrides {
    model: Vec<(String, f64)>,
    tuning: Vec<(String, Vec<f64>)>,
    rmx: Vec<(String, f64)>,
}

fn read_overrides(path: &Path) -> Result<Overrides, FesBuildError> {
    let file_err = |message: String| FesBuildError::File {
        path: path.to_path_buf(),
        message,
    };
    let text = std::fs::read_to_string(path).map_err(|e| file_err(format!("cannot read: {e}")))?;
    let table: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| file_err(e.to_string()))?;
    let mut o = Overrides::default();
    let num = |v: &toml::Value, key: &str| -> Result<f64, FesBuildError> {
        v.as_float()
            .or_else(|| v.as_integer().map(|i| i as f64))
            .filter(|x| x.is_finite())
            .ok_or_else(|| file_err(format!("`{key}` must be a number, found {v}")))
    };
    for (section, v) in &table {
        let t = v
            .as_table()
            .ok_or_else(|| file_err(format!("`{section}` must be a table ([{section}])")))?;
        for (key, val) in t {
            match section.as_str() {
                "model" => o.model.push((key.clone(), num(val, key)?)),
                "rmx" => o.rmx.push((key.clone(), num(val, key)?)),
                "tuning" => {
                    let list = match val.as_array() {
                        Some(a) => a
                            .iter()
                            .map(|x| num(x, key))
                            .collect::<Result<Vec<_>, _>>()?,
                        None => vec![num(val, key)?],
                    };
                    o.tuning.push((key.clone(), list));
                }
                other => {
                    return Err(file_err(format!(
                        "unknown section [{other}]; known: [model], [tuning], [rmx]"
                    )))
                }
            }
        }
    }
    Ok(o)
}

fn apply_tuning<const N: usize, const M: usize>(
    t: &mut ContinuousTuning<N, M>,
    o: &[(String, Vec<f64>)],
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
        match key.as_str() {
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
            other => {
                return Err(err(format!(
                    "unknown [tuning] key `{other}`; known: q, s, a, p0, max_substep"
                )))
            }
        }
    }
    Ok(())
}

/// Builds `sdre`, `ekf` or `rmx` for a trial with the given metadata and
/// layout, with optional TOML overrides.
pub fn build_fes_estimator(
    method: &str,
    meta: &TrialMeta,
    layout: &TrialLayout,
    params: Option<&Path>,
) -> Result<Box<dyn Estimator>, FesBuildError> {
    let o = match params {
        Some(p) => read_overrides(p)?,
        None => Overrides::default(),
    };
    let path = params.unwrap_or(Path::new("-"));
    if method == "rmx" {
        let mut g = MahonyGains::default();
        for (k, v) in &o.rmx {
            match k.as_str() {
                "kp" => g.kp = *v,
                "ki" => g.ki = *v,
                other => {
                    return Err(FesBuildError::File {
                        path: path.to_path_buf(),
                        message: format!("unknown [rmx] key `{other}`; known: kp, ki"),
                    })
                }
            }
        }
        return Ok(Box::new(RotationMatrixKnee::with_gains(g)));
    }
    let lin = if method == "sdre" {
        Linearisation::Sdc
    } else {
        Linearisation::Jacobian
    };
    let mut model = FesModel::from_meta(meta, method)?;
    let source = path.display().to_string();
    for (k, v) in &o.model {
        model.set(&source, k, *v)?;
    }
    model.check_layout(layout)?;
    Ok(match model {
        FesModel::Knee(p, thigh) => {
            let mut t = knee_default_tuning(lin);
            apply_tuning(&mut t, &o.tuning, path)?;
            let mut plant = KneePlant::new(KneeFesModel::new(p)?);
            plant.thigh_angle = thigh;
            Box::new(FesFilter::new(plant, lin, t))
        }
        FesModel::FixedHip(p) => {
            let mut t = fixed_hip_default_tuning(lin);
            apply_tuning(&mut t, &o.tuning, path)?;
            Box::new(FesFilter::new(
                FixedHipPlant {
                    model: FixedHipModel::new(p)?,
                },
                lin,
                t,
            ))
        }
    })
}
