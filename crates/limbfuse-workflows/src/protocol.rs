//! The validation protocol of paper 001: errors averaged over many starting
//! points.
//!
//! 001 (Experimental setup): "As the KFs convergence has been demonstrated
//! to be sensitive to the starting point, fifty different starting points
//! were used both in the optimization and validation stage [...] The first
//! and last intervals of the validation stage are indicated by horizontal
//! lines in Fig. 2." limbfuse reads this as: inside a window `[a, b]` (e.g.
//! the 20 s validation block), `N` intervals of equal length `L` are placed
//! with evenly spread start instants `s_k = a + k (b - a - L) / (N - 1)`, so
//! the first interval starts at `a` and the last one ends at `b`. For each
//! interval a *fresh* filter is started at `s_k` (it sees no earlier sample)
//! and run to `s_k + L`; the RMSE of each channel is computed over that
//! interval. The figure of a channel is the mean of its `N` RMSEs; the mean
//! RMSE is the mean of the four segment figures (001 eq 31 and Table 1).
//!
//! Default `L`: the whole window for `N = 1`, half the window otherwise (10
//! s of a 20 s block), so consecutive intervals overlap and every interval
//! is long enough for the filter to converge. Runs are parallel (rayon) and
//! reduced in start order: results do not depend on the number of threads.

use std::convert::Infallible;

use limbfuse_core::runner::{run, Observer};
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Estimator, Record};
use rayon::prelude::*;
use serde_json::{json, Map, Value};

use limbfuse_eval::{AngleMetrics, Evaluation};
use limbfuse_eval::{EvalOptions, TimeWindow};

/// Largest number of starting points.
pub const MAX_STARTS: usize = 10_000;

/// Where the starting points go.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StartPlan {
    /// The block evaluated (open ends: the trial's first / last sample).
    pub window: TimeWindow,
    /// Number of starting points `N`, 1..=10000 (paper: 50).
    pub starts: usize,
    /// Length `L` (s) of each interval; `None`: the window for `N = 1`, half
    /// the window otherwise.
    pub length_s: Option<f64>,
}

/// Why the protocol could not run.
#[derive(Debug, thiserror::Error)]
pub enum ProtocolError {
    /// A bad option or a window the trial does not cover.
    #[error("{0}")]
    Config(String),
    /// The filter could not be built or failed on a sample.
    #[error("{0}")]
    Filter(String),
}

/// `v` as messages show it (`1e300`, not 301 digits).
fn shown(v: f64) -> limbfuse_core::ShownNumber {
    limbfuse_core::ShownNumber(v)
}

/// The intervals `[s_k, s_k + L]` of `plan` over `records` (sorted by time).
pub fn plan_intervals(
    records: &[Record],
    plan: &StartPlan,
) -> Result<Vec<(f64, f64)>, ProtocolError> {
    let (Some(first), Some(last)) = (records.first(), records.last()) else {
        return Err(ProtocolError::Config("the trial has no samples".into()));
    };
    let (t0, t1) = (first.sample.t, last.sample.t);
    // A window may overhang the samples by up to 1.5 sample periods (a 20 s
    // trial at 50 Hz ends at 19.98 s and `0:20` is meant); it is clipped.
    let period = if records.len() > 1 {
        (t1 - t0) / (records.len() - 1) as f64
    } else {
        0.0
    };
    let tol = 1e-9 * t1.abs().max(1.0) + 1.5 * period;
    let a = plan.window.start.unwrap_or(t0);
    let b = plan.window.end.unwrap_or(t1);
    let bad = a < t0 - tol || b > t1 + tol || b <= a;
    let (a, b) = (a.max(t0), b.min(t1));
    if bad || b <= a {
        return Err(ProtocolError::Config(format!(
            "window {} s to {} s: the trial covers {} s to {} s, the window must lie inside it and have an end after its start",
            shown(plan.window.start.unwrap_or(t0)),
            shown(plan.window.end.unwrap_or(t1)),
            shown(t0),
            shown(t1),
        )));
    }
    if plan.starts == 0 || plan.starts > MAX_STARTS {
        return Err(ProtocolError::Config(format!(
            "starts: expected 1 to {MAX_STARTS} starting points, found {}",
            plan.starts
        )));
    }
    let span = b - a;
    let len = plan
        .length_s
        .unwrap_or(if plan.starts == 1 { span } else { 0.5 * span });
    if !(len.is_finite() && len > 0.0 && len <= span + 2.0 * tol) {
        return Err(ProtocolError::Config(format!(
            "length: each interval must last more than 0 s and at most the window's {} s, found {} s",
            shown(span),
            shown(len)
        )));
    }
    if len < period {
        return Err(ProtocolError::Config(format!(
            "length: each interval of {} s is shorter than one sample period ({} s): \
             it must hold at least two samples",
            shown(len),
            shown(period)
        )));
    }
    let len = len.min(span);
    let n = plan.starts;
    Ok((0..n)
        .map(|k| {
            let s = if n == 1 {
                a
            } else {
                a + k as f64 * (span - len) / (n - 1) as f64
            };
            (s, (s + len).min(b))
        })
        .collect())
}

