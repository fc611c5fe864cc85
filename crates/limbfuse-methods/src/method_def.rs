//! [`MethodDef`]: what a method is to the method layer. One implementation
//! per method, one line in the registry ([`crate::registry`]) and the CLI,
//! the parameter files, `limbfuse methods` / `params` and the Python
//! package know it.

use std::path::Path;

use limbfuse_core::Estimator;
use limbfuse_io::{TrialLayout, TrialMeta};
use serde::de::DeserializeOwned;

use crate::{ChannelNeeds, MethodError, MethodFlags};

/// What a user needs to know about a method before running it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MethodInfo {
    /// The `--method` name.
    pub name: &'static str,
    /// One line: paper and what it estimates.
    pub summary: &'static str,
    /// The trial columns it reads, in words.
    pub inputs: &'static str,
    /// What its parameter file (`--params`) and flags set.
    pub settings: &'static str,
    /// The columns it cannot run without (checked before any sample).
    pub needs: ChannelNeeds,
    /// Why it needs them ("estimates all four segments from their IMUs").
    pub needs_why: &'static str,
    /// What to do without them ("" or "; use `local` ...").
    pub needs_hint: &'static str,
    /// Whether `limbfuse demo` runs it on the walking trial.
    pub in_walking_demo: bool,
    /// Whether its `upd_hip/knee/ankle` diagnostics are coupled relative
    /// accelerometer rows (paper 001's global filter), which the AGR of
    /// `evaluate` counts.
    pub relative_rows: bool,
    /// Whether it reads IMU frames aligned to the segments (SPEC section 1:
    /// z medio-lateral), so that a trial declaring raw sensor frames gets
    /// [`crate::raw_frame_note`].
    pub reads_aligned: bool,
    /// Whether it models a fixed (seated) thigh, so that `estimate` checks
    /// the thigh does not move (`limbfuse_eval::FixedThighWatch`).
    pub assumes_fixed_thigh: bool,
    /// Whether it finds walking (steps, contacts, speed) and has nothing
    /// to give on a trial without any (`inspect` says so when the thigh
    /// does not move, `limbfuse_eval::fixed_thigh`).
    pub finds_walking: bool,
}

impl MethodInfo {
    /// A method with these texts and no channel needs, not in the demo.
    pub const fn new(
        name: &'static str,
        summary: &'static str,
        inputs: &'static str,
        settings: &'static str,
    ) -> Self {
        MethodInfo {
            name,
            summary,
            inputs,
            settings,
            needs: ChannelNeeds::NONE,
            needs_why: "",
            needs_hint: "",
            in_walking_demo: false,
            relative_rows: false,
            reads_aligned: false,
            assumes_fixed_thigh: false,
            finds_walking: false,
        }
    }

    /// With the columns it needs and why.
    pub const fn needing(mut self, needs: ChannelNeeds, why: &'static str) -> Self {
        self.needs = needs;
        self.needs_why = why;
        self
    }

    /// Marked as modelling a fixed (seated) thigh.
    pub const fn assuming_a_fixed_thigh(mut self) -> Self {
        self.assumes_fixed_thigh = true;
        self
    }

    /// Marked as finding walking (nothing to give without it).
    pub const fn finding_walking(mut self) -> Self {
        self.finds_walking = true;
        self
    }

    /// Marked as reading IMU frames aligned to the segments.
    pub const fn reading_aligned_frames(mut self) -> Self {
        self.reads_aligned = true;
        self
    }
}

/// A method: its description, its settings resolved from a parameter file
/// and flags, and its estimator built for a trial.
pub trait MethodDef {
    /// Name and documentation.
    const INFO: MethodInfo;
    /// Every setting, resolved and validated.
    type Settings: Clone + core::fmt::Debug + PartialEq;
    /// The settings of a parameter file's text (`None`: the defaults) with
    /// the flags applied on top. Unknown keys must be errors: read the file
    /// with [`read_file`].
    fn resolve(
        file: Option<(&str, &Path)>,
        flags: &MethodFlags,
    ) -> Result<Self::Settings, MethodError>;
    /// A new estimator for a trial with this metadata and these columns.
    fn build(
        settings: &Self::Settings,
        meta: &TrialMeta,
        layout: &TrialLayout,
    ) -> Result<Box<dyn Estimator + Send>, MethodError>;
    /// The default parameter file, every key commented; it must read back
    /// to the defaults.
    fn default_file() -> String;
}

/// A parameter file struct that may carry `method = "NAME"`.
pub trait MethodFile: DeserializeOwned + Default {
    /// The file's `method` value, if any.
    fn method(&self) -> Option<&str>;
}

/// Reads a method's typed file struct from a parameter file's text
/// (`None`: the struct's defaults), checking its `method` line against the
/// method `M`.
pub fn read_file<M: MethodDef, F: MethodFile>(
    file: Option<(&str, &Path)>,
) -> Result<F, MethodError> {
    let Some((text, path)) = file else {
        return Ok(F::default());
    };
    crate::params_toml::check_method_line(text, path, M::INFO.name)?;
    let f: F = crate::params_toml::from_str(text, path)?;
    if let Some(found) = f.method() {
        crate::name::check_file_method(found, M::INFO.name, path)?;
    }
    Ok(f)
}

/// The settings of method `M` (the generic path the registry takes).
pub fn resolve_with<M: MethodDef>(
    file: Option<(&str, &Path)>,
    flags: &MethodFlags,
) -> Result<M::Settings, MethodError> {
    M::resolve(file, flags)
}

/// The estimator of method `M`: its own checks, then the columns of
/// [`MethodInfo::needs`].
pub fn build_with<M: MethodDef>(
    settings: &M::Settings,
    meta: &TrialMeta,
    layout: &TrialLayout,
) -> Result<Box<dyn Estimator + Send>, MethodError> {
    let est = M::build(settings, meta, layout)?;
    crate::channels::check_info(&M::INFO, layout)?;
    Ok(est)
}
