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
//! from the stamps' places on a grid ([`BOOTSTRAP_STAMPS`], `steps_since`),
//! not from the steps between them. Evenly stamped samples (within 1 %)
//! are not scored: there both time bases agree and the derivative is the
//! five-point formula as before.

use core::cmp::Ordering;

use nalgebra::Vector3;

use super::position::{uniform_step, MAX_STEP_RATIO};
use super::window::Slot;
use super::KneeSelfAlign;

/// Uneven runs of five samples scored before the verdict may say "grid":
/// two strides' worth would be more, one run is too few to be a verdict;
/// ten runs of five samples cover at least 50 samples (0.5 s at 100 Hz).
pub const MIN_SCORED_RUNS: u32 = 10;

/// Stamps whose places fix the first period and phase of the sensor's
/// clock before any step is counted (2026-12-07): the period whose grid
/// the stamps fit best (`bootstrap`), then the least-squares line through
/// the stamps against the samples counted. Until then the first period was
/// a mean of stamp steps: of the steps counted as one (which, with a fifth
/// of the rows lost, settled long: a long period puts the last sample's
/// place behind its stamp, a step over a lost row rounds to one, joins the
/// mean and keeps it long, a fixed point; +-10 % jitter, 20 % lost: period
/// 6.6 % long at 56 s), then for a day of the steps within 1 +- 0.5
/// periods (which still settled 3 % long under +-30 % jitter with a fifth
/// lost, its band catching steps over a lost row). A step of stamps
/// jittered by +-30 % varies by +-60 % of a period and cannot be counted
/// on its own; a stamp varies by +-30 % and can, against a grid whose
/// period and phase are known. 64 stamps span 64-80 periods: the grid's
/// fit then tells the period within about 0.2 % (a Python model of the
/// clock, 16 seeds at +-10-30 % jitter and 0-30 % of the samples lost: at
/// most 3 of 93 000 steps miscounted; with 32 stamps one seed in eight
/// never recovered).
pub const BOOTSTRAP_STAMPS: usize = 64;

/// Recent samples whose median place on the line the steps are counted from
/// (2026-12-06): over the whole stream, the period's error times the
/// distance to the centroid miscounted steps once lost rows kept the mean
/// single step from telescoping (a unit test with +-3 ms jitter at 100 Hz
/// and every twentieth row lost: hundreds of steps in 3000 miscounted,
/// `a_sample_lost_among_the_first_steps_is_counted`); the median of sixteen
/// places is as close as a stamp's jitter allows and follows a miscounted
/// step within eight.
pub const RECENT: usize = 16;

/// Watches the sample times and gyroscope rates of a stream (see the
/// module documentation) and says which spacing the rate derivative uses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StampClock {
    /// The last five samples (oldest first) with both gyroscopes usable,
    /// consecutive in the stream; `held` of them are valid.
    last: [(f64, [Vector3<f64>; 2]); 5],
    held: usize,
    /// Time of the first and of the last sample seen (`None` before one).
    first_t: f64,
    last_t: Option<f64>,
    /// Sample index of the last sample (missing samples counted) and the
    /// running least-squares line `t - first_t = a + b index` (Welford
    /// sums: points, means, co-moments) through the samples whose step was
    /// counted on a period (the first [`BOOTSTRAP_STAMPS`] are counted
    /// again on the period they fix).
    index: f64,
    points: f64,
    mean_index: f64,
    mean_time: f64,
    c_ii: f64,
    c_it: f64,
    /// Sums of the squared cubic-prediction misses with the stamps and with
    /// the regular grid, and the number of runs scored.
    miss_stamps: f64,
    miss_grid: f64,
    scored: u32,
    /// The last sample's step from the one before on the regular grid
    /// (`None` unless the verdict is the grid).
    grid_step_last: Option<f64>,
    /// The first [`BOOTSTRAP_STAMPS`] stamps (`t - first_t`); `boot_n` of
    /// them held, `booted` once they fixed the period.
    boot: [f64; BOOTSTRAP_STAMPS],
    boot_n: usize,
    booted: bool,
    /// The last [`RECENT`] samples' `(index, t - first_t)`, a ring; `recent_n`
    /// of them valid.
    recent: [(f64, f64); RECENT],
    recent_n: usize,
    /// Samples observed (the ring's position).
    seen: usize,
    /// The place of index 0 on the line the steps are counted from
    /// (`t - first_t = intercept + period index`; see [`Self::steps_since`]),
    /// as of the last sample observed.
    intercept: f64,
}

