//! Which times the rate derivative uses when the time stamps are not evenly
//! spaced (ours, beyond paper 002, which assumes a regular sample rate).
//!
//! Uneven stamps mean one of two things:
//! * the samples really were taken at those times (the stamps are right), or
//! * the sensor sampled on its own regular clock and the stamps were given
//!   later, by a receiver or a logging host, with jitter (the stamps are
//!   wrong by up to a few milliseconds; usual for wireless IMUs).
//!
//! The five-point derivative of the angular rate (paper 002's "third-order"
//! derivative, [`super::position::rate_derivative`]) divides by the spacing,
//! so taking jittered stamps at their word turns the jitter into noise on the
//! angular acceleration: +-3 ms at 100 Hz put the knee 25 deg off on the
//! shared 0.7 m/s walk (`knee_stamp_jitter` tests). Taking real uneven
//! sampling as regular does the same the other way round.
//!
//! The data decide between the two. Between samples the angular rate of a
//! body segment is smooth (its spectrum ends far below the sample rate), so
//! on the right time base the middle of five consecutive samples is close to
//! the cubic through the other four, and on the wrong one it is off by about
//! the rate's slope times the time error. [`StampClock`] sums, over every
//! run of five unevenly stamped samples, the squared miss of that cubic
//! prediction on both gyroscopes, once with the stamps and once with the
//! samples evenly spaced, and takes the regular grid when its sum is the
//! smaller (no threshold: the better-fitting time base). Its step is then
//! the slope of the least-squares line through the stamps against the
//! samples counted (lost ones included): the sensor's clock is recovered
//! from the stamps' places on a grid ([`crate::stamp_grid`]),
//! not from the steps between them. Evenly stamped samples (within 1 %)
//! are not scored: there both time bases agree and the derivative is the
//! five-point formula as before.

use core::cmp::Ordering;

use nalgebra::Vector3;

use super::position::{uniform_step, MAX_STEP_RATIO};
use super::window::Slot;
use super::KneeSelfAlign;
use crate::stamp_grid::{Counted, StampGrid};

/// Uneven runs of five samples scored before the verdict may say "grid":
/// two strides' worth would be more, one run is too few to be a verdict;
/// ten runs of five samples cover at least 50 samples (0.5 s at 100 Hz).
pub const MIN_SCORED_RUNS: u32 = 10;

/// Watches the sample times and gyroscope rates of a stream (see the
/// module documentation) and says which spacing the rate derivative uses.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StampClock {
    /// The last five samples (oldest first) with both gyroscopes usable,
    /// consecutive in the stream; `held` of them are valid.
    last: [(f64, [Vector3<f64>; 2]); 5],
    held: usize,
    /// The sensor's sampling grid recovered from the stamps.
    grid: StampGrid,
    /// Sums of the squared cubic-prediction misses with the stamps and with
    /// the regular grid, and the number of runs scored.
    miss_stamps: f64,
    miss_grid: f64,
    scored: u32,
    /// The last sample's step from the one before on the regular grid
    /// (`None` unless the verdict is the grid).
    grid_step_last: Option<f64>,
}

impl StampClock {
    /// Observes the next sample of the stream. A sample not later than the
    /// last one seen (a re-pushed window) is ignored.
    pub fn observe(&mut self, s: &Slot) {
        self.observe_rates(s.t, s.gyr_ok.then_some(s.gyr));
    }

    /// [`Self::observe`] from a time stamp and the two gyroscopes' rates
    /// (`None` when either is missing or unusable): for a caller without a
    /// knee window's [`Slot`] (`chain_ekf::time_base`).
    pub fn observe_rates(&mut self, t: f64, rates: Option<[Vector3<f64>; 2]>) {
        let Some(Counted { steps, on_grid }) = self.grid.observe(t) else {
            return;
        };
        // runs of five are scored over counted steps only
        if steps > 1.0 || !on_grid {
            self.held = 0;
        }
        self.grid_step_last = match self.grid_step() {
            Some(b) if steps >= 1.0 => Some(steps * b),
            _ => None,
        };
        let Some(gyr) = rates else {
            self.held = 0;
            return;
        };
        if self.held == 5 {
            self.last.rotate_left(1);
            self.held = 4;
        }
        self.last[self.held] = (t, gyr);
        self.held += 1;
        if self.held == 5 {
            self.score();
        }
    }

