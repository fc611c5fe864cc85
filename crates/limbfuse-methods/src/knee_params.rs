//! The parameter file of `knee-selfalign` (paper 002) and its flags.
//!
//! ```toml
//! method = "knee-selfalign"   # optional
//! window_s = 5.0              # s_w as a duration (s): 500 samples at 100 Hz (paper 002)
//! # window = 500              # or s_w in samples, as given (--window)
//! order = 6                   # parameter-EKF iterations per window (--order)
//! zero = "sensor-positions"   # or "paper-c": which sensor pose is 0 deg
//! sign_commit = 0.9           # sign confidence at which the axis-sign pair is kept
//! sign_floor = 0.00061        # spread of the sign evidence that noise alone gives
//! acc_max_spread = 0.0152     # accelerometer angle trusted up to this spread about the gyro angle
//! acc_min_motion = 0.0152     # ... in windows where the gyro angle spreads at least this much
//! acc_rest_tolerance = 0.1    # ... until a rest reads an accelerometer norm off g by more than this (x g)
//! highpass_hz = 0.02          # drift removal while the accelerometer angle is not trusted
//! axis_prior = "upright"      # or "none": paper 002's eq 2 alone
//! upright_min_hinge_ratio = 0.15  # the prior applies where RMS e_j >= this x RMS rate
//! max_sensor_delay_s = 0.0    # thigh-shank time offset searched up to this, either way (0: off)
//! fusion = "paper"            # or "rate-bias": Algorithm 1 plus a relative gyro-bias state (ours)
//! ```

use std::path::Path;

use limbfuse_estimators::knee_gyro_axis::{KneeGyroAxis, KneeGyroAxisParams};
use limbfuse_estimators::knee_selfalign::params::{Fusion, KneeParamError};
use limbfuse_estimators::knee_selfalign::upright::UprightPrior;
use limbfuse_estimators::knee_selfalign::{AngleZero, KneeSelfAlign, KneeSelfAlignParams};
use serde::Deserialize;

use limbfuse_core::Estimator;
use limbfuse_io::{TrialLayout, TrialMeta};

use crate::knee_window::{delay_samples, WindowLength};
use crate::method_def::{read_file, MethodDef, MethodFile, MethodInfo};
use crate::{ChannelNeeds, MethodError, MethodFlags, MethodName};

/// The zero of the accelerometer angle, as written in a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
enum ZeroName {
    #[serde(rename = "sensor-positions")]
    SensorPositions,
    #[serde(rename = "paper-c")]
    PaperC,
}

/// The axis criterion, as written in a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
enum AxisPriorName {
    #[serde(rename = "upright")]
    Upright,
    #[serde(rename = "none")]
    None,
}

/// The angle fusion, as written in a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
enum FusionName {
    #[serde(rename = "paper")]
    Paper,
    #[serde(rename = "rate-bias")]
    RateBias,
}

/// A `knee-selfalign` parameter file.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct KneeSelfAlignFile {
    method: Option<String>,
    window: Option<usize>,
    window_s: Option<f64>,
    order: Option<usize>,
    zero: Option<ZeroName>,
    sign_commit: Option<f64>,
    sign_floor: Option<f64>,
    acc_max_spread: Option<f64>,
    acc_min_motion: Option<f64>,
    acc_rest_tolerance: Option<f64>,
    highpass_hz: Option<f64>,
    axis_prior: Option<AxisPriorName>,
    upright_min_hinge_ratio: Option<f64>,
    max_sensor_delay_s: Option<f64>,
    fusion: Option<FusionName>,
}

/// `knee-selfalign` settings: the estimator's parameters and its window as
/// given (samples, or a duration counted at the trial's rate:
/// [`crate::knee_window`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KneeSelfAlignSettings {
    /// The parameters; `params.window` is the window at 100 Hz, replaced
    /// for the trial by [`KneeSelfAlignSettings::for_trial`].
    pub params: KneeSelfAlignParams,
    /// The window as the file or `--window` gives it.
    pub window: WindowLength,
    /// The largest thigh-shank time offset searched (s; 0: off), counted
    /// in samples at the trial's rate into `params.max_delay`.
    pub max_delay_s: f64,
}

/// Default `max_sensor_delay_s` of both knee methods (s).
pub const DEFAULT_MAX_SENSOR_DELAY_S: f64 = 0.0;

