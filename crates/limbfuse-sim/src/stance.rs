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

use core::f64::consts::TAU;

use crate::anthropometry::Body;
use crate::fourier::{grid, Fourier, Harmonics};
use crate::gait_curves::{foot_flat_window, scale_about_mean, BaseCurves, SpeedLaw, GRID};

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

/// The prescribed path of the right hip joint centre, per stride, at a fixed
/// amplitude (see `docs/SIMULATOR.md` for the sources of the defaults):
/// `x = L phi / 2 pi - L eps / (4 pi) sin 2 (phi - phi_slow)` (forward speed
/// `v (1 - eps cos 2 (phi - phi_slow))`), `y = h0 + e/2 (cos 2 psi - b cos 4
/// psi)`, `psi = phi - phi_top`: highest at `phi_top` (mid-stance), lowest a
/// quarter stride later (double support), peak to peak `e` for `b <= 1/4`;
/// `b > 0` flattens the top and sharpens the trough.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathShape {
    /// Stride length `L` (m).
    pub stride_length: f64,
    /// Relative forward-speed fluctuation `eps`.
    pub fluctuation: f64,
    /// Phase of the slowest forward speed (rad; again half a stride later).
    pub slow_phase: f64,
    /// Vertical excursion `e`, peak to peak (m).
    pub excursion: f64,
    /// Phase of the highest point (rad; again half a stride later).
    pub top_phase: f64,
    /// Sharpness `b` of the trough (0: a pure sinusoid; at most 1/4).
    pub sharpness: f64,
}

impl PathShape {
    /// The path of `law` at amplitude 1.
    pub fn new(law: &SpeedLaw) -> Self {
        PathShape {
            stride_length: law.stride_length(),
            fluctuation: law.speed_fluctuation(),
            slow_phase: law.slow_phase(),
            excursion: law.vertical_excursion(),
            top_phase: law.top_phase(),
            sharpness: law.vertical_sharpness(),
        }
    }

    /// The path with stride length and vertical excursion scaled by `amp`.
    pub fn scaled(&self, amp: f64) -> Self {
        PathShape {
            stride_length: self.stride_length * amp,
            excursion: self.excursion * amp,
            ..*self
        }
    }

    /// Forward position (m) at phase `phi` (rad).
    pub fn x(&self, phi: f64) -> f64 {
        let l = self.stride_length;
        l * phi / TAU - l * self.fluctuation / (2.0 * TAU) * (2.0 * (phi - self.slow_phase)).sin()
    }

    /// Height above the mean `h0` (m) at phase `phi` (rad).
    pub fn y_offset(&self, phi: f64) -> f64 {
        let psi = phi - self.top_phase;
        0.5 * self.excursion * ((2.0 * psi).cos() - self.sharpness * (4.0 * psi).cos())
    }
}

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

/// Heel, metatarsal head and ankle of a planar leg relative to the hip (m).
fn leg_points(body: &Body, thigh: f64, shank: f64, foot: f64) -> [[f64; 2]; 3] {
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

fn heel(body: &Body) -> [f64; 2] {
    [body.heel.x, body.heel.y]
}

fn mtp(body: &Body) -> [f64; 2] {
    [body.mtp.x, body.mtp.y]
}

fn rot(t: f64, c: [f64; 2]) -> [f64; 2] {
    let (s, co) = t.sin_cos();
    [co * c[0] - s * c[1], s * c[0] + co * c[1]]
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

/// Two-link inverse kinematics from hip to ankle (`d` = ankle - hip): thigh
/// and shank angles (knee forward) and hip-ankle distance minus leg length.
fn two_link(body: &Body, d: [f64; 2]) -> (f64, f64, f64) {
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
fn foot_for_knee(body: &Body, hip: [f64; 2], p: [f64; 2], c: [f64; 2], knee: f64) -> f64 {
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
fn smooth_min0(x: f64) -> f64 {
    0.5 * (x - (x * x + HEEL_SMIN * HEEL_SMIN).sqrt())
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

/// Nelder-Mead minimisation in two dimensions (standard coefficients 1, 2,
/// 1/2, 1/2), `iters` iterations from `x0` with initial steps `step`.
fn nelder_mead(
    f: impl Fn([f64; 2]) -> f64,
    x0: [f64; 2],
    step: [f64; 2],
    iters: usize,
) -> (f64, f64) {
    let mut p = [x0, [x0[0] + step[0], x0[1]], [x0[0], x0[1] + step[1]]];
    let mut v = p.map(&f);
    let lerp =
        |a: [f64; 2], b: [f64; 2], t: f64| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
    for _ in 0..iters {
        let mut idx = [0usize, 1, 2];
        idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
        p = idx.map(|i| p[i]);
        v = idx.map(|i| v[i]);
        let c = lerp(p[0], p[1], 0.5);
        let r = lerp(c, p[2], -1.0);
        let fr = f(r);
        if fr < v[0] {
            let e = lerp(c, p[2], -2.0);
            let fe = f(e);
            (p[2], v[2]) = if fe < fr { (e, fe) } else { (r, fr) };
        } else if fr < v[1] {
            (p[2], v[2]) = (r, fr);
        } else {
            let k = lerp(c, p[2], 0.5);
            let fk = f(k);
            if fk < v[2] {
                (p[2], v[2]) = (k, fk);
            } else {
                for i in 1..3 {
                    p[i] = lerp(p[0], p[i], 0.5);
                    v[i] = f(p[i]);
                }
            }
        }
    }
    let i = (0..3).min_by(|&a, &b| v[a].total_cmp(&v[b])).unwrap_or(0);
    (p[i][0], p[i][1])
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

    #[test]
    fn nelder_mead_finds_a_quadratic_minimum() {
        let (x, y) = nelder_mead(
            |p| (p[0] - 0.3).powi(2) + 2.0 * (p[1] + 0.1).powi(2),
            [0.0, 0.0],
            [0.1, 0.1],
            80,
        );
        assert!((x - 0.3).abs() < 1e-4 && (y + 0.1).abs() < 1e-4);
    }
}
