//! The normative segment curves the stance leg is fitted to, and the hip
//! gain at which their feet fit one stance of the pelvis path.

use core::f64::consts::TAU;

use super::leg::leg_points;
use super::path::PathShape;
use super::{ANKLE_ORDER, TOE_OFF};
use crate::anthropometry::Body;
use crate::fourier::{grid, Fourier, Harmonics};
use crate::gait_curves::{foot_flat_window, scale_about_mean, BaseCurves, SpeedLaw, GRID};

/// The normative segment curves at one amplitude (rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Normative {
    /// Hip excursion gain (solved by [`Normative::reach_gain`]).
    pub hip_gain: f64,
    /// Trunk, thigh, shank and foot; the foot corrected to be flat in the
    /// flat-foot part of stance (smooth window, full over 10-30 %).
    pub theta: [Fourier; 4],
    /// The uncorrected foot curve (shank + ankle dorsiflexion).
    pub foot_raw: Fourier,
}

/// Trunk, thigh, shank and raw foot at a hip gain, every excursion about
/// its mean scaled by `amp`: thigh = trunk + hip flexion, shank = thigh -
/// knee flexion, foot = shank + ankle dorsiflexion (SPEC section 1 with
/// clinical signs).
fn segments(base: &BaseCurves, law: &SpeedLaw, amp: f64, hip_gain: f64) -> [Fourier; 4] {
    let trunk = scale_about_mean(&law.trunk(), amp);
    let hip = scale_about_mean(&base.hip, hip_gain);
    let knee = scale_about_mean(&base.knee, law.knee_gain() * amp);
    let ankle = scale_about_mean(&base.ankle, law.ankle_gain() * amp);
    let thigh = Fourier::combine(&[(1.0, &trunk), (1.0, &hip)]);
    let shank = Fourier::combine(&[(1.0, &thigh), (-1.0, &knee)]);
    let foot = Fourier::combine(&[(1.0, &shank), (1.0, &ankle)]);
    [trunk, thigh, shank, foot]
}

impl Normative {
    /// The hip gain at which the normative foot positions fit one stance of
    /// the path: heel ahead of the hip at heel strike + heel-to-metatarsal
    /// distance + metatarsal head behind the hip at toe-off = the hip's
    /// forward travel over stance. Bisection (the reach grows with the gain).
    pub fn reach_gain(
        body: &Body,
        base: &BaseCurves,
        law: &SpeedLaw,
        amp: f64,
        path: &PathShape,
    ) -> Option<f64> {
        let to = TOE_OFF * TAU;
        let need = path.x(to) - path.x(0.0);
        let (h0, h1) = (Harmonics::new(0.0), Harmonics::new(to));
        let gap = |g: f64| {
            let s = segments(base, law, amp, g);
            let at = |h: &Harmonics| {
                let v = s.map(|f| f.eval(h).v);
                leg_points(body, v[1], v[2], v[3])
            };
            let (hs, off) = (at(&h0), at(&h1));
            hs[0][0] - off[1][0] + (body.mtp.x - body.heel.x) - need
        };
        let (mut lo, mut hi) = (0.05, 3.0);
        if !(gap(lo) < 0.0 && gap(hi) > 0.0) {
            return None;
        }
        for _ in 0..50 {
            let mid = 0.5 * (lo + hi);
            if gap(mid) > 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Some(0.5 * (lo + hi))
    }

    /// The curves at amplitude `amp` and hip gain `hip_gain`.
    pub fn new(base: &BaseCurves, law: &SpeedLaw, amp: f64, hip_gain: f64) -> Self {
        let [trunk, thigh, shank, foot_raw] = segments(base, law, amp, hip_gain);
        // Flat foot over 10-30 %: ankle_c = ankle - w (theta_shank + ankle).
        let y: Vec<f64> = grid(GRID)
            .map(|p| {
                let (sh, f) = (shank.value(p), foot_raw.value(p));
                let a = f - sh;
                a - foot_flat_window(p) * f
            })
            .collect();
        let ankle_c = Fourier::fit(&y, ANKLE_ORDER);
        let foot = Fourier::combine(&[(1.0, &shank), (1.0, &ankle_c)]);
        Normative {
            hip_gain,
            theta: [trunk, thigh, shank, foot],
            foot_raw,
        }
    }
}
