//! Single-sample gyroscope spikes in front of the FES filters (ours, not in
//! paper 004; docs/ROBUST_INPUT.md, "Gyroscope spikes in the FES filters").
//!
//! A spike of a few rad/s within the sensor gate's range and jump bound is
//! a measurement the continuous filters weigh by their measurement noise
//! intensity, far below it: it pulled the shank rate and the gyroscope-bias
//! state, and `sdre` on the shared independent FES trial P2-R with thirty
//! +-3 rad/s spikes went from 0.073 to 18.5 deg knee RMSE, with thirty
//! +-0.5 rad/s spikes to 1.8 deg (measured; docs/ROBUST_INPUT.md section 2q). A reading is refused when it
//! departs from the median of the last three accepted readings by more than
//! both `sqrt(`[`INNOVATION_GATE_CHI2`]`)` (4.89) standard deviations of the
//! difference of two readings under the filter's own measurement noise,
//! `sqrt(2 s / dt)` (`s` the channel's measurement noise intensity of the
//! tuning; `knee-fes` `s = 1e-5` at 100 Hz: 0.22 rad/s), and 4.89 times the
//! departures' running root mean square (time constant [`SCALE_TIME_S`]: the
//! bound grows on a recording whose motion is faster than the noise), but
//! never two samples in a row: a lasting change (a spasm, a bias step) costs
//! two of its first three samples. A refused reading is replaced by that
//! median, not left out: with the papers' tuning the filters take the
//! shank rate from the gyroscope alone (`q_2 = 1000`), so one missing
//! reading frees the rate state for a step, and on limbfuse's own P1-L trial
//! each left-out spike still moved the knee by up to 0.4 deg (measured; the
//! median's error on an FES motion is its lag, 0.02-0.04 rad/s). The median,
//! not the last reading: a spike just under the bound, accepted, would make
//! the next (right) reading depart by as much. Nothing is
//! tested before [`SCALE_TIME_S`] of departures or across a time gap.
//!
//! An FES leg moves slowly and smoothly (peak shank rates below 1.3 rad/s on
//! every shared and simulated FES trial, changing by at most 0.044 rad/s from
//! one 100 Hz sample to the next), which is why a test this tight holds
//! there; it is not used on walking data (`rmx` is not tested either).

use crate::segment_kf::rate_spikes::SCALE_TIME_S;
use crate::segment_kf::robust::{ExpWeights, GAP_STEP_RATIO, INNOVATION_GATE_CHI2};

/// The test of one gyroscope channel.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct GyroSpikeTest {
    /// The last three accepted readings, the latest first.
    accepted: [Option<f64>; 3],
    /// Time of the last accepted reading and the time step before it.
    accepted_t: Option<f64>,
    step: Option<f64>,
    /// Running mean square of the departures and how long (s) it has been
    /// averaged.
    mean_square: f64,
    averaged_s: f64,
    weights: ExpWeights,
    /// The last reading was refused.
    refused_last: bool,
    /// Readings refused so far.
    refused: u64,
}

impl GyroSpikeTest {
    /// Readings refused so far.
    pub fn refused(&self) -> u64 {
        self.refused
    }

    /// The reading that replaces `y` at time `t` when `y` is a spike: the
    /// median of the last three accepted readings (`y` is then not
    /// remembered as accepted); `s` is the channel's measurement noise
    /// intensity.
    pub fn replacement(&mut self, t: f64, y: f64, s: f64) -> Option<f64> {
        self.refuses(t, y, s).then(|| {
            let [a, b, c] = self.accepted.map(|v| v.unwrap_or(y));
            median(a, b, c)
        })
    }

