//! The path of the right hip joint centre.
//!
//! Forward and vertical motion are prescribed
//! ([`crate::stance::PathShape`]: forward speed `v (1 - eps cos 2 (phi -
//! phi_slow))`, height `h0 + e/2 (cos 2 psi - b cos 4 psi)`, `psi = phi -
//! phi_top`), analytic in the
//! phase and in the amplitude `A` of the variability model (stride length and
//! excursion scale with `A`, `h0` is interpolated quadratically between the
//! fits at `A = 1 - d, 1, 1 + d`). The stance leg is made consistent with it
//! by inverse kinematics ([`crate::stance`]).
//!
//! The lateral motion is derived, as before, from the feet: both legs are
//! built from the same curves (the left half a stride later, out-of-plane
//! angles mirrored, its hip joint `hip_width` to the left of the right one in
//! the trunk frame); the body weight passes from the trailing to the leading
//! foot with a smooth ramp over each double support ([`right_leg_load`]) and
//! within a foot is split between heel and metatarsal head by a soft minimum
//! of their heights ([`SOFTMIN_M`]); the hip's lateral rate is minus the
//! weighted lateral contact velocity (the loaded foot does not slide
//! sideways), fitted with a truncated Fourier series and integrated
//! analytically. Without out-of-plane motion it is zero.

use core::f64::consts::TAU;

use nalgebra::Vector3;

use crate::anthropometry::Body;
use crate::chain::{leg, Angles, PointKin};
use crate::fourier::{grid, Fourier, Harmonics, D2};

/// Soft-minimum temperature (m).
pub const SOFTMIN_M: f64 = 0.003;
/// Harmonics of the hip path series.
pub const HIP_ORDER: usize = 16;

/// Amplitude step of the three fits the hip path interpolates between.
pub const AMP_STEP: f64 = 0.05;

/// The hip path as a function of phase and amplitude `A` (`a = A - 1`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HipPath {
    /// Stride length at `A = 1` (m).
    pub stride_length: f64,
    /// Relative forward-speed fluctuation `eps`.
    pub fluctuation: f64,
    /// Phase of the slowest forward speed (rad).
    pub slow_phase: f64,
    /// Vertical excursion at `A = 1`, peak to peak (m).
    pub excursion: f64,
    /// Phase of the highest point (rad).
    pub top_phase: f64,
    /// Sharpness `b` of the vertical trough (see [`crate::stance::PathShape`]).
    pub sharpness: f64,
    /// Mean hip height `h0 = q0 + a q1 + a^2 q2` (m).
    pub height: [f64; 3],
    /// `[q0, q1, q2]` of the lateral position (m).
    pub pz: [Fourier; 3],
}

/// `[q0, q1, q2]` with `q(A) = q0 + a q1 + a^2 q2` through the series at
/// `A = 1 - d, 1, 1 + d` ([`AMP_STEP`]).
pub fn quadratic(m: &Fourier, z: &Fourier, p: &Fourier) -> [Fourier; 3] {
    let d = AMP_STEP;
    [
        *z,
        Fourier::combine(&[(0.5 / d, p), (-0.5 / d, m)]),
        Fourier::combine(&[(0.5 / (d * d), p), (-1.0 / (d * d), z), (0.5 / (d * d), m)]),
    ]
}

/// `q(phi, A) = q0 + a q1 + a^2 q2` with total phase derivatives along `A(phi)`.
pub fn along(q: &[Fourier; 3], h: &Harmonics, amp: D2) -> D2 {
    let a = amp.v - 1.0;
    let (q0, q1, q2) = (q[0].eval(h), q[1].eval(h), q[2].eval(h));
    let qa = D2 {
        v: q1.v + 2.0 * a * q2.v,
        d1: q1.d1 + 2.0 * a * q2.d1,
        d2: 0.0,
    };
    D2 {
        v: q0.v + a * q1.v + a * a * q2.v,
        d1: q0.d1 + a * q1.d1 + a * a * q2.d1 + qa.v * amp.d1,
        d2: q0.d2
            + a * q1.d2
            + a * a * q2.d2
            + 2.0 * qa.d1 * amp.d1
            + 2.0 * q2.v * amp.d1 * amp.d1
            + qa.v * amp.d2,
    }
}

