//! Parameter files of the segment-angle filters (`--params FILE.toml`).
//!
//! A TOML file names a preset to start from and overrides any parameter of
//! [`LocalKfParams`], [`MarkovJumpKfParams`] or [`GlobalKfParams`]:
//!
//! ```toml
//! method = "mjls"            # optional; must match --method when present
//! preset = "default"         # or "paper-2014"
//! gravity = 9.81             # m/s^2
//! loop_mode = "closed"       # or "open"
//! encoder_sigma = 0.01       # rad; one number or [hip, knee, ankle]
//! accel_hold_s = 0.01        # s; quasi-static duration test, 0 = off
//! startup_s = 2              # s; start-up window, 0 = off (the papers' start)
//!
//! [segments.all]             # applied to the four segments first
//! zeta = 0.5                 # m/s^2
//!
//! [segments.thigh]           # then per segment: trunk, thigh, shank, foot
//! gyro_noise = 2e-4          # rad/s/sqrt(Hz)
//! ```
//!
//! Every key, its unit and range: `docs/TUNING.md`. Unknown keys are errors
//! that name the file, line and key (serde `deny_unknown_fields`); keys of
//! another method (e.g. `encoder_sigma` for `local`) are errors; each value
//! is checked by the filter's own `validate()` as it is applied, so a bad
//! value is reported with its key and the accepted range. [`to_toml`] writes
//! every parameter explicitly (this is what `limbfuse tune` writes), and
//! [`parse_params`] reads it back to the same parameters bit for bit.

use std::path::Path;

use limbfuse_core::discretize::Discretization;
use limbfuse_core::kalman::CovarianceUpdate;
use limbfuse_core::{Estimator, Segment};
use limbfuse_estimators::segment_kf::{
    CommonParams, GlobalKf, GlobalKfParams, LocalKf, LocalKfParams, LoopMode, MarkovJumpKf,
    MarkovJumpKfParams, ParamError, WhenUnreliable,
};
use serde::Deserialize;

pub use crate::params_toml::ParamsFileError;
use crate::MethodName;

mod writer;
pub use writer::{save_params, to_toml};

/// The three segment-angle filters that take a parameter file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FilterMethod {
    /// `local`: matricial local KF.
    Local,
    /// `mjls`: Markov-jump KF.
    Mjls,
    /// `global`: matricial global KF.
    Global,
}

impl FilterMethod {
    /// All three, in `local`, `mjls`, `global` order.
    pub const ALL: [FilterMethod; 3] = [
        FilterMethod::Local,
        FilterMethod::Mjls,
        FilterMethod::Global,
    ];

    /// The method this filter is.
    pub const fn method(self) -> MethodName {
        match self {
            FilterMethod::Local => MethodName::Local,
            FilterMethod::Mjls => MethodName::Mjls,
            FilterMethod::Global => MethodName::Global,
        }
    }

    /// The `--method` name.
    pub const fn name(self) -> &'static str {
        self.method().name()
    }

    /// The segment filter `method` is, if it is one.
    pub const fn from_method(method: MethodName) -> Option<Self> {
        match method {
            MethodName::Local => Some(FilterMethod::Local),
            MethodName::Mjls => Some(FilterMethod::Mjls),
            MethodName::Global => Some(FilterMethod::Global),
            _ => None,
        }
    }
}

/// A starting point for the parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
pub enum Preset {
    /// Physical defaults of a consumer MEMS IMU (`docs/SEGMENT_FILTERS.md`).
    #[default]
    #[serde(rename = "default")]
    Default,
    /// Paper 000 Table 2 weights with the papers' numerics.
    #[serde(rename = "paper-2014")]
    Paper2014,
}

impl Preset {
    /// `default` or `paper-2014`.
    pub const fn name(self) -> &'static str {
        match self {
            Preset::Default => "default",
            Preset::Paper2014 => "paper-2014",
        }
    }

    /// Parses `default` or `paper-2014`.
    pub fn from_name(name: &str) -> Option<Self> {
        [Preset::Default, Preset::Paper2014]
            .into_iter()
            .find(|p| p.name() == name)
    }
}

/// The parameters of one of the three filters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FilterParams {
    /// `local`.
    Local(LocalKfParams),
    /// `mjls`.
    Mjls(MarkovJumpKfParams),
    /// `global`.
    Global(GlobalKfParams),
}

impl FilterParams {
    /// The preset's parameters for `method`.
    pub fn preset(method: FilterMethod, preset: Preset) -> Self {
        match (method, preset) {
            (FilterMethod::Local, Preset::Default) => FilterParams::Local(LocalKfParams::default()),
            (FilterMethod::Local, Preset::Paper2014) => {
                FilterParams::Local(LocalKfParams::paper_2014())
            }
            (FilterMethod::Mjls, Preset::Default) => {
                FilterParams::Mjls(MarkovJumpKfParams::default())
            }
            (FilterMethod::Mjls, Preset::Paper2014) => {
                FilterParams::Mjls(MarkovJumpKfParams::paper_2014())
            }
            (FilterMethod::Global, Preset::Default) => {
                FilterParams::Global(GlobalKfParams::default())
            }
            (FilterMethod::Global, Preset::Paper2014) => {
                FilterParams::Global(GlobalKfParams::paper_2014())
            }
        }
    }

