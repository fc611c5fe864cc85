//! Rigid-body kinematics of the trunk-thigh-shank-foot chain.
//!
//! A segment's orientation is `R = Rz(theta) Rx(alpha) Ry(beta)`: `theta` is
//! the sagittal absolute angle of SPEC section 1 (rotation about the world z
//! axis, positive counter-clockwise seen from the right), `alpha` a small
//! rotation about the segment's forward (x) axis (ab/adduction, or
//! inversion/eversion for the foot) and `beta` a small rotation about its
//! vertical (y) axis (internal/external rotation, toe-in/out). With
//! `alpha = beta = 0` the motion is planar and the body angular rate is
//! `(0, 0, dtheta/dt)`.
//!
//! Angular velocity (world): `w = theta' e1 + alpha' e2 + beta' e3` with
//! `e1 = z`, `e2 = Rz x`, `e3 = Rz Rx y`; its derivative adds the transport
//! terms `alpha' (w1 x e2) + beta' (w12 x e3)`. A body-fixed point `r` of a
//! segment whose origin moves with `(p, v, a)` has position `p + R r`,
//! velocity `v + w x R r` and acceleration
//! `a + wdot x R r + w x (w x R r)` (tangential and centripetal terms; the
//! origin's acceleration carries the transported terms of the proximal chain).
//! The same code serves with the gait phase as the independent variable.

use nalgebra::{Matrix3, Vector3};

use crate::anthropometry::Body;
use crate::fourier::D2;

/// The three rotation angles of a segment with their time (or phase) derivatives.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Angles {
    /// Sagittal angle about the world z axis.
    pub theta: D2,
    /// Rotation about the segment's x axis.
    pub alpha: D2,
    /// Rotation about the segment's y axis.
    pub beta: D2,
}

/// Orientation, angular velocity and angular acceleration of a segment (world frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Rotation from segment to world coordinates.
    pub r: Matrix3<f64>,
    /// Angular velocity (rad/s), world coordinates.
    pub w: Vector3<f64>,
    /// Angular acceleration (rad/s^2), world coordinates.
    pub wd: Vector3<f64>,
}

/// Rotation about z.
pub fn rot_z(t: f64) -> Matrix3<f64> {
    let (s, c) = t.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}
/// Rotation about x.
pub fn rot_x(t: f64) -> Matrix3<f64> {
    let (s, c) = t.sin_cos();
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}
/// Rotation about y.
pub fn rot_y(t: f64) -> Matrix3<f64> {
    let (s, c) = t.sin_cos();
    Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}

impl Frame {
    /// Frame of a segment with the given angles.
    pub fn new(a: &Angles) -> Self {
        let r1 = rot_z(a.theta.v);
        let r12 = r1 * rot_x(a.alpha.v);
        let r = r12 * rot_y(a.beta.v);
        let e1 = Vector3::z();
        let e2: Vector3<f64> = r1.column(0).into();
        let e3: Vector3<f64> = r12.column(1).into();
        let w1 = e1 * a.theta.d1;
        let w12 = w1 + e2 * a.alpha.d1;
        let w = w12 + e3 * a.beta.d1;
        let wd = e1 * a.theta.d2
            + e2 * a.alpha.d2
            + w1.cross(&e2) * a.alpha.d1
            + e3 * a.beta.d2
            + w12.cross(&e3) * a.beta.d1;
        Frame { r, w, wd }
    }
}

/// Position, velocity and acceleration of a point (world frame).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PointKin {
    /// Position (m).
    pub p: Vector3<f64>,
    /// Velocity (m/s).
    pub v: Vector3<f64>,
    /// Acceleration (m/s^2).
    pub a: Vector3<f64>,
}

impl PointKin {
    /// The point fixed at `r` (segment coordinates) on a segment whose origin is `self`.
    #[inline]
    pub fn attach(&self, f: &Frame, r: &Vector3<f64>) -> PointKin {
        let rw = f.r * r;
        let wr = f.w.cross(&rw);
        PointKin {
            p: self.p + rw,
            v: self.v + wr,
            a: self.a + f.wd.cross(&rw) + f.w.cross(&wr),
        }
    }
}