/// `max_sensor_delay_s` of a file, checked: the delay search's bound, 0
/// to 1 s (docs/KNEE_SELFALIGN.md "Sensor time offset").
fn max_delay_s(v: Option<f64>) -> Result<f64, KneeParamError> {
    let s = v.unwrap_or(DEFAULT_MAX_SENSOR_DELAY_S);
    if s.is_finite() && (0.0..=1.0).contains(&s) {
        Ok(s)
    } else {
        Err(KneeParamError {
            name: "max_sensor_delay_s",
            value: s,
            range: "[0, 1] s",
        })
    }
}

/// A knee setting out of range, as the method named reports it.
pub(crate) fn out_of_range(method: MethodName) -> impl Fn(KneeParamError) -> MethodError {
    move |source| MethodError::KneeParams { method, source }
}

/// [`out_of_range`] naming the parameter file when there is one (an audit:
/// a bad `acc_max_spread` named no file).
fn out_of_range_in<'a>(
    method: MethodName,
    file: Option<(&'a str, &'a Path)>,
) -> impl Fn(KneeParamError) -> MethodError + 'a {
    move |source| match file {
        Some((_, path)) => crate::segment_params::ParamsFileError::Invalid {
            path: path.to_path_buf(),
            message: out_of_range(method)(source).to_string(),
        }
        .into(),
        None => out_of_range(method)(source),
    }
}

impl KneeSelfAlignSettings {
    /// The parameters for a trial with this metadata (the window in
    /// samples at its rate), validated.
    pub fn for_trial(&self, meta: &TrialMeta) -> Result<KneeSelfAlignParams, MethodError> {
        let p = KneeSelfAlignParams {
            window: self.window.samples(MethodName::KneeSelfAlign, meta)?,
            max_delay: delay_samples(self.max_delay_s, MethodName::KneeSelfAlign, meta)?,
            ..self.params
        };
        p.validate()
            .map_err(out_of_range(MethodName::KneeSelfAlign))?;
        Ok(p)
    }
}

/// The window at 100 Hz (what `params.window` holds before a trial is known).
fn window_at_paper_rate(w: WindowLength) -> Result<usize, MethodError> {
    w.samples(MethodName::KneeSelfAlign, &TrialMeta::new())
}

/// The settings of a parameter file's text (or the defaults for none) with
/// `--window` / `--order` applied on top, validated.
pub fn knee_params(
    file: Option<(&str, &Path)>,
    flags: &MethodFlags,
) -> Result<KneeSelfAlignSettings, MethodError> {
    let f: KneeSelfAlignFile = read_file::<KneeSelfAlignMethod, _>(file)?;
    let d = KneeSelfAlignParams::default();
    let window = WindowLength::resolve(
        MethodName::KneeSelfAlign,
        flags.window,
        f.window,
        f.window_s,
    )?;
    let p = KneeSelfAlignParams {
        window: window_at_paper_rate(window)?,
        order: flags.order.or(f.order).unwrap_or(d.order),
        zero: match f.zero {
            None => d.zero,
            Some(ZeroName::SensorPositions) => AngleZero::SensorPositions,
            Some(ZeroName::PaperC) => AngleZero::PaperC,
        },
        sign_commit: f.sign_commit.unwrap_or(d.sign_commit),
        sign_floor: f.sign_floor.unwrap_or(d.sign_floor),
        acc_max_spread: f.acc_max_spread.unwrap_or(d.acc_max_spread),
        acc_min_motion: f.acc_min_motion.unwrap_or(d.acc_min_motion),
        acc_rest_tolerance: f.acc_rest_tolerance.unwrap_or(d.acc_rest_tolerance),
        highpass_hz: f.highpass_hz.unwrap_or(d.highpass_hz),
        axis_prior: match f.axis_prior {
            Some(AxisPriorName::None) => None,
            None | Some(AxisPriorName::Upright) => {
                let u = d.axis_prior.unwrap_or_default();
                Some(UprightPrior {
                    min_hinge_ratio: f.upright_min_hinge_ratio.unwrap_or(u.min_hinge_ratio),
                    ..u
                })
            }
        },
        fusion: match f.fusion {
            None => d.fusion,
            Some(FusionName::Paper) => Fusion::Paper,
            Some(FusionName::RateBias) => Fusion::RATE_BIAS,
        },
        ..d
    };
    p.validate()
        .map_err(out_of_range_in(MethodName::KneeSelfAlign, file))?;
    let max_delay_s = max_delay_s(f.max_sensor_delay_s)
        .map_err(out_of_range_in(MethodName::KneeSelfAlign, file))?;
    Ok(KneeSelfAlignSettings {
        params: p,
        window,
        max_delay_s,
    })
}

