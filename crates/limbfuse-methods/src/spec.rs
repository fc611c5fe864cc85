//! [`MethodSpec`]: a method with every setting resolved, parsed once from
//! its name, its parameter file and the command-line flags.

use std::path::{Path, PathBuf};

use limbfuse_estimators::knee_selfalign::KneeSelfAlignParams;
use serde::Deserialize;

use crate::fes_params::{FesMethod, FesParamsFile};
use crate::imm_params::{imm_spec, ImmSpec};
use crate::knee_params::knee_params;
use crate::segment_params::{parse_params, FilterMethod, FilterParams, ParamsFileError, Preset};
use crate::{MethodError, MethodName};

/// Method settings given as command-line flags (`limbfuse estimate`); each
/// belongs to one method and overrides the same key of its parameter file.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MethodFlags {
    /// knee-selfalign: window length `s_w` (samples).
    pub window: Option<usize>,
    /// knee-selfalign: parameter-EKF iterations per window.
    pub order: Option<usize>,
    /// imm-bslip: gait library file.
    pub library: Option<PathBuf>,
    /// imm-bslip: eq 14 gain (1/m^2).
    pub kappa: Option<f64>,
    /// imm-bslip: CoM height to rescale every gait to (m).
    pub rescale_height: Option<f64>,
    /// imm-bslip: weight rule (`paper`, `recursive`).
    pub imm_weights: Option<String>,
    /// imm-bslip: touchdown rule (`height`, `step-clock`, `mixed`).
    pub imm_touchdown: Option<String>,
}

impl MethodFlags {
    /// Checks that every flag given belongs to `method`.
    pub fn check_applies_to(&self, method: MethodName) -> Result<(), MethodError> {
        let knee = self.window.is_some() || self.order.is_some();
        if knee && method != MethodName::KneeSelfAlign {
            return Err(MethodError::FlagNotForMethod {
                flags: "--window and --order",
                owner: MethodName::KneeSelfAlign,
                method,
            });
        }
        let imm = self.library.is_some()
            || self.kappa.is_some()
            || self.rescale_height.is_some()
            || self.imm_weights.is_some()
            || self.imm_touchdown.is_some();
        if imm && method != MethodName::ImmBslip {
            return Err(MethodError::FlagNotForMethod {
                flags: "--library, --kappa, --rescale-height, --imm-weights and --imm-touchdown",
                owner: MethodName::ImmBslip,
                method,
            });
        }
        Ok(())
    }
}

/// Every method with its settings resolved: what [`crate::build`] turns
/// into an estimator for a trial.
#[derive(Debug, Clone, PartialEq)]
pub enum MethodSpec {
    /// `gyro-integration` (no settings).
    GyroIntegration,
    /// `accel-inclination` (no settings).
    AccelInclination,
    /// `local`, `mjls` or `global` with their parameters.
    SegmentFilter(FilterParams),
    /// `knee-selfalign` with its parameters.
    KneeSelfAlign(KneeSelfAlignParams),
    /// `sdre`, `ekf` or `rmx` with the overrides of their file (the model
    /// itself comes from the trial).
    Fes(FesMethod, FesParamsFile),
    /// `imm-bslip` with its library.
    ImmBslip(ImmSpec),
}

/// The parameter file of a method without settings: at most its `method`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct NoSettingsFile {
    method: Option<MethodName>,
}

/// A file's `method = "..."` must be the method it is read for.
pub(crate) fn check_file_method(
    found: MethodName,
    method: MethodName,
    path: &Path,
) -> Result<(), ParamsFileError> {
    if found == method {
        return Ok(());
    }
    Err(ParamsFileError::Invalid {
        path: path.to_path_buf(),
        message: format!(
            "`method` = \"{found}\" but the file is read for method `{method}` (use --method {found} or remove the `method` line)"
        ),
    })
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
        let file = text.as_deref().zip(params);
        Self::from_parts(method, file, flags)
    }

    /// As [`MethodSpec::resolve`], from a parameter file's text and path.
    pub fn from_parts(
        method: MethodName,
        file: Option<(&str, &Path)>,
        flags: &MethodFlags,
    ) -> Result<Self, MethodError> {
        flags.check_applies_to(method)?;
        let segment = |m: FilterMethod| -> Result<Self, MethodError> {
            Ok(MethodSpec::SegmentFilter(match file {
                Some((text, path)) => parse_params(text, path, m)?,
                None => FilterParams::preset(m, Preset::Default),
            }))
        };
        let fes = |m: FesMethod| -> Result<Self, MethodError> {
            let f = match file {
                Some((text, path)) => FesParamsFile::parse(text, path)?,
                None => FesParamsFile::none(),
            };
            if let (Some(found), Some((_, path))) = (f.method, file) {
                check_file_method(found, method, path)?;
            }
            Ok(MethodSpec::Fes(m, f))
        };
        let no_settings = |spec: MethodSpec| -> Result<Self, MethodError> {
            if let Some((text, path)) = file {
                let f: NoSettingsFile = crate::params_toml::from_str(text, path)?;
                if let Some(found) = f.method {
                    check_file_method(found, method, path)?;
                }
            }
            Ok(spec)
        };
        match method {
            MethodName::GyroIntegration => no_settings(MethodSpec::GyroIntegration),
            MethodName::AccelInclination => no_settings(MethodSpec::AccelInclination),
            MethodName::Local => segment(FilterMethod::Local),
            MethodName::Mjls => segment(FilterMethod::Mjls),
            MethodName::Global => segment(FilterMethod::Global),
            MethodName::KneeSelfAlign => Ok(MethodSpec::KneeSelfAlign(knee_params(file, flags)?)),
            MethodName::Sdre => fes(FesMethod::Sdre),
            MethodName::Ekf => fes(FesMethod::Ekf),
            MethodName::Rmx => fes(FesMethod::Rmx),
            MethodName::ImmBslip => Ok(MethodSpec::ImmBslip(imm_spec(file, flags)?)),
        }
    }

    /// The method with its defaults (no file, no flags).
    pub fn defaults(method: MethodName) -> Result<Self, MethodError> {
        Self::from_parts(method, None, &MethodFlags::default())
    }

    /// Which method this is.
    pub fn method(&self) -> MethodName {
        match self {
            MethodSpec::GyroIntegration => MethodName::GyroIntegration,
            MethodSpec::AccelInclination => MethodName::AccelInclination,
            MethodSpec::SegmentFilter(p) => p.method().method(),
            MethodSpec::KneeSelfAlign(_) => MethodName::KneeSelfAlign,
            MethodSpec::Fes(m, _) => m.method(),
            MethodSpec::ImmBslip(_) => MethodName::ImmBslip,
        }
    }
}

/// The method's parameter file with every default written out and
/// commented (`limbfuse params --method NAME`); it reads back to
/// [`MethodSpec::defaults`].
pub fn default_params_file(method: MethodName) -> String {
    if let Some(m) = FilterMethod::from_method(method) {
        return crate::segment_params::to_toml(&FilterParams::preset(m, Preset::Default), &[]);
    }
    if FesMethod::from_method(method).is_some() {
        return crate::fes_params::default_file(method);
    }
    match method {
        MethodName::KneeSelfAlign => crate::knee_params::default_file(),
        MethodName::ImmBslip => crate::imm_params::default_file(),
        _ => {
            format!("# limbfuse {method}: this method has no parameters.\nmethod = \"{method}\"\n")
        }
    }
}
