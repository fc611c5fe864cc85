//! Issue 16 options of the knee-FES parameter file and their builders:
//!
//! ```toml
//! [states]            # sdre / ekf on knee-fes: optional states (absent keys false;
//!                     # no table and [model] t_a given: activation, gyro_bias, acc_bias)
//! activation = true   # a_ke' = (u_ke - a_ke) / T_a ([model] t_a)
//! disturbance = true  # unknown knee torque, a random walk
//! gyro_bias = true    # shank gyro z bias
//! acc_bias = true     # shank accelerometer x bias
//! [measurement]
//! shank_imu_m = 0.2   # accelerometer below the knee: adds r x2'' (default 0, thesis;
//!                     # t_a and no [states], and knee-kinematic: the trial's, else mid-shank)
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
use limbfuse_io::body_meta::HEIGHT_KEY;
use limbfuse_io::TrialMeta;
use limbfuse_models::DEFAULT_BODY_HEIGHT_M;
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
    /// `acc_x = g sin x1 + r x1''`; absent: see [`FesParamsFile::lever_arm`]
    /// and [`FesParamsFile::kinematic_lever_arm`].
    pub shank_imu_m: Option<f64>,
}

impl MeasurementFile {
    /// The lever arm (m), checked: finite and in [0, 1].
    pub fn radius(&self, path: &Path) -> Result<f64, FesBuildError> {
        match self.shank_imu_m {
            None => Ok(0.0),
            Some(r) if lever_arm_in_range(r) => Ok(r),
            Some(r) => Err(FesBuildError::File {
                path: path.to_path_buf(),
                message: format!(
                    "[measurement] shank_imu_m = {r}: expected the accelerometer's distance below the knee in metres, in [0, 1]"
                ),
            }),
        }
    }
}

fn lever_arm_in_range(r: f64) -> bool {
    r.is_finite() && (0.0..=1.0).contains(&r)
}

/// Shank length as a fraction of body height (knee to ankle, 0.246 H;
/// D. A. Winter, Biomechanics and Motor Control of Human Movement, 4th ed.,
/// 2009, Table 4.1 / Fig. 4.1).
pub const SHANK_LENGTH_PER_HEIGHT: f64 = 0.246;

/// The states a file that states `[model] t_a` and has no `[states]` gets
/// (the plant as stated: activation dynamics, and the turn-on biases of
/// every MEMS IMU; docs/FES_ESTIMATION.md "Default when the file states
/// T_a").
pub const PLANT_AS_STATED: KneeStateOptions = KneeStateOptions {
    activation: true,
    disturbance: false,
    gyro_bias: true,
    acc_bias: true,
};

/// The shank accelerometer's lever arm and where it came from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeverArm {
    /// Distance below the knee (m).
    pub radius: f64,
    /// Where the value came from, for the estimate's header and stderr.
    pub source: &'static str,
}

impl LeverArm {
    /// The lever arm of the thesis's measurement (`acc_x = g sin x1`).
    pub const THESIS: LeverArm = LeverArm {
        radius: 0.0,
        source: "",
    };
}

impl std::fmt::Display for LeverArm {
    /// `shank accelerometer R m below the knee (SOURCE)`, as the runs say it.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "shank accelerometer {:.4} m below the knee ({})",
            self.radius, self.source
        )
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
    (opts, LeverArm { radius: r, source }): (KneeStateOptions, LeverArm),
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
    plant.imu_radius_source = source;
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

    /// The knee model's optional states: `[states]` as stated when the
    /// file has the table (absent keys off); without it, a file whose
    /// `[model]` states `t_a` describes a plant with activation dynamics,
    /// and gets [`PLANT_AS_STATED`]; otherwise none (the thesis model).
    pub fn state_options(&self) -> KneeStateOptions {
        match self.states {
            Some(s) => s.options(),
            None if self.model.contains_key("t_a") => PLANT_AS_STATED,
            None => KneeStateOptions::default(),
        }
    }

    /// Whether `sdre` / `ekf` run the extended knee model with this file
    /// (optional states, see [`FesParamsFile::state_options`], or
    /// `[measurement]` given).
    pub fn is_extended(&self) -> bool {
        self.state_options() != KneeStateOptions::default()
            || self.measurement.shank_imu_m.is_some()
    }

    /// What `sdre` / `ekf` say on stderr for the plant-as-stated default
    /// (`[model] t_a`, no `[states]`): the states it adds and the lever
    /// arm's source; `None` otherwise (the file says what it runs).
    pub fn plant_as_stated_note(
        &self,
        method: crate::MethodName,
        meta: &TrialMeta,
    ) -> Result<Option<String>, FesBuildError> {
        let file = self.for_trial(meta)?;
        if file.states.is_some() || !file.model.contains_key("t_a") {
            return Ok(None);
        }
        if meta.get("model").map(str::trim) == Some("fixed-hip") {
            return Ok(Some(format!(
                "{method}: [model] states t_a and the file has no [states]: the fixed hip's four \
                 activation states (the plant as stated; `[states]` with `activation = false` gives \
                 the thesis estimator)"
            )));
        }
        let arm = file.lever_arm(meta)?;
        Ok(Some(format!(
            "{method}: [model] states t_a and the file has no [states]: activation, gyro bias and \
             accelerometer bias states (the plant as stated; `[states]` with `activation = false` \
             gives the thesis estimator); {arm}"
        )))
    }

    /// The shank accelerometer's lever arm of the extended knee model:
    /// `[measurement] shank_imu_m` if the file states it; else, for the
    /// plant-as-stated default (`t_a` and no `[states]`), what the trial
    /// states ([`stated_lever_arm`]); else 0 (an explicit `[states]` without
    /// `[measurement]`: the thesis's measurement).
    pub fn lever_arm(&self, meta: &TrialMeta) -> Result<LeverArm, FesBuildError> {
        if self.measurement.shank_imu_m.is_some() {
            return self.file_lever_arm();
        }
        if self.states.is_some() || !self.model.contains_key("t_a") {
            return Ok(LeverArm::THESIS);
        }
        stated_lever_arm(meta)
    }

    /// The lever arm of `knee-kinematic` (ours, no thesis measurement to
    /// keep): `[measurement] shank_imu_m` if the file states it, else what
    /// the trial states ([`stated_lever_arm`]).
    pub fn kinematic_lever_arm(&self, meta: &TrialMeta) -> Result<LeverArm, FesBuildError> {
        if self.measurement.shank_imu_m.is_some() {
            return self.file_lever_arm();
        }
        stated_lever_arm(meta)
    }

    /// What `knee-kinematic` says on stderr when the lever arm is not the
    /// parameter file's: its value and source.
    pub fn kinematic_note(&self, meta: &TrialMeta) -> Result<Option<String>, FesBuildError> {
        if self.measurement.shank_imu_m.is_some() {
            return Ok(None);
        }
        let arm = stated_lever_arm(meta)?;
        Ok(Some(format!(
            "knee-kinematic: {arm} (`[measurement] shank_imu_m` sets it)"
        )))
    }

    fn file_lever_arm(&self) -> Result<LeverArm, FesBuildError> {
        Ok(LeverArm {
            radius: self.measurement.radius(&self.path)?,
            source: "parameter file [measurement] shank_imu_m",
        })
    }
}

