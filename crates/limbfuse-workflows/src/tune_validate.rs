//! The loop of `limbfuse tune`: tune a segment filter's noise parameters on
//! a tuning window (paper 001 protocol: multi-start runs, PSO), then measure
//! the start and the tuned parameters on the tuning window and on a
//! validation window the optimiser never saw.

use std::fmt::Write as _;

use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Record, Segment};
use limbfuse_eval::TimeWindow;
use limbfuse_methods::segment_params::FilterParams;

use crate::protocol::{plan_intervals, MultiStartResult, ProtocolError, StartPlan};
use crate::tuning::{measure_params, tune, SearchSpace, TuneConfig, TuneError};

/// Which validation window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Validation {
    /// The block of the tuning window's length right after it, shortened to
    /// the trial's end; none when less than 1 s is left.
    FollowingBlock,
    /// This window.
    Window(TimeWindow),
    /// No validation.
    None,
}

/// What to tune, where, and how hard.
#[derive(Debug, Clone)]
pub struct TuneValidateConfig {
    /// The parameters to start from.
    pub start: FilterParams,
    /// The tuning window, its starting points and run length.
    pub plan: StartPlan,
    /// The validation window (same starts and run length).
    pub validation: Validation,
    /// The optimiser.
    pub tune: TuneConfig,
}

