//! Planar leg geometry of the stance solution: foot contact points, two-link
//! inverse kinematics hip to ankle, the foot angle that gives a knee flexion.

use core::f64::consts::TAU;

use super::HEEL_SMIN;
use crate::anthropometry::Body;

/// Heel, metatarsal head and ankle of a planar leg relative to the hip (m).
pub(super) fn leg_points(body: &Body, thigh: f64, shank: f64, foot: f64) -> [[f64; 2]; 3] {
    let ankle = [
        body.thigh * thigh.sin() + body.shank * shank.sin(),
        -body.thigh * thigh.cos() - body.shank * shank.cos(),
    ];
    let at = |c: [f64; 2]| {
        let r = rot(foot, c);
        [ankle[0] + r[0], ankle[1] + r[1]]
    };
    [at(heel(body)), at(mtp(body)), ankle]
}

pub(super) fn heel(body: &Body) -> [f64; 2] {
    [body.heel.x, body.heel.y]
}

pub(super) fn mtp(body: &Body) -> [f64; 2] {
    [body.mtp.x, body.mtp.y]
}

pub(super) fn rot(t: f64, c: [f64; 2]) -> [f64; 2] {
    let (s, co) = t.sin_cos();
    [co * c[0] - s * c[1], s * c[0] + co * c[1]]
}

/// Two-link inverse kinematics from hip to ankle (`d` = ankle - hip): thigh
/// and shank angles (knee forward) and hip-ankle distance minus leg length.
pub(super) fn two_link(body: &Body, d: [f64; 2]) -> (f64, f64, f64) {
    let (l1, l2) = (body.thigh, body.shank);
    let r0 = d[0].hypot(d[1]);
    let r = r0.clamp((l1 - l2).abs() + 1e-9, l1 + l2);
    let knee = core::f64::consts::PI
        - ((l1 * l1 + l2 * l2 - r * r) / (2.0 * l1 * l2))
            .clamp(-1.0, 1.0)
            .acos();
    let base = d[0].atan2(-d[1]);
    let alpha = ((l1 * l1 + r * r - l2 * l2) / (2.0 * l1 * r))
        .clamp(-1.0, 1.0)
        .acos();
    let thigh = base + alpha;
    (thigh, thigh - knee, r0 - (l1 + l2))
}

/// Foot angle that puts the ankle at the hip-ankle distance of knee flexion
/// `knee` while the foot point `c` stays at `p` (two-circle intersection; the
/// smaller of the two angles; tangent solution when the circles do not meet).
pub(super) fn foot_for_knee(
    body: &Body,
    hip: [f64; 2],
    p: [f64; 2],
    c: [f64; 2],
    knee: f64,
) -> f64 {
    let (l1, l2) = (body.thigh, body.shank);
    let r = (l1 * l1 + l2 * l2 + 2.0 * l1 * l2 * knee.cos()).sqrt();
    let rc = c[0].hypot(c[1]);
    let d = [hip[0] - p[0], hip[1] - p[1]];
    let dd = d[0].hypot(d[1]);
    let a = (rc * rc - r * r + dd * dd) / (2.0 * dd);
    let h = (rc * rc - a * a).max(0.0).sqrt();
    let e = [d[0] / dd, d[1] / dd];
    let nrm = [-e[1], e[0]];
    let c_ang = c[1].atan2(c[0]);
    let mut best = f64::NAN;
    for sgn in [1.0, -1.0] {
        // ankle = p + a e + sgn h n; R(psi) c = p - ankle.
        let u = [
            -(a * e[0] + sgn * h * nrm[0]),
            -(a * e[1] + sgn * h * nrm[1]),
        ];
        let psi = (u[1].atan2(u[0]) - c_ang + core::f64::consts::PI).rem_euclid(TAU)
            - core::f64::consts::PI;
        if best.is_nan() || psi.abs() < best.abs() {
            best = psi;
        }
    }
    best
}

/// `min(x, 0)`, smoothed over `HEEL_SMIN`.
pub(super) fn smooth_min0(x: f64) -> f64 {
    0.5 * (x - (x * x + HEEL_SMIN * HEEL_SMIN).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_link_reaches_the_ankle() {
        let body = Body::from_height(1.75);
        let d = [0.2, -0.8];
        let (t, s, over) = two_link(&body, d);
        let a = leg_points(&body, t, s, 0.0)[2];
        assert!((a[0] - d[0]).abs() < 1e-12 && (a[1] - d[1]).abs() < 1e-12);
        assert!(over < 0.0 && t > s, "knee bends forward");
    }

    #[test]
    fn foot_for_knee_gives_the_knee() {
        let body = Body::from_height(1.75);
        let (p, c) = ([0.3, 0.0], mtp(&body));
        let hip = [0.55, 0.87];
        let psi = foot_for_knee(&body, hip, p, c, 0.2);
        let rc = rot(psi, c);
        let d = [p[0] - rc[0] - hip[0], p[1] - rc[1] - hip[1]];
        let (t, s, _) = two_link(&body, d);
        assert!((t - s - 0.2).abs() < 1e-9, "{}", t - s);
        assert!(psi < 0.0, "heel up");
    }
}