impl Default for StampClock {
    fn default() -> Self {
        StampClock {
            last: Default::default(),
            held: 0,
            first_t: 0.0,
            last_t: None,
            index: 0.0,
            points: 0.0,
            mean_index: 0.0,
            mean_time: 0.0,
            c_ii: 0.0,
            c_it: 0.0,
            miss_stamps: 0.0,
            miss_grid: 0.0,
            scored: 0,
            grid_step_last: None,
            boot: [0.0; BOOTSTRAP_STAMPS],
            boot_n: 0,
            booted: false,
            recent: [(0.0, 0.0); RECENT],
            recent_n: 0,
            seen: 0,
            intercept: 0.0,
        }
    }
}

impl StampClock {
    /// Observes the next sample of the stream. A sample not later than the
    /// last one seen (a re-pushed window) is ignored.
    pub fn observe(&mut self, s: &Slot) {
        let steps = match self.last_t {
            Some(last) if s.t.partial_cmp(&last) != Some(Ordering::Greater) => return,
            Some(_) => self.steps_since(s.t),
            None => {
                self.first_t = s.t;
                0.0
            }
        };
        // whether this sample's step was counted on a period (after the
        // first `BOOTSTRAP_STAMPS`)
        let counted = self.booted;
        self.last_t = Some(s.t);
        self.index += steps;
        if counted {
            self.add_point(self.index, s.t - self.first_t);
        }
        self.recent[self.seen % RECENT] = (self.index, s.t - self.first_t);
        self.seen += 1;
        self.recent_n = (self.recent_n + 1).min(RECENT);
        if !counted {
            self.boot[self.boot_n] = s.t - self.first_t;
            self.boot_n += 1;
            if self.boot_n == BOOTSTRAP_STAMPS {
                self.bootstrap();
            }
        }
        self.intercept = self.line_intercept();
        // runs of five are scored over counted steps only
        if steps > 1.0 || !counted {
            self.held = 0;
        }
        self.grid_step_last = match self.grid_step() {
            Some(b) if steps >= 1.0 => Some(steps * b),
            _ => None,
        };
        if !s.gyr_ok {
            self.held = 0;
            return;
        }
        if self.held == 5 {
            self.last.rotate_left(1);
            self.held = 4;
        }
        self.last[self.held] = (s.t, s.gyr);
        self.held += 1;
        if self.held == 5 {
            self.score();
        }
    }

    /// Sample steps from the last sample to one at `t`: the whole number of
    /// periods from the last sample's place on the line of slope `period`
    /// through the median place of the last [`RECENT`] samples (at least
    /// one). The period is the slope of the least-squares line through the
    /// stamps against the samples counted, from the [`BOOTSTRAP_STAMPS`]
    /// on; before them every step is one (they are counted again once they
    /// fixed the period, `bootstrap`). (Until 2026-12-06 the steps were
    /// counted from the line's own prediction of the last sample; a line a
    /// few % short after its first points then made jittered steps count as
    /// two, which kept the line short, a fixed point: 7 % short under +-30 %
    /// jitter, test `the_grid_step_is_the_sampling_period_under_heavy_jitter`.
    /// Counted from the median place of recent samples, the period's error
    /// matters only over the distance to them.)
    fn steps_since(&self, t: f64) -> f64 {
        match self.period() {
            None => 1.0,
            Some(period) => {
                let on_line = self.intercept + period * self.index;
                libm::round((t - self.first_t - on_line) / period).max(1.0)
            }
        }
    }

    /// The sampling period: the slope of the line through the counted
    /// samples (`None` before [`BOOTSTRAP_STAMPS`] stamps).
    fn period(&self) -> Option<f64> {
        if self.booted {
            self.line().map(|(_, b)| b)
        } else {
            None
        }
    }

