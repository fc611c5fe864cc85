//! `lowback-speed` as a method: its parameter file and where the pendulum
//! length comes from (docs/GAIT_EVENTS.md).
//!
//! ```toml
//! method = "lowback-speed"   # optional
//! leg_length = 0.9275        # m: pendulum length (else from the trial metadata)
//! correction = 1.25          # Zijlstra & Hof 2003 factor K
//! ```

use std::path::Path;

use limbfuse_core::Estimator;
use limbfuse_estimators::lowback_speed::{
    LowbackParams, LowbackSpeed, LEG_LENGTH_PER_HEIGHT, SENSOR_HEIGHT_CORRECTION,
};
use limbfuse_io::body_meta::subject_length;
use limbfuse_io::{TrialLayout, TrialMeta};
use limbfuse_models::DEFAULT_BODY_HEIGHT_M;
use serde::Deserialize;

use crate::body_ranges::{within, BODY_HEIGHT_M, LEG_LENGTH_M, LOWER_BACK_SENSOR_M};
use crate::gait_methods::{bad_value, in_range, positive};
use crate::method_def::{read_file, MethodDef, MethodFile, MethodInfo};
use crate::{MethodError, MethodFlags};

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
    side_min_rate: Option<f64>,
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
        "beyond the papers: initial contacts (McCamley 2012), their feet (McCamley 2012, Ullrich 2021) and walking speed (Zijlstra & Hof 2003 inverted pendulum) from one lower-back IMU",
        "trunk_acc (lower back, raw sensor frame); pendulum length from the parameter file, `# sensor_height_m:`, `# leg_length:` or `# height_m:` (m)",
        "leg_length, correction, wavelet_scale, walking_rms, speed_hold, turn_rate, withhold_after_turn, gravity_follows_gyro, side_min_rate",
    )
    .needing(
        crate::ChannelNeeds {
            acc: [true, false, false, false],
            gyr: [false; 4],
            encoder: [false; 3],
            com_position: false,
        },
        "estimates walking speed from a lower-back accelerometer",
    )
    .finding_walking();
    type Settings = LowbackSettings;

    fn resolve(
        file: Option<(&str, &Path)>,
        _flags: &MethodFlags,
    ) -> Result<LowbackSettings, MethodError> {
        let f: LowbackFile = read_file::<Self, _>(file)?;
        let bad = |message: String| bad_value(file, Self::INFO.name, message);
        let mut p = LowbackParams::default();
        // The pendulum's length and correction within a human's (an audit:
        // `correction = 1e300` gave speeds of 7e299 m/s, `leg_length =
        // 1e-300` a speed of 0 everywhere, both with exit 0).
        in_range(
            "leg_length",
            f.leg_length,
            LEG_LENGTH_M,
            "m: a leg length or a lower-back sensor height",
            &mut p.leg_length,
        )
        .map_err(&bad)?;
        in_range(
            "correction",
            f.correction,
            CORRECTION,
            "(the published factors: 1.0-1.25)",
            &mut p.correction,
        )
        .map_err(&bad)?;
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
        // deg/s in the file, as `turn_rate`; 0 gives every contact a side
        // unless its rate is exactly 0 (no gyroscope).
        if let Some(v) = f.side_min_rate {
            if !(v.is_finite() && v >= 0.0) {
                return Err(bad(format!(
                    "side_min_rate = {v}: expected a rate of 0 deg/s or more"
                )));
            }
            p.side_min_rate = v.to_radians();
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
        let (p, _) = pendulum_for_trial(settings, meta)?;
        Ok(Box::new(LowbackSpeed::new(p)))
    }

    fn default_file() -> String {
        let p = LowbackParams::default();
        format!(
            "# limbfuse lowback-speed parameters (docs/GAIT_EVENTS.md); every key optional.\n\
             method = \"lowback-speed\"\n\
             # Pendulum length, m. Left unset, it is the trial's `# sensor_height_m:` (lower-back sensor\n\
             # above the ground; then correction = 4.587 / 4, Mobilise-D) or a `sensor height N cm` in its\n\
             # `# subject:` line, else its `# leg_length:`, else 0.530 x its `# height_m:` or a `height N cm`\n\
             # in its `# subject:` line, else {:?} (0.530 x {} m, Winter 2009 Table 4.1: the default body\n\
             # of every limbfuse method).\n\
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
             gravity_follows_gyro = {:?}\n\
             # Band-passed trunk rate about the vertical (deg/s) at or below which a contact's side\n\
             # (diag_ic_right / diag_ic_left; McCamley 2012, Ullrich 2021) is left unknown.\n\
             side_min_rate = {:?}\n",
            p.leg_length,
            DEFAULT_BODY_HEIGHT_M,
            p.leg_length,
            p.correction,
            p.wavelet_scale,
            p.walking_rms,
            p.speed_hold,
            // Degrees to 1e-9: 15 deg/s, not the 14.999999999999998 the
            // radian round trip gives (read back, it is the default).
            (p.turn_rate.to_degrees() * 1e9).round() / 1e9,
            p.withhold_after_turn,
            p.gravity_follows_gyro,
            (p.side_min_rate.to_degrees() * 1e9).round() / 1e9
        )
    }
}