    /// Whether the reading `y` at time `t` is a spike (then it is not
    /// remembered as accepted); `s` is the channel's measurement noise
    /// intensity.
    fn refuses(&mut self, t: f64, y: f64, s: f64) -> bool {
        let (Some(t1), [Some(a), Some(b), Some(c)]) = (self.accepted_t, self.accepted) else {
            self.accept(t, y);
            return false;
        };
        let dt = t - t1;
        let gap = self
            .step
            .is_some_and(|step| dt > GAP_STEP_RATIO * step && !self.refused_last);
        if dt.is_nan() || dt <= 0.0 || gap {
            // (a time gap, or a time that does not increase: start afresh)
            *self = GyroSpikeTest {
                refused: self.refused,
                ..GyroSpikeTest::default()
            };
            self.accept(t, y);
            return false;
        }
        let departure = y - median(a, b, c);
        let noise = 2.0 * s / dt;
        let bound = libm::sqrt(INNOVATION_GATE_CHI2 * noise.max(self.mean_square));
        if self.averaged_s >= SCALE_TIME_S && !self.refused_last && departure.abs() > bound {
            self.refused_last = true;
            self.refused += 1;
            return true;
        }
        if departure.is_finite() {
            let k = self.weights.weight(dt, SCALE_TIME_S);
            let d2 = departure * departure;
            self.mean_square = if self.averaged_s == 0.0 {
                d2
            } else {
                self.mean_square + k * (d2 - self.mean_square)
            };
            self.averaged_s += dt;
        }
        self.accept(t, y);
        false
    }

    fn accept(&mut self, t: f64, y: f64) {
        // (the step after a refusal spans two samples: not the sampling step)
        if let (Some(t1), false) = (self.accepted_t, self.refused_last) {
            self.step = Some(t - t1);
        }
        self.refused_last = false;
        self.accepted = [Some(y), self.accepted[0], self.accepted[1]];
        self.accepted_t = Some(t);
    }
}

