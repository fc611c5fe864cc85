//! The sampling clock of a sensor whose time stamps are jittered and whose
//! rows may be lost (ours, 2026-12-07): which sample of the sensor's own
//! regular clock each stamp belongs to, and the clock's period.
//!
//! A wireless IMU samples on its own clock; a receiver or a logging host
//! stamps the readings later, by a varying amount, and some readings never
//! arrive. A step between two stamps jittered by `+-j` periods varies by
//! `+-2 j`, so under `+-30 %` jitter a step over a lost reading (2 +- 0.6
//! periods) can be shorter than a step between neighbours (1 +- 0.6): no
//! rule on steps counts them. A stamp varies by `+-j` only, and against a
//! grid whose period and phase are known it is counted right while
//! `j < 1/2`. [`StampGrid`] therefore
//! 1. holds the first [`BOOTSTRAP_STAMPS`] stamps and finds the grid they
//!    fit best (`bootstrap`: the period whose phases concentrate most,
//!    their circular mean the phase), counting each step as one sample
//!    until then;
//! 2. counts every later stamp from the place of the recent ones on that
//!    grid (the median of the last [`RECENT`], not any one jittered stamp);
//! 3. refines the period as the slope of the least-squares line through
//!    the stamps against the samples counted (lost ones included: the
//!    de-jittering of Lab Streaming Layer's pyxdf).
//!
//! Used by the knee methods' time base (`knee_selfalign::stamp_clock`,
//! which decides whether the stamps are jittered at all) and by
//! `lowback-speed`'s sampling period. Neither papers 002 nor Zijlstra & Hof
//! say anything about stamps: both assume a regular sample rate.

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

/// The sensor's sampling grid recovered from its stamps (see the module
/// documentation). Fixed size, no allocation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StampGrid {
    /// Time of the first and of the last stamp seen (`None` before one).
    first_t: f64,
    last_t: Option<f64>,
    /// Sample index of the last stamp (missing samples counted) and the
    /// running least-squares line `t - first_t = a + b index` (Welford
    /// sums: points, means, co-moments) through the stamps counted on a
    /// period (the first [`BOOTSTRAP_STAMPS`] are counted again on the
    /// period they fix).
    index: f64,
    points: f64,
    mean_index: f64,
    mean_time: f64,
    c_ii: f64,
    c_it: f64,
    /// The first [`BOOTSTRAP_STAMPS`] stamps (`t - first_t`); `boot_n` of
    /// them held, `booted` once they fixed the period, `even` when every
    /// step among them was within 1 % of their median.
    boot: [f64; BOOTSTRAP_STAMPS],
    boot_n: usize,
    booted: bool,
    even: bool,
    /// The last [`RECENT`] stamps' `(index, t - first_t)`, a ring; `recent_n`
    /// of them valid.
    recent: [(f64, f64); RECENT],
    recent_n: usize,
    /// Stamps observed (the ring's position).
    seen: usize,
    /// The place of index 0 on the line the steps are counted from
    /// (`t - first_t = intercept + period index`), as of the last stamp.
    intercept: f64,
}

impl Default for StampGrid {
    fn default() -> Self {
        StampGrid {
            first_t: 0.0,
            last_t: None,
            index: 0.0,
            points: 0.0,
            mean_index: 0.0,
            mean_time: 0.0,
            c_ii: 0.0,
            c_it: 0.0,
            boot: [0.0; BOOTSTRAP_STAMPS],
            boot_n: 0,
            booted: false,
            even: false,
            recent: [(0.0, 0.0); RECENT],
            recent_n: 0,
            seen: 0,
            intercept: 0.0,
        }
    }
}

/// What [`StampGrid::observe`] found for one stamp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Counted {
    /// Samples of the sensor's clock from the last stamp to this one (one
    /// for a neighbour, two over a lost reading; 0 for the first stamp;
    /// always one before the grid is known).
    pub steps: f64,
    /// Whether the step was counted on a known grid (after the first
    /// [`BOOTSTRAP_STAMPS`] stamps).
    pub on_grid: bool,
}

impl StampGrid {
    /// Observes the next stamp; `None` (and nothing changes) when it is not
    /// later than the last one.
    pub fn observe(&mut self, t: f64) -> Option<Counted> {
        let steps = match self.last_t {
            Some(last) if t.partial_cmp(&last) != Some(core::cmp::Ordering::Greater) => {
                return None
            }
            Some(_) => self.steps_since(t),
            None => {
                self.first_t = t;
                0.0
            }
        };
        let on_grid = self.booted;
        self.last_t = Some(t);
        self.index += steps;
        if on_grid {
            self.add_point(self.index, t - self.first_t);
        }
        self.recent[self.seen % RECENT] = (self.index, t - self.first_t);
        self.seen += 1;
        self.recent_n = (self.recent_n + 1).min(RECENT);
        if !on_grid {
            self.boot[self.boot_n] = t - self.first_t;
            self.boot_n += 1;
            if self.boot_n == BOOTSTRAP_STAMPS {
                self.bootstrap();
            }
        }
        self.intercept = self.line_intercept();
        Some(Counted { steps, on_grid })
    }

