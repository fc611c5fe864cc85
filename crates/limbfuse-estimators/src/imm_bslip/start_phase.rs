//! Where in the step a trial starts (configuration `continuous`;
//! docs/GAIT_IMM.md, "Restart after a gap or a mid-stride start").
//!
//! The bank used to take its first sample as mid-stance (MS): true of paper
//! 003's simulated trials, not of a recording cut anywhere in the stride.
//! The CoM's vertical motion tells where in the step it is: highest at MS,
//! falling in SS1, lowest in the middle of double support (DS), rising in
//! SS2. The first sample's measured height and vertical velocity are
//! matched against the gait's own step: SS1 integrated from MS to
//! touchdown (B-SLIP, one leg), the rest by the step's symmetry in time
//! about MS (`y(T - t) = y(t)`, `vy(T - t) = -vy(t)`, `x(T - t) = L -
//! x(t)`), DS between them a parabola through the touchdown and lift-off
//! states (its vertex at `T / 2`).

extern crate alloc;

use alloc::vec::Vec;

use limbfuse_models::bslip::{derivative, GaitTemplate, Side, Stance, State};

/// A point of the step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct StepPoint {
    /// Time since MS (s), in `[0, step_time)`.
    pub t: f64,
    /// The CoM's forward advance from the trailing (SS1) foot (m).
    pub x: f64,
    /// The CoM's forward velocity there (m/s).
    pub vx: f64,
}

/// RK4 steps over SS1 (MS to touchdown); as many DS points.
const STEPS: usize = 200;

/// Standard deviations of the match (m, m/s): the measurement noise of
/// paper 003 eq 15 (7 and 22 mm/s) and the gait's own mismatch with the
/// walker (a family gait's MS height is within about 1 cm of another
/// gait search's at the same speed).
const SIGMA_Y: f64 = 0.012;
const SIGMA_VY: f64 = 0.03;

fn rk4(g: &GaitTemplate, stance: &Stance, x: &State, h: f64) -> State {
    let f = |s: &State| derivative(&g.body, s, stance);
    let k1 = f(x);
    let k2 = f(&(x + k1 * (0.5 * h)));
    let k3 = f(&(x + k2 * (0.5 * h)));
    let k4 = f(&(x + k3 * h));
    x + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0)
}

/// A point of the step with the CoM's height and vertical velocity there.
#[derive(Debug, Clone, Copy)]
struct Profiled {
    p: StepPoint,
    y: f64,
    vy: f64,
}

/// A buffer for the points of a gait's step, allocated once with the
/// estimator (a start is placed inside `step`, which allocates nothing).
#[derive(Debug, Clone)]
pub(super) struct StepProfile {
    points: Vec<Profiled>,
}

impl StepProfile {
    /// An empty buffer holding any step's points.
    pub(super) fn new() -> Self {
        StepProfile {
            points: Vec::with_capacity(3 * STEPS),
        }
    }

    /// The points of `g`'s step ([`fill_step_points`]).
    fn filled(&mut self, g: &GaitTemplate) -> &[Profiled] {
        fill_step_points(g, &mut self.points);
        &self.points
    }
}

