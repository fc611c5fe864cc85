//! The parameter file of `knee-selfalign` (paper 002) and its flags.
//!
//! ```toml
//! method = "knee-selfalign"   # optional
//! window = 500                # s_w, samples (--window)
//! order = 6                   # parameter-EKF iterations per window (--order)
//! zero = "sensor-positions"   # or "paper-c": which sensor pose is 0 deg
//! sign_commit = 0.9           # sign confidence at which the axis-sign pair is kept
//! sign_floor = 0.00061        # spread of the sign evidence that noise alone gives
//! acc_max_spread = 0.0152     # accelerometer angle trusted up to this spread about the gyro angle
//! acc_min_motion = 0.0152     # ... in windows where the gyro angle spreads at least this much
//! highpass_hz = 0.02          # drift removal while the accelerometer angle is not trusted
//! axis_prior = "upright"      # or "none": paper 002's eq 2 alone
//! upright_min_hinge_ratio = 0.15  # the prior applies where RMS e_j >= this x RMS rate
//! ```

use std::path::Path;

use limbfuse_estimators::knee_gyro_axis::{KneeGyroAxis, KneeGyroAxisParams};
use limbfuse_estimators::knee_selfalign::upright::UprightPrior;
use limbfuse_estimators::knee_selfalign::{AngleZero, KneeSelfAlign, KneeSelfAlignParams};
use serde::Deserialize;

use limbfuse_core::Estimator;
use limbfuse_io::{TrialLayout, TrialMeta};

use crate::method_def::{read_file, MethodDef, MethodFile, MethodInfo};
use crate::{ChannelNeeds, MethodError, MethodFlags};

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

/// A `knee-selfalign` parameter file.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct KneeSelfAlignFile {
    method: Option<String>,
    window: Option<usize>,
    order: Option<usize>,
    zero: Option<ZeroName>,
    sign_commit: Option<f64>,
    sign_floor: Option<f64>,
    acc_max_spread: Option<f64>,
    acc_min_motion: Option<f64>,
    highpass_hz: Option<f64>,
    axis_prior: Option<AxisPriorName>,
    upright_min_hinge_ratio: Option<f64>,
}

/// The parameters of a parameter file's text (or the paper defaults for
/// none) with `--window` / `--order` applied on top, validated.
pub fn knee_params(
    file: Option<(&str, &Path)>,
    flags: &MethodFlags,
) -> Result<KneeSelfAlignParams, MethodError> {
    let f: KneeSelfAlignFile = read_file::<KneeSelfAlignMethod, _>(file)?;
    let d = KneeSelfAlignParams::default();
    let p = KneeSelfAlignParams {
        window: flags.window.or(f.window).unwrap_or(d.window),
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
        ..d
    };
    p.validate()?;
    Ok(p)
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
        "window, order, zero, sign_commit, sign_floor, acc_max_spread, acc_min_motion, highpass_hz, axis_prior, upright_min_hinge_ratio (file keys or --window/--order)",
    )
    .needing(
        ChannelNeeds::imus([false, true, true, false]),
        "needs the thigh and shank accelerometers and gyroscopes (the knee axis and angle come from both)",
    );
    type Settings = KneeSelfAlignParams;

    fn resolve(
        file: Option<(&str, &Path)>,
        flags: &MethodFlags,
    ) -> Result<KneeSelfAlignParams, MethodError> {
        knee_params(file, flags)
    }

    fn build(
        p: &KneeSelfAlignParams,
        _: &TrialMeta,
        _: &TrialLayout,
    ) -> Result<Box<dyn Estimator + Send>, MethodError> {
        Ok(Box::new(KneeSelfAlign::new(*p)?))
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
         window = {}  # s_w, samples (20 to 100000); --window overrides\n\
         order = {}  # parameter-EKF iterations per window (1 to 100); --order overrides\n\
         zero = \"{}\"  # which pose is 0 deg: \"sensor-positions\" or \"paper-c\"\n\
         sign_commit = {}  # sign confidence (0 to 1) at which the axis-sign pair is kept (limbfuse)\n\
         sign_floor = {}  # spread of the sign evidence noise alone gives (0 to 1; limbfuse)\n\
         acc_max_spread = {}  # accelerometer angle trusted up to this spread about the gyro angle (0 to 1; limbfuse)\n\
         acc_min_motion = {}  # ... judged only in windows whose gyro angle spreads at least this (0 to 1; limbfuse)\n\
         highpass_hz = {}  # high-pass corner (Hz) removing the drift while it is not trusted (limbfuse)\n\
         axis_prior = \"upright\"  # \"upright\" (limbfuse, issue 15) or \"none\" (paper 002: eq 2 alone)\n\
         upright_min_hinge_ratio = {}  # upright prior only where RMS e_j >= this x RMS gyro rate (limbfuse)\n",
        d.window,
        d.order,
        d.zero.name(),
        d.sign_commit,
        d.sign_floor,
        d.acc_max_spread,
        d.acc_min_motion,
        d.highpass_hz,
        d.axis_prior.unwrap_or_default().min_hinge_ratio
    )
}

