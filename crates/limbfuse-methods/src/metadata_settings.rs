//! What a trial's metadata sets in the methods that can run on it
//! (`limbfuse inspect`, Python's `limbfuse.inspect`): the lower-back
//! pendulum, the shank IMU's lever arm, the B-SLIP body and the chain's
//! geometry, each from the function `estimate` uses to build the method, so
//! that a user sees before estimating which of the file's lines are read
//! and what a missing one falls back to.

use limbfuse_io::TrialMeta;
use limbfuse_models::DEFAULT_BODY_HEIGHT_M;

use crate::chain_method::{resolve_geometry, GeometryFile};
use crate::fes_params::FesParamsFile;
use crate::imm_body::trial_body;
use crate::lowback_method::{pendulum_for_trial, LowbackSpeedMethod};
use crate::{Availability, MethodDef, MethodFlags, MethodName};

/// One line per method that reads body or sensor geometry from the
/// metadata and is not missing columns: the values its defaults take on
/// this trial and where they come from (an invalid value: the error
/// `estimate` would give).
pub fn metadata_settings(meta: &TrialMeta, methods: &[(MethodName, Availability)]) -> Vec<String> {
    methods
        .iter()
        .filter(|(_, a)| !matches!(a, Availability::MissingColumns(_)))
        .filter_map(|(m, _)| {
            let line = match m {
                MethodName::LowbackSpeed => lowback(meta),
                MethodName::KneeKinematic => knee_kinematic(meta),
                MethodName::ImmBslip => imm_body(meta),
                MethodName::Chain => chain(meta),
                MethodName::Sdre | MethodName::Ekf => fes_model(meta)?,
                _ => return None,
            };
            Some(format!("{}: {line}", m.name()))
        })
        .collect()
}

fn lowback(meta: &TrialMeta) -> String {
    let defaults = LowbackSpeedMethod::resolve(None, &MethodFlags::default());
    match defaults.and_then(|settings| pendulum_for_trial(&settings, meta)) {
        Ok((p, source)) => format!(
            "pendulum length {} m, correction factor {} (from {})",
            p.leg_length,
            p.correction,
            source.describe()
        ),
        Err(e) => e.to_string(),
    }
}

/// `sdre` / `ekf` with no parameter file: where the model and the lever arm
/// come from, when the trial's `# param_*` lines state the model (a
/// limbfuse `# model:` line says nothing new: the thesis estimator).
fn fes_model(meta: &TrialMeta) -> Option<String> {
    let file = FesParamsFile::none();
    let with_lines = match file.for_trial(meta) {
        Ok(f) => f,
        Err(e) => return Some(e.to_string()),
    };
    if with_lines.model.is_empty() {
        return None;
    }
    Some(match with_lines.lever_arm(meta) {
        Ok(arm) => format!(
            "knee-fes model from the trial's `# param_*` lines; it states t_a, so the plant as \
             stated (activation and bias states), {arm}"
        ),
        Err(e) => e.to_string(),
    })
}

fn knee_kinematic(meta: &TrialMeta) -> String {
    match FesParamsFile::none().kinematic_lever_arm(meta) {
        Ok(arm) => arm.to_string(),
        Err(e) => e.to_string(),
    }
}

fn imm_body(meta: &TrialMeta) -> String {
    match trial_body(None, None, meta) {
        Ok(b) => match (b.mass, b.leg_length) {
            (Some(m), Some(l)) => {
                format!("body {m} kg, leg rest length {l} m (from {})", b.source)
            }
            (None, Some(l)) => format!("leg rest length {l} m (from {}), mass not stated", b.source),
            _ => "no body in the metadata (`# leg_length_m:` / `# body_mass_kg:`): a library is used \
                  for the body it was built for unless `--leg-length` / `--mass` say otherwise"
                .to_string(),
        },
        Err(e) => e.to_string(),
    }
}

