//! The registry: every method limbfuse runs, one line each. From it come
//! [`MethodName`] (parsed once, in `name.rs`), [`MethodSpec`] (every
//! setting resolved) and the dispatch of resolving, building and writing
//! default files. Adding a method: implement [`MethodDef`] for it and add
//! its line here.

use std::path::Path;

use limbfuse_core::Estimator;
use limbfuse_io::{TrialLayout, TrialMeta};

use crate::baseline_methods::{AccelInclinationMethod, GyroIntegrationMethod};
use crate::chain_method::ChainMethod;
use crate::fes_methods::{EkfMethod, KneeKinematicMethod, RmxMethod, SdreMethod};
use crate::gait_methods::GaitEventsMethod;
use crate::imm_params::ImmBslipMethod;
use crate::knee_params::{KneeGyroAxisMethod, KneeSelfAlignMethod};
use crate::lowback_method::LowbackSpeedMethod;
use crate::method_def::{build_with, resolve_with, MethodDef, MethodInfo};
use crate::segment_methods::{GlobalMethod, LocalMethod, MjlsMethod};
use crate::{MethodError, MethodFlags};

macro_rules! registry {
    ($( $(#[$doc:meta])* $variant:ident => $def:ty, )+) => {
        /// An estimation method, by name (SPEC section 4, `--method`).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum MethodName {
            $( $(#[$doc])* $variant, )+
        }

        impl MethodName {
            /// Every method, in the order `limbfuse methods` lists them.
            pub const ALL: [MethodName; [$(stringify!($variant)),+].len()] =
                [$(MethodName::$variant),+];

            /// The method's name and documentation.
            pub const fn info(self) -> MethodInfo {
                match self {
                    $( MethodName::$variant => <$def as MethodDef>::INFO, )+
                }
            }
        }

        /// Every method with its settings resolved: what [`crate::build`]
        /// turns into an estimator for a trial.
        #[derive(Debug, Clone, PartialEq)]
        pub enum MethodSpec {
            $( $(#[$doc])* $variant(<$def as MethodDef>::Settings), )+
        }

        impl MethodSpec {
            /// As [`MethodSpec::resolve`], from a parameter file's text and
            /// path.
            pub fn from_parts(
                method: MethodName,
                file: Option<(&str, &Path)>,
                flags: &MethodFlags,
            ) -> Result<Self, MethodError> {
                flags.check_applies_to(method)?;
                Ok(match method {
                    $( MethodName::$variant =>
                        MethodSpec::$variant(resolve_with::<$def>(file, flags)?), )+
                })
            }

            /// Which method this is.
            pub fn method(&self) -> MethodName {
                match self {
                    $( MethodSpec::$variant(_) => MethodName::$variant, )+
                }
            }

            /// A new estimator for a trial (see [`crate::build`]).
            pub(crate) fn build_estimator(
                &self,
                meta: &TrialMeta,
                layout: &TrialLayout,
            ) -> Result<Box<dyn Estimator + Send>, MethodError> {
                match self {
                    $( MethodSpec::$variant(s) => build_with::<$def>(s, meta, layout), )+
                }
            }
        }

        /// The method's parameter file with every default written out and
        /// commented (`limbfuse params --method NAME`); it reads back to
        /// [`MethodSpec::defaults`].
        pub fn default_params_file(method: MethodName) -> String {
            match method {
                $( MethodName::$variant => <$def as MethodDef>::default_file(), )+
            }
        }
    };
}

registry! {
    /// Baseline: integration of each aligned gyro's sagittal rate.
    GyroIntegration => GyroIntegrationMethod,
    /// Baseline: inclination from each accelerometer.
    AccelInclination => AccelInclinationMethod,
    /// Papers 000/001: per-segment error-state Kalman filters.
    Local => LocalMethod,
    /// Papers 000/001: Markov-jump Kalman filter.
    Mjls => MjlsMethod,
    /// Paper 001: matricial global Kalman filter.
    Global => GlobalMethod,
    /// Beyond the papers: kinematic-chain EKF of the four segment angles.
    Chain => ChainMethod,
    /// Paper 002: self-aligning knee angle.
    KneeSelfAlign => KneeSelfAlignMethod,
    /// Beyond the papers: knee angle from the relative gyro rate about the identified axes.
    KneeGyroAxis => KneeGyroAxisMethod,
    /// Paper 004: state-dependent Riccati equation filter.
    Sdre => SdreMethod,
    /// Paper 004: extended Kalman(-Bucy) filter.
    Ekf => EkfMethod,
    /// Paper 004: rotation-matrix (Mahony) knee.
    Rmx => RmxMethod,
    /// Beyond the papers: model-free knee EKF with sensor-bias states.
    KneeKinematic => KneeKinematicMethod,
    /// Paper 003: interacting multiple models over a B-SLIP gait library.
    ImmBslip => ImmBslipMethod,
    /// Beyond the papers: gait events, phase, stride length and speed from foot IMUs.
    GaitEvents => GaitEventsMethod,
    /// Beyond the papers: initial contacts and walking speed from a lower-back IMU.
    LowbackSpeed => LowbackSpeedMethod,
}

impl MethodSpec {
    /// Resolves `method` from its parameter file (`--params`, read here) and
    /// flags; the one entry point of the CLI and the Python package.
    pub fn resolve(
        method: MethodName,
        params: Option<&Path>,
        flags: &MethodFlags,
    ) -> Result<Self, MethodError> {
        let text = params.map(crate::params_toml::read).transpose()?;
        Self::from_parts(method, text.as_deref().zip(params), flags)
    }

    /// The method with its defaults (no file, no flags).
    pub fn defaults(method: MethodName) -> Result<Self, MethodError> {
        Self::from_parts(method, None, &MethodFlags::default())
    }
}