impl MethodFile for KneeSelfAlignFile {
    fn method(&self) -> Option<&str> {
        self.method.as_deref()
    }
}

/// `knee-selfalign` (paper 002).
#[derive(Debug, Clone, Copy)]
pub struct KneeSelfAlignMethod;

impl MethodDef for KneeSelfAlignMethod {
    const INFO: MethodInfo = MethodInfo::new(
        "knee-selfalign",
        "paper 002: knee angle from raw thigh + shank IMUs, self-identified joint axis and position",
        "raw thigh and shank IMUs (any mounting)",
        "window_s (default 5 s at the trial's rate) or window (samples), order, zero, sign_commit, sign_floor, acc_max_spread, acc_min_motion, acc_rest_tolerance, highpass_hz, axis_prior, upright_min_hinge_ratio, max_sensor_delay_s (file keys or --window/--order)",
    )
    .needing(
        ChannelNeeds::imus([false, true, true, false]),
        "needs the thigh and shank accelerometers and gyroscopes (the knee axis and angle come from both)",
    );
    type Settings = KneeSelfAlignSettings;

    fn resolve(
        file: Option<(&str, &Path)>,
        flags: &MethodFlags,
    ) -> Result<KneeSelfAlignSettings, MethodError> {
        knee_params(file, flags)
    }

    fn build(
        s: &KneeSelfAlignSettings,
        meta: &TrialMeta,
        _: &TrialLayout,
    ) -> Result<Box<dyn Estimator + Send>, MethodError> {
        Ok(Box::new(
            KneeSelfAlign::new(s.for_trial(meta)?)
                .map_err(out_of_range(MethodName::KneeSelfAlign))?,
        ))
    }

    fn default_file() -> String {
        default_file()
    }
}

/// The default file, commented (`limbfuse params --method knee-selfalign`).
pub fn default_file() -> String {
    let d = KneeSelfAlignParams::default();
    format!(
        "# limbfuse knee-selfalign parameters (paper 002; docs/KNEE_SELFALIGN.md).\n\
         method = \"knee-selfalign\"\n\
         {}  # s_w as a duration (s, 0.2 to 1000), in samples at the trial's rate: 500 at 100 Hz (paper 002); or `window = N` samples (20 to 100000) as given; --window N overrides\n\
         order = {}  # parameter-EKF iterations per window (1 to 100); --order overrides\n\
         zero = \"{}\"  # which pose is 0 deg: \"sensor-positions\" or \"paper-c\"\n\
         sign_commit = {}  # sign confidence (0 to 1) at which the axis-sign pair is kept (limbfuse)\n\
         sign_floor = {}  # spread of the sign evidence noise alone gives (0 to 1; limbfuse)\n\
         acc_max_spread = {}  # accelerometer angle trusted up to this spread about the gyro angle (0 to 1; limbfuse)\n\
         acc_min_motion = {}  # ... judged only in windows whose gyro angle spreads at least this (0 to 1; limbfuse)\n\
         acc_rest_tolerance = {}  # ... until a rest reads an accelerometer norm off g by more than this x g ((0, 1]; limbfuse)\n\
         highpass_hz = {}  # high-pass corner (Hz) removing the drift while it is not trusted (limbfuse)\n\
         axis_prior = \"upright\"  # \"upright\" (limbfuse, issue 15) or \"none\" (paper 002: eq 2 alone)\n\
         upright_min_hinge_ratio = {}  # upright prior only where RMS e_j >= this x RMS gyro rate (limbfuse)\n\
         max_sensor_delay_s = {:?}  # thigh-shank time offset searched up to this either way (0 to 1 s; 0: off; limbfuse)\n\
         fusion = \"{}\"  # \"paper\" (Algorithm 1, one state) or \"rate-bias\" (plus a relative gyro-bias state; limbfuse)\n",
        WindowLength::default().file_line(),
        d.order,
        d.zero.name(),
        d.sign_commit,
        d.sign_floor,
        d.acc_max_spread,
        d.acc_min_motion,
        d.acc_rest_tolerance,
        d.highpass_hz,
        d.axis_prior.unwrap_or_default().min_hinge_ratio,
        DEFAULT_MAX_SENSOR_DELAY_S,
        d.fusion.name()
    )
}

