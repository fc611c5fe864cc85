//! The [`AngleMetrics`] observer and the [`Evaluation`] it produces.

use std::collections::BTreeMap;

use limbfuse_core::runner::{BoxError, Observer};
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Estimate, Estimator, Record};
use serde_json::{json, Map, Value};

use crate::channel_error::ChannelError;
use crate::evaluation::{EvalOptions, TimeWindow};

/// Accumulates errors of every angle channel (and diagnostic means) over a run.
#[derive(Debug, Clone)]
pub struct AngleMetrics {
    method: String,
    options: EvalOptions,
    channels: [ChannelError; 7],
    n_samples: u64,
    diag_names: Vec<String>,
    diag_sum: Vec<f64>,
    diag_n: Vec<u64>,
}

impl AngleMetrics {
    /// Metrics for `method`, with the given options.
    pub fn new(method: impl Into<String>, options: EvalOptions) -> Self {
        AngleMetrics {
            method: method.into(),
            options,
            channels: [ChannelError::default(); 7],
            n_samples: 0,
            diag_names: Vec::new(),
            diag_sum: Vec::new(),
            diag_n: Vec::new(),
        }
    }

    /// Sets the diagnostic names (as the estimator or estimate file gives them).
    pub fn set_diagnostic_names<S: AsRef<str>>(&mut self, names: impl IntoIterator<Item = S>) {
        self.diag_names = names.into_iter().map(|s| s.as_ref().to_string()).collect();
        self.diag_sum = vec![0.0; self.diag_names.len()];
        self.diag_n = vec![0; self.diag_names.len()];
    }

    /// Adds one (record, estimate) pair, if inside the time window.
    pub fn push(&mut self, record: &Record, estimate: &Estimate) {
        if !self.options.window.contains(record.sample.t) {
            return;
        }
        self.n_samples += 1;
        for (k, c) in AngleChannel::ALL.iter().enumerate() {
            if let (Some(e), Some(r)) = (estimate.angle(*c), record.reference.angle(*c)) {
                self.channels[k].push(e, r);
            }
        }
        for (i, d) in estimate.diag.iter().take(self.diag_names.len()).enumerate() {
            if let Some(v) = d {
                self.diag_sum[i] += v;
                self.diag_n[i] += 1;
            }
        }
    }

    /// The result so far.
    pub fn evaluation(&self) -> Evaluation {
        let mut diag_mean = BTreeMap::new();
        for (i, n) in self.diag_names.iter().enumerate() {
            if self.diag_n[i] > 0 {
                diag_mean.insert(n.clone(), self.diag_sum[i] / self.diag_n[i] as f64);
            }
        }
        Evaluation {
            method: self.method.clone(),
            n_samples: self.n_samples,
            offset_free: self.options.offset_free,
            window: self.options.window,
            channels: AngleChannel::ALL
                .iter()
                .copied()
                .zip(self.channels)
                .collect(),
            diag_mean,
        }
    }
}

impl Observer for AngleMetrics {
    fn start(&mut self, estimator: &dyn Estimator) -> Result<(), BoxError> {
        self.method = estimator.name().to_string();
        self.set_diagnostic_names(estimator.diagnostic_names().iter());
        Ok(())
    }

    fn observe(&mut self, record: &Record, estimate: &Estimate) -> Result<(), BoxError> {
        self.push(record, estimate);
        Ok(())
    }
}

/// Errors of one estimate against its reference.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluation {
    /// Method name.
    pub method: String,
    /// Number of samples inside the window.
    pub n_samples: u64,
    /// Whether RMSE figures have the mean error removed per channel.
    pub offset_free: bool,
    /// Time window evaluated.
    pub window: TimeWindow,
    /// Statistics per channel (channels without estimate or reference have `n = 0`).
    pub channels: Vec<(AngleChannel, ChannelError)>,
    /// Mean of each diagnostic value over the window.
    pub diag_mean: BTreeMap<String, f64>,
}

impl Evaluation {
    /// The channel's RMSE in rad (offset-free when requested).
    pub fn rmse(&self, c: AngleChannel) -> Option<f64> {
        let s = self.channels.iter().find(|(k, _)| *k == c)?.1;
        if self.offset_free {
            s.rmse_offset_free()
        } else {
            s.rmse()
        }
    }

    /// Mean RMSE (rad) of the evaluated segment angles (the papers' figure);
    /// of the joint angles when no segment angle was evaluated.
    pub fn mean_rmse(&self) -> Option<f64> {
        let seg: Vec<f64> = self
            .channels
            .iter()
            .filter(|(c, _)| matches!(c, AngleChannel::Segment(_)))
            .filter_map(|(c, _)| self.rmse(*c))
            .collect();
        let vals = if seg.is_empty() {
            self.channels
                .iter()
                .filter_map(|(c, _)| self.rmse(*c))
                .collect()
        } else {
            seg
        };
        (!vals.is_empty()).then(|| vals.iter().sum::<f64>() / vals.len() as f64)
    }

    /// The JSON object of SPEC section 4 (angles in degrees).
    pub fn to_json(&self) -> Value {
        let mut rmse = Map::new();
        let mut max_abs = Map::new();
        let mut corr = Map::new();
        let mut mean_err = Map::new();
        for (c, s) in &self.channels {
            if s.n() == 0 {
                continue;
            }
            let name = c.name().to_string();
            rmse.insert(name.clone(), json!(self.rmse(*c).map(f64::to_degrees)));
            max_abs.insert(name.clone(), json!(s.max_abs_error().map(f64::to_degrees)));
            corr.insert(name.clone(), json!(s.correlation()));
            mean_err.insert(name, json!(s.mean_error().map(f64::to_degrees)));
        }
        json!({
            "method": self.method,
            "n_samples": self.n_samples,
            "rmse_deg": rmse,
            "mean_rmse_deg": self.mean_rmse().map(f64::to_degrees),
            "max_abs_err_deg": max_abs,
            "corr": corr,
            "mean_err_deg": mean_err,
            "offset_free": self.offset_free,
            "window_s": [self.window.start, self.window.end.filter(|e| e.is_finite())],
            "diag_mean": self.diag_mean,
        })
    }

    /// A human-readable table (degrees).
    pub fn to_text(&self) -> String {
        let mut s = format!("method: {}   samples: {}", self.method, self.n_samples);
        if self.window.start.is_some() || self.window.end.is_some() {
            s += &format!("   window: {}", self.window);
        }
        s += "\n";
        if self.offset_free {
            s += "offset-free: the mean error of each channel is removed before the RMSE (mean error shown)\n";
        }
        s += &format!(
            "{:<8}{:>10}{:>12}{:>12}{:>9}{:>9}\n",
            "channel", "RMSE deg", "max|e| deg", "mean e deg", "corr", "n"
        );
        for (c, st) in &self.channels {
            if st.n() == 0 {
                continue;
            }
            let f =
                |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{:.3}", v.to_degrees()));
            s += &format!(
                "{:<8}{:>10}{:>12}{:>12}{:>9}{:>9}\n",
                c.name(),
                f(self.rmse(*c)),
                f(st.max_abs_error()),
                f(st.mean_error()),
                st.correlation()
                    .map_or("-".to_string(), |r| format!("{r:.4}")),
                st.n()
            );
        }
        if let Some(m) = self.mean_rmse() {
            s += &format!("mean RMSE: {:.3} deg\n", m.to_degrees());
        }
        for (k, v) in &self.diag_mean {
            s += &format!("diag mean {k}: {v:.4}\n");
        }
        s
    }
}
