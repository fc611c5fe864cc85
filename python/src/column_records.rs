//! Records read in place from a trial's columns: the column of every
//! record field is resolved once ([`RecordPlan`]), then each sample fills a
//! caller-owned [`Record`] from the numpy arrays with no per-sample lookup
//! of channel names and no record moved ([`ColumnRecords`], a runner
//! [`RecordSource`]).
//!
//! Missing cells are NaN (see [`crate::columns`]). The fields are filled as
//! `limbfuse_io::TrialReader::read_into` fills them from a file: an IMU
//! vector (either leg) cell by cell (`ImuSample::set_acc_axes`: a missing
//! axis keeps the others), a quaternion or a CoM reference vector only
//! when all its components are present, a foot contact 1 / 0 as on the
//! ground / swing.

use std::convert::Infallible;

use limbfuse_core::runner::RecordSource;
use limbfuse_core::sample::GaitPhase;
use limbfuse_core::Record;
use nalgebra::Vector3;

use crate::columns::Channel;

type Column<'a> = Option<&'a [f64]>;

/// The column of every record field a trial has (`None`: not in the trial).
#[derive(Debug, Clone, Default)]
pub struct RecordPlan<'a> {
    t: &'a [f64],
    acc: [[Column<'a>; 3]; 4],
    gyr: [[Column<'a>; 3]; 4],
    quat: [Option<[&'a [f64]; 4]>; 4],
    other_acc: [[Column<'a>; 3]; 4],
    other_gyr: [[Column<'a>; 3]; 4],
    encoder: [Column<'a>; 3],
    stim: [Column<'a>; 4],
    motor: [Column<'a>; 3],
    com_meas: [Column<'a>; 6],
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

/// The three cells of an IMU vector at `i`, each present or not.
#[inline]
fn axes(c: &[Column<'_>; 3], i: usize) -> [Option<f64>; 3] {
    c.map(|a| scalar(a, i))
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
                Channel::Acc(s, k) => p.acc[s][k] = v,
                Channel::Gyr(s, k) => p.gyr[s][k] = v,
                Channel::Quat(s, k) => quat[s][k] = v,
                Channel::Encoder(j) => p.encoder[j] = v,
                Channel::Stim(k) => p.stim[k] = v,
                Channel::Motor(j) => p.motor[j] = v,
                Channel::ComMeas(k) => p.com_meas[k] = v,
                Channel::SegmentRef(s) => p.segment_ref[s] = v,
                Channel::JointRef(j) => p.joint_ref[j] = v,
                Channel::ComPos(k) => com_pos[k] = v,
                Channel::ComVel(k) => com_vel[k] = v,
                Channel::OtherAcc(_, s, k) => p.other_acc[s][k] = v,
                Channel::OtherGyr(_, s, k) => p.other_gyr[s][k] = v,
                Channel::ContactRef(side) => p.contact[side.index()] = v,
                Channel::SpeedRef => p.speed = v,
            }
        }
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
    /// `phase_ref`, `contact_*_ref`, `speed_ref`): records filled by it
    /// have an empty reference, as the CLI's `estimate` reads a trial file
    /// (`TrialReader::skip_references`).
    pub fn without_references(&self) -> Self {
        RecordPlan {
            segment_ref: [None; 4],
            joint_ref: [None; 3],
            com_pos: None,
            com_vel: None,
            phase: None,
            contact: [None; 2],
            speed: None,
            ..self.clone()
        }
    }

    /// Overwrites every field of `r` with sample `i` (`i < len()`).
    pub fn fill(&self, i: usize, r: &mut Record) {
        let s = &mut r.sample;
        s.t = self.t[i];
        for k in 0..4 {
            let imu = &mut s.imu[k];
            imu.set_acc_axes(axes(&self.acc[k], i));
            imu.set_gyr_axes(axes(&self.gyr[k], i));
            imu.quat = self.quat[k].as_ref().and_then(|q| {
                let v = q.map(|c| c[i]);
                (!v.iter().any(|x| x.is_nan())).then_some(v)
            });
            let other = &mut s.other_leg_imu[k];
            other.set_acc_axes(axes(&self.other_acc[k], i));
            other.set_gyr_axes(axes(&self.other_gyr[k], i));
            other.quat = None;
        }
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
        re.contact = [contact(self.contact[0], i), contact(self.contact[1], i)];
        re.speed = scalar(self.speed, i);
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
