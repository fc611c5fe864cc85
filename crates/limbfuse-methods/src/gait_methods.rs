//! `gait-events` as a method: its parameter file and which foot IMUs of a
//! trial it uses (docs/GAIT_EVENTS.md).
//!
//! ```toml
//! method = "gait-events"     # optional
//! swing_rate = 1.0           # rad/s: foot sagittal rate that confirms swing
//! min_swing_time = 0.15      # s: shortest swing before an initial contact
//! shoe_window = 3            # samples: zero-velocity detector window (Skog 2010)
//! shoe_gamma = 3e4           # zero-velocity detector threshold (Skog 2010)
//! axis_time_constant = 10.0  # s: averaging of the medio-lateral axis
//! speed_hold = 3.0           # s: how long a stride's speed is output
//! leg_imu = "auto"           # "auto" (foot IMU, else shank IMU), "foot" or "shank"
//! shank_contact = "zero-crossing"  # shank initial contact: "zero-crossing" or "valley"
//! ```

use std::path::Path;

use limbfuse_core::{Estimator, Segment};
use limbfuse_estimators::gait_events::shank_events::ShankContact;
use limbfuse_estimators::gait_events::{FootSource, GaitEvents, GaitEventsParams};
use limbfuse_estimators::lowback_speed::{
    LowbackParams, LowbackSpeed, LEG_LENGTH_PER_HEIGHT, SENSOR_HEIGHT_CORRECTION,
};
use limbfuse_io::{TrialLayout, TrialMeta};
use serde::Deserialize;

use crate::method_def::{read_file, MethodDef, MethodFile, MethodInfo};
use crate::params_toml::ParamsFileError;
use crate::{MethodError, MethodFlags};

/// A `gait-events` parameter file.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct GaitEventsFile {
    method: Option<String>,
    swing_rate: Option<f64>,
    min_swing_time: Option<f64>,
    shoe_window: Option<usize>,
    shoe_gamma: Option<f64>,
    axis_time_constant: Option<f64>,
    speed_hold: Option<f64>,
    leg_imu: Option<String>,
    shank_contact: Option<String>,
}

impl MethodFile for GaitEventsFile {
    fn method(&self) -> Option<&str> {
        self.method.as_deref()
    }
}

fn positive(key: &'static str, v: Option<f64>, into: &mut f64) -> Result<(), String> {
    if let Some(v) = v {
        if !(v.is_finite() && v > 0.0) {
            return Err(format!("`{key}` = {v}: expected a positive number"));
        }
        *into = v;
    }
    Ok(())
}

/// A bad value of `method`'s parameter file (naming the file when there is
/// one) or of the trial's metadata.
fn bad_value(file: Option<(&str, &Path)>, method: &'static str, message: String) -> MethodError {
    match file {
        Some((_, path)) => ParamsFileError::Invalid {
            path: path.to_path_buf(),
            message: format!("method `{method}`: {message}"),
        }
        .into(),
        None => MethodError::GaitParams { method, message },
    }
}

/// Which IMU of each leg `gait-events` uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LegImu {
    /// The foot IMU where the leg has one, else its shank IMU.
    #[default]
    Auto,
    /// Foot IMUs only.
    Foot,
    /// Shank IMUs only (events, no stride length or speed).
    Shank,
}

/// `gait-events` settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaitEventsSettings {
    /// The estimator's parameters.
    pub params: GaitEventsParams,
    /// Which IMU of each leg is used.
    pub leg_imu: LegImu,
}

/// `gait-events`.
#[derive(Debug, Clone, Copy)]
pub struct GaitEventsMethod;

impl MethodDef for GaitEventsMethod {
    const INFO: MethodInfo = MethodInfo::new(
        "gait-events",
        "beyond the papers: initial/final contacts, stance/swing, SS1/DS/SS2 phase, stride length and speed from foot IMUs (ZUPT); events from shank IMUs",
        "per leg foot_acc/gyr (foot_<other side>_ for the other leg), else shank_gyr; raw sensor frames",
        "swing_rate, min_swing_time, shoe_window, shoe_gamma, axis_time_constant, speed_hold, leg_imu, shank_contact",
    );
    type Settings = GaitEventsSettings;

