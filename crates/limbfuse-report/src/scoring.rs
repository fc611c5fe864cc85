//! `evaluate`'s scoring options on the report (`--window`, `--offset-free`,
//! `--max-lag`): the same meaning (they are handed to
//! `limbfuse_eval::evaluate_files`), applied to the error tables and to the
//! error over the gait cycle, and stated on the page and in its command.

use limbfuse_core::sample::AngleChannel;
use limbfuse_eval::{Evaluation, TimeWindow};

use crate::data::Column;

/// The scoring options of a report (all off by default: every sample, no
/// offset removal, no lag, as `evaluate` without flags).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Scoring {
    /// Only samples whose trial time `t` lies inside (`evaluate --window`,
    /// parsed by `limbfuse_eval::TimeWindow::parse`).
    pub window: TimeWindow,
    /// Each channel's mean error removed before the RMSE (`--offset-free`).
    pub offset_free: bool,
    /// Synchronise each channel within +-N samples (`--max-lag`); 0 = off.
    pub max_lag: usize,
}

/// One scoring option, named as the CLI or Python names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScoringOption {
    /// `--window` / `window=`.
    Window,
    /// `--offset-free` / `offset_free=`.
    OffsetFree,
    /// `--max-lag` / `max_lag=`.
    MaxLag,
}

impl ScoringOption {
    /// The CLI flag.
    pub fn flag(self) -> &'static str {
        match self {
            ScoringOption::Window => "--window",
            ScoringOption::OffsetFree => "--offset-free",
            ScoringOption::MaxLag => "--max-lag",
        }
    }

    /// The keyword of Python's `limbfuse.report`.
    pub fn keyword(self) -> &'static str {
        match self {
            ScoringOption::Window => "window",
            ScoringOption::OffsetFree => "offset_free",
            ScoringOption::MaxLag => "max_lag",
        }
    }
}

impl Scoring {
    /// Whether the window is bounded on either side.
    pub fn has_window(&self) -> bool {
        self.window.start.is_some() || self.window.end.is_some()
    }

    /// The options given, in flag order.
    pub fn given(&self) -> Vec<ScoringOption> {
        let mut v = Vec::new();
        if self.has_window() {
            v.push(ScoringOption::Window);
        }
        if self.offset_free {
            v.push(ScoringOption::OffsetFree);
        }
        if self.max_lag > 0 {
            v.push(ScoringOption::MaxLag);
        }
        v
    }

    /// The flags as the recorded command writes them (empty when none).
    pub fn flags(&self) -> String {
        let mut s = String::new();
        if self.has_window() {
            let end = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v}"));
            // (`=` before a negative start, which would read as a flag)
            let negative = self.window.start.is_some_and(|v| v < 0.0);
            s += &format!(
                " --window{}{}:{}",
                if negative { "=" } else { " " },
                end(self.window.start),
                end(self.window.end)
            );
        }
        if self.offset_free {
            s += " --offset-free";
        }
        if self.max_lag > 0 {
            s += &format!(" --max-lag {}", self.max_lag);
        }
        s
    }

    /// What the angle tables score, in words (the page's note).
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        parts.push(if self.has_window() {
            format!(
                "the samples with the trial's <code>t</code> in {} (<code>--window</code>)",
                self.window
            )
        } else {
            "every sample, no window".to_string()
        });
        parts.push(if self.offset_free {
            "each channel's mean error removed before the RMSE (<code>--offset-free</code>; max|e| and mean e as measured)".to_string()
        } else {
            "no offset removal".to_string()
        });
        parts.push(if self.max_lag > 0 {
            format!(
                "each channel's estimate shifted by the lag within +-{} samples that minimises its RMSE (<code>--max-lag</code>)",
                self.max_lag
            )
        } else {
            "no lag".to_string()
        });
        parts.join("; ")
    }
}

/// The error (deg) of one channel of one estimate as its evaluation
/// scored it, indexed by the reference's sample: estimate minus reference,
/// with the estimate shifted by the channel's lag when `--max-lag` found
/// one (`+L`: the estimate trails, its sample `i + L` is compared with the
/// reference's `i`, as `limbfuse_eval::sync_lag`) and the channel's mean
/// error (over the window, at that lag) removed with `--offset-free`.
/// Without an evaluation (no reference), the plain difference.
pub fn error_column(
    estimate: &Column,
    reference: &Column,
    channel: AngleChannel,
    ev: Option<&Evaluation>,
) -> Column {
    let lag = ev
        .and_then(|ev| ev.sync_lag.as_ref()?.get(channel.name()).copied())
        .unwrap_or(0);
    let offset = ev
        .filter(|ev| ev.offset_free)
        .and_then(|ev| {
            ev.channels
                .iter()
                .find(|(c, _)| *c == channel)?
                .1
                .mean_error()
        })
        .unwrap_or(0.0);
    (0..reference.len())
        .map(|i| {
            let j = usize::try_from(i as i64 + lag).ok()?;
            let e = estimate.get(j).copied().flatten()?;
            let r = reference[i]?;
            Some((e - r - offset).to_degrees())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_core::Segment;
    use limbfuse_eval::{AngleMetrics, EvalOptions};

    /// A lagged estimate with an offset: with `--max-lag` and
    /// `--offset-free` its scored error is zero everywhere the shift
    /// reaches, as the evaluation's RMSE says.
    #[test]
    fn the_error_column_is_the_error_the_evaluation_scored() {
        let thigh = AngleChannel::Segment(Segment::Thigh);
        let reference: Column = (0..50)
            .map(|k| Some(0.1 * (k as f64 * 0.3).sin()))
            .collect();
        // the estimate trails by 2 samples and sits 0.05 rad high
        let estimate: Column = (0..50)
            .map(|k| Some(0.1 * ((k as f64 - 2.0) * 0.3).sin() + 0.05))
            .collect();
        let options = EvalOptions {
            offset_free: true,
            max_lag: 4,
            ..EvalOptions::default()
        };
        let mut m = AngleMetrics::new("local", options);
        for k in 0..50 {
            let mut r = limbfuse_core::Record::default();
            r.reference.segment[1] = reference[k];
            let mut e = limbfuse_core::Estimate::empty(0.0);
            e.segment[1] = estimate[k];
            m.push(&r, &e);
        }
        let ev = m.evaluation();
        assert_eq!(ev.sync_lag.as_ref().unwrap()["thigh"], 2);
        let err = error_column(&estimate, &reference, thigh, Some(&ev));
        assert_eq!(err[48], None, "beyond the estimate's end");
        for v in err.iter().take(48).flatten() {
            assert!(v.abs() < 1e-9, "{v}");
        }
        let plain = error_column(&estimate, &reference, thigh, None);
        assert!(plain[10].unwrap() > 1.0);
    }

    #[test]
    fn the_flags_are_written_as_evaluate_takes_them() {
        let s = Scoring {
            window: TimeWindow::parse("10:").unwrap(),
            offset_free: true,
            max_lag: 5,
        };
        assert_eq!(s.flags(), " --window 10: --offset-free --max-lag 5");
        assert_eq!(Scoring::default().flags(), "");
        assert!(Scoring::default().given().is_empty());
    }
}
