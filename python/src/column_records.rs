//! Records read in place from a trial's columns: the column of every
//! record field is resolved once ([`RecordPlan`]: the inputs as
//! [`SampleColumns`], the reference here), then each sample fills a
//! caller-owned [`Record`] from the numpy arrays with no per-sample lookup
//! of channel names.
//!
//! Missing cells are NaN (see [`crate::columns`]). The reference fields are
//! filled as `limbfuse_io::TrialReader::read_into` fills them from a file:
//! a CoM reference vector only when all its components are present, a foot
//! contact 1 / 0 as on the ground / swing.

use limbfuse_core::sample::GaitPhase;
use limbfuse_core::{Record, Sample};
use nalgebra::Vector3;

use crate::column_samples::SampleColumns;
use crate::columns::Channel;

type Column<'a> = Option<&'a [f64]>;

/// The column of every record field a trial has (`None`: not in the trial).
#[derive(Debug, Clone, Default)]
pub struct RecordPlan<'a> {
    inputs: SampleColumns<'a>,
    segment_ref: [Column<'a>; 4],
    joint_ref: [Column<'a>; 3],
    com_pos: Option<[&'a [f64]; 3]>,
    com_vel: Option<[&'a [f64]; 3]>,
    phase: Option<&'a [Option<GaitPhase>]>,
    contact: [Column<'a>; 2],
    speed: Column<'a>,
}

/// All `N` components, or `None` when any is absent.
fn group<'a, const N: usize>(parts: [Column<'a>; N]) -> Option<[&'a [f64]; N]> {
    if parts.iter().all(Option::is_some) {
        Some(parts.map(|p| p.unwrap_or_default()))
    } else {
        None
    }
}

/// The value at `i` (NaN = missing).
#[inline]
fn scalar(c: Column<'_>, i: usize) -> Option<f64> {
    let v = c?[i];
    (!v.is_nan()).then_some(v)
}

/// The foot contact at `i`: 1 on the ground, 0 in swing (the cells are
/// checked by `TrialColumns::new`; any other value reads as missing).
#[inline]
fn contact(c: Column<'_>, i: usize) -> Option<bool> {
    match scalar(c, i)? {
        1.0 => Some(true),
        0.0 => Some(false),
        _ => None,
    }
}

/// The vector at `i`; missing when any component is.
#[inline]
fn vector(c: &Option<[&[f64]; 3]>, i: usize) -> Option<Vector3<f64>> {
    let [x, y, z] = c.as_ref()?;
    let v = Vector3::new(x[i], y[i], z[i]);
    (!v.iter().any(|x| x.is_nan())).then_some(v)
}

impl<'a> RecordPlan<'a> {
    /// The plan of `columns` (a trial's checked columns: every vector group
    /// complete, every column as long as `t`, contact cells 1 / 0 / NaN)
    /// and its `phase_ref` cells.
    pub fn new(
        t: &'a [f64],
        columns: &[(Channel, &'a [f64])],
        phase: Option<&'a [Option<GaitPhase>]>,
    ) -> Self {
        let (mut com_pos, mut com_vel): ([Column<'a>; 3], [Column<'a>; 3]) = ([None; 3], [None; 3]);
        let mut p = RecordPlan {
            inputs: SampleColumns::new(t, columns),
            phase,
            ..RecordPlan::default()
        };
        for &(c, v) in columns {
            let v = Some(v);
            match c {
                Channel::SegmentRef(s) => p.segment_ref[s] = v,
                Channel::JointRef(j) => p.joint_ref[j] = v,
                Channel::ComPos(k) => com_pos[k] = v,
                Channel::ComVel(k) => com_vel[k] = v,
                Channel::ContactRef(side) => p.contact[side.index()] = v,
                Channel::SpeedRef => p.speed = v,
                _ => {}
            }
        }
        p.com_pos = group(com_pos);
        p.com_vel = group(com_vel);
        p
    }

    /// Overwrites every field of `r` with sample `i` (`i < inputs.len()`).
    pub fn fill(&self, i: usize, r: &mut Record) {
        r.sample = Sample::default();
        self.inputs.fill(i, &mut r.sample);
        let re = &mut r.reference;
        for k in 0..4 {
            re.segment[k] = scalar(self.segment_ref[k], i);
        }
        for j in 0..3 {
            re.joint[j] = scalar(self.joint_ref[j], i);
        }
        re.com_pos = vector(&self.com_pos, i);
        re.com_vel = vector(&self.com_vel, i);
        re.phase = self.phase.and_then(|p| p[i]);
        re.contact = [contact(self.contact[0], i), contact(self.contact[1], i)];
        re.speed = scalar(self.speed, i);
    }
}