    fn resolve(
        file: Option<(&str, &Path)>,
        _flags: &MethodFlags,
    ) -> Result<GaitEventsSettings, MethodError> {
        let f: GaitEventsFile = read_file::<Self, _>(file)?;
        let bad = |message: String| bad_value(file, Self::INFO.name, message);
        let leg_imu = match f.leg_imu.as_deref() {
            None | Some("auto") => LegImu::Auto,
            Some("foot") => LegImu::Foot,
            Some("shank") => LegImu::Shank,
            Some(other) => {
                return Err(bad(format!(
                    "`leg_imu` = \"{other}\": expected \"auto\", \"foot\" or \"shank\""
                )))
            }
        };
        let mut p = GaitEventsParams::default();
        positive("swing_rate", f.swing_rate, &mut p.swing_rate).map_err(&bad)?;
        positive("min_swing_time", f.min_swing_time, &mut p.min_swing_time).map_err(&bad)?;
        positive("shoe_gamma", f.shoe_gamma, &mut p.shoe.gamma).map_err(&bad)?;
        positive(
            "axis_time_constant",
            f.axis_time_constant,
            &mut p.axis_time_constant,
        )
        .map_err(&bad)?;
        positive("speed_hold", f.speed_hold, &mut p.speed_hold).map_err(&bad)?;
        if let Some(w) = f.shoe_window {
            if !(1..=limbfuse_estimators::gait_events::zero_velocity::MAX_WINDOW).contains(&w) {
                return Err(bad(format!(
                    "`shoe_window` = {w}: expected 1 to {} samples",
                    limbfuse_estimators::gait_events::zero_velocity::MAX_WINDOW
                )));
            }
            p.shoe.window = w;
        }
        p.shank_contact = match f.shank_contact.as_deref() {
            None | Some("zero-crossing") => ShankContact::ZeroCrossing,
            Some("valley") => ShankContact::Valley,
            Some(other) => {
                return Err(bad(format!(
                    "`shank_contact` = \"{other}\": expected \"zero-crossing\" or \"valley\""
                )))
            }
        };
        Ok(GaitEventsSettings { params: p, leg_imu })
    }

    fn build(
        settings: &GaitEventsSettings,
        meta: &TrialMeta,
        layout: &TrialLayout,
    ) -> Result<Box<dyn Estimator + Send>, MethodError> {
        let (foot, shank) = (Segment::Foot.index(), Segment::Shank.index());
        let (use_foot, use_shank) = match settings.leg_imu {
            LegImu::Auto => (true, true),
            LegImu::Foot => (true, false),
            LegImu::Shank => (false, true),
        };
        let mut sources = [None; 2];
        let own = layout.leg.index();
        let other = layout.other_leg().index();
        if use_foot && layout.acc[foot] && layout.gyr[foot] {
            sources[own] = Some(FootSource::OwnLeg);
        } else if use_shank && layout.gyr[shank] {
            sources[own] = Some(FootSource::OwnShank);
        }
        if use_foot && layout.other_acc[foot] && layout.other_gyr[foot] {
            sources[other] = Some(FootSource::OtherLeg);
        } else if use_shank && layout.other_gyr[shank] {
            sources[other] = Some(FootSource::OtherShank);
        }
        if sources.iter().all(Option::is_none) {
            let o = layout.other_leg().name();
            let missing = match settings.leg_imu {
                LegImu::Auto => format!(
                    "foot_acc_x/y/z + foot_gyr_x/y/z, or shank_gyr_x/y/z (foot_{o}_ / shank_{o}_ for the other leg)"
                ),
                LegImu::Foot => format!(
                    "foot_acc_x/y/z + foot_gyr_x/y/z (or foot_{o}_acc/gyr_x/y/z for the other leg; `leg_imu = \"foot\"`)"
                ),
                LegImu::Shank => format!(
                    "shank_gyr_x/y/z (or shank_{o}_gyr_x/y/z for the other leg; `leg_imu = \"shank\"`)"
                ),
            };
            return Err(MethodError::MissingChannels {
                method: Self::INFO.name,
                why: "detects gait events from foot IMUs (accelerometer and gyroscope) or shank gyroscopes",
                missing: vec![missing],
                hint: "; a lower-back IMU is neither (use `lowback-speed`)",
            });
        }
        let mut p = settings.params;
        p.gravity = meta.gravity();
        GaitEvents::new(p, sources)
            .map(|e| Box::new(e) as Box<dyn Estimator + Send>)
            .map_err(|e| MethodError::GaitParams {
                method: Self::INFO.name,
                message: e.to_string(),
            })
    }

