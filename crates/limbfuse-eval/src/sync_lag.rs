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
#[derive(Debug, Clone)]
pub struct LagSearch {
    max_lag: usize,
    /// Last `max_lag + 1` (estimate, reference, counts) triples, newest last.
    history: VecDeque<(Option<f64>, Option<f64>, bool)>,
    /// Index `max_lag + L` holds lag `L`.
    per_lag: Vec<ChannelError>,
}

impl LagSearch {
    /// Lags `-max_lag..=max_lag` samples.
    pub fn new(max_lag: usize) -> Self {
        LagSearch {
            max_lag,
            history: VecDeque::with_capacity(max_lag + 1),
            per_lag: vec![ChannelError::default(); 2 * max_lag + 1],
        }
    }

    /// Adds sample `k`: its estimate, its reference and whether the sample
    /// counts (inside the evaluation window). A pair counts when the
    /// estimate's sample counts.
    pub fn push(&mut self, estimate: Option<f64>, reference: Option<f64>, counts: bool) {
        if self.history.len() == self.max_lag + 1 {
            self.history.pop_front();
        }
        self.history.push_back((estimate, reference, counts));
        let n = self.history.len();
        let (e_k, r_k, c_k) = self.history[n - 1];
        // lag L >= 0: estimate k against reference k - L
        for l in 0..n {
            if let (true, Some(e), Some(r)) = (c_k, e_k, self.history[n - 1 - l].1) {
                self.per_lag[self.max_lag + l].push(e, r);
            }
        }
        // lag -m < 0: estimate k - m against reference k
        for m in 1..n {
            let (e_m, _, c_m) = self.history[n - 1 - m];
            if let (true, Some(e), Some(r)) = (c_m, e_m, r_k) {
                self.per_lag[self.max_lag - m].push(e, r);
            }
        }
    }

    /// Statistics at lag `lag` samples.
    pub fn at(&self, lag: i64) -> Option<&ChannelError> {
        let i = self.max_lag as i64 + lag;
        usize::try_from(i).ok().and_then(|i| self.per_lag.get(i))
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
        let mut best: Option<(i64, ChannelError, f64)> = None;
        for (i, c) in self.per_lag.iter().enumerate() {
            let lag = i as i64 - self.max_lag as i64;
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
}
