//! The sampling period of `lowback-speed` from the time steps between
//! readings: the mean of the steps, robust to lost rows (ours, 2026-12-06).
//!
//! The mean of every step (2026-12-05: robust to a jittered first stamp)
//! counted a lost row's double step as one period: with a twentieth of the
//! rows removed from a walk the period came out about 5 % long, and the
//! step integration's speed with it (`lowback-speed` on the shared HA001
//! straight walk 0.028 -> 0.068 m/s stride MAE). Now the period is the time
//! the steps span over the sampling periods they span: each step counts as
//! the whole number of periods nearest to it (at least one) on the period
//! so far, the first [`FIRST_STEPS`] on their own mean. The sum of the steps
//! telescopes, so jittered stamps move the period only by the first and last
//! stamps' errors over the whole span, as the plain mean did; a step counts
//! wrongly only when a stamp is more than a quarter period off.

/// Steps counted as one period each before the period is known; then they
/// are counted again on their own mean (a row lost among them is a step
/// 1.8 of that mean, a jittered one within `1 +- 2 j` for stamp errors up to
/// `j` periods).
pub const FIRST_STEPS: usize = 8;

/// The running estimate.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SamplingPeriod {
    first: [f64; FIRST_STEPS],
    count: u64,
    sum: f64,
    periods: f64,
}

impl SamplingPeriod {
    /// Adds a time step (s) between two readings (not across a pause: the
    /// caller leaves those out); returns the period and how many steps it
    /// holds.
    pub fn add(&mut self, step: f64) -> (f64, u64) {
        let n = self.count as usize;
        self.sum += step;
        self.count += 1;
        if n < FIRST_STEPS {
            self.first[n] = step;
            self.periods += 1.0;
            if n + 1 == FIRST_STEPS {
                let mean = self.sum / FIRST_STEPS as f64;
                self.periods = self
                    .first
                    .iter()
                    .map(|s| libm::round(s / mean).max(1.0))
                    .sum();
            }
        } else {
            self.periods += libm::round(step * self.periods / (self.sum - step)).max(1.0);
        }
        (self.sum / self.periods, self.count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 100 Hz stamps jittered by up to +-2 ms (a fixed sequence), every
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
            let jitter = ((state >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 0.004;
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