fn chain(meta: &TrialMeta) -> String {
    let geometry = resolve_geometry(meta, &GeometryFile::default());
    let (g, body) = match (geometry, meta.body()) {
        (Ok(g), Ok(body)) => (g, body),
        (Err(e), _) => return e.to_string(),
        (_, Err(e)) => return e.to_string(),
    };
    let lengths = if body.thigh_length.is_some() || body.shank_length.is_some() {
        "`# segment_lengths_m:`".to_string()
    } else if let Some(h) = body.height {
        format!("Winter's proportions of `# height_m: {h}`")
    } else {
        format!("Winter's proportions of the default height {DEFAULT_BODY_HEIGHT_M} m")
    };
    let mounts = if body.imu_position.iter().any(Option::is_some) {
        "`# imu_mounts_m:` (mid-segment where it names no IMU)"
    } else {
        "mid-segment defaults"
    };
    format!(
        "thigh {:.3} m, shank {:.3} m from {lengths}; IMU positions from {mounts}",
        g.thigh_length, g.shank_length
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::availability;
    use limbfuse_io::TrialLayout;

    fn lines(meta: &[(&str, &str)], layout: &TrialLayout) -> Vec<String> {
        let mut m = TrialMeta::default();
        for (k, v) in meta {
            m.set(*k, v);
        }
        metadata_settings(&m, &availability(&m, layout))
    }

    /// A lower-back trial: the pendulum from its sensor height; nothing
    /// for the methods whose columns it lacks.
    #[test]
    fn the_lower_back_pendulum_names_its_source() {
        let mut layout = TrialLayout::default();
        layout.acc[0] = true;
        layout.gyr[0] = true;
        let got = lines(&[("sensor_height_m", "0.964")], &layout);
        assert_eq!(got.len(), 1, "{got:?}");
        assert!(
            got[0].starts_with("lowback-speed: pendulum length 0.964 m, correction factor 1.14675")
                && got[0].contains("sensor_height_m"),
            "{got:?}"
        );
        let got = lines(&[], &layout);
        let default_body = format!("0.530 x the default body height {DEFAULT_BODY_HEIGHT_M} m");
        assert!(
            got[0].starts_with("lowback-speed: pendulum length 0.9275 m, correction factor 1.25")
                && got[0].contains(&default_body),
            "{got:?}"
        );
    }

    /// An independent-simulator FES trial: sdre and ekf take the model from
    /// its `# param_*` lines, with their lever arm.
    #[test]
    fn the_param_lines_model_is_named() {
        let mut layout = TrialLayout::default();
        layout.acc[2] = true;
        layout.gyr[2] = true;
        layout.stim[0] = true;
        layout.acc[1] = true;
        layout.gyr[1] = true;
        let mut meta = vec![("model", "free text"), ("param_r_imu", "0.25")];
        let values: Vec<String> = (0..19).map(|i| format!("{}", 1.0 + i as f64)).collect();
        for ((line, _), v) in crate::fes_param_lines::PARAM_LINE_KEYS.iter().zip(&values) {
            meta.push((line, v));
        }
        let got = lines(&meta, &layout);
        assert!(
            got.iter().any(|l| l
                .starts_with("sdre: knee-fes model from the trial's `# param_*` lines")
                && l.contains("0.2500 m below the knee (trial metadata # param_r_imu)")),
            "{got:?}"
        );
    }

    /// A shank-IMU trial: knee-kinematic's lever arm from `# param_r_imu:`.
    #[test]
    fn the_lever_arm_names_its_key() {
        let mut layout = TrialLayout::default();
        layout.acc[2] = true;
        layout.gyr[2] = true;
        let got = lines(&[("param_r_imu", "0.25")], &layout);
        assert!(
            got.iter().any(|l| l
                == "knee-kinematic: shank accelerometer 0.2500 m below the knee (trial metadata # param_r_imu)"),
            "{got:?}"
        );
    }
}
