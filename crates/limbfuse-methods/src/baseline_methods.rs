//! The two baselines as methods: no settings.

use std::path::Path;

use limbfuse_core::Estimator;
use limbfuse_estimators::baseline::{AccelInclination, GyroIntegration};
use limbfuse_io::{TrialLayout, TrialMeta};
use serde::Deserialize;

use crate::method_def::{read_file, MethodDef, MethodFile, MethodInfo};
use crate::{MethodError, MethodFlags};

/// The parameter file of a method without settings: at most its `method`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct NoSettingsFile {
    method: Option<String>,
}

impl MethodFile for NoSettingsFile {
    fn method(&self) -> Option<&str> {
        self.method.as_deref()
    }
}

fn no_settings_file(name: &str) -> String {
    format!("# limbfuse {name}: this method has no parameters.\nmethod = \"{name}\"\n")
}

macro_rules! baseline_method {
    ($(#[$doc:meta])* $name:ident, $estimator:ident, $info:expr, $sensor:ident, $why:expr, $columns:expr) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy)]
        pub struct $name;

        impl MethodDef for $name {
            const INFO: MethodInfo = $info;
            type Settings = ();

            fn resolve(file: Option<(&str, &Path)>, _: &MethodFlags) -> Result<(), MethodError> {
                read_file::<Self, NoSettingsFile>(file).map(|_| ())
            }

            /// Refuses a trial with no segment's sensor of its kind: the
            /// estimate would be empty on every row (found by `limbfuse
            /// inspect` on the shared B-SLIP trial, which has no IMU).
            fn build(
                _: &(),
                _: &TrialMeta,
                layout: &TrialLayout,
            ) -> Result<Box<dyn Estimator + Send>, MethodError> {
                if !layout.$sensor.iter().any(|&has| has) {
                    return Err(MethodError::MissingChannels {
                        method: Self::INFO.name,
                        why: $why,
                        missing: vec![$columns.to_string()],
                        hint: "",
                    });
                }
                Ok(Box::new($estimator::new()))
            }

            fn default_file() -> String {
                no_settings_file(Self::INFO.name)
            }
        }
    };
}

baseline_method!(
    /// `gyro-integration`.
    GyroIntegrationMethod,
    GyroIntegration,
    MethodInfo {
        in_walking_demo: true,
        ..MethodInfo::new(
            "gyro-integration",
            "baseline: trapezoidal integration of each aligned gyro's z rate",
            "each segment's gyro (aligned: z = sagittal axis)",
            "none",
        )
        .reading_aligned_frames()
    },
    gyr,
    "integrates each segment's gyroscope",
    "trunk_, thigh_, shank_ or foot_gyr_x/y/z"
);

baseline_method!(
    /// `accel-inclination`.
    AccelInclinationMethod,
    AccelInclination,
    MethodInfo {
        in_walking_demo: true,
        ..MethodInfo::new(
            "accel-inclination",
            "baseline: theta = atan2(acc_x, acc_y) per segment",
            "each segment's accelerometer (aligned)",
            "none",
        )
        .reading_aligned_frames()
    },
    acc,
    "takes each segment's inclination from its accelerometer",
    "trunk_, thigh_, shank_ or foot_acc_x/y/z"
);