/// Where a run's pendulum length (and its correction factor) came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PendulumSource {
    /// The parameter file's `leg_length`.
    ParameterFile,
    /// The trial's `# sensor_height_m:` (Mobilise-D pair).
    SensorHeight,
    /// `sensor height N cm` in the trial's free-text `# subject:` line.
    SensorHeightInSubject,
    /// The trial's `# leg_length:`.
    LegLength,
    /// The trial's `# leg_length_m:` (imm-bslip's key), without `# leg_length:`.
    LegLengthM,
    /// 0.530 x the trial's `# height_m:`.
    BodyHeight,
    /// 0.530 x `height N cm` in the trial's free-text `# subject:` line.
    BodyHeightInSubject,
    /// The default: 0.530 x the default body height
    /// ([`DEFAULT_BODY_HEIGHT_M`], 1.75 m), the body of every method's
    /// defaults.
    Default,
}

impl PendulumSource {
    /// What a user reads.
    pub const fn describe(self) -> &'static str {
        match self {
            PendulumSource::ParameterFile => "the parameter file's `leg_length`",
            PendulumSource::SensorHeight => "the trial's `# sensor_height_m:`",
            PendulumSource::SensorHeightInSubject => {
                "the sensor height stated in the trial's `# subject:` line"
            }
            PendulumSource::LegLength => "the trial's `# leg_length:`",
            PendulumSource::LegLengthM => "the trial's `# leg_length_m:` (imm-bslip's key)",
            PendulumSource::BodyHeight => "0.530 x the trial's `# height_m:` (Winter 2009)",
            PendulumSource::BodyHeightInSubject => {
                "0.530 x the body height stated in the trial's `# subject:` line (Winter 2009)"
            }
            PendulumSource::Default => {
                "the default (0.530 x the default body height 1.75 m, Winter 2009)"
            }
        }
    }
}

/// A metadata length refused outside its plausible range
/// ([`crate::body_ranges`]).
/// The pendulum correction factors accepted: around the published 1.0
/// (the bare pendulum), 1.147-1.185 (mobgap's, Mobilise-D) and 1.25
/// (Zijlstra & Hof 2003), with room either side.
const CORRECTION: (f64, f64) = (0.5, 2.0);

fn plausible(key: &str, what: &str, v: f64, (lo, hi): (f64, f64)) -> Result<f64, MethodError> {
    within(v, (lo, hi)).ok_or_else(|| MethodError::GaitParams {
        method: LowbackSpeedMethod::INFO.name,
        message: format!(
            "trial metadata `# {key}: {}`: expected {what} of {lo} to {hi} m",
            crate::error::shown(v)
        ),
    })
}

