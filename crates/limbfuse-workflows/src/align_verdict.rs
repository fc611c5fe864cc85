//! `inspect`'s verdict on `limbfuse align`: whether it can align a trial
//! whose methods `inspect` lists "after `limbfuse align`" (an audit: it
//! promised them on a lower-back-only trial and on the knee rig, where
//! `align` fails). One source for the CLI's text and JSON and Python's
//! `limbfuse.inspect` (session 29: the JSON and Python lacked it).

use std::path::Path;

use limbfuse_core::{Record, Segment};
use limbfuse_io::{TrialLayout, TrialMeta, TrialReader};
use limbfuse_methods::{Availability, MethodName};
use limbfuse_signal::align::{AlignError, AlignOptions};

use crate::trial_alignment::{align_walking, TrialAlignmentError};

/// The longest trial (rows) on which `inspect` runs the alignment to see
/// whether it succeeds (it reads the trial whole: about 0.5 s and 30 MB
/// per 40 000 rows); longer trials get the column check only.
pub const MAX_ROWS: u64 = 200_000;

/// What `inspect` says about `limbfuse align` on a trial.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AlignVerdict {
    /// Some method reads aligned frames the trial declares raw (it runs
    /// "after `limbfuse align`"); else nothing was checked.
    pub needed: bool,
    /// `Some(true)`: `limbfuse align` (the walking procedure, defaults)
    /// aligns it; `Some(false)`: it cannot (`reason`); `None`: not
    /// checked (not needed, or longer than [`MAX_ROWS`] with the IMUs it
    /// needs).
    pub possible: Option<bool>,
    /// Why it cannot, as `inspect` prints it after "`limbfuse align`
    /// cannot align this trial: ".
    pub reason: Option<String>,
}

impl AlignVerdict {
    /// The line `inspect` prints when `align` cannot align the trial.
    pub fn line(&self) -> Option<String> {
        self.reason
            .as_ref()
            .map(|why| format!("`limbfuse align` cannot align this trial: {why}"))
    }
}

/// The verdict on the trial at `path` (metadata `meta`, columns `layout`,
/// `rows` rows) whose methods have the availability `methods`: first from
/// the columns (no thigh, shank or foot IMU), then by running the
/// alignment. `cancel` (Python's Ctrl-C; the CLI: `None`) is polled while
/// reading the trial and by the alignment
/// ([`AlignOptions::cancel`]); once it says so the verdict is "not
/// checked".
pub fn align_verdict(
    path: &Path,
    meta: &TrialMeta,
    layout: &TrialLayout,
    rows: u64,
    methods: &[(MethodName, Availability)],
    cancel: Option<fn() -> bool>,
) -> AlignVerdict {
    let needed = methods
        .iter()
        .any(|(_, a)| matches!(a, Availability::Runs { after_align: true }));
    let verdict = |possible: Option<bool>, reason: Option<String>| AlignVerdict {
        needed,
        possible,
        reason,
    };
    if !needed {
        return verdict(None, None);
    }
    let leg_imu = [Segment::Thigh, Segment::Shank, Segment::Foot]
        .into_iter()
        .any(|s| layout.acc[s.index()] || layout.gyr[s.index()]);
    if !leg_imu {
        return verdict(Some(false), Some(AlignError::NoLegImu.to_string()));
    }
    if rows > MAX_ROWS {
        return verdict(None, None);
    }
    let stop = || cancel.is_some_and(|f| f());
    let records: Option<Vec<Record>> = TrialReader::open(path).ok().and_then(|r| {
        let mut out = Vec::new();
        for (k, rec) in r.enumerate() {
            if k % 4096 == 4095 && stop() {
                return None;
            }
            out.push(rec.ok()?);
        }
        Some(out)
    });
    let Some(records) = records else {
        return verdict(None, None);
    };
    let mut meta = meta.clone();
    let opts = AlignOptions {
        cancel,
        ..AlignOptions::default()
    };
    match align_walking(&records, layout, &mut meta, &opts) {
        Ok(_) => verdict(Some(true), None),
        Err(TrialAlignmentError::Align(AlignError::Cancelled)) => verdict(None, None),
        Err(e) => verdict(Some(false), Some(e.to_string())),
    }
}
