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
//! configuration = "paper"  # or "continuous" (--imm-config)
//! extend_library = "on"    # or "off"; continuous only (--imm-extend-library)
//! leg_length = 0.95        # trial body, m (--leg-length; else the trial metadata)
//! mass = 70                # trial body, kg (--mass)
//! ```

use std::path::{Path, PathBuf};

use limbfuse_core::Estimator;
use limbfuse_estimators::imm_bslip::{
    ImmBslip, ImmBslipParams, ImmContinuous, ImmWeights, SwayRestart, TouchdownRule,
};
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
    configuration: Option<String>,
    extend_library: Option<String>,
    leg_length: Option<f64>,
    mass: Option<f64>,
}

/// Which `imm-bslip` estimator runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ImmConfig {
    /// Paper 003's IMM over every (gait, phase) of the library (default).
    #[default]
    Paper,
    /// One gait of the continuous family re-targeted to the measured speed,
    /// phase from the leg lengths ([`ImmContinuous`]; issue 19).
    Continuous,
}

impl ImmConfig {
    /// `paper` or `continuous`.
    pub const fn label(self) -> &'static str {
        match self {
            ImmConfig::Paper => "paper",
            ImmConfig::Continuous => "continuous",
        }
    }
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
    /// The touchdown rule (paper configuration).
    pub touchdown: TouchdownRule,
    /// The configuration.
    pub config: ImmConfig,
    /// Continuous configuration: whether a trial walking outside the
    /// library's speeds gets the missing gaits searched and is estimated
    /// again (`limbfuse-workflows::imm_library_extension`; default on).
    /// Always `false` for the paper configuration.
    pub extend_library: bool,
    /// The trial body's leg length (m) and mass (kg) given as flags or in
    /// the parameter file (else the trial metadata is read).
    pub leg_length: Option<f64>,
    /// See `leg_length`.
    pub mass: Option<f64>,
    /// Whether the templates were rescaled to a CoM height (then the body
    /// is not fitted again).
    pub height_rescaled: bool,
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

fn config(flag: &'static str, text: &str) -> Result<ImmConfig, MethodError> {
    [ImmConfig::Paper, ImmConfig::Continuous]
        .into_iter()
        .find(|c| c.label() == text)
        .ok_or_else(|| MethodError::BadFlagValue {
            flag,
            expected: "`paper` or `continuous`",
            found: text.to_string(),
        })
}

fn on_off(flag: &'static str, text: &str) -> Result<bool, MethodError> {
    match text {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(MethodError::BadFlagValue {
            flag,
            expected: "`on` or `off`",
            found: text.to_string(),
        }),
    }
}

/// The templates for the trial's body (rescaled by Froude similarity when
/// the library was built for another body) and the message saying so.
pub fn templates_for_trial(
    spec: &ImmSpec,
    meta: &TrialMeta,
) -> Result<(Vec<GaitTemplate>, Option<String>), MethodError> {
    if spec.height_rescaled {
        return Ok((spec.templates.clone(), None));
    }
    let body = crate::imm_body::trial_body(spec.mass, spec.leg_length, meta)?;
    crate::imm_body::fit_library(spec.templates.clone(), &body)
}

