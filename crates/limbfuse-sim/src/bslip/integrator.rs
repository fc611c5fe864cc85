//! Adaptive Dormand-Prince 5(4) integration with event location by root
//! bracketing.
//!
//! Why our own: the B-SLIP step needs three state events (touchdown,
//! lift-off, mid-stance) located to ~1e-12 s. Of the Rust ODE crates,
//! `ode_solvers` has no event location and `diffsol` (which has root finding)
//! pulls a sparse-linear-algebra stack that costs minutes of build time on the
//! project's 2-core CI for a 6-state non-stiff ODE. Dormand-Prince 5(4)
//! (Hairer, Norsett & Wanner, *Solving ODEs I*, sec II.4/II.5, with the
//! standard step-size controller) is ~60 lines. An event is bracketed between
//! the ends of an accepted step (sign change downwards) and located by
//! bisection on the step length, re-taking the single step from its start, so
//! the located state is a genuine 5th-order solution point.

use nalgebra::Vector6;

/// The state integrated (CoM position and velocity).
pub type State = Vector6<f64>;

/// Tolerances and step limits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// Largest step (s).
    pub h_max: f64,
    /// Event location: bracket width (s).
    pub event_time: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances {
            rtol: 1e-10,
            atol: 1e-12,
            h_max: 0.01,
            event_time: 1e-12,
        }
    }
}

/// How [`advance`] stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The end time was reached without an event.
    EndTime,
    /// The event function crossed zero downwards (state and time at the crossing).
    Event,
}

const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// 5th-order weights (= last row of A, FSAL).
const B5: [f64; 7] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
    0.0,
];
/// 4th-order weights (embedded error estimate).
const B4: [f64; 7] = [
    5179.0 / 57600.0,
    0.0,
    7571.0 / 16695.0,
    393.0 / 640.0,
    -92097.0 / 339200.0,
    187.0 / 2100.0,
    1.0 / 40.0,
];

/// One Dormand-Prince step of length `h`: (5th-order solution, error estimate).
fn dp_step(f: &impl Fn(&State) -> State, x: &State, h: f64) -> (State, State) {
    let _ = C;
    let mut k = [State::zeros(); 7];
    k[0] = f(x);
    for s in 1..7 {
        let mut xs = *x;
        for (j, kj) in k.iter().enumerate().take(s) {
            if A[s][j] != 0.0 {
                xs += kj * (h * A[s][j]);
            }
        }
        k[s] = f(&xs);
    }
    let mut x5 = *x;
    let mut err = State::zeros();
    for s in 0..7 {
        x5 += k[s] * (h * B5[s]);
        err += k[s] * (h * (B5[s] - B4[s]));
    }
    (x5, err)
}

fn error_norm(tol: &Tolerances, x0: &State, x1: &State, err: &State) -> f64 {
    let mut s = 0.0;
    for i in 0..6 {
        let sc = tol.atol + tol.rtol * x0[i].abs().max(x1[i].abs());
        s += (err[i] / sc).powi(2);
    }
    (s / 6.0).sqrt()
}

/// Integrates `x' = f(x)` from `*t` towards `t_end`, stopping early at the
/// first downward zero crossing of `event` (if given). On return `*t`, `*x`
/// hold the stopping time and state; `*h` carries the step-size guess
/// between calls.
pub fn advance(
    f: &impl Fn(&State) -> State,
    event: Option<&dyn Fn(&State) -> f64>,
    tol: &Tolerances,
    t: &mut f64,
    x: &mut State,
    t_end: f64,
    h: &mut f64,
) -> Stop {
    if *h <= 0.0 || !h.is_finite() {
        *h = 1e-3;
    }
    while *t < t_end {
        let step = h.min(tol.h_max).min(t_end - *t);
        let (x1, err) = dp_step(f, x, step);
        let e = error_norm(tol, x, &x1, &err);
        if e.is_nan() || e > 1.0 {
            let fac = if e.is_finite() {
                (0.9 * e.powf(-0.2)).clamp(0.1, 1.0)
            } else {
                0.1
            };
            *h = step * fac;
            if *h < 1e-14 {
                // Cannot meet the tolerance (e.g. a singular state): take the step.
                *t += step;
                *x = x1;
            }
            continue;
        }
        if let Some(g) = event {
            let g0 = g(x);
            let g1 = g(&x1);
            if g0 > 0.0 && g1 <= 0.0 {
                let (mut lo, mut hi) = (0.0, step);
                let mut x_hi = x1;
                while hi - lo > tol.event_time {
                    let mid = 0.5 * (lo + hi);
                    let (xm, _) = dp_step(f, x, mid);
                    if g(&xm) > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                        x_hi = xm;
                    }
                }
                *t += hi;
                *x = x_hi;
                return Stop::Event;
            }
        }
        let reaches_end = step >= t_end - *t;
        *t = if reaches_end { t_end } else { *t + step };
        *x = x1;
        let fac = if e > 0.0 {
            (0.9 * e.powf(-0.2)).clamp(0.2, 5.0)
        } else {
            5.0
        };
        // Keep the growth from a clipped final step out of the next guess.
        *h = (step * fac).max(*h * 0.2);
    }
    Stop::EndTime
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Harmonic oscillator x'' = -x: the event x = 0 (downwards) starting at
    /// x = 1, v = 0 fires at t = pi/2 exactly.
    #[test]
    fn event_of_a_harmonic_oscillator_fires_at_a_quarter_period() {
        let f = |s: &State| State::new(s[3], 0.0, 0.0, -s[0], 0.0, 0.0);
        let g = |s: &State| s[0];
        let mut x = State::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut t = 0.0;
        let mut h = 0.0;
        let stop = advance(
            &f,
            Some(&g),
            &Tolerances::default(),
            &mut t,
            &mut x,
            10.0,
            &mut h,
        );
        assert_eq!(stop, Stop::Event);
        assert!((t - core::f64::consts::FRAC_PI_2).abs() < 1e-10, "t = {t}");
        assert!((x[3] + 1.0).abs() < 1e-9);
    }

    #[test]
    fn reaches_the_end_time_exactly_with_5th_order_accuracy() {
        let f = |s: &State| State::new(s[3], 0.0, 0.0, -s[0], 0.0, 0.0);
        let mut x = State::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut t = 0.0;
        let mut h = 0.0;
        let stop = advance(
            &f,
            None,
            &Tolerances::default(),
            &mut t,
            &mut x,
            3.0,
            &mut h,
        );
        assert_eq!(stop, Stop::EndTime);
        assert_eq!(t, 3.0);
        assert!((x[0] - 3.0f64.cos()).abs() < 1e-9);
    }
}
