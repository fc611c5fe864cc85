//! The stance leg by inverse kinematics from a prescribed pelvis path.
//!
//! The normative (landmark) joint curves of [`crate::gait_curves`] are not
//! exactly consistent with a still stance foot under a realistic pelvis: in
//! mid-stance their thigh and shank rotate about 15-20 % too slowly for a
//! pelvis that moves forward at nearly constant speed. Deriving the pelvis
//! from them (the previous model) made the pelvis absorb that inconsistency
//! (forward speed 0.58-1.54 m/s at 1.0 m/s). Here the pelvis path is
//! prescribed ([`PathShape`]) and the stance leg absorbs it instead:
//!
//! * **Foot.** Heel rocker (0 to [`FOOT_FLAT`]): the foot angle goes from its
//!   normative heel-strike value and rate to 0 (cubic Hermite), pivoting on
//!   the heel contact point. Then the foot pivots on the metatarsal head and
//!   its angle is the one that gives the stance knee a target flexion
//!   (two-circle intersection: hip to ankle at the knee's hip-ankle distance,
//!   ankle to metatarsal head at the foot's length), limited smoothly to
//!   heel-up angles: the target is [`KNEE_MIN`] until [`HEEL_OFF`] (the foot
//!   stays flat unless the hip would pull the knee straighter: no jerky
//!   near-straight knee), then it moves to the normative knee flexion over
//!   [`HEEL_RISE_RAMP`]. The contact point never moves.
//! * **Thigh and shank**: two-link inverse kinematics from the prescribed hip
//!   joint centre to that ankle, knee bending forward.
//! * **Blending.** The inverse-kinematics angles hold in single support
//!   (10-50 % of the stride); over the two double supports (0-10 % and
//!   50-60 %) they are blended with the normative angles (quintic
//!   smoothstep weight), swing (60-100 %) is normative. While the weight is
//!   below one the foot may slip; that slip is part of the fit cost and is
//!   reported (`docs/SIMULATOR.md`).
//! * **Placement.** The two free numbers, the hip height `h0` (mean of the
//!   path) and the heel-strike point `xh`, start from the normative foot
//!   position at heel strike ([`Stance::rule`]) and are then adjusted (a small
//!   grid and a Nelder-Mead search, [`Stance::fit`]) to minimise the RMS
//!   deviation of the single-support knee, thigh and ankle angles from the
//!   normative ones plus the double-support slip, with the stance leg never
//!   over-stretched and the stance peaks kept inside published normal ranges
//!   where possible (loading-response knee flexion <= 23 deg, dorsiflexion
//!   <= 14 deg).

mod leg;
mod nelder_mead;
mod normative;
mod path;

use core::f64::consts::TAU;

use crate::anthropometry::Body;
use crate::fourier::{grid, Harmonics};
use leg::{foot_for_knee, heel, leg_points, mtp, rot, smooth_min0, two_link};
use nelder_mead::nelder_mead;
pub use normative::Normative;
pub use path::PathShape;

/// End of the heel rocker (fraction of the stride): foot flat from here.
pub const FOOT_FLAT: f64 = 0.08;
/// Heel-off (fraction of the stride): the heel may rise from here.
pub const HEEL_OFF: f64 = 0.30;
/// Fade-in of the knee-driven heel rise (fraction of the stride).
pub const HEEL_RISE_RAMP: f64 = 0.08;
/// Smallest knee flexion the stance leg keeps before heel-off (rad, 5 deg):
/// if the hip would pull it straighter, the heel rises instead.
pub const KNEE_MIN: f64 = 0.087_266_462_599_716_48;
/// Toe-off (fraction of the stride).
pub const TOE_OFF: f64 = 0.60;
/// Length of each double support (fraction of the stride).
pub const DOUBLE_SUPPORT: f64 = 0.10;
/// Smoothing width of the "heel up only" limit on the foot angle (rad, 1 deg).
const HEEL_SMIN: f64 = 0.017_453_292_519_943_295;
/// Harmonics of the fitted stance-corrected segment curves.
pub const SEGMENT_ORDER: usize = 24;
/// Harmonics of the flat-foot-corrected normative ankle curve.
const ANKLE_ORDER: usize = 16;
/// Samples per stride used while searching the placement.
pub const SEARCH_GRID: usize = 256;

