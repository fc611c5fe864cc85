//! The sampling period of `lowback-speed` from the time steps between
//! readings: the mean of the steps, robust to lost rows (ours, 2026-12-06).
//!
//! The mean of every step (2026-12-05: robust to a jittered first stamp)
//! counted a lost row's double step as one period: with a twentieth of the
//! rows removed from a walk the period came out about 5 % long, and the
//! step integration's speed with it (`lowback-speed` on the shared HA001
//! straight walk 0.028 -> 0.068 m/s stride MAE). Now the first
//! [`FIRST_STEPS`] steps give a median, and a step enters the mean only
//! within half a period of it (then of the mean so far): symmetric about the
//! period, so jittered stamps (the step is the period plus the difference of
//! two stamp errors) leave the mean where it was, while a lost row's double
//! step is left out.

/// Steps whose median anchors the band (a lost row among them is outvoted).
pub const FIRST_STEPS: usize = 8;

/// Half-width of the band, as a fraction of the period: a lost row's step
/// is twice the period, a jittered one within `1 +- 2 j` for stamp errors
/// up to `j` periods.
pub const BAND: f64 = 0.5;

/// The running estimate.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SamplingPeriod {
    first: [f64; FIRST_STEPS],
    seen: usize,
    sum: f64,
    count: u64,
}

impl SamplingPeriod {
    /// Adds a time step (s) between two readings (not across a pause: the
    /// caller leaves those out); returns the period and how many steps its
    /// mean holds.
    pub fn add(&mut self, step: f64) -> (f64, u64) {
        if self.seen < FIRST_STEPS {
            self.first[self.seen] = step;
            self.seen += 1;
            self.sum += step;
            self.count += 1;
            if self.seen == FIRST_STEPS {
                let mut sorted = self.first;
                sorted.sort_by(f64::total_cmp);
                let median = 0.5 * (sorted[FIRST_STEPS / 2 - 1] + sorted[FIRST_STEPS / 2]);
                (self.sum, self.count) = (0.0, 0);
                for s in self.first {
                    if (s - median).abs() <= BAND * median {
                        self.sum += s;
                        self.count += 1;
                    }
                }
            }
        } else {
            let mean = self.sum / self.count as f64;
            if (step - mean).abs() <= BAND * mean {
                self.sum += step;
                self.count += 1;
            }
        }
        (self.sum / self.count as f64, self.count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 100 Hz stamps jittered by up to +-3 ms (a fixed sequence), every
    /// seventh row lost, the first among the first eight steps: the period
    /// within 0.5 % of 10 ms (9.99 ms; the mean of every step: 11.66 ms).
    #[test]
    fn lost_rows_and_jitter_leave_the_period() {
        let mut p = SamplingPeriod::default();
        let mut state: u64 = 7;
        let (mut last, mut all) = (None, (0.0, 0.0));
        let mut period = 0.0;
        for k in 0..3000usize {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let jitter = ((state >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 0.006;
            if k % 7 == 3 {
                continue;
            }
            let t = k as f64 * 0.01 + jitter;
            if let Some(l) = last {
                period = p.add(t - l).0;
                all = (all.0 + t - l, all.1 + 1.0);
            }
            last = Some(t);
        }
        assert!((period - 0.01).abs() < 5e-5, "{period}");
        assert!(all.0 / all.1 > 0.0115, "{all:?}");
    }

    /// Evenly spaced steps: the plain mean, bit for bit.
    #[test]
    fn even_steps_give_their_mean() {
        let mut p = SamplingPeriod::default();
        let steps = [
            0.01, 0.0100001, 0.0099999, 0.01, 0.01, 0.01, 0.01, 0.01, 0.01, 0.01,
        ];
        let mut sum = 0.0;
        for (i, s) in steps.iter().enumerate() {
            sum += s;
            assert_eq!(p.add(*s), (sum / (i + 1) as f64, i as u64 + 1));
        }
    }
}