/// `knee-gyro-axis` settings: the estimator's parameters and the axis
/// identification's window as given ([`crate::knee_window`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KneeGyroAxisSettings {
    /// The parameters; `params.axes.window` is the window at 100 Hz.
    pub params: KneeGyroAxisParams,
    /// The window as the file or `--window` gives it.
    pub window: WindowLength,
    /// As [`KneeSelfAlignSettings::max_delay_s`].
    pub max_delay_s: f64,
}

impl KneeGyroAxisSettings {
    /// The parameters for a trial with this metadata, validated.
    pub fn for_trial(&self, meta: &TrialMeta) -> Result<KneeGyroAxisParams, MethodError> {
        let mut p = self.params;
        p.axes.window = self.window.samples(MethodName::KneeGyroAxis, meta)?;
        p.axes.max_delay = delay_samples(self.max_delay_s, MethodName::KneeGyroAxis, meta)?;
        p.validate()
            .map_err(out_of_range(MethodName::KneeGyroAxis))?;
        Ok(p)
    }
}

/// A `knee-gyro-axis` parameter file.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct KneeGyroAxisFile {
    method: Option<String>,
    window: Option<usize>,
    window_s: Option<f64>,
    order: Option<usize>,
    corner_hz: Option<f64>,
    max_sensor_delay_s: Option<f64>,
}

impl MethodFile for KneeGyroAxisFile {
    fn method(&self) -> Option<&str> {
        self.method.as_deref()
    }
}

/// `knee-gyro-axis` (issue 15, beyond the papers): the knee angle from the
/// relative gyro rate about the axes `knee-selfalign` identifies.
#[derive(Debug, Clone, Copy)]
pub struct KneeGyroAxisMethod;

impl MethodDef for KneeGyroAxisMethod {
    const INFO: MethodInfo = MethodInfo::new(
        "knee-gyro-axis",
        "beyond the papers: knee angle from the relative gyro rate about the knee axes identified as in paper 002, drift removed by the segments' inclination or a high-pass (cross-check of knee-selfalign)",
        "raw thigh and shank IMUs (any mounting)",
        "window_s (default 5 s at the trial's rate) or window (samples), order, corner_hz, max_sensor_delay_s (file keys or --window/--order)",
    )
    .needing(
        ChannelNeeds::imus([false, true, true, false]),
        "needs the thigh and shank accelerometers and gyroscopes (the knee axes come from both gyros, the inclination from both accelerometers)",
    );
    type Settings = KneeGyroAxisSettings;

    fn resolve(
        file: Option<(&str, &Path)>,
        flags: &MethodFlags,
    ) -> Result<KneeGyroAxisSettings, MethodError> {
        let f: KneeGyroAxisFile = read_file::<KneeGyroAxisMethod, _>(file)?;
        let d = KneeGyroAxisParams::default();
        let window =
            WindowLength::resolve(MethodName::KneeGyroAxis, flags.window, f.window, f.window_s)?;
        let p = KneeGyroAxisParams {
            axes: KneeSelfAlignParams {
                window: window_at_paper_rate(window)?,
                order: flags.order.or(f.order).unwrap_or(d.axes.order),
                ..d.axes
            },
            corner_hz: f.corner_hz.unwrap_or(d.corner_hz),
        };
        p.validate()
            .map_err(out_of_range_in(MethodName::KneeGyroAxis, file))?;
        let max_delay_s = max_delay_s(f.max_sensor_delay_s)
            .map_err(out_of_range_in(MethodName::KneeGyroAxis, file))?;
        Ok(KneeGyroAxisSettings {
            params: p,
            window,
            max_delay_s,
        })
    }

    fn build(
        s: &KneeGyroAxisSettings,
        meta: &TrialMeta,
        _: &TrialLayout,
    ) -> Result<Box<dyn Estimator + Send>, MethodError> {
        Ok(Box::new(
            KneeGyroAxis::new(s.for_trial(meta)?)
                .map_err(out_of_range(MethodName::KneeGyroAxis))?,
        ))
    }

