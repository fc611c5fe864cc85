//! Which samples a multi-start run scored (issue 14).
//!
//! The protocol's figure ([`MultiStartResult::mean_rmse`]) is a mean over
//! the samples a filter estimated: a run, or a segment within a run, with
//! no estimate adds nothing to it. A filter with a run-in (`startup_s`)
//! estimates nothing for `startup_s` after every (re)start, so one that
//! keeps restarting estimates almost nothing, and the few samples it does
//! estimate can give a lower mean than a filter that estimates all of
//! them. Measured: PSO-tuned `mjls` with `startup_s = 2` on calibrated
//! sensors (seed 2, 0.4 m/s) drove `encoder_sigma` to its lower bound, the
//! encoder rows were refused and the filter restarted 609 times in 50 runs,
//! and scored 40 of 20002 samples: 0.23 deg against the start's 0.81 deg
//! on all samples; on the validation window it scored none
//! (docs/RESULTS.md, "Start-up of the 10 s runs").
//!
//! Hence two things here: the **coverage** of a result (samples scored /
//! samples with a reference, per channel), which every protocol figure
//! should be read with; and the **floor** ([`ScoredFloor`]) that makes
//! figures comparable: a candidate is measured on the samples the starting
//! parameters scored, so a candidate that scores fewer samples of some
//! channel in some run than the start did has failed there (it is not
//! compared on a smaller set).

use limbfuse_core::sample::AngleChannel;

use crate::protocol::MultiStartResult;

/// Samples scored per run and channel ([`AngleChannel::ALL`] order).
fn scored(r: &MultiStartResult) -> Vec<[u64; 7]> {
    r.runs
        .iter()
        .map(|e| {
            let mut n = [0u64; 7];
            for (k, c) in AngleChannel::ALL.iter().enumerate() {
                n[k] = e
                    .channels
                    .iter()
                    .find(|(x, _)| x == c)
                    .map_or(0, |(_, s)| s.n());
            }
            n
        })
        .collect()
}

fn index(c: AngleChannel) -> usize {
    AngleChannel::ALL
        .iter()
        .position(|x| *x == c)
        .unwrap_or_default()
}

/// The samples each run must score: per run and channel, as many as the
/// starting parameters scored there.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ScoredFloor(Vec<[u64; 7]>);

impl ScoredFloor {
    /// No floor (every result meets it).
    pub fn none() -> Self {
        ScoredFloor(Vec::new())
    }

    /// What `start` scored, per run and channel.
    pub fn of(start: &MultiStartResult) -> Self {
        ScoredFloor(scored(start))
    }

    /// The first (run index, channel) where `r` scored fewer samples than
    /// the floor; `None` when `r` meets it everywhere.
    pub fn first_shortfall(&self, r: &MultiStartResult) -> Option<(usize, AngleChannel)> {
        let got = scored(r);
        self.0.iter().enumerate().find_map(|(run, floor)| {
            let have = got.get(run).copied().unwrap_or_default();
            AngleChannel::ALL
                .iter()
                .enumerate()
                .find(|(k, _)| have[*k] < floor[*k])
                .map(|(_, c)| (run, *c))
        })
    }
}

impl MultiStartResult {
    /// Samples of channel `c` scored over all runs / samples with a
    /// reference; `None` when no sample has a reference.
    pub fn coverage(&self, c: AngleChannel) -> Option<f64> {
        let k = index(c);
        let refs: u64 = self.reference_samples.iter().map(|r| r[k]).sum();
        let got: u64 = scored(self).iter().map(|n| n[k]).sum();
        (refs > 0).then(|| got as f64 / refs as f64)
    }

    /// Coverage of the four segment angles together (the channels of the
    /// papers' figure): scored / with a reference.
    pub fn segment_coverage(&self) -> Option<f64> {
        let seg = |k: &usize| matches!(AngleChannel::ALL[*k], AngleChannel::Segment(_));
        let refs: u64 = self
            .reference_samples
            .iter()
            .flat_map(|r| (0..7).filter(seg).map(move |k| r[k]))
            .sum();
        let got: u64 = scored(self)
            .iter()
            .flat_map(|n| (0..7).filter(seg).map(move |k| n[k]))
            .sum();
        (refs > 0).then(|| got as f64 / refs as f64)
    }

    /// Runs in which channel `c` has a reference but not one scored sample.
    pub fn unscored_runs(&self, c: AngleChannel) -> usize {
        let k = index(c);
        scored(self)
            .iter()
            .zip(&self.reference_samples)
            .filter(|(n, r)| r[k] > 0 && n[k] == 0)
            .count()
    }
}