    fn default_file() -> String {
        let p = GaitEventsParams::default();
        format!(
            "# limbfuse gait-events parameters (docs/GAIT_EVENTS.md); every key optional.\n\
             method = \"gait-events\"\n\
             # Which IMU of each leg: \"auto\" (its foot IMU, else its shank gyroscope), \"foot\" or \"shank\".\n\
             leg_imu = \"auto\"\n\
             # Shank initial contact: \"zero-crossing\" (end of the swing lobe) or \"valley\" (Aminian 2002 / Salarian 2004 minimum after mid-swing).\n\
             shank_contact = \"zero-crossing\"\n\
             # Foot sagittal rate (rad/s) that confirms swing.\n\
             swing_rate = {:?}\n\
             # Shortest swing (s) before an initial contact is accepted.\n\
             min_swing_time = {:?}\n\
             # Zero-velocity detector (SHOE, Skog et al. 2010, OpenShoe values): window (samples) and threshold.\n\
             shoe_window = {}\n\
             shoe_gamma = {:?}\n\
             # Averaging time constant (s) of the foot's medio-lateral axis.\n\
             axis_time_constant = {:?}\n\
             # How long (s) a stride's speed stays the `speed` output.\n\
             speed_hold = {:?}\n",
            p.swing_rate,
            p.min_swing_time,
            p.shoe.window,
            p.shoe.gamma,
            p.axis_time_constant,
            p.speed_hold
        )
    }
}

/// A `lowback-speed` parameter file.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct LowbackFile {
    method: Option<String>,
    leg_length: Option<f64>,
    correction: Option<f64>,
    wavelet_scale: Option<f64>,
    walking_rms: Option<f64>,
    speed_hold: Option<f64>,
    turn_rate: Option<f64>,
    withhold_after_turn: Option<bool>,
    gravity_follows_gyro: Option<bool>,
}

impl MethodFile for LowbackFile {
    fn method(&self) -> Option<&str> {
        self.method.as_deref()
    }
}

/// `lowback-speed` settings: the parameters, and whether the pendulum length
/// and the correction factor were given (else the trial's
/// `# sensor_height_m:` with the Mobilise-D factor, else its `# leg_length:`,
/// else 0.530 x its `# height_m:`, else the default, with Zijlstra & Hof's
/// factor).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LowbackSettings {
    /// The parameters.
    pub params: LowbackParams,
    /// `leg_length` came from the parameter file.
    pub leg_length_given: bool,
    /// `correction` came from the parameter file.
    pub correction_given: bool,
}

/// `lowback-speed`.
#[derive(Debug, Clone, Copy)]
pub struct LowbackSpeedMethod;

impl MethodDef for LowbackSpeedMethod {
    const INFO: MethodInfo = MethodInfo::new(
        "lowback-speed",
        "beyond the papers: initial contacts (McCamley 2012) and walking speed (Zijlstra & Hof 2003 inverted pendulum) from one lower-back IMU",
        "trunk_acc (lower back, raw sensor frame); pendulum length from the parameter file, `# sensor_height_m:`, `# leg_length:` or `# height_m:` (m)",
        "leg_length, correction, wavelet_scale, walking_rms, speed_hold, turn_rate, withhold_after_turn, gravity_follows_gyro",
    )
    .needing(
        crate::ChannelNeeds {
            acc: [true, false, false, false],
            gyr: [false; 4],
            encoder: [false; 3],
            com_position: false,
        },
        "estimates walking speed from a lower-back accelerometer",
    );
    type Settings = LowbackSettings;

    fn resolve(
        file: Option<(&str, &Path)>,
        _flags: &MethodFlags,
    ) -> Result<LowbackSettings, MethodError> {
        let f: LowbackFile = read_file::<Self, _>(file)?;
        let bad = |message: String| bad_value(file, Self::INFO.name, message);
        let mut p = LowbackParams::default();
        positive("leg_length", f.leg_length, &mut p.leg_length).map_err(&bad)?;
        positive("correction", f.correction, &mut p.correction).map_err(&bad)?;
        positive("wavelet_scale", f.wavelet_scale, &mut p.wavelet_scale).map_err(&bad)?;
        positive("walking_rms", f.walking_rms, &mut p.walking_rms).map_err(&bad)?;
        positive("speed_hold", f.speed_hold, &mut p.speed_hold).map_err(&bad)?;
        // The file says deg/s (El-Gohary's unit); the estimator takes rad/s.
        let mut turn_rate_deg = 0.0;
        positive("turn_rate", f.turn_rate, &mut turn_rate_deg).map_err(&bad)?;
        if f.turn_rate.is_some() {
            p.turn_rate = turn_rate_deg.to_radians();
        }
        if let Some(b) = f.withhold_after_turn {
            p.withhold_after_turn = b;
        }
        if let Some(b) = f.gravity_follows_gyro {
            p.gravity_follows_gyro = b;
        }
        Ok(LowbackSettings {
            params: p,
            leg_length_given: f.leg_length.is_some(),
            correction_given: f.correction.is_some(),
        })
    }