/// The records of `[start, end]` (a sub-slice; `records` sorted by time).
pub fn slice_interval(records: &[Record], start: f64, end: f64) -> &[Record] {
    let tol = 1e-9 * end.abs().max(1.0);
    let lo = records.partition_point(|r| r.sample.t < start - tol);
    let hi = records.partition_point(|r| r.sample.t <= end + tol);
    &records[lo..hi.max(lo)]
}

/// Errors of one filter from every starting point.
#[derive(Debug, Clone, PartialEq)]
pub struct MultiStartResult {
    /// Method name.
    pub method: String,
    /// The intervals `[s_k, s_k + L]` (s).
    pub intervals: Vec<(f64, f64)>,
    /// One evaluation per interval, in start order.
    pub runs: Vec<Evaluation>,
    /// Per interval, the samples inside it that have a reference, per
    /// channel in [`AngleChannel::ALL`] order: what a run could have
    /// scored ([`crate::coverage`]).
    pub reference_samples: Vec<[u64; 7]>,
}

fn mean(v: impl Iterator<Item = f64>) -> Option<f64> {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    (n > 0).then(|| s / n as f64)
}

impl MultiStartResult {
    /// Mean over the starting points of the channel's RMSE (rad); starts
    /// where the channel was not evaluated are left out.
    pub fn rmse(&self, c: AngleChannel) -> Option<f64> {
        mean(self.runs.iter().filter_map(|e| e.rmse(c)))
    }

    /// Mean of the four segment figures [`Self::rmse`] (rad), the papers'
    /// figure; of the joint figures when no segment was evaluated.
    pub fn mean_rmse(&self) -> Option<f64> {
        let seg = mean(
            AngleChannel::ALL
                .iter()
                .filter(|c| matches!(c, AngleChannel::Segment(_)))
                .filter_map(|c| self.rmse(*c)),
        );
        seg.or_else(|| mean(AngleChannel::ALL.iter().filter_map(|c| self.rmse(*c))))
    }

