//! Issue 16 options of the knee-FES parameter file and their builders:
//!
//! ```toml
//! [states]            # sdre / ekf on knee-fes: optional states (default all false)
//! activation = true   # a_ke' = (u_ke - a_ke) / T_a ([model] t_a)
//! disturbance = true  # unknown knee torque, a random walk
//! gyro_bias = true    # shank gyro z bias
//! acc_bias = true     # shank accelerometer x bias
//! [measurement]
//! shank_imu_m = 0.2   # accelerometer below the knee: adds r x2'' (default 0, thesis)
//! ```
//!
//! and the `knee-kinematic` estimator (model-free, same bias states), and
//! the rule that lets a trial whose `# model:` line is not a limbfuse model
//! key run with a parameter file that gives the whole knee model.
//! Equations: docs/FES_ESTIMATION.md, "Extended knee model".

use std::path::Path;

use limbfuse_core::Estimator;
use limbfuse_estimators::fes::knee_extended::{
    extended_knee_default_tuning, extended_knee_tuning, extended_shift, kinematic_default_tuning,
    ExtendedKneePlant, KinematicKneePlant,
};
use limbfuse_estimators::fes::{FesFilter, Linearisation};
use limbfuse_io::TrialMeta;
use limbfuse_models::{
    ExtendedKneeModel, KinematicKneeModel, KneeFesModel, KneeFesParams, KneeStateOptions,
    KneeSubject,
};
use serde::Deserialize;

use crate::fes_params::{apply_tuning, number, set_knee_param, FesBuildError, FesParamsFile};

/// `[states]`: the optional states of the knee model.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StatesFile {
    /// Activation state (`a_ke' = (u_ke - a_ke) / T_a`).
    pub activation: Option<bool>,
    /// Unknown knee torque (random walk).
    pub disturbance: Option<bool>,
    /// Shank gyro bias.
    pub gyro_bias: Option<bool>,
    /// Shank accelerometer bias.
    pub acc_bias: Option<bool>,
}

impl StatesFile {
    /// The options (absent keys: off).
    pub fn options(&self) -> KneeStateOptions {
        KneeStateOptions {
            activation: self.activation.unwrap_or(false),
            disturbance: self.disturbance.unwrap_or(false),
            gyro_bias: self.gyro_bias.unwrap_or(false),
            acc_bias: self.acc_bias.unwrap_or(false),
        }
    }
}

/// `[measurement]`: where the shank accelerometer is.
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeasurementFile {
    /// Distance of the shank accelerometer below the knee (m), `r` in
    /// `acc_x = g sin x1 + r x1''`; absent: 0 (the thesis's measurement).
    pub shank_imu_m: Option<f64>,
}

impl MeasurementFile {
    /// The lever arm (m), checked: finite and in [0, 1].
    pub fn radius(&self, path: &Path) -> Result<f64, FesBuildError> {
        match self.shank_imu_m {
            None => Ok(0.0),
            Some(r) if r.is_finite() && (0.0..=1.0).contains(&r) => Ok(r),
            Some(r) => Err(FesBuildError::File {
                path: path.to_path_buf(),
                message: format!(
                    "[measurement] shank_imu_m = {r}: expected the accelerometer's distance below the knee in metres, in [0, 1]"
                ),
            }),
        }
    }
}

/// Every `[model]` key of the knee-fes model (what a parameter file must
/// give to stand for a trial's free-text `# model:` line).
pub const KNEE_MODEL_KEYS: [&str; 19] = [
    "inertia",
    "mass",
    "l_c",
    "g",
    "phi0",
    "theta_eq",
    "t_a",
    "i_threshold_ma",
    "i_saturation_ma",
    "d1",
    "d2",
    "d3",
    "d4",
    "d5",
    "d6",
    "c0",
    "c1",
    "c2",
    "c3",
];

/// The knee model a parameter file gives in full, when the trial's own
/// `# model:` line is missing or not a limbfuse model key (the rule of
/// docs/FES_ESTIMATION.md "Trials of other simulators"): every key of
/// [`KNEE_MODEL_KEYS`] present in `[model]` (none left to a preset), the
/// thigh angle from `# thigh_angle_rad:` (default pi/2). `Err` names the
/// missing keys.
pub fn knee_model_from_file(
    model: &std::collections::BTreeMap<String, f64>,
    meta: &TrialMeta,
    found: Option<&str>,
) -> Result<(KneeFesParams, f64), FesBuildError> {
    let missing: Vec<&str> = KNEE_MODEL_KEYS
        .iter()
        .copied()
        .filter(|k| !model.contains_key(*k))
        .collect();
    if !missing.is_empty() {
        return Err(match found {
            None => FesBuildError::NoModelInFile {
                missing: missing.join(", "),
            },
            Some(f) => FesBuildError::UnknownModel {
                found: f.to_string(),
                missing: missing.join(", "),
            },
        });
    }
    let mut p = KneeFesParams::subject(KneeSubject::P1L);
    for (k, v) in model {
        if !set_knee_param(&mut p, k, *v) {
            return Err(FesBuildError::UnknownKey {
                source_name: "parameter file".into(),
                key: k.clone(),
                model: "knee-fes",
            });
        }
    }
    let thigh = meta_number(meta, "thigh_angle_rad", core::f64::consts::FRAC_PI_2)?;
    Ok((p, thigh))
}

