//! What an estimator receives at one instant ([`Sample`]) and what the truth
//! was ([`Reference`]), paired as a [`Record`] of a trial.
//!
//! Missing values are `None`, never NaN (a sensor dropout is an empty cell in a
//! trial file).

use nalgebra::Vector3;

use crate::limb::{Joint, Segment};

/// One IMU's readings at one instant, in the sensor frame.
///
/// An IMU *aligned* to its segment (what the segment filters and `chain`
/// read; `limbfuse align` turns raw readings into aligned ones) has z to
/// the subject's right and x, y in the sagittal plane such that the
/// accelerometer reads (0, +g, 0) in upright quiet standing: `gyr.z` is the
/// segment's angular rate, positive counter-clockwise seen from the right,
/// and a still segment's angle is `atan2(acc.x, acc.y)` (SPEC section 1).
///
/// A vector is either complete (`acc`/`gyr`, every consumer reads these) or
/// incomplete: then `acc`/`gyr` is `None` and the axes that are there are in
/// `acc_partial`/`gyr_partial` (issue 18 item 2: one dropped cell of a file
/// no longer loses the other two). The partial fields are all `None` when
/// the vector is complete or wholly missing, so setting `acc = None` on a
/// complete vector still drops the whole sensor. Estimators that need only
/// some axes read them with [`ImuSample::acc_axis`] / [`ImuSample::gyr_axis`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ImuSample {
    /// Specific force (m/s^2); `None` when any axis is missing.
    pub acc: Option<Vector3<f64>>,
    /// Angular rate (rad/s); `None` when any axis is missing.
    pub gyr: Option<Vector3<f64>>,
    /// Device orientation quaternion `[w, x, y, z]`, when the device provides one.
    pub quat: Option<[f64; 4]>,
    /// The present axes (x, y, z) of an incomplete specific-force vector
    /// (`acc` is `None`); all `None` otherwise.
    pub acc_partial: [Option<f64>; 3],
    /// The present axes (x, y, z) of an incomplete angular-rate vector
    /// (`gyr` is `None`); all `None` otherwise.
    pub gyr_partial: [Option<f64>; 3],
}

/// The complete vector of three cells, or `None` and the cells that are there.
fn split_cells(cells: [Option<f64>; 3]) -> (Option<Vector3<f64>>, [Option<f64>; 3]) {
    match cells {
        [Some(x), Some(y), Some(z)] => (Some(Vector3::new(x, y, z)), [None; 3]),
        partial => (None, partial),
    }
}

impl ImuSample {
    /// True when neither accelerometer nor gyroscope (not even one axis) nor
    /// quaternion is present.
    pub fn is_empty(&self) -> bool {
        !self.has_inertial_cells() && self.quat.is_none()
    }

    /// True when any accelerometer or gyroscope axis is present.
    pub fn has_inertial_cells(&self) -> bool {
        self.acc.is_some()
            || self.gyr.is_some()
            || self.acc_partial.iter().any(Option::is_some)
            || self.gyr_partial.iter().any(Option::is_some)
    }

    /// Specific-force axis `k` (0 = x, 1 = y, 2 = z), complete vector or not.
    #[inline]
    pub fn acc_axis(&self, k: usize) -> Option<f64> {
        match self.acc {
            Some(v) => Some(v[k]),
            None => self.acc_partial[k],
        }
    }

    /// Angular-rate axis `k` (0 = x, 1 = y, 2 = z), complete vector or not.
    #[inline]
    pub fn gyr_axis(&self, k: usize) -> Option<f64> {
        match self.gyr {
            Some(v) => Some(v[k]),
            None => self.gyr_partial[k],
        }
    }

    /// The three specific-force cells.
    pub fn acc_axes(&self) -> [Option<f64>; 3] {
        core::array::from_fn(|k| self.acc_axis(k))
    }

    /// The three angular-rate cells.
    pub fn gyr_axes(&self) -> [Option<f64>; 3] {
        core::array::from_fn(|k| self.gyr_axis(k))
    }