/// The parameters of `settings` with the pendulum length (and, for a
/// sensor height, the Mobilise-D factor 4.587 / 4 unless the file gives
/// `correction`) for `meta`: the parameter file, else the sensor height
/// (`# sensor_height_m:`, else stated in the `# subject:` line), else
/// `# leg_length:`, else 0.530 x the body height (`# height_m:`, else
/// stated in the `# subject:` line), else the default.
pub fn pendulum_for_trial(
    settings: &LowbackSettings,
    meta: &TrialMeta,
) -> Result<(LowbackParams, PendulumSource), MethodError> {
    let mut p = settings.params;
    if settings.leg_length_given {
        return Ok((p, PendulumSource::ParameterFile));
    }
    let gait_error = |message: String| MethodError::GaitParams {
        method: LowbackSpeedMethod::INFO.name,
        message,
    };
    let sensor_height = match metadata_metres(meta, "sensor_height_m", "a sensor height")? {
        Some(h) => {
            let h = plausible(
                "sensor_height_m",
                "a lower-back sensor height",
                h,
                LOWER_BACK_SENSOR_M,
            )?;
            positive(
                "sensor_height_m (trial metadata)",
                Some(h),
                &mut p.leg_length,
            )
            .map_err(gait_error)?;
            Some(PendulumSource::SensorHeight)
        }
        None => subject_length(meta, "sensor height")
            .and_then(|h| within(h, LOWER_BACK_SENSOR_M))
            .map(|h| {
                p.leg_length = h;
                PendulumSource::SensorHeightInSubject
            }),
    };
    if let Some(source) = sensor_height {
        // The lower-back literature's pendulum: the sensor's height, with
        // the factor fitted for it (Soltani et al. 2021).
        if !settings.correction_given {
            p.correction = SENSOR_HEIGHT_CORRECTION;
        }
        return Ok((p, source));
    }
    // `# leg_length:`, else imm-bslip's `# leg_length_m:` (crate::leg_length_keys).
    let keys = [
        crate::leg_length_keys::LOWBACK_KEY,
        crate::leg_length_keys::IMM_KEY,
    ];
    if let Some((key, _)) = crate::leg_length_keys::stated(meta, keys) {
        if let Some(l) = metadata_metres(meta, key, "a leg length")? {
            let l = plausible(key, "a leg length", l, LEG_LENGTH_M)?;
            let (name, source) = match key == keys[0] {
                true => ("leg_length (trial metadata)", PendulumSource::LegLength),
                false => ("leg_length_m (trial metadata)", PendulumSource::LegLengthM),
            };
            positive(name, Some(l), &mut p.leg_length).map_err(gait_error)?;
            return Ok((p, source));
        }
    }
    // (the height alone: the IMU mounts and segment lengths are not read here)
    let (height, source) = match meta.body_height().map_err(|e| gait_error(e.to_string()))? {
        Some(h) => (Some(h), PendulumSource::BodyHeight),
        None => (
            subject_length(meta, "height").and_then(|h| within(h, BODY_HEIGHT_M)),
            PendulumSource::BodyHeightInSubject,
        ),
    };
    let Some(h) = height else {
        return Ok((p, PendulumSource::Default));
    };
    let h = plausible("height_m", "a body height", h, BODY_HEIGHT_M)?;
    // Anthropometry: the greater-trochanter height of a body of height `h`.
    positive("height_m (trial metadata)", Some(h), &mut p.leg_length).map_err(gait_error)?;
    p.leg_length *= LEG_LENGTH_PER_HEIGHT;
    Ok((p, source))
}