/// The median of three numbers.
fn median(a: f64, b: f64, c: f64) -> f64 {
    a.max(b).min(a.min(b).max(c))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `knee-fes`'s gyroscope noise intensity.
    const S: f64 = 1e-5;

    /// A slow FES-like motion: 0.8 rad/s at 0.4 Hz, 100 Hz, with `extra(k)`
    /// added to sample `k`; the samples refused.
    fn refused(n: usize, extra: impl Fn(usize) -> f64) -> Vec<usize> {
        let mut test = GyroSpikeTest::default();
        (0..n)
            .filter(|&k| {
                let t = k as f64 * 0.01;
                let y = 0.8 * libm::sin(core::f64::consts::TAU * 0.4 * t) + extra(k);
                test.refuses(t, y, S)
            })
            .collect()
    }

    #[test]
    fn median_of_three() {
        for (v, m) in [
            ([1.0, 2.0, 3.0], 2.0),
            ([3.0, 1.0, 2.0], 2.0),
            ([2.0, 3.0, 1.0], 2.0),
        ] {
            assert_eq!(median(v[0], v[1], v[2]), m);
            assert_eq!(median(v[2], v[1], v[0]), m);
        }
        assert_eq!(median(1.0, 1.0, 5.0), 1.0);
    }

    #[test]
    fn a_smooth_motion_is_never_refused() {
        assert!(refused(3000, |_| 0.0).is_empty());
    }

    #[test]
    fn a_spike_is_refused_and_the_next_sample_kept() {
        // the bound: 4.89 sigma of two readings' difference, sqrt(23.93 x 2 x
        // 1e-5 / 0.01) = 0.219 rad/s (the motion's own departures are smaller)
        for s in [3.0, -1.5, 0.3] {
            assert_eq!(
                refused(1000, |k| if k == 500 { s } else { 0.0 }),
                vec![500],
                "{s}"
            );
        }
        // below the bound (with the motion's own change over the median's lag
        // of a sample, up to 0.02 rad/s): kept, and the right reading after
        // it too
        assert!(refused(1000, |k| if k == 500 { 0.15 } else { 0.0 }).is_empty());
        // before a second of history: kept
        assert!(refused(1000, |k| if k == 50 { 3.0 } else { 0.0 }).is_empty());
    }

    #[test]
    fn a_lasting_step_costs_two_samples() {
        // a bias step of 2 rad/s from sample 500 on: its first sample is
        // refused, its second accepted (never two in a row), its third
        // departs from a median still at the old level and is refused, and
        // from its fourth the median is at the new level
        assert_eq!(
            refused(1000, |k| if k >= 500 { 2.0 } else { 0.0 }),
            vec![500, 502]
        );
    }

    #[test]
    fn the_departure_is_from_the_median_of_the_last_three_accepted() {
        let mut test = GyroSpikeTest {
            averaged_s: 2.0,
            mean_square: 1e-6,
            ..GyroSpikeTest::default()
        };
        for (k, y) in [0.0, 0.1, 0.0].into_iter().enumerate() {
            assert!(!test.refuses(k as f64 * 0.01, y, S));
        }
        // the median of (0.0, 0.1, 0.0) is 0.0; the bound 0.219
        let mut a = test;
        assert!(!a.refuses(0.03, 0.21, S));
        assert!(test.refuses(0.03, 0.23, S));
        // never two refusals in a row
        assert!(!test.refuses(0.04, 9.0, S));
        // a larger departure scale raises the bound: sqrt(23.93 x 0.25) = 2.45
        let mut b = GyroSpikeTest {
            averaged_s: 2.0,
            mean_square: 0.25,
            ..GyroSpikeTest::default()
        };
        for (k, y) in [0.0, 0.0, 0.0].into_iter().enumerate() {
            assert!(!b.refuses(k as f64 * 0.01, y, S));
        }
        let mut c = b;
        assert!(!c.refuses(0.03, 2.4, S));
        assert!(b.refuses(0.03, 2.5, S));
    }

    #[test]
    fn a_refused_reading_is_replaced_by_the_median_of_the_last_three() {
        let mut test = GyroSpikeTest {
            averaged_s: 2.0,
            mean_square: 1e-6,
            ..GyroSpikeTest::default()
        };
        for (k, y) in [0.30, 0.32, 0.31].into_iter().enumerate() {
            assert_eq!(test.replacement(k as f64 * 0.01, y, S), None);
        }
        assert_eq!(test.replacement(0.03, 3.0, S), Some(0.31));
        assert_eq!(test.replacement(0.04, 0.33, S), None);
        assert_eq!(test.refused(), 1);
    }

    #[test]
    fn a_time_gap_starts_afresh() {
        let mut test = GyroSpikeTest::default();
        for k in 0..200 {
            assert!(!test.refuses(k as f64 * 0.01, 0.0, S));
        }
        // a missing row (two steps): no test, then a second of history again
        assert!(!test.refuses(2.01, 3.0, S));
        assert!(!test.refuses(2.02, 0.0, S));
        assert_eq!(test.refused(), 0);
    }

    proptest::proptest! {
        /// Whatever the readings (finite, in any order of size), no two
        /// readings in a row are refused, and a refused reading is replaced
        /// by one of the last three accepted (the median of them).
        #[test]
        fn never_two_in_a_row_and_replaced_by_an_accepted_reading(
            ys in proptest::collection::vec(-30.0f64..30.0, 1..400),
            spike_every in 3usize..50,
        ) {
            let mut test = GyroSpikeTest::default();
            let mut accepted: Vec<f64> = Vec::new();
            let mut last_refused = false;
            for (k, y) in ys.iter().enumerate() {
                let y = if k % spike_every == 0 { y * 10.0 } else { *y * 0.01 };
                match test.replacement(k as f64 * 0.01, y, S) {
                    Some(r) => {
                        proptest::prop_assert!(!last_refused, "two refusals in a row at {k}");
                        let n = accepted.len();
                        proptest::prop_assert!(accepted[n.saturating_sub(3)..].contains(&r));
                        last_refused = true;
                    }
                    None => {
                        accepted.push(y);
                        last_refused = false;
                    }
                }
            }
        }
    }
}