    /// Sets the specific force from its three cells: `acc` when all are
    /// there, else `acc_partial`.
    pub fn set_acc_axes(&mut self, cells: [Option<f64>; 3]) {
        (self.acc, self.acc_partial) = split_cells(cells);
    }

    /// Sets the angular rate from its three cells: `gyr` when all are
    /// there, else `gyr_partial`.
    pub fn set_gyr_axes(&mut self, cells: [Option<f64>; 3]) {
        (self.gyr, self.gyr_partial) = split_cells(cells);
    }
}

/// Model inputs some estimators need (paper 004): stimulation and motor torques.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ModelInputs {
    /// Normalised stimulation commands in [0, 1]: `u_ke`, `u_kf`, `u_he`, `u_hf`.
    pub stim: [Option<f64>; 4],
    /// Motor torques (N m) at hip, knee, ankle: `tau_hip_motor`, ...
    pub motor_torque: [Option<f64>; 3],
}

impl ModelInputs {
    /// Column names of the stimulation channels, in [`ModelInputs::stim`] order.
    pub const STIM_NAMES: [&'static str; 4] = ["u_ke", "u_kf", "u_he", "u_hf"];
}

/// Centre-of-mass measurements (paper 003), world frame (x forward, y up,
/// z right), each axis optional: the paper's full set measures position and
/// the sagittal velocities only. File columns `com_meas_x`..`com_meas_vz`
/// (limbfuse addition: SPEC's `com_*` columns are the reference).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ComMeasurement {
    /// Position (m) per axis.
    pub pos: [Option<f64>; 3],
    /// Velocity (m/s) per axis.
    pub vel: [Option<f64>; 3],
}

impl ComMeasurement {
    /// Column names, position then velocity.
    pub const NAMES: [&'static str; 6] = [
        "com_meas_x",
        "com_meas_y",
        "com_meas_z",
        "com_meas_vx",
        "com_meas_vy",
        "com_meas_vz",
    ];

    /// The six values, position then velocity.
    pub fn values(&self) -> [Option<f64>; 6] {
        [
            self.pos[0],
            self.pos[1],
            self.pos[2],
            self.vel[0],
            self.vel[1],
            self.vel[2],
        ]
    }

    /// Sets value `i` of [`ComMeasurement::values`].
    pub fn set(&mut self, i: usize, v: Option<f64>) {
        if i < 3 {
            self.pos[i] = v;
        } else if i < 6 {
            self.vel[i - 3] = v;
        }
    }
}

/// Everything measured at one instant: the input of [`crate::Estimator::step`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sample {
    /// Time (s). Estimators take `dt` from successive timestamps.
    pub t: f64,
    /// IMU readings per segment, indexed by [`Segment::index`].
    pub imu: [ImuSample; 4],
    /// IMU readings of the other leg's segments (two-leg recordings, SPEC
    /// section 2: `S_left_...` when the trial's `# leg:` is right, the
    /// default), indexed by [`Segment::index`]; all empty in one-leg trials.
    pub other_leg_imu: [ImuSample; 4],
    /// Joint encoders (rad) per joint, indexed by [`Joint::index`]: the
    /// joint angles `hip = theta_trunk - theta_thigh`, `knee = theta_thigh -
    /// theta_shank`, `ankle = theta_shank - theta_foot`, zero in upright
    /// quiet standing.
    pub encoder: [Option<f64>; 3],
    /// Model inputs (stimulation, motor torques).
    pub inputs: ModelInputs,
    /// Centre-of-mass measurements (paper 003).
    pub com: ComMeasurement,
}

impl Sample {
    /// A sample at time `t` with every channel missing.
    pub fn empty(t: f64) -> Self {
        Sample {
            t,
            ..Default::default()
        }
    }

    /// The IMU of a segment.
    pub fn imu(&self, s: Segment) -> &ImuSample {
        &self.imu[s.index()]
    }

    /// The encoder of a joint.
    pub fn encoder(&self, j: Joint) -> Option<f64> {
        self.encoder[j.index()]
    }
}

/// Gait phase of the bipedal SLIP model (paper 003).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GaitPhase {
    /// First single support.
    Ss1,
    /// Double support.
    Ds,
    /// Second single support.
    Ss2,
}

