//! The warning for a trial whose metadata declares raw sensor frames, given
//! to a method that reads IMU frames aligned to the segments.
//!
//! SPEC section 1: an aligned IMU has z along the segment's medio-lateral
//! axis; raw sensors are mounted anyhow and `limbfuse align` turns their
//! readings into aligned ones. The importers of real recordings (gaittoolbox,
//! knee rig) write `# imu_frame: raw sensor frames (unaligned) ...`; `align`
//! writes `# align_method:` and restates `imu_frame`. A segment filter or the
//! chain run on raw frames integrates whatever axis the sensor's z happens to
//! be (on the shared S02 walk: thigh 82 deg, shank 88 deg RMSE for `chain`),
//! with nothing to say so. The paper-004 knee methods (`sdre`, `ekf`, `rmx`,
//! and our `knee-kinematic`) read the shank's aligned `acc_x` and `gyr_z` or
//! the relative orientation of aligned frames too (`rmx` on the shared S02
//! walk as imported: 20 deg RMSE; on the knee rig: 61 deg; warned since
//! 2026-12-04).

use limbfuse_io::TrialMeta;

use crate::MethodName;

/// The metadata key importers use to declare the IMU frames.
pub const IMU_FRAME_KEY: &str = "imu_frame";

/// The free-text metadata key in which the shared recordings' converters
/// describe the sensors (`# sensors: ... RAW sensor frames ...` in the
/// gaitmap foot walk and the Mobilise-D lower-back files).
pub const SENSORS_KEY: &str = "sensors";

/// Whether `meta` declares raw (unaligned) IMU frames and no alignment:
/// `imu_frame` starting with `raw`, or a `sensors` line saying `raw sensor
/// frame(s)`; and no `align_method`.
pub fn declares_raw_frames(meta: &TrialMeta) -> bool {
    let keyed = meta
        .get(IMU_FRAME_KEY)
        .is_some_and(|v| v.trim_start().to_ascii_lowercase().starts_with("raw"));
    let in_words = meta
        .get(SENSORS_KEY)
        .is_some_and(|v| v.to_ascii_lowercase().contains("raw sensor frame"));
    meta.get("align_method").is_none() && (keyed || in_words)
}

/// A warning when `method` reads aligned frames and the trial `label`
/// declares raw ones ([`declares_raw_frames`]); `None` otherwise.
pub fn raw_frame_note(method: MethodName, meta: &TrialMeta, label: &str) -> Option<String> {
    (method.info().reads_aligned && declares_raw_frames(meta)).then(|| {
        let key = if meta.get(IMU_FRAME_KEY).is_some() {
            IMU_FRAME_KEY
        } else {
            SENSORS_KEY
        };
        format!(
            "warning: {label} declares raw sensor frames (`# {key}:`) and no \
             alignment, but `{}` reads IMU frames aligned to the segments (z = medio-lateral \
             axis, SPEC section 1): its angles will not mean anything. Align the trial first \
             (`limbfuse align TRIAL -o ALIGNED.csv`, docs/ALIGNMENT.md), or use a method that \
             reads raw frames (knee-selfalign, knee-gyro-axis, gait-events, lowback-speed)",
            method.info().name
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn meta(entries: &[(&str, &str)]) -> TrialMeta {
        let mut m = TrialMeta::new();
        for (k, v) in entries {
            m.set(*k, *v);
        }
        m
    }

    #[test]
    fn raw_frames_warn_only_methods_reading_aligned_ones() {
        let raw = meta(&[(IMU_FRAME_KEY, "raw sensor frames (unaligned)")]);
        for name in [
            "gyro-integration",
            "accel-inclination",
            "local",
            "mjls",
            "global",
            "chain",
            "sdre",
            "ekf",
            "rmx",
            "knee-kinematic",
        ] {
            let m = MethodName::parse(name).unwrap();
            let note = raw_frame_note(m, &raw, "t.csv").expect(name);
            assert!(note.contains("t.csv") && note.contains(name), "{note}");
        }
        for name in [
            "knee-selfalign",
            "knee-gyro-axis",
            "gait-events",
            "lowback-speed",
        ] {
            let m = MethodName::parse(name).unwrap();
            assert_eq!(raw_frame_note(m, &raw, "t.csv"), None, "{name}");
        }
    }

    /// The shared gaitmap and Mobilise-D files say it in words.
    #[test]
    fn raw_frames_said_in_the_sensors_line() {
        let gyro = MethodName::parse("gyro-integration").unwrap();
        let said = meta(&[(
            SENSORS_KEY,
            "NilsPod IMUs on the lateral side of each shoe; RAW sensor frames (imu_sample_not_rotated.csv)",
        )]);
        assert!(raw_frame_note(gyro, &said, "t.csv").is_some());
        let aligned = meta(&[(SENSORS_KEY, "ALIGNED (SPEC frame): x forward, y up")]);
        assert_eq!(raw_frame_note(gyro, &aligned, "t.csv"), None);
    }

    #[test]
    fn aligned_or_undeclared_frames_do_not_warn() {
        let local = MethodName::parse("local").unwrap();
        let aligned = meta(&[
            (IMU_FRAME_KEY, "raw sensor frames (unaligned)"),
            ("align_method", "limbfuse-align/1"),
        ]);
        assert_eq!(raw_frame_note(local, &aligned, "t.csv"), None);
        assert_eq!(raw_frame_note(local, &TrialMeta::new(), "t.csv"), None);
        let said_aligned = meta(&[(IMU_FRAME_KEY, "aligned to the segments")]);
        assert_eq!(raw_frame_note(local, &said_aligned, "t.csv"), None);
    }
}