/// Quintic smoothstep on [0, 1] (zero first and second derivative at both ends).
pub fn smoothstep(u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)
}

/// Weight of the inverse-kinematics stance angles at stride fraction `s`:
/// 0 -> 1 over the first double support, 1 in single support, 1 -> 0 over
/// the second, 0 in swing.
pub fn stance_weight(s: f64) -> f64 {
    let s = s.rem_euclid(1.0);
    if s < DOUBLE_SUPPORT {
        smoothstep(s / DOUBLE_SUPPORT)
    } else if s < TOE_OFF - DOUBLE_SUPPORT {
        1.0
    } else if s < TOE_OFF {
        1.0 - smoothstep((s - (TOE_OFF - DOUBLE_SUPPORT)) / DOUBLE_SUPPORT)
    } else {
        0.0
    }
}

/// Where the stance foot lands and how high the hip rides.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Mean height of the hip joint centre above the floor, `h0` (m).
    pub hip_height: f64,
    /// Heel-strike point, forward, in the coordinates of [`PathShape::x`] (m).
    pub heel_strike: f64,
}

/// The stance problem of one amplitude, sampled on a uniform phase grid.
#[derive(Debug, Clone)]
pub struct Stance {
    body: Body,
    s: Vec<f64>,
    n: [Vec<f64>; 4],
    x: Vec<f64>,
    y: Vec<f64>,
    foot_hs: (f64, f64),
    rule: Placement,
}

/// Sagittal segment angles over one stride (rad) with what the fit needs.
#[derive(Debug, Clone, PartialEq)]
pub struct Solved {
    /// Trunk, thigh, shank, foot, one value per grid phase.
    pub theta: [Vec<f64>; 4],
    /// Largest hip-to-ankle distance minus leg length over stance, times
    /// the stance weight (m; positive: the leg cannot reach, the knee is
    /// straight and the contact point is not held).
    pub overreach: f64,
    /// Stride fraction where that happens.
    pub overreach_at: f64,
}

/// Figures of merit of a solution (degrees and metres).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StanceFigures {
    /// RMS deviation of knee, thigh and ankle from the normative curves in
    /// single support (deg, root of the summed mean squares).
    pub deviation_deg: f64,
    /// Largest displacement of the stance contact point from its floor
    /// point during the blend windows (m, horizontal or vertical).
    pub slip_m: f64,
    /// Peak knee flexion in the first 40 % of the stride (deg).
    pub knee_stance_deg: f64,
    /// Peak dorsiflexion (deg).
    pub dorsiflexion_deg: f64,
    /// Smallest knee flexion in stance (deg).
    pub knee_min_deg: f64,
    /// Largest heel-up foot angle before heel-off (deg).
    pub early_heel_rise_deg: f64,
}

impl Stance {
    /// Samples the problem on `n` phases.
    pub fn new(body: &Body, nrm: &Normative, path: &PathShape, n: usize) -> Self {
        let mut th: [Vec<f64>; 4] = Default::default();
        let (mut x, mut y, mut s) = (Vec::new(), Vec::new(), Vec::new());
        for p in grid(n) {
            let h = Harmonics::new(p);
            for (v, f) in th.iter_mut().zip(&nrm.theta) {
                v.push(f.eval(&h).v);
            }
            x.push(path.x(p));
            y.push(path.y_offset(p));
            s.push(p / TAU);
        }
        let f0 = nrm.foot_raw.eval(&Harmonics::new(0.0));
        // Rule: the heel lands where the normative leg puts it at heel strike.
        let hs = leg_points(body, th[1][0], th[2][0], th[3][0])[0];
        let rule = Placement {
            hip_height: -hs[1] - y[0],
            heel_strike: x[0] + hs[0],
        };
        Stance {
            body: *body,
            s,
            n: th,
            x,
            y,
            foot_hs: (f0.v, f0.d1),
            rule,
        }
    }