/// The points of `g`'s step (from MS on its trailing foot): SS1 from MS
/// to touchdown interleaved with its mirror in SS2, then DS (MS first),
/// into `points` (cleared; at most `3 STEPS` of them, so a buffer of that
/// capacity never grows).
fn fill_step_points(g: &GaitTemplate, points: &mut Vec<Profiled>) {
    let t_td = g.t_touchdown.clamp(0.0, 0.5 * g.step_time);
    let half = 0.5 * g.step_time;
    let stance = Stance {
        trailing: Some([0.0, -Side::Left.sign() * g.gait.lateral]),
        leading: None,
    };
    let mut x = State::new(0.0, g.gait.height, 0.0, g.gait.forward_speed, 0.0, 0.0);
    let h = t_td / STEPS as f64;
    points.clear();
    for k in 0..=STEPS {
        let t = k as f64 * h;
        points.push(Profiled {
            p: StepPoint {
                t,
                x: x[0],
                vx: x[3],
            },
            y: x[1],
            vy: x[4],
        });
        if k > 0 {
            // The mirror point in SS2.
            points.push(Profiled {
                p: StepPoint {
                    t: g.step_time - t,
                    x: g.step_length - x[0],
                    vx: x[3],
                },
                y: x[1],
                vy: -x[4],
            });
        }
        if k < STEPS {
            x = rk4(g, &stance, &x, h);
        }
    }
    // DS: y = y_min + a (t - T/2)^2 through the touchdown state.
    let (x_td, y_td, vx_td, vy_td) = (x[0], x[1], x[3], x[4]);
    if half > t_td {
        let a = -vy_td / (2.0 * (half - t_td));
        let y_min = y_td - a * (half - t_td) * (half - t_td);
        for k in 1..STEPS {
            let t = t_td + (g.step_time - 2.0 * t_td) * k as f64 / STEPS as f64;
            let s = t - half;
            let f = (t - t_td) / (g.step_time - 2.0 * t_td);
            points.push(Profiled {
                p: StepPoint {
                    t,
                    x: x_td + f * (g.step_length - 2.0 * x_td),
                    vx: vx_td,
                },
                y: y_min + a * s * s,
                vy: 2.0 * a * s,
            });
        }
    }
}

/// The point of `g`'s step (from MS on its trailing foot) whose height and
/// vertical velocity are nearest to the measured `y`, `vy`, and how much
/// worse MS itself fits: the squared normalised distance at MS less that
/// at the best point (a chi-square difference with two degrees of
/// freedom). Near MS the top of the arc is flat (`vy` within one noise
/// standard deviation for about a tenth of a step either side), so a single
/// sample cannot tell MS from its neighbours there.
pub(super) fn locate_in_step(
    g: &GaitTemplate,
    y: f64,
    vy: f64,
    profile: &mut StepProfile,
) -> (StepPoint, f64) {
    let cost = |py: f64, pvy: f64| {
        let a = (y - py) / SIGMA_Y;
        let b = (vy - pvy) / SIGMA_VY;
        a * a + b * b
    };
    let points = profile.filled(g);
    let at_ms = cost(points[0].y, points[0].vy);
    let mut best = (f64::INFINITY, points[0].p);
    for q in points {
        let c = cost(q.y, q.vy);
        if c < best.0 {
            best = (c, q.p);
        }
    }
    (best.1, at_ms - best.0)
}

/// The middle of double support of `g`'s step: the trough of the CoM's
/// height, half a step after MS, the CoM half a step length past the
/// trailing foot (the step's symmetry about MS).
pub(super) fn mid_double_support(g: &GaitTemplate, profile: &mut StepProfile) -> StepPoint {
    let half = 0.5 * g.step_time;
    let nearest = profile
        .filled(g)
        .iter()
        .min_by(|a, b| (a.p.t - half).abs().total_cmp(&(b.p.t - half).abs()))
        .map_or(g.gait.forward_speed, |q| q.p.vx);
    StepPoint {
        t: half,
        x: 0.5 * g.step_length,
        vx: nearest,
    }
}

/// How much worse the window's vertical velocities `seen` (time since the
/// start, `vy`) fit `g`'s step followed from MS than followed from the
/// middle of DS: the difference of their squared normalised misses (a
/// chi-square difference, [`SIGMA_VY`]). A rising `vy` alone does not tell
/// the trough: on a slow gait the CoM is pushed up again soon after MS
/// (limbfuse's 0.5 m/s walker, a start in SS1 0.05 s after MS: `vy` from
/// -0.05 rising at 0.7 m/s^2, 3.4 standard deviations, taken for the
/// trough; 56.5 -> 39.4 % after that gap).
pub(super) fn ms_worse_than_trough<I>(g: &GaitTemplate, seen: I, profile: &mut StepProfile) -> f64
where
    I: Iterator<Item = (f64, f64)>,
{
    let points = profile.filled(g);
    let vy_at = |t: f64| {
        points
            .iter()
            .min_by(|a, b| (a.p.t - t).abs().total_cmp(&(b.p.t - t).abs()))
            .map_or(0.0, |q| q.vy)
    };
    let half = 0.5 * g.step_time;
    let mut worse = 0.0;
    for (dt, vy) in seen {
        let at_ms = (vy - vy_at(dt)) / SIGMA_VY;
        let at_ds = (vy - vy_at(half + dt)) / SIGMA_VY;
        worse += at_ms * at_ms - at_ds * at_ds;
    }
    worse
}