    /// Which filter.
    pub fn method(&self) -> FilterMethod {
        match self {
            FilterParams::Local(_) => FilterMethod::Local,
            FilterParams::Mjls(_) => FilterMethod::Mjls,
            FilterParams::Global(_) => FilterMethod::Global,
        }
    }

    /// The shared parameters.
    pub fn common(&self) -> &CommonParams {
        match self {
            FilterParams::Local(p) => &p.common,
            FilterParams::Mjls(p) => &p.common,
            FilterParams::Global(p) => &p.common,
        }
    }

    /// The shared parameters, mutable.
    pub fn common_mut(&mut self) -> &mut CommonParams {
        match self {
            FilterParams::Local(p) => &mut p.common,
            FilterParams::Mjls(p) => &mut p.common,
            FilterParams::Global(p) => &mut p.common,
        }
    }

    /// The filter's own validation.
    pub fn validate(&self) -> Result<(), ParamError> {
        match self {
            FilterParams::Local(p) => p.validate(),
            FilterParams::Mjls(p) => p.validate(),
            FilterParams::Global(p) => p.validate(),
        }
    }

    /// A new filter with these parameters.
    pub fn build(&self) -> Result<Box<dyn Estimator + Send>, ParamError> {
        Ok(match self {
            FilterParams::Local(p) => Box::new(LocalKf::new(*p)?),
            FilterParams::Mjls(p) => Box::new(MarkovJumpKf::new(*p)?),
            FilterParams::Global(p) => Box::new(GlobalKf::new(*p)?),
        })
    }
}

#[derive(Debug, Clone, Copy, Deserialize)]
enum RawLoop {
    #[serde(rename = "closed")]
    Closed,
    #[serde(rename = "open")]
    Open,
}

#[derive(Debug, Clone, Copy, Deserialize)]
enum RawDiscretization {
    #[serde(rename = "exact")]
    Exact,
    #[serde(rename = "euler")]
    Euler,
}

#[derive(Debug, Clone, Copy, Deserialize)]
enum RawCovariance {
    #[serde(rename = "joseph")]
    Joseph,
    #[serde(rename = "standard")]
    Standard,
}

#[derive(Debug, Clone, Copy, Deserialize)]
enum RawWhenUnreliable {
    #[serde(rename = "predict-only")]
    PredictOnly,
    #[serde(rename = "encoders-only")]
    EncodersOnly,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSegment {
    gyro_noise: Option<f64>,
    bias_drive: Option<f64>,
    bias_tau: Option<f64>,
    accel_angle_sigma: Option<f64>,
    zeta: Option<f64>,
    initial_gyro_bias: Option<f64>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSegments {
    all: Option<RawSegment>,
    trunk: Option<RawSegment>,
    thigh: Option<RawSegment>,
    shank: Option<RawSegment>,
    foot: Option<RawSegment>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    method: Option<MethodName>,
    preset: Option<Preset>,
    gravity: Option<f64>,
    p0_angle_sigma: Option<f64>,
    p0_bias_sigma: Option<f64>,
    loop_mode: Option<RawLoop>,
    discretization: Option<RawDiscretization>,
    covariance_update: Option<RawCovariance>,
    accel_hold_s: Option<f64>,
    accel_max_rate: Option<f64>,
    startup_s: Option<f64>,
    first_sample_start: Option<bool>,
    rate_spike_test: Option<bool>,
    min_reliable: Option<i64>,
    encoder_sigma: Option<toml::Value>,
    when_unreliable: Option<RawWhenUnreliable>,
    relative_sigma: Option<toml::Value>,
    segments: Option<RawSegments>,
}

fn three(path: &Path, key: &str, what: &str, v: &toml::Value) -> Result<[f64; 3], ParamsFileError> {
    let num = |v: &toml::Value| match v {
        toml::Value::Float(x) => Some(*x),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    };
    let out = match v {
        toml::Value::Array(a) if a.len() == 3 => {
            let n: Vec<f64> = a.iter().filter_map(num).collect();
            (n.len() == 3).then(|| [n[0], n[1], n[2]])
        }
        other => num(other).map(|x| [x; 3]),
    };
    out.ok_or_else(|| ParamsFileError::Invalid {
        path: path.to_path_buf(),
        message: format!(
            "`{key}`: expected a number or an array of 3 numbers [hip, knee, ankle] ({what}), found `{v}`"
        ),
    })
}

/// Unit and meaning of a key, for error messages.
fn unit_of(key: &str) -> &'static str {
    let field = key.rsplit('.').next().unwrap_or(key);
    match field {
        "gyro_noise" => "gyro white-noise density, rad/s/sqrt(Hz)",
        "bias_drive" => "bias random-walk density, rad/s/sqrt(s)",
        "bias_tau" => "bias correlation time, s (inf allowed)",
        "accel_angle_sigma" => "accelerometer-angle standard deviation, rad",
        "zeta" => "reliability threshold on | ||a|| - g |, m/s^2",
        "initial_gyro_bias" => "gyro bias at start, rad/s",
        "gravity" => "m/s^2",
        "p0_angle_sigma" => "initial angle standard deviation, rad",
        "p0_bias_sigma" => "initial bias standard deviation, rad/s",
        "min_reliable" => "count s of the criterion Psi_s",
        "accel_hold_s" => "quasi-static duration of rho < zeta, s (0 = off)",
        "accel_max_rate" => "angular-rate bound of the accelerometer test, rad/s (inf = off)",
        "startup_s" => "start-up window, s (0 = off: the papers' start)",
        "first_sample_start" => {
            "start every segment at its first accelerometer sample (the start before 2026-12-06)"
        }
        "rate_spike_test" => {
            "replace a gyroscope spike the encoders contradict (false = apply every reading, the papers')"
        }
        "encoder_sigma" => "encoder standard deviation, rad",
        "relative_sigma" => "relative-row standard deviation, rad",
        _ => "",
    }
}

struct Applier<'a> {
    path: &'a Path,
    params: FilterParams,
}