/// Why tune-then-validate failed.
#[derive(Debug, thiserror::Error)]
pub enum TuneValidateError {
    /// The tuning window's starting points.
    #[error("tuning window: {0}")]
    TuningWindow(ProtocolError),
    /// The validation window's starting points.
    #[error("validation window: {0}")]
    ValidationWindow(ProtocolError),
    /// A filter failed while measuring.
    #[error(transparent)]
    Measure(#[from] ProtocolError),
    /// The optimiser.
    #[error(transparent)]
    Tune(#[from] TuneError),
}

/// The tuned parameters and the errors before and after.
#[derive(Debug, Clone)]
pub struct TuneValidateReport {
    /// The tuned parameters.
    pub params: FilterParams,
    /// Objective evaluations spent.
    pub evaluations: usize,
    /// Coordinates searched.
    pub dims: usize,
    /// The tuning intervals.
    pub tuning: Vec<(f64, f64)>,
    /// The validation intervals, if any.
    pub validation: Option<Vec<(f64, f64)>>,
    /// Start and tuned parameters on the tuning window.
    pub tuning_before_after: [MultiStartResult; 2],
    /// Start and tuned parameters on the validation window.
    pub validation_before_after: Option<[MultiStartResult; 2]>,
}

fn measure(
    p: &FilterParams,
    records: &[Record],
    iv: &[(f64, f64)],
) -> Result<MultiStartResult, TuneValidateError> {
    measure_params(p, records, iv)?
        .ok_or_else(|| TuneError::Config("parameters: invalid".into()).into())
}

fn following_block(tuning: &[(f64, f64)], t_last: f64) -> Option<TimeWindow> {
    let start = tuning.iter().map(|i| i.0).fold(f64::INFINITY, f64::min);
    let end = tuning.iter().map(|i| i.1).fold(f64::NEG_INFINITY, f64::max);
    let vend = (end + (end - start)).min(t_last);
    (vend - end >= 1.0).then_some(TimeWindow {
        start: Some(end),
        end: Some(vend),
    })
}

/// Tunes on the tuning window and measures on both windows. `on_eval` is
/// called after every objective evaluation (progress).
pub fn tune_and_validate(
    records: &[Record],
    cfg: &TuneValidateConfig,
    on_eval: &(dyn Fn() + Sync),
) -> Result<TuneValidateReport, TuneValidateError> {
    let tuning = plan_intervals(records, &cfg.plan).map_err(TuneValidateError::TuningWindow)?;
    let t_last = records.last().map_or(0.0, |r| r.sample.t);
    let window = match cfg.validation {
        Validation::None => None,
        Validation::Window(w) => Some(w),
        Validation::FollowingBlock => following_block(&tuning, t_last),
    };
    let validation = match window {
        Some(w) => Some(
            plan_intervals(
                records,
                &StartPlan {
                    window: w,
                    ..cfg.plan
                },
            )
            .map_err(TuneValidateError::ValidationWindow)?,
        ),
        None => None,
    };
    let dims = SearchSpace::around(&cfg.start).knobs.len();
    let result = tune(&cfg.start, records, &tuning, &cfg.tune, on_eval)?;
    let tuning_before_after = [
        measure(&cfg.start, records, &tuning)?,
        measure(&result.params, records, &tuning)?,
    ];
    let validation_before_after = match &validation {
        Some(iv) => Some([
            measure(&cfg.start, records, iv)?,
            measure(&result.params, records, iv)?,
        ]),
        None => None,
    };
    Ok(TuneValidateReport {
        params: result.params,
        evaluations: result.evaluations,
        dims,
        tuning,
        validation,
        tuning_before_after,
        validation_before_after,
    })
}

/// `S:E s, N starting points x L s`.
pub fn span(iv: &[(f64, f64)]) -> String {
    format!(
        "{:.3}:{:.3} s, {} starting points x {:.3} s",
        iv[0].0,
        iv[iv.len() - 1].1,
        iv.len(),
        iv[0].1 - iv[0].0
    )
}

fn deg(m: Option<&MultiStartResult>) -> String {
    m.and_then(MultiStartResult::mean_rmse)
        .map_or("-".to_string(), |v| format!("{:.3}", v.to_degrees()))
}

/// Segment-angle coverage in percent (scored / with a reference).
fn pct(m: Option<&MultiStartResult>) -> String {
    m.and_then(MultiStartResult::segment_coverage)
        .map_or("-".to_string(), |v| format!("{:.1}", 100.0 * v))
}

impl TuneValidateReport {
    /// Provenance lines for the parameter file (`optimiser`, windows and
    /// the errors before and after); the caller adds how it was invoked.
    pub fn provenance(&self) -> Vec<String> {
        let [tb, ta] = &self.tuning_before_after;
        let mut h = vec![
            format!(
                "optimiser: particle swarm (argmin), {} log10 coordinates, {} evaluations",
                self.dims, self.evaluations
            ),
            format!(
                "tuning window {}: mean segment RMSE {} -> {} deg, segment samples scored {} -> {} %",
                span(&self.tuning),
                deg(Some(tb)),
                deg(Some(ta)),
                pct(Some(tb)),
                pct(Some(ta))
            ),
        ];
        if let (Some(iv), Some([vb, va])) = (&self.validation, &self.validation_before_after) {
            h.push(format!(
                "validation window {}: mean segment RMSE {} -> {} deg, segment samples scored {} -> {} %",
                span(iv),
                deg(Some(vb)),
                deg(Some(va)),
                pct(Some(vb)),
                pct(Some(va))
            ));
        }
        h
    }

    /// What a user is told about the validation (an audit found both
    /// missing): a validation window overlapping the tuning window (its
    /// figures are not held out), and tuned parameters that do worse than
    /// the start on it (they fit the tuning window only); `written` says
    /// what the caller does with them anyway (the CLI: "`out.toml` is
    /// written as asked"), `window` names its tuning-window option.
    pub fn validation_warnings(&self, written: &str, window: &str) -> Vec<String> {
        let hull = |iv: &[(f64, f64)]| {
            let lo = iv.iter().map(|i| i.0).fold(f64::INFINITY, f64::min);
            let hi = iv.iter().map(|i| i.1).fold(f64::NEG_INFINITY, f64::max);
            (lo, hi)
        };
        let mut out = Vec::new();
        let Some(valid) = &self.validation else {
            return out;
        };
        let ((t0, t1), (v0, v1)) = (hull(&self.tuning), hull(valid));
        let overlap = t1.min(v1) - t0.max(v0);
        if overlap > 1e-9 {
            out.push(format!(
                "the validation window ({v0}:{v1} s) overlaps the tuning window ({t0}:{t1} s) \
                 by {overlap:.3} s: its figures are not on held-out data"
            ));
        }
        if let Some([before, after]) = &self.validation_before_after {
            if let (Some(b), Some(t)) = (before.mean_rmse(), after.mean_rmse()) {
                if t > b {
                    out.push(format!(
                        "the tuned parameters do worse than the start on the validation window \
                         (mean RMSE {:.3} -> {:.3} deg): they fit the tuning window only; \
                         {written} (a longer {window}, or the start parameters, may serve \
                         better)",
                        b.to_degrees(),
                        t.to_degrees(),
                    ));
                }
            }
        }
        out
    }

    /// The RMSE table (deg, mean over starting points): one row per
    /// segment and the mean, then the share of segment samples with a
    /// reference that were scored (`scored %`, [`crate::coverage`]);
    /// columns start/tuned on each window.
    pub fn table(&self) -> String {
        let v = self.validation_before_after.as_ref();
        let cols = [
            Some(&self.tuning_before_after[0]),
            Some(&self.tuning_before_after[1]),
            v.map(|v| &v[0]),
            v.map(|v| &v[1]),
        ];
        let mut s = format!(
            "{:<10}{:>12}{:>12}{:>14}{:>14}\n",
            "segment", "tune start", "tune tuned", "valid. start", "valid. tuned"
        );
        let cell = |m: Option<&MultiStartResult>, c: Option<AngleChannel>| {
            let v = match c {
                Some(c) => m.and_then(|m| m.rmse(c)),
                None => m.and_then(MultiStartResult::mean_rmse),
            };
            v.map_or("-".to_string(), |v| format!("{:.3}", v.to_degrees()))
        };
        let rows = Segment::ALL
            .map(|seg| (seg.name(), Some(AngleChannel::Segment(seg))))
            .into_iter()
            .chain([("mean", None)]);
        for (name, c) in rows {
            let _ = writeln!(
                s,
                "{name:<10}{:>12}{:>12}{:>14}{:>14}",
                cell(cols[0], c),
                cell(cols[1], c),
                cell(cols[2], c),
                cell(cols[3], c)
            );
        }
        let _ = writeln!(
            s,
            "{:<10}{:>12}{:>12}{:>14}{:>14}",
            "scored %",
            pct(cols[0]),
            pct(cols[1]),
            pct(cols[2]),
            pct(cols[3])
        );
        s
    }
}
