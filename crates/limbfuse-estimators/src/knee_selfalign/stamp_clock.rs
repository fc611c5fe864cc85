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
//! the mean step since the first sample. Evenly stamped samples (within 1 %)
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

/// Stamp steps averaged before a step may count as more than one sample:
/// the mean of `n` steps jittered by +-`j` is off by about `j / sqrt(n)`,
/// so eight pin it to a third of one stamp's jitter (a mean from two or
/// three steps made a jittered step count twice).
pub const MIN_PERIOD_STEPS: f64 = 8.0;

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
#[derive(Debug, Clone, Copy, PartialEq, Default)]
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
    /// sums: points, means, co-moments).
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
    /// Sum and count of the stamp steps counted as one sample.
    single_steps: (f64, f64),
    /// The last [`RECENT`] samples' `(index, t - first_t)`, a ring; `recent_n`
    /// of them valid.
    recent: [(f64, f64); RECENT],
    recent_n: usize,
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
        if let (Some(last), 1.0) = (self.last_t, steps) {
            self.single_steps.0 += s.t - last;
            self.single_steps.1 += 1.0;
        }
        self.last_t = Some(s.t);
        self.index += steps;
        self.add_point(self.index, s.t - self.first_t);
        self.recent[self.points as usize % RECENT] = (self.index, s.t - self.first_t);
        self.recent_n = (self.recent_n + 1).min(RECENT);
        if steps > 1.0 {
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
    /// through the median place of the last [`RECENT`] samples (through the
    /// stamps' centroid until that many are held; at least one). The period is the mean
    /// of the stamp steps counted as one sample so far: it converges to the
    /// sampling period whatever the jitter, as it does not depend on how
    /// the steps were counted; before [`MIN_PERIOD_STEPS`] of them every
    /// step is one (a gap that early shifts the later indices by its
    /// missing samples, a slope error that fades as 1 / samples). (Until 2026-12-06 the steps were counted
    /// from the line through the stamps; a line a few % short after its
    /// first points then made jittered steps count as two, which kept the
    /// line short, a fixed point: 7 % short under +-30 % jitter, test
    /// `the_grid_step_is_the_sampling_period_under_heavy_jitter`.)
    fn steps_since(&self, t: f64) -> f64 {
        if self.single_steps.1 < MIN_PERIOD_STEPS {
            return 1.0;
        }
        let period = self.single_steps.0 / self.single_steps.1;
        // the line of slope `period` through the points' centroid: the last
        // sample's place on it, not its jittered stamp; once sixteen samples
        // are held, through the median place of the recent ones ([`RECENT`])
        let on_line = if self.recent_n == RECENT {
            let mut at: [f64; RECENT] =
                core::array::from_fn(|k| self.recent[k].1 - period * self.recent[k].0);
            at.sort_by(f64::total_cmp);
            0.5 * (at[RECENT / 2 - 1] + at[RECENT / 2]) + period * self.index
        } else {
            self.mean_time + period * (self.index - self.mean_index)
        };
        libm::round((t - self.first_t - on_line) / period).max(1.0)
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
mod tests {
    use super::*;

    fn slot(t: f64, rate: f64) -> Slot {
        Slot {
            t,
            gyr: [Vector3::new(rate, 0.0, 0.0), Vector3::new(0.0, -rate, 0.0)],
            gyr_ok: true,
            acc_ok: true,
            ..Slot::default()
        }
    }

    /// A deterministic +-`amp` s pattern (no random generator in the crate).
    fn jitter(k: usize, amp: f64) -> f64 {
        let u = ((k * 7919 + 13) % 101) as f64 / 100.0;
        amp * (2.0 * u - 1.0)
    }

    fn rate(t: f64) -> f64 {
        3.0 * libm::sin(2.0 * core::f64::consts::PI * 1.1 * t) + libm::sin(9.0 * t)
    }

    #[test]
    fn the_cubic_weights_reproduce_a_cubic() {
        let t = [0.0, 0.011, 0.019, 0.032, 0.04];
        let f = |x: f64| 1.0 - 2.0 * x + 30.0 * x * x - 500.0 * x * x * x;
        let w = middle_cubic_weights(&t);
        let p = w[0] * f(t[0]) + w[1] * f(t[1]) + w[2] * f(t[3]) + w[3] * f(t[4]);
        assert!((p - f(t[2])).abs() < 1e-12, "{p} vs {}", f(t[2]));
        let even = middle_cubic_weights(&[0.0, 1.0, 2.0, 3.0, 4.0]);
        for (a, b) in even
            .iter()
            .zip([-1.0 / 6.0, 4.0 / 6.0, 4.0 / 6.0, -1.0 / 6.0])
        {
            assert!((a - b).abs() < 1e-15);
        }
    }

    #[test]
    fn jittered_stamps_of_regular_samples_choose_the_grid() {
        let mut c = StampClock::default();
        for k in 0..500 {
            let t_true = k as f64 * 0.01;
            c.observe(&slot(t_true + jitter(k, 0.003), rate(t_true)));
        }
        let step = c.grid_step().expect("the grid fits better");
        assert!((step - 0.01).abs() < 1e-4, "{step}");
        // Every jittered step (4-16 ms) is one grid step; a dropped sample two.
        let mut steps = Vec::new();
        for k in 500..900 {
            if k % 97 == 0 {
                continue;
            }
            let t_true = k as f64 * 0.01;
            c.observe(&slot(t_true + jitter(k, 0.003), rate(t_true)));
            let n = c.last_grid_step().expect("grid") / c.grid_step().expect("grid");
            steps.push((k, libm::round(n) as usize, (n - libm::round(n)).abs()));
        }
        for (k, n, off) in steps {
            assert_eq!(n, if k % 97 == 1 { 2 } else { 1 }, "sample {k}");
            assert!(off < 1e-12);
        }
    }

    #[test]
    fn truly_uneven_sampling_keeps_the_stamps() {
        let mut c = StampClock::default();
        for k in 0..500 {
            let t = k as f64 * 0.01 + jitter(k, 0.003);
            c.observe(&slot(t, rate(t)));
        }
        assert!(c.scored >= MIN_SCORED_RUNS);
        assert_eq!(c.grid_step(), None);
    }

    #[test]
    fn even_stamps_are_not_scored() {
        let mut c = StampClock::default();
        for k in 0..500 {
            let t = k as f64 * 0.01;
            c.observe(&slot(t, rate(t)));
        }
        assert_eq!(c.scored, 0);
        assert_eq!(c.grid_step(), None);
    }

    #[test]
    fn samples_missing_are_counted_and_earlier_times_are_ignored() {
        let mut c = StampClock::default();
        for k in (0..400).filter(|k| !(300..350).contains(k)) {
            let t_true = k as f64 * 0.01;
            c.observe(&slot(t_true + jitter(k, 0.003), rate(t_true)));
            if k == 350 {
                let gap = c.last_grid_step().expect("grid");
                assert!((gap - 0.51).abs() < 1e-3, "{gap}");
            }
        }
        let step = c.grid_step().expect("grid");
        assert!((step - 0.01).abs() < 2e-5, "{step}");
        let before = c;
        c.observe(&slot(1.0, 0.0));
        assert_eq!(c, before);
    }

    /// The grid's step settled 7 % short of the sampling period under
    /// +-30 % stamp jitter (found 2026-12-06: the shared 1.2 m/s walk with
    /// +-3 ms at 100 Hz, `knee-gyro-axis` 0.84 -> 3.20 deg, `knee-selfalign`
    /// 1.06 -> 2.93): a line fitted on its first nine stamps came out a few
    /// % short, its prediction then drifted behind the stamps until a
    /// jittered step counted as two samples, which kept the slope short, a
    /// fixed point. A step of at most `MAX_STEP_RATIO` grid steps between
    /// stamps is now one sample (jitter, not a gap). Twenty jitter
    /// patterns (a linear congruential sequence, uniform +-0.3 periods).
    /// A fixed sequence of uniform numbers in [0, 1) (linear congruential).
    fn uniform(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15);
        move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// The stamp of sample `k` at period `dt`, moved by up to +-0.3 periods
    /// (the first one exact).
    fn jittered(k: usize, dt: f64, u: &mut impl FnMut() -> f64) -> f64 {
        let t0 = k as f64 * dt;
        if k == 0 {
            0.0
        } else {
            t0 + 0.3 * dt * (2.0 * u() - 1.0)
        }
    }

    #[test]
    fn the_grid_step_is_the_sampling_period_under_heavy_jitter() {
        let dt = 0.01;
        let mut worst: f64 = 0.0;
        for seed in 1..=20u64 {
            let mut u = uniform(seed);
            let mut c = StampClock::default();
            for k in 0..3000 {
                let t0 = k as f64 * dt;
                c.observe(&slot(jittered(k, dt, &mut u), rate(t0)));
            }
            let b = c.grid_step().expect("jittered stamps choose the grid");
            worst = worst.max((b / dt - 1.0).abs());
        }
        assert!(
            worst < 0.005,
            "grid step {:.2} % off the period",
            100.0 * worst
        );
    }

    /// Stamps jittered by up to +-3 ms at 100 Hz with a sample lost among
    /// the first eight steps and every twentieth one after: once the grid is
    /// chosen every step counts the samples it spans.
    #[test]
    fn a_sample_lost_among_the_first_steps_is_counted() {
        let dt = 0.01;
        let mut bad = 0;
        for seed in 1..=10u64 {
            let mut u = uniform(seed);
            let mut c = StampClock::default();
            let mut last_k = 0usize;
            for k in 0..3000usize {
                if k == 4 || (k > 10 && k % 20 == 7) {
                    continue;
                }
                let t0 = k as f64 * dt;
                c.observe(&slot(jittered(k, dt, &mut u), rate(t0)));
                if k > 200 {
                    let counted = c.last_grid_step().map(|s| libm::round(s / dt));
                    if counted != Some((k - last_k) as f64) {
                        bad += 1;
                    }
                }
                last_k = k;
            }
        }
        assert_eq!(bad, 0);
    }
}
