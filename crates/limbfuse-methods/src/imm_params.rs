//! The parameter file of `imm-bslip` (paper 003) and its flags; loading the
//! gait library it runs over.
//!
//! ```toml
//! method = "imm-bslip"     # optional
//! library = "lib.json"     # relative to this file (--library)
//! kappa = 1e5              # physical-likelihood gain, 1/m^2 (eq 14; --kappa)
//! rescale_height = 0.95    # CoM height at mid-stance, m (sec IV-B; --rescale-height)
//! weights = "paper"        # or "recursive" (--imm-weights)
//! touchdown = "height"     # or "step-clock", "mixed" (--imm-touchdown)
//! ```

use std::path::{Path, PathBuf};

use limbfuse_core::Estimator;
use limbfuse_estimators::imm_bslip::{ImmBslip, ImmBslipParams, ImmWeights, TouchdownRule};
use limbfuse_io::gait_library::GaitLibraryFile;
use limbfuse_io::{TrialLayout, TrialMeta};
use limbfuse_models::bslip::GaitTemplate;
use serde::Deserialize;

use crate::method_def::{read_file, MethodDef, MethodFile, MethodInfo};
use crate::{ChannelNeeds, MethodError, MethodFlags, MethodName};

/// An `imm-bslip` parameter file.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct ImmBslipFile {
    method: Option<String>,
    library: Option<PathBuf>,
    kappa: Option<f64>,
    rescale_height: Option<f64>,
    weights: Option<String>,
    touchdown: Option<String>,
}

/// `imm-bslip` resolved: the library's templates (rescaled if asked) and
/// the options; the measurement model (full CoM or position only) is chosen
/// from the trial's columns when it is built.
#[derive(Debug, Clone, PartialEq)]
pub struct ImmSpec {
    /// The library file.
    pub library: PathBuf,
    /// Its gaits.
    pub templates: Vec<GaitTemplate>,
    /// eq 14 gain (1/m^2); `None` keeps the measurement model's default.
    pub kappa: Option<f64>,
    /// The weight rule.
    pub weights: ImmWeights,
    /// The touchdown rule.
    pub touchdown: TouchdownRule,
}

fn weights(flag: &'static str, text: &str) -> Result<ImmWeights, MethodError> {
    [ImmWeights::Paper, ImmWeights::Recursive]
        .into_iter()
        .find(|w| w.label() == text)
        .ok_or_else(|| MethodError::BadFlagValue {
            flag,
            expected: "`paper` or `recursive`",
            found: text.to_string(),
        })
}

fn touchdown(flag: &'static str, text: &str) -> Result<TouchdownRule, MethodError> {
    [
        TouchdownRule::Height,
        TouchdownRule::StepClock,
        TouchdownRule::Mixed,
    ]
    .into_iter()
    .find(|w| w.label() == text)
    .ok_or_else(|| MethodError::BadFlagValue {
        flag,
        expected: "`height`, `step-clock` or `mixed`",
        found: text.to_string(),
    })
}

/// Reads a library file's templates, optionally rescaled to a CoM height
/// at mid-stance (paper 003 sec IV-B).
pub fn load_templates(path: &Path, height: Option<f64>) -> Result<Vec<GaitTemplate>, MethodError> {
    let lib = GaitLibraryFile::read(path)?;
    let mut t = lib.templates();
    if let Some(h) = height {
        t = t
            .iter()
            .map(|g| g.rescaled_to_height(h))
            .collect::<Option<Vec<_>>>()
            .ok_or(MethodError::RescaleHeight(h))?;
    }
    Ok(t)
}

