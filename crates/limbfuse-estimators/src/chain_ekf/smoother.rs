//! Offline Rauch-Tung-Striebel smoother over the chain EKF (issue 14,
//! docs/CHAIN.md "Offline smoothing").
//!
//! The filter stays as it is (real-time, allocation-free); this layer keeps,
//! per step, the filtered state `x_f`, its covariance `P_f` (lower triangle)
//! and the step's [`Link`] (step length and turn widening), and goes back
//! over them with the extended RTS recursion (Särkkä, *Bayesian Filtering
//! and Smoothing*, Cambridge University Press 2013, ch. 8 eqs 8.2-8.3 and
//! ch. 9 eq 9.5):
//!
//! ```text
//! x_p = F x_f,  P_p = F P_f F^T + Q + W        (the filter's own prediction)
//! C   = P_f F^T P_p^-1                          (Cholesky solve, no inverse)
//! x_s = x_f + C (x_s,next - x_p)
//! P_s = P_f + C (P_s,next - P_p) C^T            (then symmetrised)
//! ```
//!
//! The chain's prediction is linear (constant angular acceleration, a
//! Gauss-Markov hip acceleration), so `F` is the exact transition; the
//! predicted pair is recomputed from the stored filtered pair with the
//! filter's own functions (bit for bit what the filter used) instead of
//! being stored, which halves the memory.
//!
//! Memory is bounded by smoothing over blocks with overlap: once the steps
//! held span `block + overlap` seconds, the backward pass runs from the
//! newest held step and the first `block` seconds are emitted, so every
//! emitted step has seen at least `overlap` seconds of the future. The
//! backward pass never crosses a step whose [`Link`] is not
//! [`Link::Continue`] (a start or restart of the filter): there the
//! smoothed state is the filtered one.

use alloc::collections::VecDeque;
use alloc::vec::Vec;

use super::covariance::{predict_covariance, predict_state, Covariance, ProcessNoise, StateVector};
use super::state::{theta, N};
use super::Link;

/// Entries of a packed lower triangle of an `N x N` matrix.
pub const PACKED: usize = N * (N + 1) / 2;

/// Block and overlap of the fixed-interval smoother.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SmootherSettings {
    /// Seconds emitted per backward pass (infinity: the whole trial in
    /// one pass, memory growing with the trial).
    pub block_s: f64,
    /// Seconds of look-ahead beyond each block (at least the smoother's
    /// memory; docs/CHAIN.md measures it).
    pub overlap_s: f64,
}

impl Default for SmootherSettings {
    fn default() -> Self {
        SmootherSettings {
            block_s: 10.0,
            overlap_s: 2.0,
        }
    }
}

impl SmootherSettings {
    /// The whole trial in one backward pass (tests, comparisons).
    pub const WHOLE_TRIAL: SmootherSettings = SmootherSettings {
        block_s: f64::INFINITY,
        overlap_s: 0.0,
    };

    /// Whether the values can be used: `block_s > 0`, `overlap_s >= 0`
    /// and finite (`block_s` may be infinite).
    pub fn is_valid(&self) -> bool {
        self.block_s > 0.0 && self.overlap_s >= 0.0 && self.overlap_s.is_finite()
    }
}

/// One step's smoothed state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Smoothed {
    /// Smoothed state.
    pub x: StateVector,
    /// Smoothed 1-sigma of every state (square root of `P_s`'s diagonal).
    pub sd: [f64; N],
}

impl Smoothed {
    /// Smoothed angle of segment `i` (rad).
    pub fn angle(&self, i: usize) -> f64 {
        self.x[theta(i)]
    }
}

/// The lower triangle of `p`, column by column.
pub fn pack(p: &Covariance) -> [f64; PACKED] {
    let mut out = [0.0; PACKED];
    let mut k = 0;
    for c in 0..N {
        for r in c..N {
            out[k] = p[(r, c)];
            k += 1;
        }
    }
    out
}

/// The symmetric matrix of a packed lower triangle.
pub fn unpack(packed: &[f64; PACKED]) -> Covariance {
    let mut p = Covariance::zeros();
    let mut k = 0;
    for c in 0..N {
        for r in c..N {
            p[(r, c)] = packed[k];
            p[(c, r)] = packed[k];
            k += 1;
        }
    }
    p
}

/// The filter's prediction from `(x_f, P_f)` over a step: `(x_p, P_p)`,
/// with `widening` added to every angle's variance (the turn widening).
pub fn predict(
    x_f: &StateVector,
    p_f: &Covariance,
    dt: f64,
    widening: f64,
    q: &ProcessNoise,
) -> (StateVector, Covariance) {
    let mut x = *x_f;
    let mut p = *p_f;
    predict_state(&mut x, dt, q);
    predict_covariance(&mut p, dt, q);
    for i in 0..4 {
        p[(theta(i), theta(i))] += widening;
    }
    (x, p)
}

/// The transition `F` over `dt` (column `j` is the prediction of unit vector `j`).
pub fn transition(dt: f64, q: &ProcessNoise) -> Covariance {
    let mut f = Covariance::identity();
    for j in 0..N {
        let mut x = StateVector::zeros();
        x[j] = 1.0;
        predict_state(&mut x, dt, q);
        f.set_column(j, &x);
    }
    f
}