    /// The starting placement (normative heel position at heel strike).
    pub fn rule(&self) -> Placement {
        self.rule
    }

    /// Segment angles over the stride for placement `pl`.
    pub fn solve(&self, pl: Placement) -> Solved {
        let b = &self.body;
        let (c_heel, c_mtp) = (heel(b), mtp(b));
        let p_heel = [pl.heel_strike, 0.0];
        let p_mtp = [pl.heel_strike + c_mtp[0] - c_heel[0], 0.0];
        let nn = self.s.len();
        let mut out: [Vec<f64>; 4] = [
            self.n[0].clone(),
            Vec::with_capacity(nn),
            Vec::with_capacity(nn),
            Vec::with_capacity(nn),
        ];
        let (mut overreach, mut overreach_at) = (f64::MIN, 0.0);
        let span = FOOT_FLAT * TAU;
        for (i, &s) in self.s.iter().enumerate() {
            let (nt, ns, nf) = (self.n[1][i], self.n[2][i], self.n[3][i]);
            let w = stance_weight(s);
            if w == 0.0 {
                out[1].push(nt);
                out[2].push(ns);
                out[3].push(nf);
                continue;
            }
            let hip = [self.x[i], pl.hip_height + self.y[i]];
            let (psi, p, c) = if s < FOOT_FLAT {
                let u = s / FOOT_FLAT;
                let (u2, u3) = (u * u, u * u * u);
                let (y0, m0) = self.foot_hs;
                let psi = (2.0 * u3 - 3.0 * u2 + 1.0) * y0 + (u3 - 2.0 * u2 + u) * span * m0;
                (psi, p_heel, c_heel)
            } else {
                let r = smoothstep((s - HEEL_OFF) / HEEL_RISE_RAMP);
                let knee = KNEE_MIN + r * (nt - ns - KNEE_MIN);
                let k = foot_for_knee(b, hip, p_mtp, c_mtp, knee);
                (smooth_min0(k), p_mtp, c_mtp)
            };
            let rc = rot(psi, c);
            let d = [p[0] - rc[0] - hip[0], p[1] - rc[1] - hip[1]];
            let (t, sh, over) = two_link(b, d);
            if w * over > overreach {
                overreach = w * over;
                overreach_at = s;
            }
            out[1].push(w * t + (1.0 - w) * nt);
            out[2].push(w * sh + (1.0 - w) * ns);
            out[3].push(w * psi + (1.0 - w) * nf);
        }
        Solved {
            theta: out,
            overreach,
            overreach_at,
        }
    }

