//! The paper-004 estimators as methods: `sdre`, `ekf`, `rmx`, and the
//! model-free baseline `knee-kinematic` (issue 16). The model
//! comes from the trial's metadata; the parameter file
//! ([`crate::fes_params`]) overrides it and the tuning.

use std::path::Path;

use limbfuse_core::Estimator;
use limbfuse_io::{TrialLayout, TrialMeta};

use crate::fes_default_file::default_file;
use crate::fes_params::{build_fes_estimator, FesMethod, FesParamsFile};
use crate::method_def::{MethodDef, MethodInfo};
use crate::name::check_file_method;
use crate::{ChannelNeeds, MethodError, MethodFlags};

fn resolve(name: &'static str, file: Option<(&str, &Path)>) -> Result<FesParamsFile, MethodError> {
    let Some((text, path)) = file else {
        return Ok(FesParamsFile::none());
    };
    crate::params_toml::check_method_line(text, path, name)?;
    let f = FesParamsFile::parse(text, path)?;
    if let Some(found) = f.method {
        check_file_method(found.name(), name, path)?;
    }
    Ok(f)
}

fn build(
    m: FesMethod,
    file: &FesParamsFile,
    meta: &TrialMeta,
    layout: &TrialLayout,
) -> Result<Box<dyn Estimator + Send>, MethodError> {
    build_fes_estimator(m, meta, layout, file).map_err(|source| MethodError::Fes {
        method: m.method(),
        source,
    })
}

const SHANK_IMU: ChannelNeeds = ChannelNeeds::imus([false, false, true, false]);
const MODEL_IMUS: &str = "needs the IMUs its model measures";

macro_rules! fes_method {
    ($(#[$doc:meta])* $name:ident, $m:expr, $info:expr) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy)]
        pub struct $name;

        impl MethodDef for $name {
            const INFO: MethodInfo = $info;
            type Settings = FesParamsFile;

            fn resolve(
                file: Option<(&str, &Path)>,
                _: &MethodFlags,
            ) -> Result<FesParamsFile, MethodError> {
                resolve(Self::INFO.name, file)
            }

            fn build(
                f: &FesParamsFile,
                meta: &TrialMeta,
                layout: &TrialLayout,
            ) -> Result<Box<dyn Estimator + Send>, MethodError> {
                build($m, f, meta, layout)
            }

            fn default_file() -> String {
                default_file($m.method())
            }
        }
    };
}

fes_method!(
    /// `sdre`: SDRE estimator on the trial's model.
    SdreMethod,
    FesMethod::Sdre,
    MethodInfo::new(
        "sdre",
        "paper 004: SDRE estimator on the trial's model (knee-fes or fixed-hip metadata)",
        "thigh and shank IMUs, stimulation (and motor) columns; `# model:` metadata",
        "[model] parameter overrides, [tuning] q, s, a, p0, max_substep",
    )
    .needing(SHANK_IMU, MODEL_IMUS)
    .reading_aligned_frames()
);

fes_method!(
    /// `ekf`: extended Kalman(-Bucy) filter on the trial's model.
    EkfMethod,
    FesMethod::Ekf,
    MethodInfo::new(
        "ekf",
        "paper 004: extended Kalman(-Bucy) filter on the trial's model",
        "thigh and shank IMUs, stimulation (and motor) columns; `# model:` metadata",
        "[model] parameter overrides, [tuning] q, s, a, p0, max_substep",
    )
    .needing(SHANK_IMU, MODEL_IMUS)
    .reading_aligned_frames()
);

fes_method!(
    /// `rmx`: knee from the relative orientation of two Mahony filters.
    RmxMethod,
    FesMethod::Rmx,
    MethodInfo::new(
        "rmx",
        "paper 004: knee from the relative orientation of thigh and shank IMUs",
        "thigh and shank IMUs",
        "[rmx] kp, ki (Mahony gains)",
    )
    .needing(
        ChannelNeeds::imus([false, true, true, false]),
        "needs the thigh and shank IMUs (their relative orientation is the knee)",
    )
    .reading_aligned_frames()
);

fes_method!(
    /// `knee-kinematic`: model-free EKF of the shank with gyro and
    /// accelerometer bias states, the baseline a knee model must beat.
    KneeKinematicMethod,
    FesMethod::KneeKinematic,
    MethodInfo::new(
        "knee-kinematic",
        "beyond the papers: model-free knee EKF (shank angle, rate, acceleration, gyro and accelerometer biases) on a fixed-thigh FES trial",
        "shank IMU (the thigh is the seat's, `# thigh_angle_rad:`, default horizontal)",
        "[measurement] shank_imu_m, [tuning] q, s, p0, max_substep (5 states)",
    )
    .needing(SHANK_IMU, "needs the shank IMU")
    .reading_aligned_frames()
    .assuming_a_fixed_thigh()
);