    /// The sampling period: the slope of the line through the counted
    /// stamps (`None` before [`BOOTSTRAP_STAMPS`] stamps).
    pub fn period(&self) -> Option<f64> {
        if self.booted {
            self.line().map(|(_, b)| b)
        } else {
            None
        }
    }

    /// Whether the first [`BOOTSTRAP_STAMPS`] stamps were evenly spaced
    /// (every step within 1 % of their median; `false` before them).
    pub fn even(&self) -> bool {
        self.even
    }

    /// Sample steps from the last stamp to one at `t`: the whole number of
    /// periods from the last stamp's place on the line of slope `period`
    /// through the median place of the last [`RECENT`] stamps (at least
    /// one); one before the grid is known. (Until 2026-12-06 the knee
    /// methods counted from the line's own prediction of the last sample; a
    /// line a few % short after its first points then made jittered steps
    /// count as two, which kept the line short, a fixed point: 7 % short
    /// under +-30 % jitter. Counted from the median place of recent
    /// stamps, the period's error matters only over the distance to them.)
    fn steps_since(&self, t: f64) -> f64 {
        match self.period() {
            None => 1.0,
            Some(period) => {
                let on_line = self.intercept + period * self.index;
                libm::round((t - self.first_t - on_line) / period).max(1.0)
            }
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
        // the stamps' own, no search (it would cost 0.3 ms).
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
        self.even = even;
    }

    /// Where index 0 lies on the line of slope `period` the steps are
    /// counted from: through the median place of the recent stamps (not
    /// the jittered stamp of any one).
    fn line_intercept(&self) -> f64 {
        let Some(period) = self.period() else {
            return 0.0;
        };
        let mut at: [f64; RECENT] =
            core::array::from_fn(|k| self.recent[k].1 - period * self.recent[k].0);
        at.sort_by(f64::total_cmp);
        0.5 * (at[RECENT / 2 - 1] + at[RECENT / 2])
    }

    /// Whether stamps `t` (in time order) are consecutive samples of the
    /// sensor's clock, no sample lost between them: each stamp placed on
    /// the grid and rounded to its sample. `true` before the grid is known.
    pub fn consecutive(&self, t: &[f64]) -> bool {
        let Some(period) = self.period() else {
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
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A fixed sequence of uniform numbers in [0, 1) (linear congruential;
    /// no generator crate), for the stamp tests here and in
    /// `knee_selfalign::stamp_clock`.
    pub(crate) fn uniform(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15);
        move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// +-30 % jitter and a fifth of the samples lost at 204.8 Hz, from a
    /// clock starting at 1000 s: the bootstrap's period within 0.3 % of the
    /// sampling period and every sample after it counted.
    #[test]
    fn the_grid_is_recovered_from_jittered_stamps_with_lost_samples() {
        let dt = 1.0 / 204.8;
        for seed in 1..=10u64 {
            let (mut u, mut lose) = (uniform(seed), uniform(seed + 50));
            let mut g = StampGrid::default();
            let (mut last_k, mut bad) = (0usize, 0);
            for k in 0..2000usize {
                let t = 1000.0 + k as f64 * dt + 0.3 * dt * (2.0 * u() - 1.0);
                if k > 0 && lose() < 0.2 {
                    continue;
                }
                let c = g.observe(t).expect("later stamp");
                if c.on_grid && c.steps != (k - last_k) as f64 {
                    bad += 1;
                }
                if g.booted && g.points == BOOTSTRAP_STAMPS as f64 {
                    let p = g.period().expect("booted");
                    assert!((p / dt - 1.0).abs() < 0.003, "seed {seed}: {p}");
                }
                last_k = k;
            }
            assert_eq!(bad, 0, "seed {seed}");
            assert!(!g.even());
            let p = g.period().expect("booted");
            assert!((p / dt - 1.0).abs() < 1e-4, "seed {seed}: {p}");
        }
    }

    /// Evenly spaced stamps: `even`, their step, every step one; a stamp
    /// not later than the last is ignored.
    #[test]
    fn even_stamps_are_their_own_grid() {
        let mut g = StampGrid::default();
        for k in 0..100 {
            let c = g.observe(k as f64 * 0.01).expect("later");
            assert_eq!(c.steps, if k == 0 { 0.0 } else { 1.0 });
        }
        assert!(g.even());
        assert!((g.period().unwrap() - 0.01).abs() < 1e-12);
        let before = g;
        assert_eq!(g.observe(0.5), None);
        assert_eq!(g, before);
        assert!(g.consecutive(&[0.97, 0.98, 0.99]));
        assert!(!g.consecutive(&[0.96, 0.98, 0.99]));
    }
}