/// The independent FES simulator's metadata key for the shank IMU's distance
/// below the knee (its `# param_*` lines state every model parameter;
/// `../shared/data/independent-sim/README.md`). Read after limbfuse's own
/// `# shank_imu_m:` (docs/FES_ESTIMATION.md, "Where the shank IMU is").
pub const PARAM_R_IMU_KEY: &str = "param_r_imu";

/// The shank accelerometer's lever arm as the trial states it: `#
/// shank_imu_m:` (limbfuse's key), else `# param_r_imu:` (the independent FES
/// simulator's), else mid-shank for the trial's `# height_m:` (default
/// [`DEFAULT_BODY_HEIGHT_M`], 1.75 m, the body of every method's defaults):
/// `0.5 x 0.246 H` (Winter 2009). A stated value outside [0, 1] m
/// is an error naming the key.
pub fn stated_lever_arm(meta: &TrialMeta) -> Result<LeverArm, FesBuildError> {
    for (key, source) in [
        ("shank_imu_m", "trial metadata # shank_imu_m"),
        (PARAM_R_IMU_KEY, "trial metadata # param_r_imu"),
    ] {
        let Some(v) = meta.get(key) else {
            continue;
        };
        let r = number("metadata", key, v)?;
        if !lever_arm_in_range(r) {
            return Err(FesBuildError::NotApplicable {
                path: "trial metadata".into(),
                what: format!("`# {key}: {v}`: expected the shank accelerometer's distance below the knee in metres, in [0, 1]"),
            });
        }
        return Ok(LeverArm { radius: r, source });
    }
    let (height, source) = match meta.get(HEIGHT_KEY) {
        Some(v) => (
            number("metadata", HEIGHT_KEY, v)?,
            "anthropometric default: mid-shank, 0.5 x 0.246 x # height_m, Winter 2009 Table 4.1",
        ),
        None => (
            DEFAULT_BODY_HEIGHT_M,
            "anthropometric default: mid-shank, 0.5 x 0.246 x 1.75 m, Winter 2009 Table 4.1; the trial states neither # shank_imu_m, # param_r_imu nor # height_m",
        ),
    };
    if crate::body_ranges::within(height, crate::body_ranges::BODY_HEIGHT_M).is_none() {
        return Err(FesBuildError::NotApplicable {
            path: "trial metadata".into(),
            what: format!(
                "`# {HEIGHT_KEY}: {height}`: expected a body height in metres, in [1, 2.5]"
            ),
        });
    }
    Ok(LeverArm {
        radius: 0.5 * SHANK_LENGTH_PER_HEIGHT * height,
        source,
    })
}

/// `sdre` / `ekf` on the extended knee model with `opts` and the lever arm,
/// with the `[tuning]` overrides (one value per state of the extended
/// model, in its state order) applied to the tuning of the relative torque
/// error `torque_error` (default: `extended_defaults::TORQUE_ERROR`).
pub fn build_extended_knee(
    base: KneeFesModel,
    thigh: f64,
    states: (KneeStateOptions, LeverArm),
    lin: (Linearisation, Option<f64>),
    tuning: &[(&'static str, Vec<f64>)],
    path: &Path,
) -> Result<Box<dyn Estimator + Send>, FesBuildError> {
    match states.0.states() {
        2 => extended::<2>(base, thigh, states, lin, tuning, path),
        3 => extended::<3>(base, thigh, states, lin, tuning, path),
        4 => extended::<4>(base, thigh, states, lin, tuning, path),
        5 => extended::<5>(base, thigh, states, lin, tuning, path),
        _ => extended::<6>(base, thigh, states, lin, tuning, path),
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
