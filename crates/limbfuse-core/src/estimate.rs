//! What an estimator returns at one instant.

use nalgebra::Vector3;

use crate::limb::{Joint, Segment};
use crate::sample::{AngleChannel, GaitPhase};

/// Maximum number of diagnostic values an estimate carries.
pub const MAX_DIAG: usize = 64;

/// One estimate: angles (rad), optional gait quantities and diagnostics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Time (s), same as the sample's.
    pub t: f64,
    /// Absolute sagittal segment angles (rad), `None` where not estimated.
    pub segment: [Option<f64>; 4],
    /// Joint angles (rad), `None` where not estimated.
    pub joint: [Option<f64>; 3],
    /// Most likely gait phase (paper 003).
    pub phase: Option<GaitPhase>,
    /// Walking speed (m/s) (paper 003).
    pub speed: Option<f64>,
    /// Foot contact per side `[left, right]` (columns `contact_left`,
    /// `contact_right`: 1 stance, 0 swing).
    pub contact: [Option<bool>; 2],
    /// Centre-of-mass position (m) (paper 003), columns `com_x, com_y, com_z`.
    pub com_pos: Option<Vector3<f64>>,
    /// Centre-of-mass velocity (m/s), columns `com_vx, com_vy, com_vz`.
    pub com_vel: Option<Vector3<f64>>,
    /// Diagnostic values, named by [`crate::Estimator::diagnostic_names`].
    pub diag: [Option<f64>; MAX_DIAG],
}

impl Estimate {
    /// An estimate at time `t` with nothing estimated.
    pub const fn empty(t: f64) -> Self {
        Estimate {
            t,
            segment: [None; 4],
            joint: [None; 3],
            phase: None,
            speed: None,
            contact: [None; 2],
            com_pos: None,
            com_vel: None,
            diag: [None; MAX_DIAG],
        }
    }

    /// Fills every joint angle whose two segments are estimated and which is not already set.
    pub fn fill_joints_from_segments(&mut self) {
        for j in Joint::ALL {
            let (p, d) = j.segments();
            if self.joint[j.index()].is_none() {
                if let (Some(a), Some(b)) = (self.segment[p.index()], self.segment[d.index()]) {
                    self.joint[j.index()] = Some(a - b);
                }
            }
        }
    }

    /// The estimated value of an angle channel.
    pub fn angle(&self, channel: AngleChannel) -> Option<f64> {
        match channel {
            AngleChannel::Segment(s) => self.segment[s.index()],
            AngleChannel::Joint(j) => self.joint[j.index()],
        }
    }

    /// Sets the absolute angle of a segment.
    pub fn set_segment(&mut self, s: Segment, value: f64) {
        self.segment[s.index()] = Some(value);
    }
}