impl Applier<'_> {
    /// Applies one override and validates the result; an error names `key`.
    fn set(
        &mut self,
        key: &str,
        shown: impl std::fmt::Display,
        f: impl FnOnce(&mut FilterParams),
    ) -> Result<(), ParamsFileError> {
        f(&mut self.params);
        // (numbers as `shown`: `1e-300`, not 300 zeros)
        let shown = shown.to_string();
        let shown = shown.parse::<f64>().map_or(shown, crate::shown);
        self.params
            .validate()
            .map_err(|e| ParamsFileError::Invalid {
                path: self.path.to_path_buf(),
                message: format!("`{key}` = {shown}: {} ({})", e.reason, unit_of(key)),
            })
    }

    fn only_for(&self, key: &str, methods: &[FilterMethod]) -> Result<(), ParamsFileError> {
        let m = self.params.method();
        if methods.contains(&m) {
            return Ok(());
        }
        Err(ParamsFileError::Invalid {
            path: self.path.to_path_buf(),
            message: format!(
                "`{key}` applies to method {} only, but the file is read for method `{}`",
                methods
                    .iter()
                    .map(|m| format!("`{}`", m.name()))
                    .collect::<Vec<_>>()
                    .join(" and "),
                m.name()
            ),
        })
    }

    fn segment(
        &mut self,
        name: &str,
        idx: &[usize],
        s: &RawSegment,
    ) -> Result<(), ParamsFileError> {
        type Field = (&'static str, Option<f64>, fn(&mut CommonParams, usize, f64));
        let fields: [Field; 6] = [
            ("gyro_noise", s.gyro_noise, |c, i, v| {
                c.segments[i].gyro_noise = v
            }),
            ("bias_drive", s.bias_drive, |c, i, v| {
                c.segments[i].bias_drive = v
            }),
            ("bias_tau", s.bias_tau, |c, i, v| c.segments[i].bias_tau = v),
            ("accel_angle_sigma", s.accel_angle_sigma, |c, i, v| {
                c.segments[i].accel_angle_sigma = v
            }),
            ("zeta", s.zeta, |c, i, v| c.segments[i].zeta = v),
            ("initial_gyro_bias", s.initial_gyro_bias, |c, i, v| {
                c.initial_gyro_bias[i] = v
            }),
        ];
        for (field, value, apply) in fields {
            if let Some(v) = value {
                self.set(&format!("segments.{name}.{field}"), v, |p| {
                    for &i in idx {
                        apply(p.common_mut(), i, v);
                    }
                })?;
            }
        }
        Ok(())
    }
}

