//! A whole trial as the mirror-image leg's sensors would read it: every
//! record mirrored ([`super::mirror::mirror_record_in`]), optionally
//! re-mounted at random, and the metadata saying so (`limbfuse mirror`,
//! Python `limbfuse.mirror`; docs/ALIGNMENT.md, "Both legs").

use limbfuse_core::{Leg, Record};
use limbfuse_io::{TrialLayout, TrialMeta};

use super::mirror::{mirror_record_in, remount_rotations_both_legs, world_reflection};
use super::mirror_truth::mirror_truth_lines;
use crate::recording_variants::remount_both_legs;

/// Why a trial cannot be mirrored.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum MirrorTrialError {
    /// The trial has no accelerometer, gyroscope or orientation column.
    #[error(
        "{0}: no IMU channel to mirror (`mirror` turns the accelerometer, gyroscope and \
         orientation columns into the other leg's; this trial has none)"
    )]
    NoImu(String),
    /// `# leg:` is neither right nor left.
    #[error("{trial}: metadata `leg`: expected right or left, found `{found}`")]
    Leg {
        /// The trial, as named in messages.
        trial: String,
        /// The value found.
        found: String,
    },
}

/// A mirrored trial, held in memory.
#[derive(Debug, Clone, PartialEq)]
pub struct MirroredTrial {
    /// The input's metadata with `leg`, `mirrored` (and, re-mounted,
    /// `imu_frame` / `mounting`) set and the simulator's sensor truth mirrored.
    pub meta: TrialMeta,
    /// The input's channels; `leg` is the other leg.
    pub layout: TrialLayout,
    /// One mirrored record per input record.
    pub records: Vec<Record>,
    /// The leg the input was recorded on (`# leg:`, right when unstated).
    pub from: Leg,
    /// The leg the output describes.
    pub to: Leg,
    /// Metadata keys left out because they could not be mirrored.
    pub dropped_meta: Vec<String>,
}

/// The leg a trial was recorded on (`# leg:`, right when unstated), after
/// checking that it has something to mirror: what [`mirror_trial`] checks
/// first, for a caller that wants to know before it reads the records.
pub fn mirrored_leg(
    meta: &TrialMeta,
    layout: &TrialLayout,
    source: &str,
) -> Result<Leg, MirrorTrialError> {
    let has_imu = (0..4).any(|i| {
        layout.acc[i]
            || layout.gyr[i]
            || layout.quat[i]
            || layout.other_acc[i]
            || layout.other_gyr[i]
    });
    if !has_imu {
        return Err(MirrorTrialError::NoImu(source.to_string()));
    }
    match meta.get("leg") {
        None => Ok(Leg::Right),
        Some(text) => Leg::parse(text).ok_or_else(|| MirrorTrialError::Leg {
            trial: source.to_string(),
            found: text.to_string(),
        }),
    }
}

/// Mirrors a trial across the sagittal plane (`source` names it in
/// messages and in the `# mirrored:` line); with `remount_seed`, every
/// sensor is also re-mounted at a random orientation drawn from that seed.
pub fn mirror_trial(
    records: &[Record],
    meta: &TrialMeta,
    layout: TrialLayout,
    source: &str,
    remount_seed: Option<u64>,
) -> Result<MirroredTrial, MirrorTrialError> {
    let from = mirrored_leg(meta, &layout, source)?;
    let to = from.other();
    let mut meta = meta.clone();
    let mut layout = layout;
    meta.set("leg", to.name());
    // Two-leg recordings: the other leg's columns are named after the
    // recorded leg now (`foot_right_...` on a mirrored right-leg trial).
    layout.leg = to;
    let two_legs = (0..4).any(|i| layout.other_acc[i] || layout.other_gyr[i]);
    let world = world_reflection(records);
    meta.set(
        "mirrored",
        format!(
            "from {source} ({} leg): sensors mirrored across the sagittal plane (acc (x, y, -z), gyro (-x, -y, z), {}; two legs: both mirrored, contact references swapped){}{}",
            from.name(),
            world.formula(),
            remount_seed.map_or(String::new(), |s| format!(", re-mounted at random (seed {s})")),
            if two_legs {
                format!(
                    "; the columns without a leg suffix are now the {} leg's, the `_{}_` ones the \
                     {} leg's (description lines above this one describe the recording before \
                     mirroring)",
                    to.name(),
                    from.name(),
                    from.name()
                )
            } else {
                String::new()
            }
        ),
    );
    // A two-leg recording's own description of its columns no longer holds.
    if let Some(legs) = meta.get("legs").map(str::to_string) {
        meta.set("legs", format!("(before `limbfuse mirror`) {legs}"));
    }
    if let Some(seed) = remount_seed {
        meta.set(
            "imu_frame",
            "raw sensor frames (re-mounted at random by limbfuse mirror)",
        );
        if meta.get("mounting").is_some() {
            meta.set(
                "mounting",
                format!("random (re-mounted by limbfuse mirror, seed {seed})"),
            );
        }
    }
    let remount = remount_seed.map(remount_rotations_both_legs);
    // The simulator's truth of each sensor (mounting, biases, positions)
    // follows the readings (an audit: copied unchanged, it no longer
    // described them).
    let dropped_meta = mirror_truth_lines(&mut meta, remount.as_ref().map(|(own, _)| own));
    let records = records
        .iter()
        .map(|r| {
            let m = mirror_record_in(r, world);
            match &remount {
                Some((own, other)) => remount_both_legs(&m, own, other),
                None => m,
            }
        })
        .collect();
    Ok(MirroredTrial {
        meta,
        layout,
        records,
        from,
        to,
        dropped_meta,
    })
}
