//! Synchronisation lag between an estimate and its reference
//! (`limbfuse evaluate --max-lag N`).
//!
//! Wearable IMUs and motion capture run on separate clocks and pipelines: a
//! constant lag of a few samples between the two streams is common (the
//! shared gaittoolbox trial's Xsens streams trail the Vicon by 0.7-2.6
//! samples, docs/IMPORTERS.md). During walking a shank turns at up to
//! 5 rad/s, so a 2-sample lag at 60 Hz alone costs several degrees of RMSE
//! that say nothing about the estimator. [`LagSearch`] measures, per channel,
//! the error statistics of the estimate shifted by every lag `L` in
//! `-N..=N` samples (estimate at sample `k` against reference at `k - L`;
//! positive `L` = the estimate trails the reference), streaming: memory is
//! `O(N)`, not `O(samples)`. The caller reports the lag it picked, so an
//! evaluation after synchronisation is never mistaken for one without.

use std::collections::VecDeque;

use crate::channel_error::ChannelError;

/// Per-lag error statistics of one channel.
///
/// Memory grows with the samples seen, up to `max_lag + 1` per direction: a
/// `max_lag` far beyond the trial costs no more than the trial itself (the
/// caller still bounds it against the trial, see
/// [`crate::evaluation::max_lag_bound`]).
#[derive(Debug, Clone)]
pub struct LagSearch {
    max_lag: usize,
    /// Last `max_lag + 1` (estimate, reference, counts) triples, newest last.
    history: VecDeque<(Option<f64>, Option<f64>, bool)>,
    /// Index `L` holds lag `L >= 0`.
    positive: Vec<ChannelError>,
    /// Index `m - 1` holds lag `-m < 0`.
    negative: Vec<ChannelError>,
}

impl LagSearch {
    /// Lags `-max_lag..=max_lag` samples.
    pub fn new(max_lag: usize) -> Self {
        LagSearch {
            max_lag,
            history: VecDeque::with_capacity(max_lag.saturating_add(1).min(1 << 12)),
            positive: Vec::new(),
            negative: Vec::new(),
        }
    }

    /// Adds sample `k`: its estimate, its reference and whether the sample
    /// counts (inside the evaluation window). A pair counts when the
    /// estimate's sample counts.
    pub fn push(&mut self, estimate: Option<f64>, reference: Option<f64>, counts: bool) {
        if self.history.len() > self.max_lag {
            self.history.pop_front();
        }
        self.history.push_back((estimate, reference, counts));
        let n = self.history.len();
        if self.positive.len() < n {
            self.positive.resize(n, ChannelError::default());
        }
        if self.negative.len() < n - 1 {
            self.negative.resize(n - 1, ChannelError::default());
        }
        let (e_k, r_k, c_k) = self.history[n - 1];
        // lag L >= 0: estimate k against reference k - L
        for l in 0..n {
            if let (true, Some(e), Some(r)) = (c_k, e_k, self.history[n - 1 - l].1) {
                self.positive[l].push(e, r);
            }
        }
        // lag -m < 0: estimate k - m against reference k
        for m in 1..n {
            let (e_m, _, c_m) = self.history[n - 1 - m];
            if let (true, Some(e), Some(r)) = (c_m, e_m, r_k) {
                self.negative[m - 1].push(e, r);
            }
        }
    }

    /// Statistics at lag `lag` samples (`None` outside `-max_lag..=max_lag`
    /// or beyond the samples seen).
    pub fn at(&self, lag: i64) -> Option<&ChannelError> {
        if lag >= 0 {
            usize::try_from(lag).ok().and_then(|l| self.positive.get(l))
        } else {
            usize::try_from(lag.unsigned_abs())
                .ok()
                .and_then(|m| self.negative.get(m - 1))
        }
    }

    /// The lag (samples) with the smallest RMSE (offset-free RMSE if
    /// `offset_free`), and its statistics; ties go to the lag nearest zero.
    /// `None` without pairs.
    pub fn best(&self, offset_free: bool) -> Option<(i64, ChannelError)> {
        let score = |c: &ChannelError| {
            if offset_free {
                c.rmse_offset_free()
            } else {
                c.rmse()
            }
        };
        let lags = self
            .negative
            .iter()
            .enumerate()
            .rev()
            .map(|(i, c)| (-(i as i64) - 1, c))
            .chain(self.positive.iter().enumerate().map(|(i, c)| (i as i64, c)));
        let mut best: Option<(i64, ChannelError, f64)> = None;
        for (lag, c) in lags {
            let Some(s) = score(c) else { continue };
            let better = match &best {
                None => true,
                Some((bl, _, bs)) => s < *bs || (s == *bs && lag.abs() < bl.abs()),
            };
            if better {
                best = Some((lag, *c, s));
            }
        }
        best.map(|(l, c, _)| (l, c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reference sine and an estimate that is the same sine delayed by
    /// `d` samples: the search finds lag `d` with zero error.
    #[test]
    fn finds_the_delay_of_a_delayed_copy() {
        for d in [-3i64, -1, 0, 2, 3] {
            let mut s = LagSearch::new(4);
            let f = |k: i64| (0.1 * k as f64).sin();
            for k in 0..500i64 {
                s.push(Some(f(k - d)), Some(f(k)), true);
            }
            let (lag, c) = s.best(false).unwrap();
            assert_eq!(lag, d);
            assert!(c.rmse().unwrap() < 1e-12);
            // every other lag has a clearly larger error
            for l in -4..=4 {
                if l != d {
                    assert!(s.at(l).unwrap().rmse().unwrap() > 0.05, "lag {l} vs {d}");
                }
            }
        }
    }

    #[test]
    fn lag_zero_equals_the_plain_statistics() {
        let mut s = LagSearch::new(2);
        let mut plain = ChannelError::default();
        for k in 0..100 {
            let (e, r) = ((k as f64 * 0.37).cos(), (k as f64 * 0.31).sin());
            let counts = k % 7 != 0;
            s.push(Some(e), Some(r), counts);
            if counts {
                plain.push(e, r);
            }
        }
        assert_eq!(s.at(0), Some(&plain));
    }

    #[test]
    fn missing_values_and_windows_are_skipped() {
        let mut s = LagSearch::new(1);
        s.push(Some(1.0), None, true);
        s.push(None, Some(1.0), true);
        s.push(Some(2.0), Some(2.0), false);
        // pairs: lag +1 (e2 vs r1) does not count (sample 2 outside window);
        // lag -1: (e0 vs r1) counts.
        assert_eq!(s.at(-1).unwrap().n(), 1);
        assert_eq!(s.at(0).unwrap().n(), 0);
        assert_eq!(s.at(1).unwrap().n(), 0);
        assert!(LagSearch::new(3).best(false).is_none());
    }

    /// A lag far beyond the data allocates for the data only (no abort).
    #[test]
    fn a_huge_max_lag_costs_what_the_data_costs() {
        let mut s = LagSearch::new(usize::MAX);
        for k in 0..50 {
            s.push(Some(k as f64), Some(k as f64), true);
        }
        assert_eq!(s.best(false).unwrap().0, 0);
        assert!(s.at(50).is_none() && s.at(-50).is_none() && s.at(i64::MIN).is_none());
        assert_eq!(s.at(49).unwrap().n(), 1);
    }
}