/// Parses a parameter file's text for `method`; `path` names it in errors.
pub fn parse_params(
    text: &str,
    path: &Path,
    method: FilterMethod,
) -> Result<FilterParams, ParamsFileError> {
    crate::params_toml::check_method_line(text, path, method.name())?;
    let raw: RawFile = crate::params_toml::from_str(text, path)?;
    if let Some(m) = raw.method {
        if m != method.method() {
            return Err(ParamsFileError::Invalid {
                path: path.to_path_buf(),
                message: format!(
                    "`method` = \"{m}\" but the file is read for method `{}` (use --method {m} or remove the `method` line)",
                    method.name(),
                ),
            });
        }
    }
    let mut a = Applier {
        path,
        params: FilterParams::preset(method, raw.preset.unwrap_or_default()),
    };
    if let Some(v) = raw.gravity {
        a.set("gravity", v, |p| p.common_mut().gravity = v)?;
    }
    if let Some(v) = raw.p0_angle_sigma {
        a.set("p0_angle_sigma", v, |p| p.common_mut().p0_angle_sigma = v)?;
    }
    if let Some(v) = raw.p0_bias_sigma {
        a.set("p0_bias_sigma", v, |p| p.common_mut().p0_bias_sigma = v)?;
    }
    if let Some(v) = raw.loop_mode {
        let v = match v {
            RawLoop::Closed => LoopMode::Closed,
            RawLoop::Open => LoopMode::Open,
        };
        a.set("loop_mode", v.label(), |p| p.common_mut().loop_mode = v)?;
    }
    if let Some(v) = raw.discretization {
        let v = match v {
            RawDiscretization::Exact => Discretization::Exact,
            RawDiscretization::Euler => Discretization::Euler,
        };
        a.set("discretization", "", |p| p.common_mut().discretization = v)?;
    }
    if let Some(v) = raw.covariance_update {
        let v = match v {
            RawCovariance::Joseph => CovarianceUpdate::Joseph,
            RawCovariance::Standard => CovarianceUpdate::Standard,
        };
        a.set("covariance_update", "", |p| {
            p.common_mut().covariance_update = v
        })?;
    }
    if let Some(v) = raw.accel_hold_s {
        a.set("accel_hold_s", v, |p| p.common_mut().accel_gate.hold_s = v)?;
    }
    if let Some(v) = raw.accel_max_rate {
        a.set("accel_max_rate", v, |p| {
            p.common_mut().accel_gate.max_rate = v
        })?;
    }
    if let Some(v) = raw.startup_s {
        a.set("startup_s", v, |p| p.common_mut().startup_s = v)?;
    }
    if let Some(v) = raw.first_sample_start {
        a.set("first_sample_start", v, |p| {
            p.common_mut().first_sample_start = v
        })?;
    }
    if let Some(v) = raw.rate_spike_test {
        a.only_for(
            "rate_spike_test",
            &[FilterMethod::Mjls, FilterMethod::Global],
        )?;
        a.set("rate_spike_test", v, |p| p.common_mut().rate_spike_test = v)?;
    }
    if let Some(segs) = &raw.segments {
        if let Some(s) = &segs.all {
            a.segment("all", &[0, 1, 2, 3], s)?;
        }
        for (seg, s) in
            Segment::ALL
                .into_iter()
                .zip([&segs.trunk, &segs.thigh, &segs.shank, &segs.foot])
        {
            if let Some(s) = s {
                a.segment(seg.name(), &[seg.index()], s)?;
            }
        }
    }
    if let Some(v) = raw.min_reliable {
        a.only_for("min_reliable", &[FilterMethod::Local, FilterMethod::Global])?;
        let s = u8::try_from(v).unwrap_or(0);
        a.set("min_reliable", v, |p| match p {
            FilterParams::Local(l) => l.min_reliable = s,
            FilterParams::Global(g) => g.min_reliable = s,
            FilterParams::Mjls(_) => {}
        })?;
    }
    if let Some(v) = &raw.encoder_sigma {
        a.only_for("encoder_sigma", &[FilterMethod::Mjls])?;
        let e = three(path, "encoder_sigma", "rad", v)?;
        a.set("encoder_sigma", v, |p| {
            if let FilterParams::Mjls(m) = p {
                m.encoder_sigma = e;
            }
        })?;
    }
    if let Some(v) = raw.when_unreliable {
        a.only_for("when_unreliable", &[FilterMethod::Mjls])?;
        let w = match v {
            RawWhenUnreliable::PredictOnly => WhenUnreliable::PredictOnly,
            RawWhenUnreliable::EncodersOnly => WhenUnreliable::EncodersOnly,
        };
        a.set("when_unreliable", w.label(), |p| {
            if let FilterParams::Mjls(m) = p {
                m.when_unreliable = w;
            }
        })?;
    }
    if let Some(v) = &raw.relative_sigma {
        a.only_for("relative_sigma", &[FilterMethod::Global])?;
        let r = three(path, "relative_sigma", "rad", v)?;
        a.set("relative_sigma", v, |p| {
            if let FilterParams::Global(g) = p {
                g.relative_sigma = r.map(Some);
            }
        })?;
    }
    Ok(a.params)
}

/// Reads and parses a parameter file for `method`.
pub fn load_params(path: &Path, method: FilterMethod) -> Result<FilterParams, ParamsFileError> {
    parse_params(&crate::params_toml::read(path)?, path, method)
}
