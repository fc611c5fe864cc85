//! Where the simulated leg walks: which leg it is (the left leg is the
//! mirror image of the right) and turns of the walking path.
//!
//! **Left leg.** Mirroring across the sagittal plane is `S = diag(1, 1, -1)`
//! (world). Points are polar vectors: `p -> S p` (and so their velocities and
//! accelerations). A mirrored right-handed frame `S R` would be left-handed;
//! the left segment's frame is `R_L = S R S` (its x, y mirrored, its z still
//! pointing to the subject's right, SPEC section 1; a planar `Rz(theta)`
//! maps to itself, so the sagittal angles are unchanged). Angular velocity is
//! an axial vector: from `[w_L]x = dR_L/dt R_L^T = S [w]x S = -[S w]x`,
//! `w_L = -S w` (likewise the angular acceleration). A sensor on the left
//! segment then reads, in the segment frame, `R_L^T (S f) = S (R^T f)` and
//! `R_L^T w_L = -S (R^T w)`: accelerometer `(f_x, f_y, -f_z)`, gyroscope
//! `(-w_x, -w_y, w_z)`.
//!
//! **Turns.** The body turns about the vertical through the hip joint
//! centre by the heading `psi(t)` (positive = to the left, counter-clockwise
//! seen from above): with `h` the hip's horizontal position and `H` the
//! turned hip path (`dH/dt = Ry(psi) dh/dt`), a point `p = h + r` moves to
//! `p' = H + Ry(psi) r`, a frame `R` to `Ry(psi) R`. Differentiating twice
//! (`e = y`, the vertical):
//! `w' = Ry w + psi' e`, `w'dot = Ry wdot + psi' e x Ry w + psi'' e`,
//! `v' = Ry (h' + r') + psi' e x Ry r`,
//! `a' = Ry (h'' + r'' + psi' e x (h' + 2 r') + psi'' e x r + psi'^2 e x (e x r))`.
//! The gait itself (sagittal angles, stride) is unchanged during the turn.
//! The leg's heading `psi` changes only in its swings (a step turn: the
//! stance foot stays planted and does not turn; [`crate::turn_schedule`])
//! and the hip path follows it (`dH/dt = Ry(psi) dh/dt`); the trunk turns by
//! its own heading `psi_T` about the same vertical (`p' = H + Ry(psi_T) r`,
//! the formulas above with `psi_T` for the rotation of `r` and `psi` for
//! `H`), spread over the strides around the swings, so that `psi - psi_T`
//! is the hip's rotation about the vertical. Each heading change follows the
//! quintic smoothstep `s(u) = 10u^3 - 15u^4 + 6u^5` (continuous heading
//! rate and acceleration). Until session 44 the whole body turned with one
//! smooth heading at every instant, so the stance foot turned and slid with
//! it.

use limbfuse_core::Leg;
use nalgebra::{Matrix3, Vector3};

use crate::chain::{rot_y, Frame, LegKin, PointKin};
use crate::fourier::D2;

/// Turns of the walking path: the `k`-th turn (k = 1, 2, ...) turns by
/// `angle_rad` in the simulated leg's swings whose toe off falls in
/// `[k every_s, k every_s + duration_s)` (at least one, and enough that none
/// turns by more than 90 deg; [`crate::turn_schedule`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turns {
    /// Interval between turn starts (s), > `duration_s`.
    pub every_s: f64,
    /// Duration of one turn (s), > 0.
    pub duration_s: f64,
    /// Heading change of one turn (rad; positive = to the left).
    pub angle_rad: f64,
}

/// `S = diag(1, 1, -1)` applied to a vector.
fn mirror(v: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(v.x, v.y, -v.z)
}

/// The left leg: every point and frame of `k` mirrored (module docs).
pub fn mirror_to(leg: Leg, k: &mut LegKin) {
    if leg == Leg::Right {
        return;
    }
    let s = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0));
    for f in k.frames.iter_mut() {
        f.r = s * f.r * s;
        f.w = -mirror(&f.w);
        f.wd = -mirror(&f.wd);
    }
    let pm = |p: &mut PointKin| {
        p.p = mirror(&p.p);
        p.v = mirror(&p.v);
        p.a = mirror(&p.a);
    };
    k.joints.iter_mut().for_each(pm);
    k.imu.iter_mut().for_each(pm);
    k.contacts.iter_mut().for_each(pm);
}