    /// Figures of merit of `sol` for placement `pl`.
    pub fn figures(&self, pl: Placement, sol: &Solved) -> StanceFigures {
        let b = &self.body;
        let deg = |x: f64| x.to_degrees();
        let mut f = StanceFigures {
            knee_stance_deg: f64::MIN,
            dorsiflexion_deg: f64::MIN,
            knee_min_deg: f64::MAX,
            ..Default::default()
        };
        let (mut sk, mut st, mut sa, mut cnt) = (0.0, 0.0, 0.0, 0.0);
        let (mut heel_ref, mut mtp_ref) = (None::<f64>, None::<f64>);
        let mut heel_pts: Vec<[f64; 2]> = Vec::new();
        let [_, th, sh, ft] = &sol.theta;
        for (i, &s) in self.s.iter().enumerate() {
            let knee = deg(th[i] - sh[i]);
            let dorsi = deg(ft[i] - sh[i]);
            f.dorsiflexion_deg = f.dorsiflexion_deg.max(dorsi);
            if s < 0.4 {
                f.knee_stance_deg = f.knee_stance_deg.max(knee);
            }
            if s > 0.02 && s < TOE_OFF - 0.02 {
                f.knee_min_deg = f.knee_min_deg.min(knee);
            }
            if (FOOT_FLAT..HEEL_OFF).contains(&s) {
                f.early_heel_rise_deg = f.early_heel_rise_deg.max(-deg(ft[i]));
            }
            if (DOUBLE_SUPPORT..=TOE_OFF - DOUBLE_SUPPORT).contains(&s) {
                let (nt, ns, nf) = (self.n[1][i], self.n[2][i], self.n[3][i]);
                sk += (knee - deg(nt - ns)).powi(2);
                st += deg(th[i] - nt).powi(2);
                sa += (dorsi - deg(nf - ns)).powi(2);
                cnt += 1.0;
            }
            if s <= TOE_OFF {
                let pts = leg_points(b, th[i], sh[i], ft[i]);
                let hip = [self.x[i], pl.hip_height + self.y[i]];
                let w = |q: [f64; 2]| [hip[0] + q[0], hip[1] + q[1]];
                if s < 0.25 {
                    heel_pts.push(w(pts[0]));
                    heel_ref = Some(w(pts[0])[0]);
                } else {
                    let m = w(pts[1]);
                    let r = *mtp_ref.get_or_insert(m[0]);
                    f.slip_m = f.slip_m.max((m[0] - r).abs()).max(m[1].abs());
                }
            }
        }
        if let Some(r) = heel_ref {
            for q in heel_pts {
                f.slip_m = f.slip_m.max((q[0] - r).abs()).max(q[1].abs());
            }
        }
        f.deviation_deg = if cnt > 0.0 {
            (sk / cnt + st / cnt + sa / cnt).sqrt()
        } else {
            0.0
        };
        f
    }

    /// Cost of a placement (see the module docs).
    pub fn cost(&self, pl: Placement) -> f64 {
        let sol = self.solve(pl);
        let f = self.figures(pl, &sol);
        let pen = 1e5 * (sol.overreach + 1e-4).max(0.0)
            + 10.0 * (3.0 - f.knee_min_deg).max(0.0)
            + 10.0 * (f.early_heel_rise_deg - 0.5).max(0.0)
            + 5.0 * (f.dorsiflexion_deg - 14.0).max(0.0)
            + 5.0 * (f.knee_stance_deg - 23.0).max(0.0);
        f.deviation_deg + 30.0 * f.slip_m + pen
    }

    /// Searches the placement: offsets from [`Stance::rule`] of the hip
    /// height (-30..+10 mm) and heel-strike point (-20..+60 mm) on a 5 x 5
    /// grid, then 60 Nelder-Mead iterations. Returns the offsets.
    pub fn fit(&self) -> (f64, f64) {
        let r = self.rule;
        let cost = |o: [f64; 2]| {
            self.cost(Placement {
                hip_height: r.hip_height + o[0],
                heel_strike: r.heel_strike + o[1],
            })
        };
        let mut best = ([0.0, 0.0], f64::INFINITY);
        for i in 0..5 {
            for j in 0..5 {
                let o = [-0.03 + 0.01 * i as f64, -0.02 + 0.02 * j as f64];
                let c = cost(o);
                if c < best.1 {
                    best = (o, c);
                }
            }
        }
        nelder_mead(cost, best.0, [0.003, 0.005], 60)
    }

    /// Like [`Stance::fit`] but only 40 Nelder-Mead iterations from the
    /// offsets `start` (used to follow the amplitude-1 solution).
    pub fn fit_from(&self, start: (f64, f64)) -> (f64, f64) {
        let r = self.rule;
        let cost = |o: [f64; 2]| {
            self.cost(Placement {
                hip_height: r.hip_height + o[0],
                heel_strike: r.heel_strike + o[1],
            })
        };
        nelder_mead(cost, [start.0, start.1], [0.002, 0.003], 40)
    }

    /// Placement `pl` moved by offsets `o` (hip height, heel strike).
    pub fn offset(&self, o: (f64, f64)) -> Placement {
        Placement {
            hip_height: self.rule.hip_height + o.0,
            heel_strike: self.rule.heel_strike + o.1,
        }
    }
}