/// The slope (m/s^2) of a straight line fitted to `samples` (time,
/// vertical velocity) and its standard deviation in independent noise
/// `noise` (m/s); `None` with fewer than three samples or one instant.
pub(super) fn vy_slope<I>(samples: I, noise: f64) -> Option<(f64, f64)>
where
    I: Iterator<Item = (f64, f64)> + Clone,
{
    let (mut n, mut t_sum, mut v_sum) = (0usize, 0.0, 0.0);
    for (t, v) in samples.clone() {
        n += 1;
        t_sum += t;
        v_sum += v;
    }
    if n < 3 {
        return None;
    }
    let (t_mean, v_mean) = (t_sum / n as f64, v_sum / n as f64);
    let (mut sxx, mut sxy) = (0.0, 0.0);
    for (t, v) in samples {
        sxx += (t - t_mean) * (t - t_mean);
        sxy += (t - t_mean) * (v - v_mean);
    }
    (sxx > 0.0).then(|| (sxy / sxx, noise / libm::sqrt(sxx)))
}

/// A start is located in the step only when its vertical velocity is this
/// far from zero (m/s; three standard deviations of paper 003's eq 15
/// noise): with `vy` near zero it is MS or the middle of double support,
/// told apart by the absolute height alone, which depends on the gait
/// branch (a 34 % double-support walker at 0.8 m/s tracked with the
/// default library rescaled was located in double support at its MS:
/// 24.4 % phase accuracy instead of 95 %).
pub(super) const VY_EVIDENCE: f64 = 0.066;

/// A start located within this share of a step from MS is taken as MS.
pub(super) const MS_SNAP_STEPS: f64 = 0.06;

/// A start is taken as MS unless MS fits the first sample this much worse
/// than the best point of the step (squared normalised distance, chi-square
/// with two degrees of freedom: 9.2 is its 1 % tail). The top of the arc is
/// flat: on the shared 0.85 m/s trial cut at its mid-stances, a single
/// sample placed the start up to a sixth of a step off (phase 96.8 / 97.1 /
/// 94.2 % -> 92.9 / 90.9 / 91.3 % when always located).
pub(super) const MS_REJECTED: f64 = 9.2;

/// The samples over which a start with `vy` near zero is placed again (s;
/// `ImmContinuous::place_from_window`). The top of the arc (MS) and the
/// trough of double support both have `vy` near zero; at the top `vy`
/// cannot rise, at the trough it does (+1.0-3.0 m/s^2 over the family's
/// gaits, 0.4-1.0 m/s, default and 70 kg / 0.95 m bodies, but 0 at 0.9
/// m/s, whose DS is flat). Over 0.1 s at 100 Hz (11 samples) the slope of
/// `vy` is known to 0.21 m/s^2 (one standard deviation in eq 15's 22 mm/s
/// noise); a seventh of a step or less, over which the provisional MS
/// start's error costs little.
pub(super) const START_WINDOW_S: f64 = 0.1;

/// Most samples kept in the window (allocated once with the estimator; at
/// rates over 1.2 kHz the window is cut short).
pub(super) const WINDOW_CAPACITY: usize = 128;

/// The measurement noise of `vy` (m/s, paper 003 eq 15).
pub(super) const NOISE_VY: f64 = 0.022;

/// A rise of `vy` over the window this many standard deviations above
/// zero places the start in the middle of DS (one-sided tail 0.13 %).
pub(super) const TROUGH_EVIDENCE: f64 = 3.0;

/// Where a start is placed: MS (`located` `None`), or a point of the step
/// with the step time and length of the gait it was located on; the
/// walking speed guessed there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Placement {
    pub located: Option<(StepPoint, f64, f64)>,
    pub speed: f64,
}
