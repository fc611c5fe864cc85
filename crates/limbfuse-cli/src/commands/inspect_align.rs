//! `inspect`: whether `limbfuse align` can align a trial whose methods it
//! lists "after `limbfuse align`" (an audit: it promised them on a
//! lower-back-only trial and on the knee rig, where `align` fails).

use std::path::Path;

use limbfuse_core::{Record, Segment};
use limbfuse_io::{TrialLayout, TrialMeta, TrialReader};
use limbfuse_signal::align::{AlignError, AlignOptions};
use limbfuse_workflows::trial_alignment::align_walking;

/// The longest trial (rows) on which `inspect` runs the alignment to see
/// whether it succeeds (it reads the trial whole: about 0.5 s and 30 MB
/// per 40 000 rows); longer trials get the column check only.
pub const MAX_ROWS: u64 = 200_000;

/// Why `limbfuse align` (the walking procedure with its defaults) cannot
/// align the trial at `path`, or `None` when it can (or the trial is too
/// long to try): first from the columns (no thigh, shank or foot IMU),
/// then by running it.
pub fn align_failure(
    path: &Path,
    meta: &TrialMeta,
    layout: &TrialLayout,
    rows: u64,
) -> Option<String> {
    let leg_imu = [Segment::Thigh, Segment::Shank, Segment::Foot]
        .into_iter()
        .any(|s| layout.acc[s.index()] || layout.gyr[s.index()]);
    if !leg_imu {
        return Some(AlignError::NoLegImu.to_string());
    }
    if rows > MAX_ROWS {
        return None;
    }
    let records: Vec<Record> = TrialReader::open(path)
        .ok()?
        .collect::<Result<_, _>>()
        .ok()?;
    let mut meta = meta.clone();
    align_walking(&records, layout, &mut meta, &AlignOptions::default())
        .err()
        .map(|e| e.to_string())
}