/// Turns the body of `k` about the vertical through the hip (module docs):
/// the leg (thigh, shank, foot, their joints, sensors and contact points)
/// by heading `psi`, the trunk and its sensor by `psi_trunk` (the hip's
/// rotation about the vertical is their difference); `hip_path` is the
/// turned hip's horizontal position `H`, whose rate is `Ry(psi) dh/dt` (the
/// caller integrates it).
pub fn turn(k: &mut LegKin, psi: D2, psi_trunk: D2, hip_path: Vector3<f64>) {
    let e = Vector3::y();
    let hip = k.joints[0];
    let (h, hd, hdd) = (horizontal(&hip.p), horizontal(&hip.v), horizontal(&hip.a));
    // The hip path: H' = Ry(psi) h', H'' = Ry(psi) (h'' + psi' e x h').
    let ry = rot_y(psi.v);
    let path_v = ry * hd;
    let path_a = ry * (hdd + e.cross(&hd) * psi.d1);
    let frame = |f: &mut Frame, q: &D2| {
        let ry = rot_y(q.v);
        let w = ry * f.w;
        f.wd = ry * f.wd + e.cross(&w) * q.d1 + e * q.d2;
        f.w = w + e * q.d1;
        f.r = ry * f.r;
    };
    // A point `H + Ry(q) r`, `r` its offset from the hip.
    let point = |p: &mut PointKin, q: &D2| {
        let ry = rot_y(q.v);
        let (r, rd, rdd) = (p.p - h, p.v - hd, p.a - hdd);
        let ey_r = e.cross(&r);
        p.a = path_a
            + ry * (rdd + e.cross(&rd) * (2.0 * q.d1) + ey_r * q.d2 + e.cross(&ey_r) * q.d1 * q.d1);
        p.v = path_v + ry * (rd + ey_r * q.d1);
        p.p = hip_path + ry * r;
    };
    frame(&mut k.frames[0], &psi_trunk);
    k.frames[1..].iter_mut().for_each(|f| frame(f, &psi));
    k.joints.iter_mut().for_each(|p| point(p, &psi));
    point(&mut k.imu[0], &psi_trunk);
    k.imu[1..].iter_mut().for_each(|p| point(p, &psi));
    k.contacts.iter_mut().for_each(|p| point(p, &psi));
}

/// Horizontal velocity of the turned hip path, `Ry(psi) dh/dt`, of the
/// unturned kinematics `k` at heading `psi` (rad).
pub fn hip_path_rate(k: &LegKin, psi: f64) -> Vector3<f64> {
    rot_y(psi) * horizontal(&k.joints[0].v)
}

/// Horizontal part (x, z) of a vector.
pub fn horizontal(v: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(v.x, 0.0, v.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirroring_twice_is_the_identity_and_keeps_planar_frames() {
        let f = Frame::new(&crate::chain::Angles {
            theta: D2 {
                v: 0.3,
                d1: 1.0,
                d2: -2.0,
            },
            ..Default::default()
        });
        let p = PointKin {
            p: Vector3::new(1.0, 2.0, 3.0),
            v: Vector3::new(0.1, 0.2, 0.3),
            a: Vector3::new(-1.0, 0.5, 0.7),
        };
        let mut k = LegKin {
            frames: [f; 4],
            joints: [p; 3],
            imu: [p; 4],
            contacts: [p; 2],
        };
        let orig = k;
        mirror_to(Leg::Left, &mut k);
        // A planar frame is its own mirror image; z offsets flip.
        assert!((k.frames[1].r - orig.frames[1].r).norm() < 1e-15);
        assert!((k.frames[1].w - orig.frames[1].w).norm() < 1e-15);
        assert_eq!(k.imu[2].p.z, -3.0);
        mirror_to(Leg::Left, &mut k);
        assert_eq!(k, orig);
    }
}
