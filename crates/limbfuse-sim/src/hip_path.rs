//! The hip path that keeps the stance foot on the ground and still.
//!
//! Both legs are built from the same curves (the left half a stride later,
//! out-of-plane angles mirrored, its hip joint `hip_width` to the left of the
//! right one in the trunk frame). Over one stride, on a grid of phases, with
//! the right hip joint centre as origin, the four contact points (heel and
//! metatarsal head of each foot) are weighted: the body weight passes from
//! the trailing to the leading foot with a smooth ramp over each double
//! support ([`right_leg_load`]), and within a foot it is split between heel
//! and metatarsal head by a soft minimum of their heights (logistic in the
//! height difference, scale `T` = [`SOFTMIN_M`]), so the lower point carries
//! it and heel-to-forefoot roll-over is smooth. (A height-only soft minimum
//! across both feet hands over within milliseconds at heel strike, because
//! normative curves are not exactly consistent with two still feet, and gives
//! hip accelerations of several g; spreading the hand-over over the double
//! support spreads that inconsistency as a few centimetres of foot slip
//! during double support instead.) Then
//! * hip height `= -sum w_i y_i` (the weighted contact point is on the floor),
//! * hip horizontal and lateral rates `= -sum w_i dr_i/dphi` (the weighted
//!   contact point does not slide),
//!
//! and the three are fitted with truncated Fourier series in the phase: the
//! forward rate's mean times `2 pi` is the stride length `L`, its zero-mean
//! part is integrated analytically, so `x(phi) = L phi / 2 pi + p_x(phi)`,
//! `y = y(phi)`, `z = p_z(phi)`, each with analytic phase derivatives. Under
//! amplitude modulation the path is interpolated between fits at three
//! amplitudes ([`HipPath`]).

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
pub const AMP_STEP: f64 = 0.1;

/// The hip path of one stride at a fixed amplitude.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathFit {
    /// Stride length (m).
    pub stride_length: f64,
    /// Periodic part of the forward position (m).
    pub px: Fourier,
    /// Height of the right hip joint centre above the floor (m).
    pub y: Fourier,
    /// Lateral position (m).
    pub pz: Fourier,
}

/// The hip path as a function of phase and amplitude `A`: fits at
/// `A = 1 - d, 1, 1 + d` ([`AMP_STEP`]) combined as `q0 + a q1 + a^2 q2`
/// (`a = A - 1`), so that at any fixed amplitude the stance foot stays still
/// to third order in `a`; the forward position is
/// `x = L0/(2 pi) phi + L1/(2 pi) int (A - 1) dphi + p_x(phi, A)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HipPath {
    /// Stride length at `A = 1` (m).
    pub stride_length: f64,
    /// `dL/dA` (m).
    pub stride_length_slope: f64,
    /// `[q0, q1, q2]` of the periodic forward part.
    pub px: [Fourier; 3],
    /// `[q0, q1, q2]` of the height.
    pub y: [Fourier; 3],
    /// `[q0, q1, q2]` of the lateral position.
    pub pz: [Fourier; 3],
}

/// Scales the sagittal excursions about their means by `amp`.
pub fn scaled(curves: &Curves, amp: f64) -> Curves {
    let mut c = *curves;
    for f in c.theta.iter_mut() {
        let c0 = f.c0;
        *f = Fourier::combine(&[(amp, f)]);
        f.c0 = c0;
    }
    c
}

fn quadratic(m: &Fourier, z: &Fourier, p: &Fourier) -> [Fourier; 3] {
    let d = AMP_STEP;
    [
        *z,
        Fourier::combine(&[(0.5 / d, p), (-0.5 / d, m)]),
        Fourier::combine(&[(0.5 / (d * d), p), (-1.0 / (d * d), z), (0.5 / (d * d), m)]),
    ]
}

/// `q(phi, A) = q0 + a q1 + a^2 q2` with total phase derivatives along `A(phi)`.
fn along(q: &[Fourier; 3], h: &Harmonics, amp: D2) -> D2 {
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

impl PathFit {
    /// Computes and fits the hip path for the given curves.
    pub fn fit(body: &Body, curves: &Curves, n: usize) -> Self {
        let mut hy = Vec::with_capacity(n);
        let mut dx = Vec::with_capacity(n);
        let mut dz = Vec::with_capacity(n);
        for phi in grid(n) {
            let c = contact_points(body, curves, phi);
            let w = contact_weights(&c, phi);
            let (mut y, mut vx, mut vz) = (0.0, 0.0, 0.0);
            for (wi, p) in w.iter().zip(&c) {
                y += wi * p.p.y;
                vx += wi * p.v.x;
                vz += wi * p.v.z;
            }
            hy.push(-y);
            dx.push(-vx);
            dz.push(-vz);
        }
        let fx = Fourier::fit(&dx, HIP_ORDER);
        let fz = Fourier::fit(&dz, HIP_ORDER);
        PathFit {
            stride_length: TAU * fx.c0,
            px: fx.integral(),
            y: Fourier::fit(&hy, HIP_ORDER),
            pz: fz.integral(),
        }
    }
}

impl HipPath {
    /// Fits the path at the three amplitudes.
    pub fn fit(body: &Body, curves: &Curves, n: usize) -> Self {
        let m = PathFit::fit(body, &scaled(curves, 1.0 - AMP_STEP), n);
        let z = PathFit::fit(body, curves, n);
        let p = PathFit::fit(body, &scaled(curves, 1.0 + AMP_STEP), n);
        HipPath {
            stride_length: z.stride_length,
            stride_length_slope: (p.stride_length - m.stride_length) / (2.0 * AMP_STEP),
            px: quadratic(&m.px, &z.px, &p.px),
            y: quadratic(&m.y, &z.y, &p.y),
            pz: quadratic(&m.pz, &z.pz, &p.pz),
        }
    }

    /// Hip position (x, y, z) and its phase derivatives, under amplitude
    /// modulation `amp` (`A`, `dA/dphi`, `d2A/dphi2`) whose integral from
    /// phase 0 is `amp_integral`.
    pub fn eval(&self, h: &Harmonics, phi: f64, amp: D2, amp_integral: f64) -> [D2; 3] {
        let (k0, k1) = (self.stride_length / TAU, self.stride_length_slope / TAU);
        let px = along(&self.px, h, amp);
        let x = D2 {
            v: k0 * phi + k1 * (amp_integral - phi) + px.v,
            d1: k0 + k1 * (amp.v - 1.0) + px.d1,
            d2: k1 * amp.d1 + px.d2,
        };
        [x, along(&self.y, h, amp), along(&self.pz, h, amp)]
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