/// One backward RTS step: the smoothed pair at step `k` from the filtered
/// pair at `k`, the link to `k + 1` (`dt`, `widening`) and the smoothed
/// pair at `k + 1`. `None` when the predicted covariance is not positive
/// definite (the caller keeps the filtered pair).
pub fn rts_step(
    x_f: &StateVector,
    p_f: &Covariance,
    dt: f64,
    widening: f64,
    q: &ProcessNoise,
    next: (&StateVector, &Covariance),
) -> Option<(StateVector, Covariance)> {
    let (x_p, p_p) = predict(x_f, p_f, dt, widening, q);
    let f = transition(dt, q);
    // C^T = P_p^-1 F P_f (P_f symmetric): one Cholesky solve.
    let chol = p_p.cholesky()?;
    let c_t = chol.solve(&(f * p_f));
    let c = c_t.transpose();
    let x_s = x_f + c * (next.0 - x_p);
    let mut p_s = p_f + c * (next.1 - p_p) * c_t;
    p_s = (p_s + p_s.transpose()) * 0.5;
    (x_s.iter().all(|v| v.is_finite()) && p_s.iter().all(|v| v.is_finite())).then_some((x_s, p_s))
}

/// A step held for the backward pass.
#[derive(Debug, Clone)]
struct Held<T> {
    t: f64,
    link: Link,
    x: StateVector,
    p: [f64; PACKED],
    item: T,
}

/// The fixed-interval RTS smoother over blocks with overlap: push every
/// filter step (with an item carried along, e.g. the filter's estimate),
/// pop the smoothed steps in order, delayed by up to `block + overlap`
/// seconds.
#[derive(Debug, Clone)]
pub struct RtsSmoother<T> {
    q: ProcessNoise,
    settings: SmootherSettings,
    held: VecDeque<Held<T>>,
    ready: VecDeque<(T, Option<Smoothed>)>,
    scratch: Vec<Option<Smoothed>>,
    fallbacks: u64,
}

impl<T> RtsSmoother<T> {
    /// A smoother for a filter with process noise `q`.
    pub fn new(q: ProcessNoise, settings: SmootherSettings) -> Self {
        RtsSmoother {
            q,
            settings,
            held: VecDeque::new(),
            ready: VecDeque::new(),
            scratch: Vec::new(),
            fallbacks: 0,
        }
    }

    /// The settings.
    pub fn settings(&self) -> SmootherSettings {
        self.settings
    }

    /// Steps at which the predicted covariance was not positive definite
    /// (the filtered state was kept and the backward pass cut there).
    pub fn fallbacks(&self) -> u64 {
        self.fallbacks
    }

    /// Steps held (not yet smoothed).
    pub fn held(&self) -> usize {
        self.held.len()
    }

    /// Adds the filter's step at time `t`: its link, state and covariance
    /// (ignored when `link` is [`Link::None`]) and `item`.
    pub fn push(&mut self, t: f64, link: Link, x: &StateVector, p: &Covariance, item: T) {
        let (x, p) = match link {
            Link::None => (StateVector::zeros(), [0.0; PACKED]),
            _ => (*x, pack(p)),
        };
        self.held.push_back(Held {
            t,
            link,
            x,
            p,
            item,
        });
        let span = self.held.back().map_or(0.0, |h| h.t) - self.held.front().map_or(0.0, |h| h.t);
        if span >= self.settings.block_s + self.settings.overlap_s {
            self.smooth(false);
        }
    }

    /// Smooths every step still held (end of the trial).
    pub fn finish(&mut self) {
        if !self.held.is_empty() {
            self.smooth(true);
        }
    }

    /// The next smoothed step in time order: its item and smoothed state
    /// (`None` where the filter had no state).
    pub fn pop(&mut self) -> Option<(T, Option<Smoothed>)> {
        self.ready.pop_front()
    }

    /// One backward pass over the held steps; emits the first block (all
    /// of them when `all`).
    fn smooth(&mut self, all: bool) {
        let n = self.held.len();
        let t0 = self.held[0].t;
        let emit = if all {
            n
        } else {
            self.held
                .iter()
                .take_while(|h| h.t < t0 + self.settings.block_s)
                .count()
                .max(1)
        };
        self.scratch.clear();
        self.scratch.resize(emit, None);
        let mut next: Option<(StateVector, Covariance)> = None;
        let mut next_link = Link::None;
        for k in (0..n).rev() {
            let h = &self.held[k];
            let current = match h.link {
                Link::None => None,
                _ => {
                    let p_f = unpack(&h.p);
                    let smoothed = match (&next, next_link) {
                        (Some((xn, pn)), Link::Continue { dt, widening }) => {
                            let s = rts_step(&h.x, &p_f, dt, widening, &self.q, (xn, pn));
                            if s.is_none() {
                                self.fallbacks += 1;
                            }
                            s
                        }
                        _ => None,
                    };
                    Some(smoothed.unwrap_or((h.x, p_f)))
                }
            };
            if k < emit {
                self.scratch[k] = current.as_ref().map(|(x, p)| Smoothed {
                    x: *x,
                    sd: core::array::from_fn(|i| libm::sqrt(p[(i, i)].max(0.0))),
                });
            }
            next = current;
            next_link = h.link;
        }
        for s in self.scratch.drain(..) {
            if let Some(h) = self.held.pop_front() {
                self.ready.push_back((h.item, s));
            }
        }
    }
}

#[cfg(test)]
#[path = "smoother_tests.rs"]
mod tests;
