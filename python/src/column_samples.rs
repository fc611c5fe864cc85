//! Samples read in place from a trial's input columns: the columns a
//! trial has are listed once ([`SampleColumns`]), then each sample
//! overwrites only the fields those columns fill; a field no column fills
//! is never written, so it keeps the `None` of the first
//! [`Sample::default`] for the whole run (no per-sample work for the many
//! channels a trial does not have).
//!
//! Missing cells are NaN (see [`crate::columns`]). The fields are filled as
//! `limbfuse_io::TrialReader::read_into` fills them from a file: an IMU
//! vector (either leg) cell by cell (`ImuSample::set_acc_axes`: a missing
//! axis keeps the others), a quaternion only when all its components are
//! present.

use limbfuse_core::Sample;
use limbfuse_eval::{AccRailWatch, FixedThighWatch, SensorUnitsWatch};
use nalgebra::Vector3;

use crate::columns::Channel;

/// Which three-axis IMU vector of a sample a column group fills.
#[derive(Debug, Clone, Copy)]
enum VectorSlot {
    /// Specific force of segment `k` (this leg).
    Acc(usize),
    /// Angular rate of segment `k` (this leg).
    Gyr(usize),
    /// Specific force of segment `k` of the other leg.
    OtherAcc(usize),
    /// Angular rate of segment `k` of the other leg.
    OtherGyr(usize),
}

/// Which scalar field of a sample a column fills.
#[derive(Debug, Clone, Copy)]
enum ScalarSlot {
    Encoder(usize),
    Stim(usize),
    Motor(usize),
    ComMeas(usize),
}