/// The line the CLI shows when the pendulum length comes from the trial's
/// metadata: its value, the factor, and where it came from.
pub fn pendulum_note(
    settings: &LowbackSettings,
    meta: &TrialMeta,
) -> Result<Option<String>, MethodError> {
    let (p, source) = pendulum_for_trial(settings, meta)?;
    Ok(match source {
        PendulumSource::ParameterFile | PendulumSource::Default => None,
        _ => Some(format!(
            "{}: pendulum length {} m from {}, correction factor {}",
            LowbackSpeedMethod::INFO.name,
            p.leg_length,
            source.describe(),
            p.correction
        )),
    })
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

    /// The pendulum length (m) of the defaults on a trial with `meta`.
    fn leg_length_m(meta: &TrialMeta) -> f64 {
        leg_length_line(meta, None)
            .trim_start_matches("leg_length: ")
            .trim_end_matches(" m")
            .parse()
            .unwrap()
    }

    /// The message of the defaults refusing a trial with `meta`.
    fn build_error(meta: &TrialMeta) -> String {
        let settings = LowbackSpeedMethod::resolve(None, &MethodFlags::default()).unwrap();
        match LowbackSpeedMethod::build(&settings, meta, &TrialLayout::default()) {
            Ok(_) => panic!("built"),
            Err(e) => e.to_string(),
        }
    }

    /// `limbfuse params --method lowback-speed` writes `turn_rate = 15.0`
    /// (was 14.999999999999998, the radian round trip), and the file read
    /// back gives the default parameters bit for bit.
    #[test]
    fn default_file_reads_back_as_the_defaults() {
        let text = LowbackSpeedMethod::default_file();
        assert!(text.contains("\nturn_rate = 15.0\n"), "{text}");
        let settings = LowbackSpeedMethod::resolve(
            Some((&text, Path::new("p.toml"))),
            &MethodFlags::default(),
        )
        .unwrap();
        let d = LowbackParams::default();
        assert_eq!(settings.params.turn_rate.to_bits(), d.turn_rate.to_bits());
        assert_eq!(settings.params.leg_length.to_bits(), d.leg_length.to_bits());
        assert!(text.contains("\nside_min_rate = 3.0\n"), "{text}");
        assert_eq!(settings.params.side_min_rate, d.side_min_rate);
    }

    /// `side_min_rate` is in deg/s, 0 or more (2026-12-07).
    #[test]
    fn side_min_rate_is_read_in_degrees_per_second() {
        let read = |v: &str| {
            LowbackSpeedMethod::resolve(
                Some((&format!("side_min_rate = {v}\n"), Path::new("p.toml"))),
                &MethodFlags::default(),
            )
        };
        let p = read("6.0").unwrap().params;
        assert!((p.side_min_rate - 6.0_f64.to_radians()).abs() < 1e-15);
        assert_eq!(read("0.0").unwrap().params.side_min_rate, 0.0);
        let e = read("-1.0").unwrap_err().to_string();
        assert!(
            e.contains("p.toml")
                && e.contains("side_min_rate = -1: expected a rate of 0 deg/s or more"),
            "{e}"
        );
    }

    /// The pendulum length: the parameter file, else `# leg_length:`, else
    /// 0.530 x `# height_m:` (Winter 2009), else 0.530 x the default body
    /// height, 0.9275 m (0.90 m = 0.530 x 1.70 m until 2026-12-05).
    #[test]
    fn leg_length_from_the_body_height() {
        let mut meta = TrialMeta::new();
        assert_eq!(leg_length_line(&meta, None), "leg_length: 0.9275 m");
        meta.set("height_m", "1.6");
        let l = leg_length_m(&meta);
        assert!((l - 0.530 * 1.6).abs() < 1e-12, "{l}");
        meta.set("leg_length", "0.8");
        assert_eq!(leg_length_line(&meta, None), "leg_length: 0.8 m");
        assert_eq!(
            leg_length_line(&meta, Some("leg_length = 0.95\n")),
            "leg_length: 0.95 m"
        );
        let mut bad = TrialMeta::new();
        bad.set("height_m", "tall");
        let err = build_error(&bad);
        assert!(err.contains("height_m"), "{err}");
    }

    /// Session 31 audit: a trial stating its IMU mounts in words (the
    /// independent simulator's FES trials: `thigh: static; ...`) made
    /// lowback-speed, which reads no mount, fail on that line (so a cohort
    /// over such a folder blamed the metadata, not the missing trunk IMU).
    /// Only `# height_m:` is read; a bad height is still refused.
    #[test]
    fn imu_mounts_it_does_not_read_do_not_stop_lowback_speed() {
        let mut meta = TrialMeta::new();
        meta.set("imu_mounts_m", "thigh: static; shank: on the shank axis");
        meta.set("height_m", "1.6");
        let l = leg_length_m(&meta);
        assert!((l - 0.530 * 1.6).abs() < 1e-12, "{l}");
        meta.set("height_m", "tall");
        let err = build_error(&meta);
        assert!(err.contains("height_m"), "{err}");
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

    /// An audit: `# height_m: 1e300` gave a walking speed of 7e149 m/s with
    /// exit 0. The body, leg and sensor heights of the metadata are refused
    /// outside a human's range, naming the key.
    #[test]
    fn implausible_metadata_lengths_are_refused() {
        let settings = LowbackSpeedMethod::resolve(None, &MethodFlags::default()).unwrap();
        for (key, value) in [
            ("height_m", "1e300"),
            ("height_m", "0.3"),
            ("leg_length", "3"),
            ("sensor_height_m", "2.5"),
        ] {
            let mut meta = TrialMeta::new();
            meta.set(key, value);
            let err = LowbackSpeedMethod::build(&settings, &meta, &TrialLayout::default())
                .err()
                .unwrap()
                .to_string();
            assert!(err.contains(&format!("`# {key}: ")), "{key}: {err}");
        }
        let mut ok = TrialMeta::new();
        ok.set("height_m", "1.59");
        assert!(LowbackSpeedMethod::build(&settings, &ok, &TrialLayout::default()).is_ok());
    }

    /// Issue 19: the HA001 files (`mobgap-lowerback`) state the sensor and
    /// body heights only in their free-text `# subject:` line; the
    /// pendulum comes from the sensor height there (Mobilise-D pair), after
    /// the structured keys and before the body height. Fails without the
    /// fix (0.9 m, K 1.25).
    #[test]
    fn issue_19_lowback_sensor_height_from_the_subject_line() {
        let settings = LowbackSpeedMethod::resolve(None, &MethodFlags::default()).unwrap();
        let mut meta = TrialMeta::new();
        meta.set(
            "subject",
            "healthy adult (HA/001), height 159 cm, weight 73 kg, sensor height 96.4 cm; Test5",
        );
        let (p, source) = pendulum_for_trial(&settings, &meta).unwrap();
        assert_eq!(source, PendulumSource::SensorHeightInSubject);
        assert!((p.leg_length - 0.964).abs() < 1e-12, "{}", p.leg_length);
        assert_eq!(p.correction, SENSOR_HEIGHT_CORRECTION);
        let note = pendulum_note(&settings, &meta).unwrap().unwrap();
        assert!(note.contains("`# subject:`"), "{note}");
        meta.set("sensor_height_m", "0.9");
        assert_eq!(
            pendulum_for_trial(&settings, &meta).unwrap().1,
            PendulumSource::SensorHeight
        );
        let mut meta = TrialMeta::new();
        meta.set("subject", "adult, height 159 cm, sensor height 3 m");
        let (p, source) = pendulum_for_trial(&settings, &meta).unwrap();
        assert_eq!(source, PendulumSource::BodyHeightInSubject);
        assert!((p.leg_length - 0.530 * 1.59).abs() < 1e-12);
        assert_eq!(p.correction, LowbackParams::default().correction);
        meta.set("subject", "adult");
        assert_eq!(
            pendulum_for_trial(&settings, &meta).unwrap().1,
            PendulumSource::Default
        );
        assert_eq!(pendulum_note(&settings, &meta).unwrap(), None);
    }
}