/// Segment angle series of the right leg: sagittal, and out-of-plane (alpha, beta).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Curves {
    /// Sagittal absolute angles: trunk, thigh, shank, foot (rad).
    pub theta: [Fourier; 4],
    /// Rotation about the segment x axis (rad).
    pub alpha: [Fourier; 4],
    /// Rotation about the segment y axis (rad).
    pub beta: [Fourier; 4],
}

impl Curves {
    /// Angles of the four segments at phase table `h` (phase derivatives),
    /// optionally as the mirrored left leg (out-of-plane signs flipped; the
    /// caller passes the half-stride-later table).
    pub fn angles(&self, h: &Harmonics, mirrored: bool) -> [Angles; 4] {
        let sign = if mirrored { -1.0 } else { 1.0 };
        let neg = |d: D2| D2 {
            v: sign * d.v,
            d1: sign * d.d1,
            d2: sign * d.d2,
        };
        let mut out = [Angles::default(); 4];
        for (i, o) in out.iter_mut().enumerate() {
            *o = Angles {
                theta: self.theta[i].eval(h),
                alpha: neg(self.alpha[i].eval(h)),
                beta: neg(self.beta[i].eval(h)),
            };
        }
        out
    }
}

/// Contact points of both feet, relative to the right hip, with phase derivatives.
pub fn contact_points(body: &Body, curves: &Curves, phi: f64) -> [PointKin; 4] {
    let hr = Harmonics::new(phi);
    let hl = Harmonics::new(phi + TAU / 2.0);
    let right = curves.angles(&hr, false);
    let mut left = curves.angles(&hl, true);
    // Both legs hang from the same pelvis.
    left[0] = right[0];
    let root = PointKin::default();
    let kr = leg(body, root, &right, 1.0);
    let left_hip = root.attach(&kr.frames[0], &Vector3::new(0.0, 0.0, -body.hip_width));
    let kl = leg(body, left_hip, &left, -1.0);
    [
        kr.contacts[0],
        kr.contacts[1],
        kl.contacts[0],
        kl.contacts[1],
    ]
}

/// Fraction of the stride each double-support phase lasts (toe-off of the
/// keypoint curves is at 60 %, so 10 %).
pub const DOUBLE_SUPPORT: f64 = 0.10;

/// Share of the body weight on the right foot: 0 -> 1 over the initial
/// double support (0-10 %), 1 in single support, 1 -> 0 over the second
/// double support (50-60 %), raised-cosine ramps.
pub fn right_leg_load(phi: f64) -> f64 {
    let x = (phi / TAU).rem_euclid(1.0);
    let ramp = |u: f64| 0.5 - 0.5 * (core::f64::consts::PI * u.clamp(0.0, 1.0)).cos();
    if x < 0.5 {
        ramp(x / DOUBLE_SUPPORT)
    } else {
        1.0 - ramp((x - 0.5) / DOUBLE_SUPPORT)
    }
}

/// Contact weights: the leg load (see [`right_leg_load`]) split between the
/// heel and the metatarsal head of each foot by a soft minimum of their heights.
pub fn contact_weights(c: &[PointKin; 4], phi: f64) -> [f64; 4] {
    let split = |a: &PointKin, b: &PointKin| {
        let d = ((b.p.y - a.p.y) / SOFTMIN_M).clamp(-700.0, 700.0);
        // weight of a = 1 / (1 + exp(-(y_b - y_a)/T))
        let wa = 1.0 / (1.0 + (-d).exp());
        (wa, 1.0 - wa)
    };
    let load = right_leg_load(phi);
    let (rh, rm) = split(&c[0], &c[1]);
    let (lh, lm) = split(&c[2], &c[3]);
    [load * rh, load * rm, (1.0 - load) * lh, (1.0 - load) * lm]
}

