//! `limbfuse align` as one step for the CLI and the Python `limbfuse.align`:
//! the rotations of a trial's sensors and what its metadata then says, by
//! either procedure (walking data, docs/ALIGNMENT.md; paper 004's quiet
//! standing + rotations, sec 3.3). Applying the rotations to the records
//! and writing them stays with the caller (the CLI streams them to a file).
//!
//! An audit found the Python `align` had neither the CLI's reading gate
//! (one 1e308 gyro cell made it blame the sensor's placement) nor its leg
//! detection (a left-leg recording declared right kept `leg: right`), nor
//! the static-rotation procedure: both front ends now call this.

use limbfuse_core::{Leg, Record, SampleGate, Segment};
use limbfuse_io::{TrialLayout, TrialMeta};
use limbfuse_methods::raw_frames::IMU_FRAME_KEY;
use limbfuse_signal::align::static_rotation::{
    quat_wxyz, static_rotation_alignment, StaticRotationAlignment, StaticRotationError,
    StaticRotationOptions,
};
use limbfuse_signal::align::{estimate_alignment, AlignError, AlignOptions, Alignment};

/// Why a trial could not be aligned.
#[derive(Debug, thiserror::Error)]
pub enum TrialAlignmentError {
    /// The trial's `# gyro_range_rad_s:` / `# acc_range_m_s2:` line.
    #[error(transparent)]
    SensorRange(#[from] limbfuse_methods::MethodError),
    /// The trial has no gyroscope channel.
    #[error("the trial has no gyroscope channels (`<segment>_gyr_x` ...), which alignment needs")]
    NoGyroscope,
    /// The trial's `# g:` line.
    #[error("{0}")]
    Gravity(String),
    /// The procedure failed (the message names the sensor and why).
    #[error(transparent)]
    Align(#[from] AlignError),
    /// The static-rotation procedure failed.
    #[error(transparent)]
    StaticRotation(#[from] StaticRotationError),
}

/// The walking procedure's result.
#[derive(Debug, Clone)]
pub struct WalkingAlignment {
    /// The rotations and their confidence.
    pub alignment: Alignment,
    /// `leg: right (detected, score +0.41; ...)`: the leg line.
    pub leg_line: String,
    /// Set when the detected leg replaced the trial's declared one.
    pub leg_replaced: bool,
    /// Gyroscope and accelerometer readings out of range or implausible
    /// that were left out of the estimate (the trial keeps them), and the
    /// time of the first.
    pub left_out: Option<(u64, u64, f64)>,
    /// The other leg's IMUs (`foot_left_...` of a right-leg trial), which
    /// `align` leaves in their raw sensor frames: what to do about them
    /// (the CLI's warning and Python's `LimbfuseWarning`).
    pub other_leg_raw: Option<String>,
}

/// The rotations from walking data; `meta` gets them (`<segment>_align_quat`
/// ...) and the detected leg.
pub fn align_walking(
    records: &[Record],
    layout: &TrialLayout,
    meta: &mut TrialMeta,
    opts: &AlignOptions,
) -> Result<WalkingAlignment, TrialAlignmentError> {
    if !layout.gyr.iter().any(|&g| g) {
        return Err(TrialAlignmentError::NoGyroscope);
    }
    // The axes come from the readings `estimate` would keep (the written
    // trial keeps every reading).
    let mut gate = SampleGate::new(limbfuse_methods::gated::sensor_ranges(meta)?);
    let screened: Vec<Record> = records
        .iter()
        .map(|r| Record {
            sample: gate.screen(&r.sample),
            ..*r
        })
        .collect();
    let rej = gate.rejections();
    let left_out =
        (rej.gyro + rej.acc > 0).then(|| (rej.gyro, rej.acc, rej.first_t.unwrap_or(f64::NAN)));
    let alignment = estimate_alignment(&screened, opts)?;
    alignment.annotate(meta);
    let (leg_line, leg_replaced) = leg_report(meta, &alignment);
    let other_leg_raw = state_raw_sensors(meta, layout, &alignment);
    Ok(WalkingAlignment {
        alignment,
        leg_line,
        leg_replaced,
        left_out,
        other_leg_raw,
    })
}

/// The metadata key describing a two-leg recording's column naming.
const LEGS_KEY: &str = "legs";

/// When the trial has IMUs `align` leaves raw (the other leg's, or sensors
/// skipped with `--partial`) and declares raw frames in words only
/// (`# sensors: ... RAW sensor frames`, or `# legs:`) or has the other
/// leg's IMUs, its `# imu_frame:` says which are aligned and which raw, and
/// each of `# sensors:` and `# legs:` that says raw points to it (a
/// fresh-user audit, session 28: the gaitmap two-foot walk came out with
/// `foot_` aligned, `foot_left_` raw and "RAW sensor frames" still in
/// `# sensors:` and `# legs:`, and `inspect` said "IMU frames: not
/// stated").
/// Returns the warning about the other leg's IMUs.
fn state_raw_sensors(
    meta: &mut TrialMeta,
    layout: &TrialLayout,
    alignment: &Alignment,
) -> Option<String> {
    use limbfuse_methods::raw_frames::SENSORS_KEY;
    let other = layout.other_leg();
    let other_leg: Vec<String> = Segment::ALL
        .into_iter()
        .filter(|s| layout.other_acc[s.index()] || layout.other_gyr[s.index()])
        .map(|s| format!("{}_{}", s.name(), other.name()))
        .collect();
    // `# sensors:` and `# legs:` may say "RAW sensor frames" (the gaitmap
    // trial says it in both; `# legs:` was left as it was, session 28).
    let says_raw = |key: &str| {
        meta.get(key)
            .is_some_and(|v| v.to_ascii_lowercase().contains("raw sensor frame"))
    };
    let raw_in: Vec<&str> = [SENSORS_KEY, LEGS_KEY]
        .into_iter()
        .filter(|&k| says_raw(k))
        .collect();
    let in_words = meta.get(IMU_FRAME_KEY).is_none() && !raw_in.is_empty();
    if other_leg.is_empty() && !in_words {
        return None;
    }
    let aligned: Vec<&str> = Segment::ALL
        .into_iter()
        .filter(|s| alignment.per_segment[s.index()].is_some())
        .map(Segment::name)
        .collect();
    let mut raw: Vec<String> = alignment
        .skipped
        .iter()
        .map(|(s, _)| s.name().to_string())
        .collect();
    raw.extend(other_leg.iter().cloned());
    let list = |v: &[String]| {
        if v.is_empty() {
            "none".to_string()
        } else {
            v.join(", ")
        }
    };
    let before = match meta.get(IMU_FRAME_KEY) {
        Some(b) => format!("; before: {b}"),
        None => "; before: raw sensor frames (said in `# sensors:`)".to_string(),
    };
    meta.set(
        IMU_FRAME_KEY,
        format!(
            "aligned to the segments by limbfuse align (SPEC section 1): {}; raw sensor frames \
             (not aligned): {}{before}",
            list(&aligned.iter().map(|s| s.to_string()).collect::<Vec<_>>()),
            list(&raw)
        ),
    );
    if in_words {
        for key in raw_in {
            if let Some(s) = meta.get(key).map(str::to_string) {
                meta.set(
                    key,
                    format!("{s} [as recorded; after limbfuse align: see imu_frame]"),
                );
            }
        }
    }
    (!other_leg.is_empty()).then(|| {
        format!(
            "`align` aligns the IMUs of the trial's leg ({}: the columns without a side); {} \
             stay{} in {} raw sensor frame{} (`# imu_frame:` says so). To align {}, make a trial \
             whose leg is the {} (its `{}_...` columns renamed without the side, `# leg: {}`) and \
             align that; `limbfuse import --format gaittoolbox --leg {}` imports a gaittoolbox \
             recording's {} leg that way",
            layout.leg.name(),
            other_leg.join(", "),
            if other_leg.len() == 1 { "s" } else { "" },
            if other_leg.len() == 1 { "its" } else { "their" },
            if other_leg.len() == 1 { "" } else { "s" },
            if other_leg.len() == 1 { "it" } else { "them" },
            other.name(),
            other_leg[0],
            other.name(),
            other.name(),
            other.name()
        )
    })
}

/// The detected leg against the trial's `# leg:` line; a detected leg that
/// differs replaces it (the declared one is kept as `leg_declared`).
fn leg_report(meta: &mut TrialMeta, a: &Alignment) -> (String, bool) {
    let declared = meta.get("leg").map(str::to_string);
    let Some(d) = a.leg else {
        return (
            "leg: not detected (no thigh or shank sensor aligned)".into(),
            false,
        );
    };
    let what = format!("score {:+.2}; right > 0, left < 0", d.score);
    match (d.leg, declared.as_deref().and_then(Leg::parse)) {
        (None, _) => (
            format!(
                "leg: undetermined from the data ({what}); trial says {}",
                declared.as_deref().unwrap_or("nothing")
            ),
            false,
        ),
        (Some(l), Some(dl)) if l == dl => (
            format!("leg: {} (detected, {what}; as the trial says)", l.name()),
            false,
        ),
        (Some(l), _) => {
            let line = format!(
                "leg: {} (detected, {what}); the trial says {}: `leg` set to {}, the declared value kept as `leg_declared`",
                l.name(),
                declared.as_deref().unwrap_or("nothing"),
                l.name()
            );
            let replaced = declared.is_some();
            if let Some(dv) = declared {
                meta.set("leg_declared", dv);
            }
            meta.set("leg", l.name());
            (line, replaced)
        }
    }
}

/// Paper 004's procedure: the rotations from `calibration` (quiet standing
/// and flexion/extension rotations of the same sensors; `calibration_name`
/// names it in `meta`), for every segment of `layout` with both an
/// accelerometer and a gyroscope; `meta` gets them.
pub fn align_static_rotation(
    calibration: &[Record],
    calibration_name: &str,
    layout: &TrialLayout,
    meta: &mut TrialMeta,
) -> Result<StaticRotationAlignment, TrialAlignmentError> {
    let g = meta.gravity().map_err(TrialAlignmentError::Gravity)?;
    let segments: Vec<Segment> = Segment::ALL
        .into_iter()
        .filter(|s| layout.acc[s.index()] && layout.gyr[s.index()])
        .collect();
    let opts = StaticRotationOptions {
        g,
        ..StaticRotationOptions::default()
    };
    let al = static_rotation_alignment(calibration, &segments, &opts)?;
    meta.set("align_method", "static-rotation (paper 004 section 3.3)");
    // (as the walking procedure restates a declaration of raw frames)
    if let Some(before) = meta.get(IMU_FRAME_KEY).map(str::to_string) {
        if before.trim_start().to_ascii_lowercase().starts_with("raw") {
            meta.set(
                IMU_FRAME_KEY,
                format!(
                    "aligned to the segments by limbfuse align --procedure static-rotation \
                     (segments with a `<seg>_align_quat`); before: {before}"
                ),
            );
        }
    }
    meta.set("align_calibration", calibration_name);
    meta.set(
        "align_quiet",
        format!("{:.2}-{:.2} s", al.quiet.0, al.quiet.1),
    );
    for s in &segments {
        let i = s.index();
        if let Some(r) = al.rotations[i] {
            let q = quat_wxyz(&r);
            meta.set(
                format!("{}_align_quat", s.name()),
                format!("{:.9} {:.9} {:.9} {:.9}", q[0], q[1], q[2], q[3]),
            );
            meta.set(
                format!("{}_align_rotations", s.name()),
                al.positive_rotations[i],
            );
            meta.set(
                format!("{}_align_z_correction_deg", s.name()),
                format!("{:.3}", al.z_correction[i].to_degrees()),
            );
        }
    }
    Ok(al)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_trial_without_gyroscopes_is_refused_before_anything_runs() {
        let mut meta = TrialMeta::trial_v1();
        let e = align_walking(
            &[],
            &TrialLayout::default(),
            &mut meta,
            &AlignOptions::default(),
        )
        .unwrap_err();
        assert!(matches!(e, TrialAlignmentError::NoGyroscope), "{e}");
    }
}
