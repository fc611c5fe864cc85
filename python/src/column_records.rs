//! Records read in place from a trial's columns: the column of every
//! record field is resolved once ([`RecordPlan`]), then each sample fills a
//! caller-owned [`Record`] from the numpy arrays with no per-sample lookup
//! of channel names and no record moved ([`ColumnRecords`], a runner
//! [`RecordSource`]).
//!
//! Missing cells are NaN (see [`crate::columns`]); a 3-axis vector or a
//! quaternion is present only when all its components are.

use std::convert::Infallible;

use limbfuse_core::runner::RecordSource;
use limbfuse_core::sample::{GaitPhase, ImuSample};
use limbfuse_core::Record;
use nalgebra::Vector3;

use crate::columns::Channel;

type Column<'a> = Option<&'a [f64]>;

/// The column of every record field a trial has (`None`: not in the trial).
#[derive(Debug, Clone, Default)]
pub struct RecordPlan<'a> {
    t: &'a [f64],
    acc: [Option<[&'a [f64]; 3]>; 4],
    gyr: [Option<[&'a [f64]; 3]>; 4],
    quat: [Option<[&'a [f64]; 4]>; 4],
    encoder: [Column<'a>; 3],
    stim: [Column<'a>; 4],
    motor: [Column<'a>; 3],
    com_meas: [Column<'a>; 6],
    segment_ref: [Column<'a>; 4],
    joint_ref: [Column<'a>; 3],
    com_pos: Option<[&'a [f64]; 3]>,
    com_vel: Option<[&'a [f64]; 3]>,
    phase: Option<&'a [Option<GaitPhase>]>,
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

/// The vector at `i`; missing when any component is.
#[inline]
fn vector(c: &Option<[&[f64]; 3]>, i: usize) -> Option<Vector3<f64>> {
    let [x, y, z] = c.as_ref()?;
    let v = Vector3::new(x[i], y[i], z[i]);
    (!v.iter().any(|x| x.is_nan())).then_some(v)
}

impl<'a> RecordPlan<'a> {
    /// The plan of `columns` (a trial's checked columns: every vector group
    /// complete, every column as long as `t`) and its `phase_ref` cells.
    pub fn new(
        t: &'a [f64],
        columns: &[(Channel, &'a [f64])],
        phase: Option<&'a [Option<GaitPhase>]>,
    ) -> Self {
        let mut acc: [[Column<'a>; 3]; 4] = [[None; 3]; 4];
        let mut gyr: [[Column<'a>; 3]; 4] = [[None; 3]; 4];
        let mut quat: [[Column<'a>; 4]; 4] = [[None; 4]; 4];
        let (mut com_pos, mut com_vel): ([Column<'a>; 3], [Column<'a>; 3]) = ([None; 3], [None; 3]);
        let mut p = RecordPlan {
            t,
            phase,
            ..RecordPlan::default()
        };
        for &(c, v) in columns {
            let v = Some(v);
            match c {
                Channel::Acc(s, k) => acc[s][k] = v,
                Channel::Gyr(s, k) => gyr[s][k] = v,
                Channel::Quat(s, k) => quat[s][k] = v,
                Channel::Encoder(j) => p.encoder[j] = v,
                Channel::Stim(k) => p.stim[k] = v,
                Channel::Motor(j) => p.motor[j] = v,
                Channel::ComMeas(k) => p.com_meas[k] = v,
                Channel::SegmentRef(s) => p.segment_ref[s] = v,
                Channel::JointRef(j) => p.joint_ref[j] = v,
                Channel::ComPos(k) => com_pos[k] = v,
                Channel::ComVel(k) => com_vel[k] = v,
            }
        }
        p.acc = acc.map(group);
        p.gyr = gyr.map(group);
        p.quat = quat.map(group);
        p.com_pos = group(com_pos);
        p.com_vel = group(com_vel);
        p
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// The same plan without the reference columns (`*_ref`, `com_*`,
    /// `phase_ref`): records filled by it have an empty reference, as the
    /// CLI's `estimate` reads a trial file.
    pub fn without_references(&self) -> Self {
        RecordPlan {
            segment_ref: [None; 4],
            joint_ref: [None; 3],
            com_pos: None,
            com_vel: None,
            phase: None,
            ..self.clone()
        }
    }

    /// Overwrites every field of `r` with sample `i` (`i < len()`).
    pub fn fill(&self, i: usize, r: &mut Record) {
        let s = &mut r.sample;
        s.t = self.t[i];
        for k in 0..4 {
            let imu = &mut s.imu[k];
            imu.acc = vector(&self.acc[k], i);
            imu.gyr = vector(&self.gyr[k], i);
            imu.quat = self.quat[k].as_ref().and_then(|q| {
                let v = q.map(|c| c[i]);
                (!v.iter().any(|x| x.is_nan())).then_some(v)
            });
            imu.acc_partial = [None; 3];
            imu.gyr_partial = [None; 3];
        }
        s.other_leg_imu = [ImuSample::default(); 4];
        for j in 0..3 {
            s.encoder[j] = scalar(self.encoder[j], i);
            s.inputs.motor_torque[j] = scalar(self.motor[j], i);
        }
        for k in 0..4 {
            s.inputs.stim[k] = scalar(self.stim[k], i);
        }
        for k in 0..6 {
            s.com.set(k, scalar(self.com_meas[k], i));
        }
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
        re.contact = [None; 2];
        re.speed = None;
    }
}

/// A trial's records in order, each filled in place ([`RecordPlan::fill`]).
#[derive(Debug)]
pub struct ColumnRecords<'a> {
    plan: RecordPlan<'a>,
    next: usize,
}

impl<'a> ColumnRecords<'a> {
    /// The records of `plan`, from the first.
    pub fn new(plan: RecordPlan<'a>) -> Self {
        ColumnRecords { plan, next: 0 }
    }
}

impl RecordSource for ColumnRecords<'_> {
    type Error = Infallible;

    fn read_into(&mut self, record: &mut Record) -> Result<bool, Infallible> {
        if self.next >= self.plan.len() {
            return Ok(false);
        }
        self.plan.fill(self.next, record);
        self.next += 1;
        Ok(true)
    }
}