/// The slowest and fastest gait (m/s) of the library as used on a trial
/// with metadata `meta` (rescaled to its body, as [`templates_for_trial`]).
pub fn library_speed_range(spec: &ImmSpec, meta: &TrialMeta) -> Result<(f64, f64), MethodError> {
    let (templates, _) = templates_for_trial(spec, meta)?;
    Ok(templates
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), g| {
            (lo.min(g.speed), hi.max(g.speed))
        }))
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
    if let (Some((_, path)), Some(l)) = (file, &f.library) {
        if l.as_os_str().is_empty() {
            return Err(crate::params_toml::ParamsFileError::Invalid {
                path: path.to_path_buf(),
                message: "`library` is empty: expected the path of a gait-library file".into(),
            }
            .into());
        }
    }
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
    // The body sizes, whichever configuration reads them (an audit:
    // `rescale_height = 1e300` gave a constant phase, and with it in the
    // file `mass = nan` passed unchecked).
    use crate::body_ranges::{leg_length_m, mass_kg};
    let named = |by_flag: bool, flag: &str, key: &str| match by_flag {
        true => flag.to_string(),
        false => match file {
            Some((_, path)) => format!("{}: `{key}`", path.display()),
            None => format!("the parameter file's `{key}`"),
        },
    };
    if let Some(h) = flags.rescale_height.or(f.rescale_height) {
        let name = named(
            flags.rescale_height.is_some(),
            "--rescale-height",
            "rescale_height",
        );
        leg_length_m(&name, h).map_err(MethodError::ImmParams)?;
    }
    if let Some(l) = flags.leg_length.or(f.leg_length) {
        let name = named(flags.leg_length.is_some(), "--leg-length", "leg_length");
        leg_length_m(&name, l).map_err(MethodError::ImmParams)?;
    }
    if let Some(m) = flags.mass.or(f.mass) {
        let name = named(flags.mass.is_some(), "--mass", "mass");
        mass_kg(&name, m).map_err(MethodError::ImmParams)?;
    }
    let templates = load_templates(&library, flags.rescale_height.or(f.rescale_height))?;
    let weights = match (&flags.imm_weights, &f.weights) {
        (Some(w), _) => weights("--imm-weights", w)?,
        (None, Some(w)) => weights("weights", w)?,
        (None, None) => ImmWeights::Paper,
    };
    let config = match (&flags.imm_config, &f.configuration) {
        (Some(c), _) => config("--imm-config", c)?,
        (None, Some(c)) => config("configuration", c)?,
        (None, None) => ImmConfig::Paper,
    };
    if config == ImmConfig::Continuous && flags.imm_touchdown.is_some() {
        return Err(MethodError::ImmParams(
            "--imm-touchdown applies to the paper configuration only (continuous places feet \
             from the data)"
                .into(),
        ));
    }
    let extend_library = match (&flags.imm_extend_library, &f.extend_library) {
        (Some(e), _) => Some(on_off("--imm-extend-library", e)?),
        (None, Some(e)) => Some(on_off("extend_library", e)?),
        (None, None) => None,
    };
    if config == ImmConfig::Paper && extend_library == Some(true) {
        return Err(MethodError::ImmParams(
            "--imm-extend-library on applies to the continuous configuration only (the paper \
             configuration keeps its library as it is)"
                .into(),
        ));
    }
    let extend_library = config == ImmConfig::Continuous && extend_library.unwrap_or(true);
    let touchdown = match (&flags.imm_touchdown, &f.touchdown) {
        (Some(w), _) => touchdown("--imm-touchdown", w)?,
        (None, Some(w)) => touchdown("touchdown", w)?,
        (None, None) => TouchdownRule::Height,
    };
    // The continuous configuration's weights default to the standard IMM
    // mode probability (docs/GAIT_IMM.md).
    let weights = match (config, flags.imm_weights.is_some() || f.weights.is_some()) {
        (ImmConfig::Continuous, false) => ImmWeights::Recursive,
        _ => weights,
    };
    // (an audit: `--kappa nan` was reported against the trial file, as the
    // estimator's "kappa must be non-negative")
    if let Some(k) = flags
        .kappa
        .or(f.kappa)
        .filter(|k| !(k.is_finite() && *k >= 0.0))
    {
        let source = if flags.kappa.is_some() {
            "--kappa".to_string()
        } else {
            "the parameter file's `kappa`".to_string()
        };
        return Err(MethodError::ImmParams(format!(
            "{source} {k}: expected a gain of 0 (off) or more, in 1/m^2 (eq 14)"
        )));
    }
    Ok(ImmSpec {
        library,
        height_rescaled: flags.rescale_height.or(f.rescale_height).is_some(),
        templates,
        kappa: flags.kappa.or(f.kappa),
        weights,
        touchdown,
        config,
        extend_library,
        leg_length: flags.leg_length.or(f.leg_length),
        mass: flags.mass.or(f.mass),
    })
}

/// The estimator for a trial: position-only defaults (eqs 17-18) when the
/// trial has no CoM velocity channel, else eqs 15-16.
pub fn build_imm(spec: &ImmSpec, layout: &TrialLayout) -> Result<ImmBslip, MethodError> {
    let params = imm_params(spec, layout);
    ImmBslip::new(&spec.templates, params).map_err(|e| MethodError::ImmParams(e.to_string()))
}

/// The estimator of `spec`'s configuration for a trial (metadata: the
/// body; columns: the measurement model).
pub fn build_for_trial(
    spec: &ImmSpec,
    meta: &TrialMeta,
    layout: &TrialLayout,
) -> Result<Box<dyn Estimator + Send>, MethodError> {
    let (templates, _) = templates_for_trial(spec, meta)?;
    build_over(spec, &templates, layout)
}

/// The estimator of `spec`'s configuration over `templates`, already fitted
/// to the trial's body (as [`templates_for_trial`] gives them, or extended
/// by the gait search).
pub fn build_over(
    spec: &ImmSpec,
    templates: &[GaitTemplate],
    layout: &TrialLayout,
) -> Result<Box<dyn Estimator + Send>, MethodError> {
    let params = imm_params(spec, layout);
    let err =
        |e: limbfuse_estimators::imm_bslip::ImmBslipError| MethodError::ImmParams(e.to_string());
    Ok(match spec.config {
        ImmConfig::Paper => Box::new(SwayRestart::new(
            ImmBslip::new(templates, params).map_err(err)?,
        )),
        ImmConfig::Continuous => Box::new(SwayRestart::new(
            ImmContinuous::new(templates, params).map_err(err)?,
        )),
    })
}

fn imm_params(spec: &ImmSpec, layout: &TrialLayout) -> ImmBslipParams {
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
    params
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
        "library, kappa, rescale_height, weights, touchdown, configuration, extend_library, leg_length, mass (file keys or --library, --kappa, --imm-config, ...)",
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
        meta: &TrialMeta,
        layout: &TrialLayout,
    ) -> Result<Box<dyn Estimator + Send>, MethodError> {
        build_for_trial(spec, meta, layout)
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
         touchdown = \"{}\"  # \"height\", \"step-clock\" or \"mixed\"\n\
         configuration = \"paper\"  # or \"continuous\" (then weights default to \"recursive\" and touchdown is not used)\n\
         # extend_library = \"on\"  # continuous: search the gaits a trial outside the library's speeds needs (\"off\": keep the library)\n\
         # leg_length = 0.95  # trial body, m (else the trial metadata); a library for another body is rescaled\n\
         # mass = 70  # trial body, kg\n",
        full.kappa,
        full.kappa,
        pos.kappa,
        full.weights.label(),
        full.touchdown.label()
    )
}