impl GaitPhase {
    /// The label used in files (`SS1`, `DS`, `SS2`).
    pub const fn label(self) -> &'static str {
        match self {
            GaitPhase::Ss1 => "SS1",
            GaitPhase::Ds => "DS",
            GaitPhase::Ss2 => "SS2",
        }
    }

    /// Parses a file label.
    pub fn from_label(s: &str) -> Option<Self> {
        match s {
            "SS1" => Some(GaitPhase::Ss1),
            "DS" => Some(GaitPhase::Ds),
            "SS2" => Some(GaitPhase::Ss2),
            _ => None,
        }
    }
}

/// Ground truth at one instant (from simulation or motion capture).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Reference {
    /// Absolute sagittal angle (rad) per segment (`S_ref`).
    pub segment: [Option<f64>; 4],
    /// Joint angles (rad) (`hip_ref`, `knee_ref`, `ankle_ref`).
    pub joint: [Option<f64>; 3],
    /// Centre-of-mass position (m).
    pub com_pos: Option<Vector3<f64>>,
    /// Centre-of-mass velocity (m/s).
    pub com_vel: Option<Vector3<f64>>,
    /// Gait phase.
    pub phase: Option<GaitPhase>,
    /// Foot contact per side `[left, right]` (`contact_left_ref`,
    /// `contact_right_ref`): `true` from initial contact to final contact.
    pub contact: [Option<bool>; 2],
    /// Walking speed (m/s, `speed_ref`), per stride.
    pub speed: Option<f64>,
}

impl Reference {
    /// Reference value of the named estimate channel (segment or joint name).
    pub fn angle(&self, channel: AngleChannel) -> Option<f64> {
        match channel {
            AngleChannel::Segment(s) => self.segment[s.index()],
            AngleChannel::Joint(j) => self.joint[j.index()],
        }
    }
}

/// One of the seven angle channels an estimate and a reference share.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum AngleChannel {
    /// A segment's absolute angle.
    Segment(Segment),
    /// A joint angle.
    Joint(Joint),
}

impl AngleChannel {
    /// All seven channels: trunk, thigh, shank, foot, hip, knee, ankle.
    pub const ALL: [AngleChannel; 7] = [
        AngleChannel::Segment(Segment::Trunk),
        AngleChannel::Segment(Segment::Thigh),
        AngleChannel::Segment(Segment::Shank),
        AngleChannel::Segment(Segment::Foot),
        AngleChannel::Joint(Joint::Hip),
        AngleChannel::Joint(Joint::Knee),
        AngleChannel::Joint(Joint::Ankle),
    ];

    /// Column name (`trunk`, ..., `ankle`).
    pub const fn name(self) -> &'static str {
        match self {
            AngleChannel::Segment(s) => s.name(),
            AngleChannel::Joint(j) => j.name(),
        }
    }
}

/// A sample paired with its ground truth: one row of a trial.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Record {
    /// What the sensors measured.
    pub sample: Sample,
    /// What was true (all `None` when the trial has no reference).
    pub reference: Reference,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn issue_18_an_incomplete_vector_keeps_its_present_axes() {
        let mut imu = ImuSample::default();
        imu.set_gyr_axes([None, Some(0.5), Some(2.0)]);
        assert_eq!(imu.gyr, None);
        assert_eq!(imu.gyr_axes(), [None, Some(0.5), Some(2.0)]);
        assert!(imu.has_inertial_cells() && !imu.is_empty());
        imu.set_gyr_axes([Some(1.0), Some(0.5), Some(2.0)]);
        assert_eq!(imu.gyr, Some(Vector3::new(1.0, 0.5, 2.0)));
        assert_eq!(imu.gyr_partial, [None; 3]);
        assert_eq!(imu.gyr_axis(0), Some(1.0));
        // dropping a complete vector drops the sensor
        imu.gyr = None;
        assert!(imu.is_empty());
        imu.set_acc_axes([None; 3]);
        assert_eq!((imu.acc, imu.acc_partial), (None, [None; 3]));
    }
}