/// `imm-bslip` from a parameter file's text (or none) and the flags, which
/// override the file.
pub fn imm_spec(file: Option<(&str, &Path)>, flags: &MethodFlags) -> Result<ImmSpec, MethodError> {
    let f: ImmBslipFile = read_file::<ImmBslipMethod, _>(file)?;
    let in_file = |p: &PathBuf| match file {
        Some((_, path)) => path.parent().unwrap_or(Path::new("")).join(p),
        None => p.clone(),
    };
    let library = match (&flags.library, &f.library) {
        (Some(l), _) => l.clone(),
        (None, Some(l)) => in_file(l),
        (None, None) => {
            return Err(MethodError::Missing {
                method: MethodName::ImmBslip,
                what: "--library LIB.json (build one with `limbfuse gait-library build`)",
            })
        }
    };
    let templates = load_templates(&library, flags.rescale_height.or(f.rescale_height))?;
    let weights = match (&flags.imm_weights, &f.weights) {
        (Some(w), _) => weights("--imm-weights", w)?,
        (None, Some(w)) => weights("weights", w)?,
        (None, None) => ImmWeights::Paper,
    };
    let touchdown = match (&flags.imm_touchdown, &f.touchdown) {
        (Some(w), _) => touchdown("--imm-touchdown", w)?,
        (None, Some(w)) => touchdown("touchdown", w)?,
        (None, None) => TouchdownRule::Height,
    };
    Ok(ImmSpec {
        library,
        templates,
        kappa: flags.kappa.or(f.kappa),
        weights,
        touchdown,
    })
}

/// The estimator for a trial: position-only defaults (eqs 17-18) when the
/// trial has no CoM velocity channel, else eqs 15-16.
pub fn build_imm(spec: &ImmSpec, layout: &TrialLayout) -> Result<ImmBslip, MethodError> {
    let mut params = if layout.com_meas[3] || layout.com_meas[4] {
        ImmBslipParams::full_com()
    } else {
        ImmBslipParams::position_only()
    };
    if let Some(k) = spec.kappa {
        params.kappa = k;
    }
    params.weights = spec.weights;
    params.touchdown = spec.touchdown;
    ImmBslip::new(&spec.templates, params).map_err(|e| MethodError::ImmParams(e.to_string()))
}

impl MethodFile for ImmBslipFile {
    fn method(&self) -> Option<&str> {
        self.method.as_deref()
    }
}

/// `imm-bslip` (paper 003).
#[derive(Debug, Clone, Copy)]
pub struct ImmBslipMethod;

impl MethodDef for ImmBslipMethod {
    const INFO: MethodInfo = MethodInfo::new(
        "imm-bslip",
        "paper 003: gait phase and speed from CoM measurements, IMM over a B-SLIP gait library (--library)",
        "com_meas_x/y/z (and com_meas_vx/vy when present)",
        "library, kappa, rescale_height, weights, touchdown (file keys or --library, --kappa, ...)",
    )
    .needing(
        ChannelNeeds {
            com_position: true,
            ..ChannelNeeds::NONE
        },
        "needs CoM measurement columns",
    );
    type Settings = ImmSpec;

    fn resolve(file: Option<(&str, &Path)>, flags: &MethodFlags) -> Result<ImmSpec, MethodError> {
        imm_spec(file, flags)
    }

    fn build(
        spec: &ImmSpec,
        _: &TrialMeta,
        layout: &TrialLayout,
    ) -> Result<Box<dyn Estimator + Send>, MethodError> {
        Ok(Box::new(build_imm(spec, layout)?))
    }

    fn default_file() -> String {
        default_file()
    }
}

/// The default file, commented (`limbfuse params --method imm-bslip`).
pub fn default_file() -> String {
    let full = ImmBslipParams::full_com();
    let pos = ImmBslipParams::position_only();
    format!(
        "# limbfuse imm-bslip parameters (paper 003; docs/GAIT_IMM.md).\n\
         method = \"imm-bslip\"\n\
         # library = \"lib.json\"  # required (here or --library): `limbfuse gait-library build`\n\
         # kappa = {}  # eq 14 gain, 1/m^2 (default {} with CoM velocity, {} position only)\n\
         # rescale_height = 0.95  # rescale every gait to this mid-stance CoM height, m\n\
         weights = \"{}\"  # \"paper\" (eq 8) or \"recursive\"\n\
         touchdown = \"{}\"  # \"height\", \"step-clock\" or \"mixed\"\n",
        full.kappa,
        full.kappa,
        pos.kappa,
        full.weights.label(),
        full.touchdown.label()
    )
}