/// Metadata value `key` as a finite number, `default` when absent.
fn meta_number(meta: &TrialMeta, key: &str, default: f64) -> Result<f64, FesBuildError> {
    meta.get(key)
        .map_or(Ok(default), |v| number("metadata", key, v))
}

fn extended<const N: usize>(
    base: KneeFesModel,
    thigh: f64,
    opts: KneeStateOptions,
    r: f64,
    (lin, torque_error): (Linearisation, Option<f64>),
    tuning: &[(&'static str, Vec<f64>)],
    path: &Path,
) -> Result<Box<dyn Estimator + Send>, FesBuildError> {
    let model = ExtendedKneeModel::<N>::new(base, opts, r)?;
    let mut t = match torque_error {
        Some(e) => extended_knee_tuning(&model, lin, e),
        None => extended_knee_default_tuning(&model, lin),
    };
    apply_tuning(&mut t, tuning, path)?;
    // The per-state shift follows a `[tuning] a` override.
    t.a_states = Some(extended_shift(&model, t.a));
    let mut plant = ExtendedKneePlant::new(model);
    plant.thigh_angle = thigh;
    Ok(Box::new(FesFilter::new(plant, lin, t)))
}

impl FesParamsFile {
    /// The same file with `[tuning] torque_error = e` (`limbfuse tune`).
    pub fn with_torque_error(mut self, e: f64) -> Self {
        self.tuning.torque_error = Some(e);
        self
    }

    /// `[tuning] torque_error`, if the file sets it.
    pub fn torque_error(&self) -> Option<f64> {
        self.tuning.torque_error
    }

    /// Whether `sdre` / `ekf` run the extended knee model with this file
    /// (`[states]` or `[measurement]` given).
    pub fn is_extended(&self) -> bool {
        self.states.options() != KneeStateOptions::default()
            || self.measurement.shank_imu_m.is_some()
    }
}

/// `sdre` / `ekf` on the extended knee model with `opts` and the lever arm
/// `r`, with the `[tuning]` overrides (one value per state of the extended
/// model, in its state order) applied to the tuning of the relative torque
/// error `torque_error` (default: `extended_defaults::TORQUE_ERROR`).
pub fn build_extended_knee(
    base: KneeFesModel,
    thigh: f64,
    (opts, r): (KneeStateOptions, f64),
    lin: (Linearisation, Option<f64>),
    tuning: &[(&'static str, Vec<f64>)],
    path: &Path,
) -> Result<Box<dyn Estimator + Send>, FesBuildError> {
    match opts.states() {
        2 => extended::<2>(base, thigh, opts, r, lin, tuning, path),
        3 => extended::<3>(base, thigh, opts, r, lin, tuning, path),
        4 => extended::<4>(base, thigh, opts, r, lin, tuning, path),
        5 => extended::<5>(base, thigh, opts, r, lin, tuning, path),
        _ => extended::<6>(base, thigh, opts, r, lin, tuning, path),
    }
}

/// `knee-kinematic` for a trial: `g` from `# param.g:` (default 9.81), the
/// thigh angle from `# thigh_angle_rad:` (default pi/2), the lever arm `r`.
pub fn build_kinematic(
    meta: &TrialMeta,
    r: f64,
    tuning: &[(&'static str, Vec<f64>)],
    path: &Path,
) -> Result<Box<dyn Estimator + Send>, FesBuildError> {
    let model = KinematicKneeModel::new(meta_number(meta, "param.g", 9.81)?, r)?;
    let mut t = kinematic_default_tuning();
    apply_tuning(&mut t, tuning, path)?;
    let plant = KinematicKneePlant {
        model,
        thigh_angle: meta_number(meta, "thigh_angle_rad", core::f64::consts::FRAC_PI_2)?,
    };
    Ok(Box::new(FesFilter::new(plant, Linearisation::Jacobian, t)))
}