    /// Sample standard deviation over the starting points of each run's mean
    /// RMSE (rad): how much the result depends on where the filter starts.
    pub fn mean_rmse_spread(&self) -> Option<f64> {
        let v: Vec<f64> = self.runs.iter().filter_map(Evaluation::mean_rmse).collect();
        let m = mean(v.iter().copied())?;
        (v.len() > 1)
            .then(|| (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt())
    }

    /// Largest absolute error of a channel over all runs (rad).
    pub fn max_abs_error(&self, c: AngleChannel) -> Option<f64> {
        self.runs
            .iter()
            .filter_map(|e| e.channels.iter().find(|(k, _)| *k == c)?.1.max_abs_error())
            .reduce(f64::max)
    }

    /// Mean over runs of a channel's correlation.
    pub fn correlation(&self, c: AngleChannel) -> Option<f64> {
        mean(
            self.runs
                .iter()
                .filter_map(|e| e.channels.iter().find(|(k, _)| *k == c)?.1.correlation()),
        )
    }

    /// Total number of samples evaluated over all runs.
    pub fn n_samples(&self) -> u64 {
        self.runs.iter().map(|e| e.n_samples).sum()
    }

    /// The SPEC section 4 JSON object of `evaluate`, with the protocol's
    /// fields: `starts`, `interval_s` (length), `start_times_s`,
    /// `mean_rmse_spread_deg` (std over starts), `window_s`,
    /// `segment_coverage` (segment samples scored / with a reference,
    /// [`crate::coverage`]).
    pub fn to_json(&self) -> Value {
        let deg = |v: Option<f64>| json!(v.map(f64::to_degrees));
        let (mut rmse, mut max_abs, mut corr) = (Map::new(), Map::new(), Map::new());
        for c in AngleChannel::ALL {
            if self.rmse(c).is_none() {
                continue;
            }
            rmse.insert(c.name().into(), deg(self.rmse(c)));
            max_abs.insert(c.name().into(), deg(self.max_abs_error(c)));
            corr.insert(c.name().into(), json!(self.correlation(c)));
        }
        let ar = mean(self.runs.iter().filter_map(|e| e.accel_reliability_pct));
        let agr = mean(
            self.runs
                .iter()
                .filter_map(|e| e.accel_global_reliability_pct),
        );
        json!({
            "method": self.method,
            "n_samples": self.n_samples(),
            "rmse_deg": rmse,
            "mean_rmse_deg": deg(self.mean_rmse()),
            "max_abs_err_deg": max_abs,
            "corr": corr,
            "starts": self.intervals.len(),
            "interval_s": self.intervals.first().map(|(a, b)| b - a),
            "start_times_s": self.intervals.iter().map(|(a, _)| *a).collect::<Vec<_>>(),
            "window_s": [self.intervals.first().map(|i| i.0), self.intervals.last().map(|i| i.1)],
            "mean_rmse_spread_deg": deg(self.mean_rmse_spread()),
            "segment_coverage": self.segment_coverage(),
            "offset_free": self.runs.first().is_some_and(|e| e.offset_free),
            "accel_reliability_pct": ar,
            "accel_global_reliability_pct": agr,
        })
    }

    /// A human-readable table (degrees).
    pub fn to_text(&self) -> String {
        let n = self.intervals.len();
        let (first, last) = (self.intervals[0], self.intervals[n - 1]);
        let mut s = format!(
            "method: {}   starting points: {n}   interval: {:.3} s   first [{:.3}, {:.3}] s   last [{:.3}, {:.3}] s\n",
            self.method,
            first.1 - first.0,
            first.0,
            first.1,
            last.0,
            last.1
        );
        s += "RMSE = mean over the starting points of each run's RMSE\n";
        s += &format!(
            "{:<8}{:>10}{:>12}{:>9}\n",
            "channel", "RMSE deg", "max|e| deg", "corr"
        );
        let f = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{:.3}", v.to_degrees()));
        for c in AngleChannel::ALL {
            if self.rmse(c).is_none() {
                continue;
            }
            s += &format!(
                "{:<8}{:>10}{:>12}{:>9}\n",
                c.name(),
                f(self.rmse(c)),
                f(self.max_abs_error(c)),
                self.correlation(c)
                    .map_or("-".to_string(), |r| format!("{r:.4}")),
            );
        }
        if let Some(m) = self.mean_rmse() {
            s += &format!("mean RMSE: {:.3} deg", m.to_degrees());
            if let Some(sd) = self.mean_rmse_spread() {
                s += &format!(" (std over starting points {:.3} deg)", sd.to_degrees());
            }
            s += "\n";
        }
        if let Some(c) = self.segment_coverage() {
            s += &format!(
                "segment samples scored: {:.1} % of those with a reference\n",
                100.0 * c
            );
        }
        s
    }
}

/// A factory of fresh filters, called once per starting point on the
/// thread that runs that start (so the filter itself need not be `Send`).
pub type FilterFactory<'a> = dyn Fn() -> Result<Box<dyn Estimator>, String> + Sync + 'a;

/// Runs a fresh filter from `make` over each interval of `records` and
/// evaluates it there (see the module docs).
pub fn multi_start(
    make: &FilterFactory<'_>,
    records: &[Record],
    intervals: &[(f64, f64)],
    offset_free: bool,
) -> Result<MultiStartResult, ProtocolError> {
    if intervals.is_empty() {
        return Err(ProtocolError::Config("no starting point".into()));
    }
    let runs: Vec<(Evaluation, [u64; 7])> = intervals
        .par_iter()
        .map(|&(s, e)| {
            let recs = slice_interval(records, s, e);
            let window = TimeWindow {
                start: Some(s),
                end: Some(e),
            };
            let mut refs = [0u64; 7];
            for r in recs.iter().filter(|r| window.contains(r.sample.t)) {
                for (n, c) in refs.iter_mut().zip(AngleChannel::ALL) {
                    *n += u64::from(r.reference.angle(c).is_some());
                }
            }
            let mut est = make().map_err(ProtocolError::Filter)?;
            let mut m = AngleMetrics::new(
                est.name(),
                EvalOptions {
                    window,
                    offset_free,
                    ..EvalOptions::default()
                },
            );
            let observers: &mut [&mut dyn Observer] = &mut [&mut m];
            run(
                est.as_mut(),
                recs.iter().map(|r| Ok::<_, Infallible>(*r)),
                observers,
            )
            .map_err(|err| ProtocolError::Filter(format!("start at {s} s: {err}")))?;
            Ok((m.evaluation(), refs))
        })
        .collect::<Result<_, ProtocolError>>()?;
    let (runs, reference_samples): (Vec<Evaluation>, Vec<[u64; 7]>) = runs.into_iter().unzip();
    let method = runs.first().map(|e| e.method.clone()).unwrap_or_default();
    Ok(MultiStartResult {
        method,
        intervals: intervals.to_vec(),
        runs,
        reference_samples,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn recs(n: usize, dt: f64) -> Vec<Record> {
        (0..n)
            .map(|k| {
                let mut r = Record::default();
                r.sample.t = k as f64 * dt;
                r
            })
            .collect()
    }

    #[test]
    fn intervals_spread_evenly_and_end_at_the_window_end() {
        let r = recs(2001, 0.02); // 0..40 s
        let plan = StartPlan {
            window: TimeWindow::parse("20:40").unwrap(),
            starts: 50,
            length_s: None,
        };
        let iv = plan_intervals(&r, &plan).unwrap();
        assert_eq!(iv.len(), 50);
        assert_eq!(iv[0], (20.0, 30.0));
        assert!((iv[49].0 - 30.0).abs() < 1e-12 && (iv[49].1 - 40.0).abs() < 1e-12);
        assert!((iv[1].0 - iv[0].0 - 10.0 / 49.0).abs() < 1e-12);
        let one = StartPlan { starts: 1, ..plan };
        assert_eq!(plan_intervals(&r, &one).unwrap(), vec![(20.0, 40.0)]);
        let clipped = StartPlan {
            window: TimeWindow::parse("20:40.02").unwrap(),
            starts: 1,
            ..plan
        };
        assert_eq!(plan_intervals(&r, &clipped).unwrap(), vec![(20.0, 40.0)]);
        let bad = StartPlan {
            window: TimeWindow::parse("20:40.1").unwrap(),
            ..plan
        };
        assert!(plan_intervals(&r, &bad)
            .unwrap_err()
            .to_string()
            .contains("covers"));
        assert!(plan_intervals(&r, &StartPlan { starts: 0, ..plan }).is_err());
        assert!(plan_intervals(
            &r,
            &StartPlan {
                length_s: Some(30.0),
                ..plan
            }
        )
        .is_err());
        assert_eq!(slice_interval(&r, 20.0, 30.0).len(), 501);
    }
}