    /// Whether samples stamped `t` (in time order) are consecutive samples of
    /// the sensor's own clock, no sample lost between them, when the verdict
    /// is the grid ([`Self::grid_step`]): [`StampGrid::consecutive`]. With
    /// jittered stamps a lost sample cannot be told from the stamps of five
    /// samples alone: under +-30 % jitter a step over a lost sample can be
    /// shorter than a step between neighbours (found 2026-12-07,
    /// `five_jittered_stamps_over_a_lost_sample_are_not_consecutive`).
    /// `true` when the verdict is not the grid (the stamps are then taken
    /// at their word, and their steps tell a gap).
    pub fn consecutive(&self, t: &[f64]) -> bool {
        self.grid_step().is_none() || self.grid.consecutive(t)
    }

    /// Scores the five samples held when their stamps are uneven (not
    /// within 1 %) but without a gap.
    fn score(&mut self) {
        let t: [f64; 5] = core::array::from_fn(|k| self.last[k].0);
        if uniform_step(&t).is_some() {
            return;
        }
        let mean = (t[4] - t[0]) / 4.0;
        let regular = (0..4).all(|i| {
            let step = t[i + 1] - t[i];
            step >= mean / MAX_STEP_RATIO && step <= mean * MAX_STEP_RATIO
        });
        if !regular {
            return;
        }
        let w_stamps = middle_cubic_weights(&t);
        // Evenly spaced nodes -2, -1, 1, 2 around 0: (-1, 4, 4, -1) / 6.
        let w_grid = [-1.0 / 6.0, 4.0 / 6.0, 4.0 / 6.0, -1.0 / 6.0];
        for seg in 0..2 {
            let g: [Vector3<f64>; 5] = core::array::from_fn(|k| self.last[k].1[seg]);
            let miss = |w: &[f64; 4]| {
                (g[2] - (g[0] * w[0] + g[1] * w[1] + g[3] * w[2] + g[4] * w[3])).norm_squared()
            };
            self.miss_stamps += miss(&w_stamps);
            self.miss_grid += miss(&w_grid);
        }
        self.scored = self.scored.saturating_add(1);
    }

    /// The step the rate derivative takes for unevenly stamped samples:
    /// `Some(slope of the line through the stamps)` when the regular grid
    /// fits the rates better than the stamps (after [`MIN_SCORED_RUNS`]
    /// runs), else `None` (the stamps are taken at their word).
    pub fn grid_step(&self) -> Option<f64> {
        let grid_fits_better =
            self.miss_grid.partial_cmp(&self.miss_stamps) == Some(Ordering::Less);
        if self.scored < MIN_SCORED_RUNS || !grid_fits_better {
            return None;
        }
        self.grid.period()
    }

    /// The step from the sample before to the last sample observed, on the
    /// regular grid (a whole number of grid steps), when the verdict is the
    /// grid; `None` otherwise (and after a gap).
    pub fn last_grid_step(&self) -> Option<f64> {
        self.grid_step_last
    }

    /// Forgets everything (estimator reset).
    pub fn reset(&mut self) {
        *self = StampClock::default();
    }
}

impl KneeSelfAlign {
    /// The step `dt` between the last two time stamps as the samples' own
    /// clock has it: whole grid steps when the stamps are jittered
    /// ([`StampClock::last_grid_step`] of the window's clock), else `dt`.
    pub fn on_stamp_grid(&self, dt: f64) -> f64 {
        self.window.last_grid_step().unwrap_or(dt)
    }
}

/// Lagrange weights of the cubic through the samples at `t[0]`, `t[1]`,
/// `t[3]`, `t[4]`, evaluated at `t[2]`.
fn middle_cubic_weights(t: &[f64; 5]) -> [f64; 4] {
    let nodes = [t[0], t[1], t[3], t[4]];
    core::array::from_fn(|j| {
        let mut w = 1.0;
        for (m, tm) in nodes.iter().enumerate() {
            if m != j {
                w *= (t[2] - tm) / (nodes[j] - tm);
            }
        }
        w
    })
}

#[cfg(test)]
#[path = "stamp_clock_tests.rs"]
mod tests;
