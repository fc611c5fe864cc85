//! The fixed-hip model of `sdre` / `ekf`: its parameter keys and the
//! estimator, with the four muscle activations as states when the file
//! asks for them (issue 16: `[states] activation = true`, or a `[model]`
//! that states `t_a` without `[states]`, the plant as stated;
//! docs/FES_ESTIMATION.md "Fixed hip with activation").

use std::path::Path;

use limbfuse_core::Estimator;
use limbfuse_estimators::fes::fixed_hip::fixed_hip_default_tuning;
use limbfuse_estimators::fes::fixed_hip_activation::{
    fixed_hip_activation_shift, fixed_hip_activation_tuning,
};
use limbfuse_estimators::fes::{FesFilter, FixedHipActivationPlant, FixedHipPlant, Linearisation};
use limbfuse_models::{FixedHipActivationModel, FixedHipModel, FixedHipParams};

use crate::fes_params::{apply_tuning, FesBuildError, FesParamsFile};

/// Sets one fixed-hip parameter by name (`t_a`: the activation time
/// constant of the activation states); `false` for an unknown name.
pub fn set_hip_param(p: &mut FixedHipParams, t_a: &mut f64, key: &str, v: f64) -> bool {
    match key {
        "t_a" => *t_a = v,
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

/// Whether the fixed hip runs with the activation states for `file`:
/// `[states] activation` when the table is there (the knee's other states
/// are refused), else whether `[model]` states `t_a`. `[measurement]` and
/// `[tuning] torque_error` belong to the knee model and are refused.
pub fn fixed_hip_activation(file: &FesParamsFile) -> Result<bool, FesBuildError> {
    let refuse = |what: &str| FesBuildError::NotApplicable {
        path: file.path.display().to_string(),
        what: what.to_string(),
    };
    if file.measurement.shank_imu_m.is_some() {
        return Err(refuse(
            "[measurement] shank_imu_m applies to the knee-fes model only (the fixed hip measures g sin q)",
        ));
    }
    if file.tuning.torque_error.is_some() {
        return Err(refuse(
            "[tuning] torque_error applies to the extended knee-fes model only",
        ));
    }
    Ok(match file.states {
        Some(st) => {
            if [st.disturbance, st.gyro_bias, st.acc_bias].contains(&Some(true)) {
                return Err(refuse(
                    "[states] disturbance, gyro_bias and acc_bias apply to the knee-fes model only (the fixed hip has `activation`)",
                ));
            }
            st.activation.unwrap_or(false)
        }
        None => file.model.contains_key("t_a"),
    })
}

/// `sdre` / `ekf` on the fixed hip, with the activation states when
/// [`fixed_hip_activation`] says so (activation time constant `t_a`).
pub(crate) fn build_fixed_hip(
    model: FixedHipModel,
    t_a: f64,
    file: &FesParamsFile,
    lin: Linearisation,
    tuning: &[(&'static str, Vec<f64>)],
) -> Result<Box<dyn Estimator + Send>, FesBuildError> {
    let path: &Path = file.path.as_path();
    if !fixed_hip_activation(file)? {
        let mut t = fixed_hip_default_tuning(lin);
        apply_tuning(&mut t, tuning, path)?;
        return Ok(Box::new(FesFilter::new(FixedHipPlant { model }, lin, t)));
    }
    let model = FixedHipActivationModel::new(model, t_a)?;
    let mut t = fixed_hip_activation_tuning(&model, lin);
    apply_tuning(&mut t, tuning, path)?;
    // The per-state shift follows a `[tuning] a` override.
    t.a_states = Some(fixed_hip_activation_shift(&model, t.a));
    Ok(Box::new(FesFilter::new(
        FixedHipActivationPlant { model },
        lin,
        t,
    )))
}
