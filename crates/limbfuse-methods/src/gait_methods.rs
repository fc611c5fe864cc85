//! `gait-events` as a method: its parameter file and which foot IMUs of a
//! trial it uses (docs/GAIT_EVENTS.md).
//!
//! ```toml
//! method = "gait-events"     # optional
//! swing_rate = 1.0           # rad/s: foot sagittal rate that confirms swing
//! min_swing_time = 0.15      # s: shortest swing before an initial contact
//! min_rest_time = 0.05       # s: shortest rest that ends a stride's integration
//! shoe_window = 3            # samples: zero-velocity detector window (Skog 2010)
//! shoe_gamma = 3e4           # zero-velocity detector threshold (Skog 2010)
//! axis_time_constant = 10.0  # s: averaging of the medio-lateral axis
//! speed_hold = 3.0           # s: how long a stride's speed is output
//! turn_rate = 15.0           # deg/s: a stride turning faster has no length or speed
//! leg_imu = "auto"           # "auto" (foot IMU, else shank IMU), "foot" or "shank"
//! shank_contact = "zero-crossing"  # shank initial contact: "zero-crossing" or "valley"
//! ```

use std::path::Path;

use limbfuse_core::{Estimator, Segment};
use limbfuse_estimators::gait_events::shank_events::ShankContact;
use limbfuse_estimators::gait_events::{FootSource, GaitEvents, GaitEventsParams};
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
    min_rest_time: Option<f64>,
    shoe_window: Option<usize>,
    shoe_gamma: Option<f64>,
    axis_time_constant: Option<f64>,
    speed_hold: Option<f64>,
    turn_rate: Option<f64>,
    leg_imu: Option<String>,
    shank_contact: Option<String>,
}

impl MethodFile for GaitEventsFile {
    fn method(&self) -> Option<&str> {
        self.method.as_deref()
    }
}

pub(crate) fn positive(key: &'static str, v: Option<f64>, into: &mut f64) -> Result<(), String> {
    if let Some(v) = v {
        if !(v.is_finite() && v > 0.0) {
            return Err(format!("`{key}` = {v}: expected a positive number"));
        }
        *into = v;
    }
    Ok(())
}

/// A parameter-file value within `(lo, hi)`, written into `into` (an
/// audit: thresholds at 1e300 were accepted and found no gait, or a speed
/// of 7e299 m/s).
pub(crate) fn in_range(
    key: &'static str,
    v: Option<f64>,
    (lo, hi): (f64, f64),
    unit: &str,
    into: &mut f64,
) -> Result<(), String> {
    if let Some(v) = v {
        if !(lo..=hi).contains(&v) {
            return Err(format!(
                "`{key}` = {}: expected {lo} to {hi} {unit}",
                crate::shown(v)
            ));
        }
        *into = v;
    }
    Ok(())
}

/// A bad value of `method`'s parameter file (naming the file when there is
/// one) or of the trial's metadata.
pub(crate) fn bad_value(
    file: Option<(&str, &Path)>,
    method: &'static str,
    message: String,
) -> MethodError {
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
        "swing_rate, min_swing_time, min_rest_time, shoe_window, shoe_gamma, axis_time_constant, speed_hold, turn_rate, leg_imu, shank_contact",
    )
    .finding_walking();
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
        // (rad/s: within a 2000 deg/s gyro's range; s: a swing or a foot's
        // rest of walking lasts well under 2 s)
        in_range(
            "swing_rate",
            f.swing_rate,
            (1e-3, 35.0),
            "rad/s (a gyro's range: 2000 deg/s = 34.9 rad/s)",
            &mut p.swing_rate,
        )
        .map_err(&bad)?;
        in_range(
            "min_swing_time",
            f.min_swing_time,
            (1e-3, 2.0),
            "s (a walking swing lasts about 0.4 s)",
            &mut p.min_swing_time,
        )
        .map_err(&bad)?;
        in_range(
            "min_rest_time",
            f.min_rest_time,
            (0.0, 2.0),
            "s",
            &mut p.min_rest_time,
        )
        .map_err(&bad)?;
        positive("shoe_gamma", f.shoe_gamma, &mut p.shoe.gamma).map_err(&bad)?;
        // (below a stride the average follows the swing's own rotation: 0.02 s
        // missed 14 of 56 contacts on the shared two-foot walk, 1 s none)
        in_range(
            "axis_time_constant",
            f.axis_time_constant,
            (1.0, 1e6),
            "s (an average over whole strides: a walking stride lasts about 1 s)",
            &mut p.axis_time_constant,
        )
        .map_err(&bad)?;
        positive("speed_hold", f.speed_hold, &mut p.speed_hold).map_err(&bad)?;
        // The file says deg/s (El-Gohary's unit, as `lowback-speed`'s); the
        // estimator takes rad/s.
        let mut turn_rate_deg = p.turn_rate.to_degrees();
        positive("turn_rate", f.turn_rate, &mut turn_rate_deg).map_err(&bad)?;
        if f.turn_rate.is_some() {
            p.turn_rate = turn_rate_deg.to_radians();
        }
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
        p.gravity = meta.gravity().map_err(MethodError::Metadata)?;
        // A stated accelerometer range is the full scale, as for the gyroscope.
        if meta.get(crate::gated::ACC_RANGE_KEY).is_some() {
            p.acc_full_scale = crate::gated::sensor_ranges(meta)?.acc_m_s2;
        }
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
             # Shortest rest (s) that ends a stride's integration (0: the first rest sample).\n\
             min_rest_time = {:?}\n\
             # Zero-velocity detector (SHOE, Skog et al. 2010, OpenShoe values): window (samples) and threshold.\n\
             shoe_window = {}\n\
             shoe_gamma = {:?}\n\
             # Averaging time constant (s) of the foot's medio-lateral axis.\n\
             axis_time_constant = {:?}\n\
             # How long (s) a stride's speed stays the `speed` output.\n\
             speed_hold = {:?}\n\
             # Mean heading rate (deg/s) above which a stride turns: no length or speed\n\
             # (El-Gohary et al. 2014's turn threshold, as lowback-speed's).\n\
             turn_rate = {:?}\n",
            p.swing_rate,
            p.min_swing_time,
            p.min_rest_time,
            p.shoe.window,
            p.shoe.gamma,
            p.axis_time_constant,
            p.speed_hold,
            (p.turn_rate.to_degrees() * 1e9).round() / 1e9
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
