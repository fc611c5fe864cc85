//! The complete kinematic gait model at one speed: a prescribed hip path,
//! segment-angle curves whose stance part is made consistent with it by
//! inverse kinematics ([`crate::stance`]), out-of-plane angles, and their
//! dependence on the amplitude of the variability model.

use core::f64::consts::TAU;

use crate::anthropometry::Body;
use crate::chain::{leg, Angles, LegKin, PointKin};
use crate::fourier::{grid, Fourier, Harmonics, D2};
use crate::gait_curves::{BaseCurves, SpeedLaw, GRID};
use crate::hip_path::{along, lateral_fit, quadratic, to_time, Curves, HipPath, AMP_STEP};
use crate::stance::{
    Normative, PathShape, Placement, Stance, StanceFigures, SEARCH_GRID, SEGMENT_ORDER,
};
use crate::variability::Modulation;

/// Harmonics of the out-of-plane curves.
const OOP_ORDER: usize = 8;
/// Largest stretch of the stance leg accepted (m) before calibration fails.
const MAX_OVERREACH: f64 = 1e-3;

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
    /// Speed law (cadence, gains, path).
    pub law: SpeedLaw,
    /// Hip excursion gain of the normative curves at amplitude 1.
    pub hip_gain: f64,
    /// Segment-angle curves of the right leg at amplitude 1.
    pub curves: Curves,
    /// `[q0, q1, q2]` of each sagittal angle (trunk, thigh, shank, foot) in
    /// `a = A - 1` (fits at `A = 1 - d, 1, 1 + d`, [`AMP_STEP`]).
    pub theta: [[Fourier; 3]; 4],
    /// Hip path.
    pub hip: HipPath,
    /// Stance placement at amplitude 1 (hip height, heel-strike point).
    pub placement: Placement,
    /// Offsets of that placement from its rule (m): hip height, heel strike.
    pub placement_offset: (f64, f64),
    /// Figures of the stance fit at amplitude 1 (before the Fourier fit).
    pub stance: StanceFigures,
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
/// foot is planted). The thigh and shank ab/adduction are then scaled so that
/// the lateral hip excursion they produce matches
/// [`SpeedLaw::lateral_excursion`] (see [`GaitModel::new`]).
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

/// Fit weight of the single-support samples relative to the others: the
/// stance foot must stay still there, the truncation error goes to swing.
const SINGLE_SUPPORT_WEIGHT: f64 = 100.0;

fn sampled_fit(y: &[f64]) -> Fourier {
    let w: Vec<f64> = grid(y.len())
        .map(|p| {
            let s = p / TAU;
            if (FIT_STANCE.0..=FIT_STANCE.1).contains(&s) {
                SINGLE_SUPPORT_WEIGHT
            } else {
                1.0
            }
        })
        .collect();
    Fourier::fit_penalised(y, &w, SEGMENT_ORDER, FIT_SMOOTHING)
}

/// Curvature penalty of the segment fits (relative to the summed weights).
const FIT_SMOOTHING: f64 = 1e-6;

/// Stride fractions fitted with [`SINGLE_SUPPORT_WEIGHT`].
const FIT_STANCE: (f64, f64) = (0.08, 0.52);

/// One amplitude of the model.
struct AtAmplitude {
    theta: [Fourier; 4],
    height: f64,
    pz: Fourier,
    hip_gain: f64,
    placement: Placement,
    figures: StanceFigures,
}

