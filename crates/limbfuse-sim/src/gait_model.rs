//! The complete kinematic gait model at one speed: segment-angle curves,
//! out-of-plane angles and the hip path, calibrated so that
//! stride length x stride frequency equals the requested speed.

use core::f64::consts::TAU;

use crate::anthropometry::Body;
use crate::chain::{leg, Angles, LegKin, PointKin};
use crate::fourier::{grid, Fourier, Harmonics, D2};
use crate::gait_curves::{foot_flat_window, scale_about_mean, BaseCurves, SpeedLaw, GRID};
use crate::hip_path::{modulate, to_time, Curves, HipPath, PathFit};
use crate::variability::Modulation;

/// Harmonics of the foot-flat-corrected ankle curve.
const ANKLE_ORDER: usize = 16;
/// Harmonics of the out-of-plane curves.
const OOP_ORDER: usize = 8;

/// Why the model could not be calibrated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CalibrationFailed {
    /// Stride length reached (m).
    pub reached: f64,
    /// Stride length wanted (m).
    pub wanted: f64,
}

/// A calibrated gait.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaitModel {
    /// Geometry.
    pub body: Body,
    /// Speed law (cadence, gains).
    pub law: SpeedLaw,
    /// Hip excursion gain found by calibration.
    pub hip_gain: f64,
    /// Segment-angle curves of the right leg.
    pub curves: Curves,
    /// Hip path.
    pub hip: HipPath,
    /// Highest harmonic of any series (harmonic tables stop there).
    pub order: usize,
}

/// Smooth swing window: 0 over 2-50 % of the stride, 1 over 62-92 %.
fn swing_window(phi: f64) -> f64 {
    let x = (phi / TAU * 100.0).rem_euclid(100.0);
    let ramp = |u: f64| 0.5 - 0.5 * (core::f64::consts::PI * u.clamp(0.0, 1.0)).cos();
    if x < 50.0 {
        1.0 - ramp(x / 2.0)
    } else if x < 62.0 {
        ramp((x - 50.0) / 12.0)
    } else if x < 92.0 {
        1.0
    } else {
        1.0 - ramp((x - 92.0) / 10.0)
    }
}

fn sampled(f: impl Fn(f64) -> f64, order: usize) -> Fourier {
    let y: Vec<f64> = grid(GRID).map(f).collect();
    Fourier::fit(&y, order)
}

/// Out-of-plane angles (rad): `[alpha; 4]`, `[beta; 4]`. Amplitudes (deg) are
/// a few degrees, of the order of the frontal/transverse excursions in
/// Perry & Burnfield (2010) ch. 4-8: pelvic obliquity 3 and rotation 4, hip
/// ab/adduction 4 (adduction peak at ~17 % of the stride), thigh rotation 4,
/// shank 2 and 5, foot inversion 4 and toe-out 3 in swing only (the stance
/// foot is planted).
fn out_of_plane() -> ([Fourier; 4], [Fourier; 4]) {
    let d = |x: f64| x.to_radians();
    let alpha = [
        sampled(|p| d(3.0) * (p - 0.2 * TAU).cos(), OOP_ORDER),
        sampled(|p| d(4.0) * (p - 0.17 * TAU).cos(), OOP_ORDER),
        sampled(|p| d(2.0) * (p - 0.17 * TAU).cos(), OOP_ORDER),
        sampled(|p| d(4.0) * swing_window(p), OOP_ORDER),
    ];
    let beta = [
        sampled(|p| d(4.0) * p.cos(), OOP_ORDER),
        sampled(|p| d(4.0) * p.sin(), OOP_ORDER),
        sampled(|p| d(5.0) * (p - 0.3 * TAU).cos(), OOP_ORDER),
        sampled(|p| -d(3.0) * swing_window(p), OOP_ORDER),
    ];
    (alpha, beta)
}

/// Sagittal segment curves for a given hip gain (the ankle corrected so that
/// the foot is flat, theta_foot = 0, in the flat-foot part of stance).
fn sagittal(base: &BaseCurves, law: &SpeedLaw, hip_gain: f64) -> [Fourier; 4] {
    let trunk = law.trunk();
    let hip = scale_about_mean(&base.hip, hip_gain);
    let knee = scale_about_mean(&base.knee, law.knee_gain());
    let ankle = scale_about_mean(&base.ankle, law.ankle_gain());
    // theta_thigh = theta_trunk + hip_flex, theta_shank = theta_thigh - knee_flex,
    // theta_foot = theta_shank + ankle_dorsi (SPEC section 1 with clinical signs).
    let thigh = Fourier::combine(&[(1.0, &trunk), (1.0, &hip)]);
    let shank = Fourier::combine(&[(1.0, &thigh), (-1.0, &knee)]);
    let ankle_c = sampled(
        |p| {
            let a = ankle.value(p);
            a - foot_flat_window(p) * (shank.value(p) + a)
        },
        ANKLE_ORDER,
    );
    let foot = Fourier::combine(&[(1.0, &shank), (1.0, &ankle_c)]);
    [trunk, thigh, shank, foot]
}

