//! Segment lengths, contact points and IMU mounting points.
//!
//! Lengths are fractions of body height `H` from D. A. Winter, *Biomechanics
//! and Motor Control of Human Movement*, 4th ed., Wiley 2009, Fig. 4.1:
//! thigh (hip to knee) 0.245 H, shank (knee to ankle) 0.246 H, foot length
//! 0.152 H, ankle height 0.039 H, foot breadth/hip width 0.191 H (we use 0.10 H
//! between the hip joint centres, a common pelvis-width estimate).
//!
//! Every point is given in its segment's frame, which equals the world frame
//! (x forward, y up, z to the subject's right) in upright quiet standing. The
//! simulated leg is the right one, so "lateral" is `+z`.

use nalgebra::Vector3;

/// Geometry of the simulated body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    /// Body height (m).
    pub height: f64,
    /// Hip joint to knee joint (m).
    pub thigh: f64,
    /// Knee joint to ankle joint (m).
    pub shank: f64,
    /// Ankle joint height above the sole in standing (m).
    pub ankle_height: f64,
    /// Distance between the two hip joint centres (m).
    pub hip_width: f64,
    /// Heel contact point, foot frame, origin at the ankle joint (m).
    pub heel: Vector3<f64>,
    /// Metatarsal-head (toe-off pivot) contact point, foot frame (m).
    pub mtp: Vector3<f64>,
    /// IMU positions in their segment frames (trunk: from the right hip joint
    /// centre; thigh: from the hip; shank: from the knee; foot: from the ankle).
    pub imu: [Vector3<f64>; 4],
}

impl Body {
    /// Winter's proportions for a body of height `h` metres.
    ///
    /// IMU mounting points (scaled with `h / 1.75`):
    /// * trunk: lower back over the sacrum, 0.10 m behind, 0.08 m above and
    ///   0.09 m medial of the right hip joint centre;
    /// * thigh: lateral, mid-segment, 0.08 m lateral of the femur axis;
    /// * shank: lateral, mid-segment, 0.05 m lateral of the tibia axis;
    /// * foot: dorsum (instep), 0.07 m in front of and 0.005 m below the ankle
    ///   joint centre, on the midline.
    pub fn from_height(h: f64) -> Self {
        let thigh = 0.245 * h;
        let shank = 0.246 * h;
        let ankle_height = 0.039 * h;
        let s = h / 1.75;
        let foot_len = 0.152 * h;
        let heel_back = 0.23 * foot_len;
        let mtp_fwd = 0.75 * foot_len - heel_back;
        Body {
            height: h,
            thigh,
            shank,
            ankle_height,
            hip_width: 0.10 * h,
            heel: Vector3::new(-heel_back, -ankle_height, 0.0),
            mtp: Vector3::new(mtp_fwd, -ankle_height, 0.0),
            imu: [
                Vector3::new(-0.10 * s, 0.08 * s, -0.09 * s),
                Vector3::new(0.0, -0.5 * thigh, 0.08 * s),
                Vector3::new(0.0, -0.5 * shank, 0.05 * s),
                Vector3::new(0.07 * s, -0.005 * s, 0.0),
            ],
        }
    }

    /// Hip joint height above the floor in upright standing (m).
    pub fn standing_hip_height(&self) -> f64 {
        self.thigh + self.shank + self.ankle_height
    }
}