    fn default_file() -> String {
        let d = KneeGyroAxisParams::default();
        format!(
            "# limbfuse knee-gyro-axis parameters (issue 15; docs/KNEE_SELFALIGN.md).\n\
             method = \"knee-gyro-axis\"\n\
             {}  # s_w of the axis identification as a duration (s), in samples at the trial's rate: 500 at 100 Hz; or `window = N` samples as given; --window N overrides\n\
             order = {}  # parameter-EKF iterations per window; --order overrides\n\
             corner_hz = {}  # drift-removal corner frequency (Hz, 0 to 10)\n\
             max_sensor_delay_s = {:?}  # thigh-shank time offset searched up to this either way (0 to 1 s; 0: off)\n",
            WindowLength::default().file_line(),
            d.axes.order,
            d.corner_hz,
            DEFAULT_MAX_SENSOR_DELAY_S
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_override_the_file_and_unknown_keys_are_errors() {
        let path = Path::new("k.toml");
        let flags = MethodFlags {
            order: Some(3),
            ..Default::default()
        };
        let p = knee_params(Some(("window = 300\norder = 5\n", path)), &flags).unwrap();
        assert_eq!((p.params.window, p.params.order), (300, 3));
        assert_eq!(p.window, WindowLength::Samples(300));
        let e = knee_params(Some(("windw = 300\n", path)), &flags).unwrap_err();
        assert!(e.to_string().contains("k.toml:1:1"), "{e}");
        let e = knee_params(Some(("window = 3\n", path)), &MethodFlags::default()).unwrap_err();
        assert!(e.to_string().contains("window"), "{e}");
    }

    #[test]
    fn the_default_file_reads_back_to_the_defaults() {
        let p = knee_params(
            Some((&default_file(), Path::new("d.toml"))),
            &MethodFlags::default(),
        )
        .unwrap();
        assert_eq!(p.params, KneeSelfAlignParams::default());
        assert_eq!(p.window, WindowLength::default());
    }

    #[test]
    fn the_window_is_counted_at_the_trials_rate_unless_given_in_samples() {
        let mut meta = TrialMeta::new();
        meta.set("sample_rate_hz", 250);
        let path = Path::new("k.toml");
        let none = MethodFlags::default();
        let p = knee_params(None, &none).unwrap();
        assert_eq!(p.for_trial(&meta).unwrap().window, 1250);
        assert_eq!(p.for_trial(&TrialMeta::new()).unwrap().window, 500);
        let p = knee_params(Some(("window_s = 2.0\n", path)), &none).unwrap();
        assert_eq!(p.for_trial(&meta).unwrap().window, 500);
        let p = knee_params(Some(("window = 500\n", path)), &none).unwrap();
        assert_eq!(p.for_trial(&meta).unwrap().window, 500);
        // a duration that is too short at this rate is refused when built
        let p = knee_params(Some(("window_s = 0.2\n", path)), &none).unwrap();
        meta.set("sample_rate_hz", 50);
        let e = p.for_trial(&meta).unwrap_err();
        assert!(e.to_string().contains("window"), "{e}");
        let g = KneeGyroAxisMethod::resolve(None, &none).unwrap();
        meta.set("sample_rate_hz", 250);
        assert_eq!(g.for_trial(&meta).unwrap().axes.window, 1250);
        let g =
            KneeGyroAxisMethod::resolve(Some((&KneeGyroAxisMethod::default_file(), path)), &none)
                .unwrap();
        assert_eq!(g.params, KneeGyroAxisParams::default());
    }

    #[test]
    fn axis_prior_keys() {
        let path = Path::new("k.toml");
        let flags = MethodFlags::default();
        let p = knee_params(Some(("axis_prior = \"none\"\n", path)), &flags).unwrap();
        assert_eq!(p.params.axis_prior, None);
        let p = knee_params(Some(("upright_min_hinge_ratio = 0.2\n", path)), &flags).unwrap();
        assert_eq!(p.params.axis_prior.map(|u| u.min_hinge_ratio), Some(0.2));
        let e = knee_params(Some(("upright_min_hinge_ratio = -1\n", path)), &flags).unwrap_err();
        assert!(e.to_string().contains("upright_min_hinge_ratio"), "{e}");
    }

    #[test]
    fn fusion_key() {
        let path = Path::new("k.toml");
        let flags = MethodFlags::default();
        assert_eq!(
            knee_params(None, &flags).unwrap().params.fusion,
            Fusion::Paper
        );
        let p = knee_params(Some(("fusion = \"rate-bias\"\n", path)), &flags).unwrap();
        assert_eq!(p.params.fusion, Fusion::RATE_BIAS);
        let p = knee_params(Some(("fusion = \"paper\"\n", path)), &flags).unwrap();
        assert_eq!(p.params.fusion, Fusion::Paper);
        let e = knee_params(Some(("fusion = \"bias\"\n", path)), &flags).unwrap_err();
        assert!(e.to_string().contains("k.toml:1"), "{e}");
    }
}