/// A `knee-gyro-axis` parameter file.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct KneeGyroAxisFile {
    method: Option<String>,
    window: Option<usize>,
    order: Option<usize>,
    corner_hz: Option<f64>,
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
        "knee angle from the relative gyro rate about the identified knee axes, drift removed by the segments' inclination or a high-pass (cross-check of knee-selfalign)",
        "raw thigh and shank IMUs (any mounting)",
        "window, order, corner_hz (file keys or --window/--order)",
    )
    .needing(
        ChannelNeeds::imus([false, true, true, false]),
        "needs the thigh and shank accelerometers and gyroscopes (the knee axes come from both gyros, the inclination from both accelerometers)",
    );
    type Settings = KneeGyroAxisParams;

    fn resolve(
        file: Option<(&str, &Path)>,
        flags: &MethodFlags,
    ) -> Result<KneeGyroAxisParams, MethodError> {
        let f: KneeGyroAxisFile = read_file::<KneeGyroAxisMethod, _>(file)?;
        let d = KneeGyroAxisParams::default();
        let p = KneeGyroAxisParams {
            axes: KneeSelfAlignParams {
                window: flags.window.or(f.window).unwrap_or(d.axes.window),
                order: flags.order.or(f.order).unwrap_or(d.axes.order),
                ..d.axes
            },
            corner_hz: f.corner_hz.unwrap_or(d.corner_hz),
        };
        p.validate()?;
        Ok(p)
    }

    fn build(
        p: &KneeGyroAxisParams,
        _: &TrialMeta,
        _: &TrialLayout,
    ) -> Result<Box<dyn Estimator + Send>, MethodError> {
        Ok(Box::new(KneeGyroAxis::new(*p)?))
    }

    fn default_file() -> String {
        let d = KneeGyroAxisParams::default();
        format!(
            "# limbfuse knee-gyro-axis parameters (issue 15; docs/KNEE_SELFALIGN.md).\n\
             method = \"knee-gyro-axis\"\n\
             window = {}  # s_w of the axis identification, samples; --window overrides\n\
             order = {}  # parameter-EKF iterations per window; --order overrides\n\
             corner_hz = {}  # drift-removal corner frequency (Hz, 0 to 10)\n",
            d.axes.window, d.axes.order, d.corner_hz
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
        assert_eq!((p.window, p.order), (300, 3));
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
        assert_eq!(p, KneeSelfAlignParams::default());
    }

    #[test]
    fn axis_prior_keys() {
        let path = Path::new("k.toml");
        let flags = MethodFlags::default();
        let p = knee_params(Some(("axis_prior = \"none\"\n", path)), &flags).unwrap();
        assert_eq!(p.axis_prior, None);
        let p = knee_params(Some(("upright_min_hinge_ratio = 0.2\n", path)), &flags).unwrap();
        assert_eq!(p.axis_prior.map(|u| u.min_hinge_ratio), Some(0.2));
        let e = knee_params(Some(("upright_min_hinge_ratio = -1\n", path)), &flags).unwrap_err();
        assert!(e.to_string().contains("upright_min_hinge_ratio"), "{e}");
    }
}