    fn build(
        settings: &LowbackSettings,
        meta: &TrialMeta,
        _layout: &TrialLayout,
    ) -> Result<Box<dyn Estimator + Send>, MethodError> {
        let mut p = settings.params;
        let gait_error = |message: String| MethodError::GaitParams {
            method: Self::INFO.name,
            message,
        };
        if !settings.leg_length_given {
            if let Some(h) = metadata_metres(meta, "sensor_height_m", "a sensor height")? {
                // The lower-back literature's pendulum: the sensor's height,
                // with the factor fitted for it (Soltani et al. 2021).
                positive(
                    "sensor_height_m (trial metadata)",
                    Some(h),
                    &mut p.leg_length,
                )
                .map_err(gait_error)?;
                if !settings.correction_given {
                    p.correction = SENSOR_HEIGHT_CORRECTION;
                }
            } else if let Some(l) = metadata_metres(meta, "leg_length", "a leg length")? {
                positive("leg_length (trial metadata)", Some(l), &mut p.leg_length)
                    .map_err(gait_error)?;
            } else if let Some(h) = meta.body().map_err(|e| gait_error(e.to_string()))?.height {
                // Anthropometry: the greater-trochanter height of a body of height `h`.
                positive("height_m (trial metadata)", Some(h), &mut p.leg_length)
                    .map_err(gait_error)?;
                p.leg_length *= LEG_LENGTH_PER_HEIGHT;
            }
        }
        Ok(Box::new(LowbackSpeed::new(p)))
    }

    fn default_file() -> String {
        let p = LowbackParams::default();
        format!(
            "# limbfuse lowback-speed parameters (docs/GAIT_EVENTS.md); every key optional.\n\
             method = \"lowback-speed\"\n\
             # Pendulum length, m. Left unset, it is the trial's `# sensor_height_m:` (lower-back sensor\n\
             # above the ground; then correction = 4.587 / 4, Mobilise-D), else its `# leg_length:`, else\n\
             # 0.530 x its `# height_m:`, else {:?} (0.530 x 1.70 m, Winter 2009 Table 4.1).\n\
             # leg_length = {:?}\n\
             # Zijlstra & Hof 2003 correction factor K (left unset with `# sensor_height_m:`: 4.587 / 4).\n\
             # correction = {:?}\n\
             # McCamley 2012 wavelet scale, s (gaus1 at his 1.25 Hz: 0.2 / 1.25 Hz).\n\
             wavelet_scale = {:?}\n\
             # RMS vertical acceleration (m/s^2) over 2 s above which the subject walks.\n\
             walking_rms = {:?}\n\
             # How long (s) a stride's speed stays the `speed` output.\n\
             speed_hold = {:?}\n\
             # Mean heading rate (deg/s) above which a stride is a turn, its speed unknown\n\
             # (El-Gohary et al. 2014's turn-peak threshold).\n\
             turn_rate = {:?}\n\
             # The stride after a turning stride (its first step turned) has no speed either.\n\
             withhold_after_turn = {:?}\n\
             # The gravity mean is rotated with the trunk gyroscope (follows posture changes).\n\
             gravity_follows_gyro = {:?}\n",
            p.leg_length,
            p.leg_length,
            p.correction,
            p.wavelet_scale,
            p.walking_rms,
            p.speed_hold,
            p.turn_rate.to_degrees(),
            p.withhold_after_turn,
            p.gravity_follows_gyro
        )
    }
}

