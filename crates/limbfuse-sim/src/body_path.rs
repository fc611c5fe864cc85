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
//! **Turns.** The whole body turns about the vertical through the hip joint
//! centre by the heading `psi(t)` (positive = to the left, counter-clockwise
//! seen from above): with `h` the hip's horizontal position and `H` the
//! turned hip path (`dH/dt = Ry(psi) dh/dt`), a point `p = h + r` moves to
//! `p' = H + Ry(psi) r`, a frame `R` to `Ry(psi) R`. Differentiating twice
//! (`e = y`, the vertical):
//! `w' = Ry w + psi' e`, `w'dot = Ry wdot + psi' e x Ry w + psi'' e`,
//! `v' = Ry (h' + r') + psi' e x Ry r`,
//! `a' = Ry (h'' + r'' + psi' e x (h' + 2 r') + psi'' e x r + psi'^2 e x (e x r))`.
//! The gait itself (sagittal angles, stride) is unchanged during the turn:
//! the body walks along an arc of radius `speed / psi'`. A turn follows the
//! quintic smoothstep `s(u) = 10u^3 - 15u^4 + 6u^5` (continuous heading rate
//! and acceleration).

use limbfuse_core::Leg;
use nalgebra::{Matrix3, Vector3};

use crate::chain::{rot_y, Frame, LegKin, PointKin};
use crate::fourier::D2;

/// Turns of the walking path: the `k`-th turn (k = 1, 2, ...) starts at
/// `k * every_s` and lasts `duration_s`, turning by `angle_rad` each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turns {
    /// Interval between turn starts (s), > `duration_s`.
    pub every_s: f64,
    /// Duration of one turn (s), > 0.
    pub duration_s: f64,
    /// Heading change of one turn (rad; positive = to the left).
    pub angle_rad: f64,
}

impl Turns {
    /// Heading `psi` (rad) with its first two time derivatives at `t` (s).
    pub fn heading(&self, t: f64) -> D2 {
        if t <= 0.0 {
            return D2::constant(0.0);
        }
        let k = (t / self.every_s).floor();
        let done = (k - 1.0).max(0.0) * self.angle_rad;
        let u = if k >= 1.0 {
            (t - k * self.every_s) / self.duration_s
        } else {
            0.0
        };
        if k < 1.0 || u >= 1.0 {
            let whole = if k >= 1.0 { self.angle_rad } else { 0.0 };
            return D2::constant(done + whole);
        }
        let (a, d) = (self.angle_rad, self.duration_s);
        D2 {
            v: done + a * u * u * u * (10.0 + u * (-15.0 + 6.0 * u)),
            d1: a / d * 30.0 * u * u * (1.0 - u) * (1.0 - u),
            d2: a / (d * d) * 60.0 * u * (1.0 + u * (-3.0 + 2.0 * u)),
        }
    }
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

/// Turns the whole body of `k` by heading `psi` about the vertical through
/// the hip (module docs); `hip_path` is the turned hip's horizontal
/// position `H` (the caller integrates it).
pub fn turn(k: &mut LegKin, psi: D2, hip_path: Vector3<f64>) {
    let ry = rot_y(psi.v);
    let e = Vector3::y();
    let hip = k.joints[0];
    let (h, hd, hdd) = (horizontal(&hip.p), horizontal(&hip.v), horizontal(&hip.a));
    let frame = |f: &mut Frame| {
        let w = ry * f.w;
        f.wd = ry * f.wd + e.cross(&w) * psi.d1 + e * psi.d2;
        f.w = w + e * psi.d1;
        f.r = ry * f.r;
    };
    k.frames.iter_mut().for_each(frame);
    let point = |p: &mut PointKin| {
        let (r, rd, rdd) = (p.p - h, p.v - hd, p.a - hdd);
        let ey_r = e.cross(&r);
        p.a = ry
            * (hdd
                + rdd
                + e.cross(&(hd + 2.0 * rd)) * psi.d1
                + ey_r * psi.d2
                + e.cross(&ey_r) * psi.d1 * psi.d1);
        p.v = ry * (hd + rd + ey_r * psi.d1);
        p.p = hip_path + ry * r;
    };
    k.joints.iter_mut().for_each(point);
    k.imu.iter_mut().for_each(point);
    k.contacts.iter_mut().for_each(point);
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
    fn heading_derivatives_match_finite_differences() {
        let t = Turns {
            every_s: 5.0,
            duration_s: 2.0,
            angle_rad: 3.0,
        };
        for &x in &[0.5, 5.3, 6.0, 6.9, 8.0, 10.4, 11.99] {
            let h = 1e-5;
            let (p, m, c) = (t.heading(x + h), t.heading(x - h), t.heading(x));
            assert!(((p.v - m.v) / (2.0 * h) - c.d1).abs() < 1e-6, "{x}");
            assert!(((p.d1 - m.d1) / (2.0 * h) - c.d2).abs() < 1e-5, "{x}");
        }
        assert_eq!(t.heading(7.5).v, 3.0);
        assert!((t.heading(12.0).v - 6.0).abs() < 1e-12);
    }

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