impl GaitModel {
    /// Builds and calibrates the gait for `law`: at amplitude 1 the placement
    /// of the stance leg is searched ([`Stance::fit`]), at the amplitudes
    /// `1 -+ d` it is followed from there ([`Stance::fit_from`]).
    pub fn new(law: SpeedLaw, out_of_plane_on: bool) -> Result<Self, CalibrationFailed> {
        let body = Body::from_height(law.height);
        let base = BaseCurves::fit();
        let (alpha, beta) = if out_of_plane_on {
            out_of_plane()
        } else {
            ([Fourier::default(); 4], [Fourier::default(); 4])
        };
        let path1 = PathShape::new(&law);
        let mut alpha = alpha;
        let wanted = law.stride_length();
        let fail = CalibrationFailed {
            reached: f64::NAN,
            wanted,
        };
        let normative = |amp: f64| {
            let path = path1.scaled(amp);
            Normative::reach_gain(&body, &base, &law, amp, &path)
                .map(|g| (Normative::new(&base, &law, amp, g), path))
                .ok_or(fail)
        };
        let (n1, p1) = normative(1.0)?;
        let offset = Stance::new(&body, &n1, &p1, SEARCH_GRID).fit();
        if out_of_plane_on {
            // Scale the stance-leg ab/adduction (thigh, shank) so that the
            // lateral hip excursion matches the speed law; the lateral path is
            // linear in these small angles to first order.
            let st = Stance::new(&body, &n1, &p1, GRID);
            let sol = st.solve(st.offset(offset));
            let theta = [
                n1.theta[0],
                sampled_fit(&sol.theta[1]),
                sampled_fit(&sol.theta[2]),
                sampled_fit(&sol.theta[3]),
            ];
            let z = lateral_fit(&body, &Curves { theta, alpha, beta }, GRID);
            let (lo, hi) = grid(GRID)
                .map(|p| z.value(p))
                .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
            if hi > lo {
                let k = law.lateral_excursion() / (hi - lo);
                for f in &mut alpha[1..3] {
                    *f = Fourier::combine(&[(k, f)]);
                }
            }
        }
        let alpha = alpha;
        let at = |amp: f64| -> Result<AtAmplitude, CalibrationFailed> {
            let (nrm, path, off) = if amp == 1.0 {
                (n1, p1, offset)
            } else {
                let (nrm, path) = normative(amp)?;
                let off = Stance::new(&body, &nrm, &path, SEARCH_GRID).fit_from(offset);
                (nrm, path, off)
            };
            let st = Stance::new(&body, &nrm, &path, GRID);
            let pl = st.offset(off);
            let sol = st.solve(pl);
            if sol.overreach.is_nan() || sol.overreach >= MAX_OVERREACH {
                return Err(fail);
            }
            let figures = st.figures(pl, &sol);
            let theta = [
                nrm.theta[0],
                sampled_fit(&sol.theta[1]),
                sampled_fit(&sol.theta[2]),
                sampled_fit(&sol.theta[3]),
            ];
            let pz = if out_of_plane_on {
                lateral_fit(&body, &Curves { theta, alpha, beta }, GRID)
            } else {
                Fourier::default()
            };
            Ok(AtAmplitude {
                theta,
                height: pl.hip_height,
                pz,
                hip_gain: nrm.hip_gain,
                placement: pl,
                figures,
            })
        };
        let (m, z, p) = (at(1.0 - AMP_STEP)?, at(1.0)?, at(1.0 + AMP_STEP)?);
        let theta: [[Fourier; 3]; 4] =
            core::array::from_fn(|i| quadratic(&m.theta[i], &z.theta[i], &p.theta[i]));
        let d = AMP_STEP;
        let hip = HipPath {
            stride_length: p1.stride_length,
            fluctuation: p1.fluctuation,
            slow_phase: p1.slow_phase,
            excursion: p1.excursion,
            top_phase: p1.top_phase,
            sharpness: p1.sharpness,
            height: [
                z.height,
                (p.height - m.height) / (2.0 * d),
                (p.height - 2.0 * z.height + m.height) / (2.0 * d * d),
            ],
            pz: quadratic(&m.pz, &z.pz, &p.pz),
        };
        let curves = Curves {
            theta: z.theta,
            alpha,
            beta,
        };
        let order = theta
            .iter()
            .flatten()
            .chain(&alpha)
            .chain(&beta)
            .chain(hip.pz.iter())
            .map(|f| f.order)
            .max()
            .unwrap_or(0)
            .max(4);
        Ok(GaitModel {
            body,
            law,
            hip_gain: z.hip_gain,
            curves,
            theta,
            hip,
            placement: z.placement,
            placement_offset: offset,
            stance: z.figures,
            order,
        })
    }

    /// Right-leg segment angles with time derivatives, at clock reading
    /// `phase` (phi, phi', phi'') under amplitude modulation `amp`.
    pub fn angles(&self, h: &Harmonics, phase: D2, amp: D2) -> [Angles; 4] {
        core::array::from_fn(|i| Angles {
            theta: to_time(along(&self.theta[i], h, amp), phase),
            alpha: to_time(self.curves.alpha[i].eval(h), phase),
            beta: to_time(self.curves.beta[i].eval(h), phase),
        })
    }

    /// Sagittal segment angles only (rad), for the encoder path.
    pub fn sagittal_angles(&self, phi: f64, amp: f64) -> [f64; 4] {
        let h = Harmonics::up_to(phi, self.order);
        let a = D2::constant(amp);
        core::array::from_fn(|i| along(&self.theta[i], &h, a).v)
    }

    /// Full chain kinematics at clock reading `phase` under modulation `m`,
    /// with the sagittal segment angles (rad).
    pub fn kinematics(&self, phase: D2, m: &Modulation) -> (LegKin, [f64; 4]) {
        let h = Harmonics::up_to(phase.v, self.order);
        let amp = m.amp(phase.v);
        let seg = self.angles(&h, phase, amp);
        let [x, y, z] = self.hip.eval(&h, amp, m.integral(phase.v));
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