impl GaitModel {
    /// Builds and calibrates the gait for `law`. The hip gain is found by the
    /// secant method on `stride_length(gain) - law.stride_length()`.
    pub fn new(law: SpeedLaw, out_of_plane_on: bool) -> Result<Self, CalibrationFailed> {
        let body = Body::from_height(law.height);
        let base = BaseCurves::fit();
        let (alpha, beta) = if out_of_plane_on {
            out_of_plane()
        } else {
            ([Fourier::default(); 4], [Fourier::default(); 4])
        };
        let wanted = law.stride_length();
        let build = |g: f64| {
            let curves = Curves {
                theta: sagittal(&base, &law, g),
                alpha,
                beta,
            };
            let hip = PathFit::fit(&body, &curves, GRID);
            (curves, hip)
        };
        let done = |curves: Curves, g: f64| {
            let hip = HipPath::fit(&body, &curves, GRID);
            let series = curves.theta.iter().chain(&curves.alpha).chain(&curves.beta);
            let order = series
                .chain(hip.px.iter())
                .chain(hip.y.iter())
                .chain(hip.pz.iter())
                .map(|f| f.order)
                .max()
                .unwrap_or(0);
            GaitModel {
                body,
                law,
                hip_gain: g,
                curves,
                hip,
                order,
            }
        };
        let (mut g0, mut g1) = (0.8, 1.0);
        let mut l0 = build(g0).1.stride_length;
        let (mut curves, mut hip) = build(g1);
        for _ in 0..30 {
            let l1 = hip.stride_length;
            if (l1 - wanted).abs() < 1e-9 * wanted {
                return Ok(done(curves, g1));
            }
            let slope = (l1 - l0) / (g1 - g0);
            if !(slope.is_finite() && slope > 0.0) {
                break;
            }
            let g2 = (g1 + (wanted - l1) / slope).clamp(0.1, 3.0);
            (g0, l0, g1) = (g1, l1, g2);
            (curves, hip) = build(g1);
        }
        if (hip.stride_length - wanted).abs() < 1e-6 * wanted {
            return Ok(done(curves, g1));
        }
        Err(CalibrationFailed {
            reached: hip.stride_length,
            wanted,
        })
    }

    /// Right-leg segment angles with time derivatives, at clock reading
    /// `phase` (phi, phi', phi'') under amplitude modulation `m`.
    pub fn angles(&self, h: &Harmonics, phase: D2, amp: D2) -> [Angles; 4] {
        let mut a = self.curves.angles(h, false);
        for (i, s) in a.iter_mut().enumerate() {
            let c0 = self.curves.theta[i].c0;
            let mut dev = s.theta;
            dev.v -= c0;
            let mut th = modulate(dev, amp);
            th.v += c0;
            s.theta = to_time(th, phase);
            s.alpha = to_time(s.alpha, phase);
            s.beta = to_time(s.beta, phase);
        }
        a
    }

    /// Sagittal segment angles only (rad), for the encoder path.
    pub fn sagittal_angles(&self, phi: f64, amp: f64) -> [f64; 4] {
        let h = Harmonics::up_to(phi, self.order);
        let mut out = [0.0; 4];
        for (o, f) in out.iter_mut().zip(&self.curves.theta) {
            *o = f.c0 + amp * (f.eval(&h).v - f.c0);
        }
        out
    }

    /// Full chain kinematics at clock reading `phase` under modulation `m`,
    /// with the sagittal segment angles (rad).
    pub fn kinematics(&self, phase: D2, m: &Modulation) -> (LegKin, [f64; 4]) {
        let h = Harmonics::up_to(phase.v, self.order);
        let amp = m.amp(phase.v);
        let seg = self.angles(&h, phase, amp);
        let [x, y, z] = self.hip.eval(&h, phase.v, amp, m.integral(phase.v));
        let (x, y, z) = (to_time(x, phase), to_time(y, phase), to_time(z, phase));
        let hip = PointKin {
            p: [x.v, y.v, z.v].into(),
            v: [x.d1, y.d1, z.d1].into(),
            a: [x.d2, y.d2, z.d2].into(),
        };
        let theta = [
            seg[0].theta.v,
            seg[1].theta.v,
            seg[2].theta.v,
            seg[3].theta.v,
        ];
        (leg(&self.body, hip, &seg, 1.0), theta)
    }

    /// Upright quiet standing: every angle zero, hip at standing height.
    pub fn standing(&self) -> LegKin {
        let hip = PointKin {
            p: [0.0, self.body.standing_hip_height(), 0.0].into(),
            ..Default::default()
        };
        leg(&self.body, hip, &[Angles::default(); 4], 1.0)
    }
}