    /// Fixes the first period and phase from the [`BOOTSTRAP_STAMPS`]
    /// stamps held: the period `p` whose grid they fit best, i.e. whose
    /// phases `2 pi t / p` are most concentrated (`|sum exp(2 pi i t / p)|`,
    /// the Rayleigh test's statistic; a lost sample leaves the phases
    /// alone), searched within 0.6-1.4 times the median stamp step (a
    /// median of single steps while under half the samples are lost; the
    /// range leaves out half and twice the period, whose grids fit as
    /// well), in steps of 1 % and then of 0.05 % around the best; the
    /// phase is the phases' circular mean. The stamps are then counted on
    /// that grid and start the line, and the recent places are theirs.
    fn bootstrap(&mut self) {
        const N: usize = BOOTSTRAP_STAMPS;
        let t = self.boot;
        let mut steps: [f64; N - 1] = core::array::from_fn(|k| t[k + 1] - t[k]);
        steps.sort_by(f64::total_cmp);
        let median = steps[(N - 1) / 2];
        // Evenly stamped (every step within 1 % of the median): the grid is
        // the stamps' own, no search (such stamps are never scored, so the
        // verdict cannot be the grid; the search would cost 0.3 ms).
        let even = steps[0] >= 0.99 * median && steps[N - 2] <= 1.01 * median;
        let phasor = |p: f64| {
            t.iter().fold((0.0, 0.0), |(c, s), &x| {
                let a = core::f64::consts::TAU * x / p;
                (c + libm::cos(a), s + libm::sin(a))
            })
        };
        let power = |p: f64| {
            let (c, s) = phasor(p);
            c * c + s * s
        };
        let best_of = |candidates: &mut dyn Iterator<Item = f64>| {
            candidates.fold((f64::NEG_INFINITY, median), |best, p| {
                let r = power(p);
                if r > best.0 {
                    (r, p)
                } else {
                    best
                }
            })
        };
        let p = if even {
            (t[N - 1] - t[0]) / (N - 1) as f64
        } else {
            let (_, coarse) = best_of(&mut (0..=80).map(|i| median * (0.6 + 0.01 * i as f64)));
            best_of(&mut (0..=40).map(|i| coarse + median * 0.0005 * (i as f64 - 20.0))).1
        };
        let (c, s) = phasor(p);
        let phase = libm::atan2(s, c) / core::f64::consts::TAU * p;
        let place = |x: f64| libm::round((x - phase) / p);
        (
            self.points,
            self.mean_index,
            self.mean_time,
            self.c_ii,
            self.c_it,
        ) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for &x in &t {
            self.add_point(place(x), x);
        }
        self.index = place(t[N - 1]);
        for j in 0..RECENT {
            let x = t[N - RECENT + j];
            self.recent[(self.seen - RECENT + j) % RECENT] = (place(x), x);
        }
        self.recent_n = RECENT;
        self.booted = true;
    }

    /// Where index 0 lies on the line of slope `period` the steps are
    /// counted from: through the median place of the recent samples (not
    /// the jittered stamp of any one sample).
    fn line_intercept(&self) -> f64 {
        let Some(period) = self.period() else {
            return 0.0;
        };
        let mut at: [f64; RECENT] =
            core::array::from_fn(|k| self.recent[k].1 - period * self.recent[k].0);
        at.sort_by(f64::total_cmp);
        0.5 * (at[RECENT / 2 - 1] + at[RECENT / 2])
    }

    /// Whether samples stamped `t` (in time order) are consecutive samples of
    /// the sensor's own clock, no sample lost between them, when the verdict
    /// is the grid ([`Self::grid_step`]): each stamp is placed on the
    /// line the steps are counted from and rounded to its sample. With
    /// jittered stamps a lost sample cannot be told from the stamps of five
    /// samples alone: under +-30 % jitter a step over a lost sample can be
    /// shorter than a step between neighbours (found 2026-12-07, below
    /// `five_jittered_stamps_over_a_lost_sample_are_not_consecutive`).
    /// `true` when the verdict is not the grid (the stamps are then taken
    /// at their word, and their steps tell a gap).
    pub fn consecutive(&self, t: &[f64]) -> bool {
        let (Some(_), Some(period)) = (self.grid_step(), self.period()) else {
            return true;
        };
        let place = |t: f64| libm::round((t - self.first_t - self.intercept) / period);
        t.windows(2).all(|w| place(w[1]) - place(w[0]) == 1.0)
    }

    fn add_point(&mut self, i: f64, t: f64) {
        self.points += 1.0;
        let di = i - self.mean_index;
        self.mean_index += di / self.points;
        self.mean_time += (t - self.mean_time) / self.points;
        self.c_ii += di * (i - self.mean_index);
        self.c_it += di * (t - self.mean_time);
    }

    /// The line `t - first_t = a + b index` (`None` before two indices).
    fn line(&self) -> Option<(f64, f64)> {
        if self.c_ii.is_nan() || self.c_ii <= 0.0 {
            return None;
        }
        let b = self.c_it / self.c_ii;
        (b > 0.0).then_some((self.mean_time - b * self.mean_index, b))
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
        self.line().map(|(_, b)| b)
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
