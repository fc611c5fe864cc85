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
    ($(#[$doc:meta])* $name:ident, $estimator:ident, $info:expr) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy)]
        pub struct $name;

        impl MethodDef for $name {
            const INFO: MethodInfo = $info;
            type Settings = ();

            fn resolve(file: Option<(&str, &Path)>, _: &MethodFlags) -> Result<(), MethodError> {
                read_file::<Self, NoSettingsFile>(file).map(|_| ())
            }

            fn build(
                _: &(),
                _: &TrialMeta,
                _: &TrialLayout,
            ) -> Result<Box<dyn Estimator + Send>, MethodError> {
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
    }
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
    }
);