/// Lateral position of the right hip (m, zero-mean series) for the given
/// curves: minus the load-weighted lateral contact velocity, integrated.
pub fn lateral_fit(body: &Body, curves: &Curves, n: usize) -> Fourier {
    let mut dz = Vec::with_capacity(n);
    for phi in grid(n) {
        let c = contact_points(body, curves, phi);
        let w = contact_weights(&c, phi);
        dz.push(-w.iter().zip(&c).map(|(wi, p)| wi * p.v.z).sum::<f64>());
    }
    Fourier::fit(&dz, HIP_ORDER).integral()
}

impl HipPath {
    /// Hip position (x, y, z) and its phase derivatives, under amplitude
    /// modulation `amp` (`A`, `dA/dphi`, `d2A/dphi2`) whose integral from
    /// phase 0 is `amp_integral`; `h` is the harmonic table of the phase
    /// (filled to at least the fourth harmonic).
    pub fn eval(&self, h: &Harmonics, amp: D2, amp_integral: f64) -> [D2; 3] {
        let l = self.stride_length;
        // sin/cos of 2 (phi - phase) from the table: angle subtraction.
        // sin/cos of k (phi - p) from the table (angle subtraction).
        let shifted = |k: usize, p: f64| {
            let (sp, cp) = (k as f64 * p).sin_cos();
            (h.sin(k) * cp - h.cos(k) * sp, h.cos(k) * cp + h.sin(k) * sp)
        };
        let (s2, c2) = shifted(2, self.slow_phase);
        let k = l * self.fluctuation / (2.0 * TAU);
        let x = D2 {
            v: l / TAU * amp_integral - k * amp.v * s2,
            d1: l / TAU * amp.v - k * (amp.d1 * s2 + 2.0 * amp.v * c2),
            d2: l / TAU * amp.d1 - k * (amp.d2 * s2 + 4.0 * amp.d1 * c2 - 4.0 * amp.v * s2),
        };
        // g = cos 2 psi - b cos 4 psi, psi = phi - phi_top.
        let ((s2, c2), (s4, c4)) = (shifted(2, self.top_phase), shifted(4, self.top_phase));
        let b = self.sharpness;
        let g = D2 {
            v: c2 - b * c4,
            d1: -2.0 * s2 + 4.0 * b * s4,
            d2: -4.0 * c2 + 16.0 * b * c4,
        };
        let e = 0.5 * self.excursion;
        let a = amp.v - 1.0;
        let q = &self.height;
        let ha = q[1] + 2.0 * a * q[2];
        let y = D2 {
            v: q[0] + a * q[1] + a * a * q[2] + e * amp.v * g.v,
            d1: ha * amp.d1 + e * (amp.d1 * g.v + amp.v * g.d1),
            d2: ha * amp.d2
                + 2.0 * q[2] * amp.d1 * amp.d1
                + e * (amp.d2 * g.v + 2.0 * amp.d1 * g.d1 + amp.v * g.d2),
        };
        [x, y, along(&self.pz, h, amp)]
    }
}

/// `A f` with its phase derivatives (product rule).
#[inline]
pub fn modulate(f: D2, a: D2) -> D2 {
    D2 {
        v: a.v * f.v,
        d1: a.d1 * f.v + a.v * f.d1,
        d2: a.d2 * f.v + 2.0 * a.d1 * f.d1 + a.v * f.d2,
    }
}

/// Converts phase derivatives to time derivatives given the phase's own
/// time derivatives (`phi'`, `phi''` in `phase.d1`, `phase.d2`).
#[inline]
pub fn to_time(q: D2, phase: D2) -> D2 {
    D2 {
        v: q.v,
        d1: q.d1 * phase.d1,
        d2: q.d2 * phase.d1 * phase.d1 + q.d1 * phase.d2,
    }
}