/// A length (m) from the trial metadata `# key: value` (an optional `m`
/// unit), `None` when the key is absent; an unparseable value is an error
/// naming the key and the value.
fn metadata_metres(meta: &TrialMeta, key: &str, what: &str) -> Result<Option<f64>, MethodError> {
    let Some(text) = meta.get(key) else {
        return Ok(None);
    };
    text.trim()
        .trim_end_matches('m')
        .trim()
        .parse()
        .map(Some)
        .map_err(|_| MethodError::GaitParams {
            method: LowbackSpeedMethod::INFO.name,
            message: format!("trial metadata `# {key}: {text}`: expected {what} in metres"),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `key: value` line the estimator built from `meta` and the
    /// parameter file describes.
    fn parameter_line(meta: &TrialMeta, file: Option<&str>, key: &str) -> String {
        let settings = LowbackSpeedMethod::resolve(
            file.map(|f| (f, Path::new("p.toml"))),
            &MethodFlags::default(),
        )
        .unwrap();
        let est = LowbackSpeedMethod::build(&settings, meta, &TrialLayout::default()).unwrap();
        let mut s = String::new();
        est.describe_parameters(&mut s).unwrap();
        s.lines().find(|l| l.starts_with(key)).unwrap().to_string()
    }

    fn leg_length_line(meta: &TrialMeta, file: Option<&str>) -> String {
        parameter_line(meta, file, "leg_length")
    }

    /// The pendulum length: the parameter file, else `# leg_length:`, else
    /// 0.530 x `# height_m:` (Winter 2009), else 0.90 m.
    #[test]
    fn leg_length_from_the_body_height() {
        let mut meta = TrialMeta::new();
        assert_eq!(leg_length_line(&meta, None), "leg_length: 0.9 m");
        meta.set("height_m", "1.6");
        let l: f64 = leg_length_line(&meta, None)
            .trim_start_matches("leg_length: ")
            .trim_end_matches(" m")
            .parse()
            .unwrap();
        assert!((l - 0.530 * 1.6).abs() < 1e-12, "{l}");
        meta.set("leg_length", "0.8");
        assert_eq!(leg_length_line(&meta, None), "leg_length: 0.8 m");
        assert_eq!(
            leg_length_line(&meta, Some("leg_length = 0.95\n")),
            "leg_length: 0.95 m"
        );
        let mut bad = TrialMeta::new();
        bad.set("height_m", "tall");
        let settings = LowbackSpeedMethod::resolve(None, &MethodFlags::default()).unwrap();
        let err = LowbackSpeedMethod::build(&settings, &bad, &TrialLayout::default())
            .err()
            .unwrap();
        assert!(err.to_string().contains("height_m"), "{err}");
    }

    /// Issue 19 (`lowback4`): `# sensor_height_m:` is the pendulum length with
    /// the Mobilise-D factor 4.587 / 4; it comes before `# leg_length:`; the
    /// parameter file's `leg_length` or `correction` wins; a bad value names
    /// the key. Fails without the fix (the key was ignored: 0.9 m, K 1.25).
    #[test]
    fn issue_19_lowback_sensor_height_metadata_sets_the_pendulum_pair() {
        let line = parameter_line;
        let mut meta = TrialMeta::new();
        meta.set("leg_length", "0.8");
        meta.set("sensor_height_m", "0.964 m");
        assert_eq!(line(&meta, None, "leg_length"), "leg_length: 0.964 m");
        assert_eq!(line(&meta, None, "correction"), "correction: 1.14675");
        let file = Some("correction = 1.3\n");
        assert_eq!(line(&meta, file, "leg_length"), "leg_length: 0.964 m");
        assert_eq!(line(&meta, file, "correction"), "correction: 1.3");
        let file = Some("leg_length = 0.95\n");
        assert_eq!(line(&meta, file, "leg_length"), "leg_length: 0.95 m");
        assert_eq!(line(&meta, file, "correction"), "correction: 1.25");
        let mut bad = TrialMeta::new();
        bad.set("sensor_height_m", "waist");
        let settings = LowbackSpeedMethod::resolve(None, &MethodFlags::default()).unwrap();
        let err = LowbackSpeedMethod::build(&settings, &bad, &TrialLayout::default())
            .err()
            .unwrap()
            .to_string();
        assert!(
            err.contains("sensor_height_m") && err.contains("waist"),
            "{err}"
        );
        bad.set("sensor_height_m", "-1");
        let err = LowbackSpeedMethod::build(&settings, &bad, &TrialLayout::default())
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains("sensor_height_m"), "{err}");
    }

    #[test]
    fn leg_imu_and_shank_contact_settings_are_checked() {
        let r = |text: &str| {
            GaitEventsMethod::resolve(Some((text, Path::new("p.toml"))), &MethodFlags::default())
        };
        assert_eq!(r("leg_imu = \"shank\"\n").unwrap().leg_imu, LegImu::Shank);
        assert_eq!(
            r("shank_contact = \"valley\"\n")
                .unwrap()
                .params
                .shank_contact,
            ShankContact::Valley
        );
        let e = r("leg_imu = \"knee\"\n").unwrap_err().to_string();
        assert!(e.contains("leg_imu") && e.contains("knee"), "{e}");
        let e = r("shank_contact = \"peak\"\n").unwrap_err().to_string();
        assert!(e.contains("shank_contact"), "{e}");
    }
}