/// The input columns of a trial, each with the sample field it fills.
#[derive(Debug, Clone, Default)]
pub struct SampleColumns<'a> {
    t: &'a [f64],
    vectors: Vec<(VectorSlot, [&'a [f64]; 3])>,
    quats: Vec<(usize, [&'a [f64]; 4])>,
    scalars: Vec<(ScalarSlot, &'a [f64])>,
}

/// The value at `i` (NaN = missing).
#[inline]
fn cell(c: &[f64], i: usize) -> Option<f64> {
    let v = c[i];
    (!v.is_nan()).then_some(v)
}

/// Sets a vector and its partial cells from three cells (NaN = missing),
/// as `ImuSample::set_acc_axes` / `set_gyr_axes` do.
#[inline]
fn set_vector(
    vector: &mut Option<Vector3<f64>>,
    partial: &mut [Option<f64>; 3],
    [x, y, z]: [f64; 3],
) {
    if x.is_nan() || y.is_nan() || z.is_nan() {
        *vector = None;
        *partial = [x, y, z].map(|v| (!v.is_nan()).then_some(v));
    } else {
        *vector = Some(Vector3::new(x, y, z));
        *partial = [None; 3];
    }
}

impl<'a> SampleColumns<'a> {
    /// The input columns among `columns` (a trial's checked columns: every
    /// vector group complete, every column as long as `t`); reference
    /// columns are left out.
    pub fn new(t: &'a [f64], columns: &[(Channel, &'a [f64])]) -> Self {
        let mut acc: [[Option<&'a [f64]>; 3]; 4] = [[None; 3]; 4];
        let (mut gyr, mut other_acc, mut other_gyr) = (acc, acc, acc);
        let mut quat: [[Option<&'a [f64]>; 4]; 4] = [[None; 4]; 4];
        let mut scalars = Vec::new();
        for &(c, v) in columns {
            match c {
                Channel::Acc(s, k) => acc[s][k] = Some(v),
                Channel::Gyr(s, k) => gyr[s][k] = Some(v),
                Channel::OtherAcc(_, s, k) => other_acc[s][k] = Some(v),
                Channel::OtherGyr(_, s, k) => other_gyr[s][k] = Some(v),
                Channel::Quat(s, k) => quat[s][k] = Some(v),
                Channel::Encoder(j) => scalars.push((ScalarSlot::Encoder(j), v)),
                Channel::Stim(k) => scalars.push((ScalarSlot::Stim(k), v)),
                Channel::Motor(j) => scalars.push((ScalarSlot::Motor(j), v)),
                Channel::ComMeas(k) => scalars.push((ScalarSlot::ComMeas(k), v)),
                Channel::SegmentRef(_)
                | Channel::JointRef(_)
                | Channel::ComPos(_)
                | Channel::ComVel(_)
                | Channel::ContactRef(_)
                | Channel::SpeedRef => {}
            }
        }
        let mut vectors = Vec::new();
        for s in 0..4 {
            let groups = [
                (VectorSlot::Acc(s), acc[s]),
                (VectorSlot::Gyr(s), gyr[s]),
                (VectorSlot::OtherAcc(s), other_acc[s]),
                (VectorSlot::OtherGyr(s), other_gyr[s]),
            ];
            for (slot, [x, y, z]) in groups {
                // A group is complete or absent (`TrialColumns::new`).
                if let (Some(x), Some(y), Some(z)) = (x, y, z) {
                    vectors.push((slot, [x, y, z]));
                }
            }
        }
        let quats: Vec<(usize, [&'a [f64]; 4])> = quat
            .iter()
            .enumerate()
            .filter_map(|(s, q)| match *q {
                [Some(w), Some(x), Some(y), Some(z)] => Some((s, [w, x, y, z])),
                _ => None,
            })
            .collect();
        SampleColumns {
            t,
            vectors,
            quats,
            scalars,
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Counts the complete IMU vectors of the columns (both legs) and the
    /// encoder readings in `units`, of the samples `limbfuse estimate`
    /// counts (every [`SensorUnitsWatch::STRIDE`]-th).
    pub fn count_units(&self, units: &mut SensorUnitsWatch) {
        for &(slot, [x, y, z]) in &self.vectors {
            for i in (0..self.t.len()).step_by(SensorUnitsWatch::STRIDE) {
                let v = Vector3::new(x[i], y[i], z[i]);
                if v.iter().any(|c| c.is_nan()) {
                    continue;
                }
                match slot {
                    VectorSlot::Acc(k) => units.push_acc(k, &v),
                    VectorSlot::OtherAcc(k) => units.push_acc(4 + k, &v),
                    VectorSlot::Gyr(k) => units.push_gyr(k, &v),
                    VectorSlot::OtherGyr(k) => units.push_gyr(4 + k, &v),
                }
            }
        }
        for &(slot, c) in &self.scalars {
            if let ScalarSlot::Encoder(_) = slot {
                for i in (0..self.t.len()).step_by(SensorUnitsWatch::STRIDE) {
                    if let Some(v) = cell(c, i) {
                        units.push_encoder(v);
                    }
                }
            }
        }
    }

    /// Adds every [`AccRailWatch::STRIDE`]-th accelerometer reading of the
    /// columns (both legs) to `w` (as `estimate`'s observer counts the
    /// records).
    pub fn count_rails(&self, w: &mut AccRailWatch) {
        for &(slot, axes) in &self.vectors {
            let k = match slot {
                VectorSlot::Acc(k) => k,
                VectorSlot::OtherAcc(k) => 4 + k,
                VectorSlot::Gyr(_) | VectorSlot::OtherGyr(_) => continue,
            };
            for (j, column) in axes.iter().enumerate() {
                let counted = || column.iter().step_by(AccRailWatch::STRIDE);
                let largest = counted().fold(0.0f64, |m, v| m.max(v.abs()));
                let count = counted().filter(|v| v.abs() == largest).count();
                w.push_largest(k, j, largest, count as u64);
            }
        }
    }

    /// Adds every [`FixedThighWatch::STRIDE`]-th thigh accelerometer
    /// reading to `w` (as `estimate`'s observer sees the records).
    pub fn count_thigh(&self, w: &mut FixedThighWatch) {
        for &(slot, [x, y, z]) in &self.vectors {
            if !matches!(slot, VectorSlot::Acc(1)) {
                continue;
            }
            for i in (0..self.t.len()).step_by(FixedThighWatch::STRIDE) {
                let v = Vector3::new(x[i], y[i], z[i]);
                if !v.iter().any(|c| c.is_nan()) {
                    w.push_acc(&v);
                }
            }
        }
    }

    /// Overwrites the fields of `s` that the columns fill with sample `i`
    /// (`i < len()`); every other field is left as it is.
    #[inline]
    pub fn fill(&self, i: usize, s: &mut Sample) {
        s.t = self.t[i];
        for &(slot, [x, y, z]) in &self.vectors {
            let cells = [x[i], y[i], z[i]];
            let imu = match slot {
                VectorSlot::Acc(k) | VectorSlot::Gyr(k) => &mut s.imu[k],
                VectorSlot::OtherAcc(k) | VectorSlot::OtherGyr(k) => &mut s.other_leg_imu[k],
            };
            match slot {
                VectorSlot::Acc(_) | VectorSlot::OtherAcc(_) => {
                    set_vector(&mut imu.acc, &mut imu.acc_partial, cells)
                }
                VectorSlot::Gyr(_) | VectorSlot::OtherGyr(_) => {
                    set_vector(&mut imu.gyr, &mut imu.gyr_partial, cells)
                }
            }
        }
        for &(k, [w, x, y, z]) in &self.quats {
            let q = [w[i], x[i], y[i], z[i]];
            s.imu[k].quat = (!q.iter().any(|v| v.is_nan())).then_some(q);
        }
        for &(slot, c) in &self.scalars {
            let v = cell(c, i);
            match slot {
                ScalarSlot::Encoder(j) => s.encoder[j] = v,
                ScalarSlot::Stim(k) => s.inputs.stim[k] = v,
                ScalarSlot::Motor(j) => s.inputs.motor_torque[j] = v,
                ScalarSlot::ComMeas(k) => s.com.set(k, v),
            }
        }
    }
}