/// Kinematics of the whole chain of one leg (plus the trunk).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LegKin {
    /// Segment frames: trunk, thigh, shank, foot.
    pub frames: [Frame; 4],
    /// Hip, knee and ankle joint centres.
    pub joints: [PointKin; 3],
    /// IMU points: trunk, thigh, shank, foot.
    pub imu: [PointKin; 4],
    /// Heel and metatarsal-head contact points.
    pub contacts: [PointKin; 2],
}

/// Forward kinematics from the hip joint centre `hip` and the segment angles.
/// `lateral_sign` is +1 for the right leg and -1 for the mirrored left leg
/// (it flips the z offsets of the IMU points).
pub fn leg(body: &Body, hip: PointKin, seg: &[Angles; 4], lateral_sign: f64) -> LegKin {
    let frames = [
        Frame::new(&seg[0]),
        Frame::new(&seg[1]),
        Frame::new(&seg[2]),
        Frame::new(&seg[3]),
    ];
    let knee = hip.attach(&frames[1], &Vector3::new(0.0, -body.thigh, 0.0));
    let ankle = knee.attach(&frames[2], &Vector3::new(0.0, -body.shank, 0.0));
    let mirror = |v: &Vector3<f64>| Vector3::new(v.x, v.y, lateral_sign * v.z);
    let origins = [hip, hip, knee, ankle];
    let mut imu = [PointKin::default(); 4];
    for i in 0..4 {
        imu[i] = origins[i].attach(&frames[i], &mirror(&body.imu[i]));
    }
    let contacts = [
        ankle.attach(&frames[3], &body.heel),
        ankle.attach(&frames[3], &body.mtp),
    ];
    LegKin {
        frames,
        joints: [hip, knee, ankle],
        imu,
        contacts,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn angles_at(t: f64) -> Angles {
        // theta = 0.4 sin(3t), alpha = 0.1 cos(2t), beta = 0.2 sin(t + 1)
        Angles {
            theta: D2 {
                v: 0.4 * (3.0 * t).sin(),
                d1: 1.2 * (3.0 * t).cos(),
                d2: -3.6 * (3.0 * t).sin(),
            },
            alpha: D2 {
                v: 0.1 * (2.0 * t).cos(),
                d1: -0.2 * (2.0 * t).sin(),
                d2: -0.4 * (2.0 * t).cos(),
            },
            beta: D2 {
                v: 0.2 * (t + 1.0).sin(),
                d1: 0.2 * (t + 1.0).cos(),
                d2: -0.2 * (t + 1.0).sin(),
            },
        }
    }

    #[test]
    fn angular_velocity_and_acceleration_match_finite_differences() {
        let h = 1e-5;
        let t = 0.37;
        let f = Frame::new(&angles_at(t));
        let rp = Frame::new(&angles_at(t + h)).r;
        let rm = Frame::new(&angles_at(t - h)).r;
        // [w]x = Rdot R^T
        let wx = (rp - rm) / (2.0 * h) * f.r.transpose();
        let w = Vector3::new(wx[(2, 1)], wx[(0, 2)], wx[(1, 0)]);
        assert!((w - f.w).norm() < 1e-8, "{w} vs {}", f.w);
        let wd = (Frame::new(&angles_at(t + h)).w - Frame::new(&angles_at(t - h)).w) / (2.0 * h);
        assert!((wd - f.wd).norm() < 1e-7);
    }

    #[test]
    fn standing_pose_is_world_aligned() {
        let body = Body::from_height(1.75);
        let k = leg(&body, PointKin::default(), &[Angles::default(); 4], 1.0);
        let sole = k.contacts[0].p.y;
        assert!((sole + body.standing_hip_height()).abs() < 1e-12);
        assert_eq!(k.frames[3].r, Matrix3::identity());
    }
}
