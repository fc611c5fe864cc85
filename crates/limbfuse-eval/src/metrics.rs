//! The [`AngleMetrics`] observer and the [`Evaluation`] it produces.

use limbfuse_methods::MethodName;
use std::collections::BTreeMap;

use limbfuse_core::runner::{BoxError, Observer};
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Estimate, Estimator, Record};

use crate::channel_error::ChannelError;
use crate::evaluation::{EvalOptions, TimeWindow};
use crate::resets::{ResetWatch, Resets};
use crate::sync_lag::LagSearch;

/// Accumulates errors of every angle channel (and diagnostic means) over a run.
#[derive(Debug, Clone)]
pub struct AngleMetrics {
    method: String,
    options: EvalOptions,
    channels: [ChannelError; 7],
    /// Per channel, when `options.max_lag > 0`.
    lags: Vec<LagSearch>,
    n_samples: u64,
    diag_names: Vec<String>,
    diag_sum: Vec<f64>,
    diag_n: Vec<u64>,
    reliability: ReliabilityCounter,
    resets: ResetWatch,
    reference_units: crate::ReferenceUnitsWatch,
    /// Per channel, the rows inside the window with a reference.
    reference_rows: [u64; 7],
    /// Which angle channels the estimate carries (`None`: those with any
    /// estimate).
    carried: Option<[bool; 7]>,
}

/// Counts the samples in which accelerometer rows update the estimate
/// (001 Table 2): AR = any `upd_<segment>` diagnostic set; AGR (matricial
/// global only) = any coupled row `upd_hip|knee|ankle` set.
#[derive(Debug, Clone, Default)]
struct ReliabilityCounter {
    segment_cols: Vec<usize>,
    coupled_cols: Vec<usize>,
    /// The `missing_inputs` diagnostic (segment filters), if present.
    missing_col: Vec<usize>,
    n: u64,
    ar: u64,
    agr: u64,
    /// Samples in which at least one input was missing.
    missing: u64,
}

impl ReliabilityCounter {
    fn new(method: &str, names: &[String]) -> Self {
        let find = |ns: &[&str]| -> Vec<usize> {
            ns.iter()
                .filter_map(|n| names.iter().position(|m| m == &format!("upd_{n}")))
                .collect()
        };
        ReliabilityCounter {
            segment_cols: find(&["trunk", "thigh", "shank", "foot"]),
            coupled_cols: if MethodName::parse(method).is_ok_and(MethodName::has_relative_rows) {
                find(&["hip", "knee", "ankle"])
            } else {
                Vec::new()
            },
            missing_col: names
                .iter()
                .position(|m| m == "missing_inputs")
                .into_iter()
                .collect(),
            ..Default::default()
        }
    }

    fn push(&mut self, diag: &[Option<f64>]) {
        let set = |cols: &[usize]| {
            cols.iter()
                .any(|&c| diag.get(c).copied().flatten().is_some_and(|v| v > 0.5))
        };
        self.n += 1;
        self.ar += u64::from(set(&self.segment_cols));
        self.agr += u64::from(set(&self.coupled_cols));
        self.missing += u64::from(set(&self.missing_col));
    }

    fn pct(&self, count: u64, cols: &[usize]) -> Option<f64> {
        (!cols.is_empty() && self.n > 0).then(|| 100.0 * count as f64 / self.n as f64)
    }
}

impl AngleMetrics {
    /// Metrics for `method`, with the given options.
    pub fn new(method: impl Into<String>, options: EvalOptions) -> Self {
        AngleMetrics {
            method: method.into(),
            options,
            channels: [ChannelError::default(); 7],
            lags: if options.max_lag > 0 {
                vec![LagSearch::new(options.max_lag); 7]
            } else {
                Vec::new()
            },
            n_samples: 0,
            diag_names: Vec::new(),
            diag_sum: Vec::new(),
            diag_n: Vec::new(),
            reliability: ReliabilityCounter::default(),
            resets: ResetWatch::default(),
            reference_units: Default::default(),
            reference_rows: [0; 7],
            carried: None,
        }
    }

    /// Which angle channels (in [`AngleChannel::ALL`] order) the estimate
    /// carries: its angle columns, or what its estimator outputs
    /// ([`Observer::start`] sets it from [`Estimator::outputs`]). A carried
    /// channel with a reference on rows where it has no estimate is
    /// reported ([`Evaluation::coverage`]); without this call, the channels
    /// with any estimate count as carried.
    pub fn set_carried_channels(&mut self, carried: [bool; 7]) {
        self.carried = Some(carried);
    }

    /// Sets the diagnostic names (as the estimator or estimate file gives them).
    pub fn set_diagnostic_names<S: AsRef<str>>(&mut self, names: impl IntoIterator<Item = S>) {
        self.diag_names = names.into_iter().map(|s| s.as_ref().to_string()).collect();
        self.diag_sum = vec![0.0; self.diag_names.len()];
        self.diag_n = vec![0; self.diag_names.len()];
        self.reliability = ReliabilityCounter::new(&self.method, &self.diag_names);
        self.resets = ResetWatch::new(&self.diag_names);
    }

    /// Adds one (record, estimate) pair, if inside the time window
    /// (restarts count over the whole run, window or not).
    pub fn push(&mut self, record: &Record, estimate: &Estimate) {
        self.resets.push(estimate);
        self.reference_units.push(&record.reference);
        let inside = self.options.window.contains(record.sample.t);
        for (lag, c) in self.lags.iter_mut().zip(AngleChannel::ALL) {
            lag.push(estimate.angle(c), record.reference.angle(c), inside);
        }
        if !inside {
            return;
        }
        self.n_samples += 1;
        for (k, c) in AngleChannel::ALL.iter().enumerate() {
            if let Some(r) = record.reference.angle(*c) {
                self.reference_rows[k] += 1;
                if let Some(e) = estimate.angle(*c) {
                    self.channels[k].push(e, r);
                }
            }
        }
        self.reliability
            .push(&estimate.diag[..self.diag_names.len().min(estimate.diag.len())]);
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
        let coverage = AngleChannel::ALL
            .iter()
            .enumerate()
            .filter(|(k, _)| {
                let carried = self.carried.map_or(self.channels[*k].n() > 0, |c| c[*k]);
                carried && self.reference_rows[*k] > 0
            })
            .map(|(k, c)| ChannelCoverage {
                channel: *c,
                scored: self.channels[k].n(),
                with_reference: self.reference_rows[k],
            })
            .collect();
        let mut channels: Vec<(AngleChannel, ChannelError)> = AngleChannel::ALL
            .iter()
            .copied()
            .zip(self.channels)
            .collect();
        let mut sync_lag = BTreeMap::new();
        for ((c, stats), lag) in channels.iter_mut().zip(&self.lags) {
            if let Some((l, best)) = lag.best(self.options.offset_free) {
                *stats = best;
                sync_lag.insert(c.name().to_string(), l);
            }
        }
        Evaluation {
            method: self.method.clone(),
            n_samples: self.n_samples,
            offset_free: self.options.offset_free,
            window: self.options.window,
            channels,
            sync_lag: (self.options.max_lag > 0).then_some(sync_lag),
            diag_mean,
            accel_reliability_pct: self
                .reliability
                .pct(self.reliability.ar, &self.reliability.segment_cols),
            accel_global_reliability_pct: self
                .reliability
                .pct(self.reliability.agr, &self.reliability.coupled_cols),
            missing_input_pct: self
                .reliability
                .pct(self.reliability.missing, &self.reliability.missing_col),
            trial_check: Default::default(),
            resets: self.resets.resets(),
            reference_units: self.reference_units.warning(),
            coverage,
            cut_lines: Vec::new(),
        }
    }
}

impl Observer for AngleMetrics {
    fn start(&mut self, estimator: &dyn Estimator) -> Result<(), BoxError> {
        self.method = estimator.name().to_string();
        self.set_diagnostic_names(estimator.diagnostic_names().iter());
        let o = estimator.outputs();
        self.set_carried_channels(core::array::from_fn(|k| match k {
            0..=3 => o.segment[k],
            _ => o.joint[k - 4],
        }));
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
    /// With `--max-lag`: per channel, the lag (samples; positive = the
    /// estimate trails the reference) at which `channels` were measured.
    pub sync_lag: Option<BTreeMap<String, i64>>,
    /// Mean of each diagnostic value over the window.
    pub diag_mean: BTreeMap<String, f64>,
    /// AR (001 Table 2): % of samples in which an accelerometer row updated
    /// some segment angle (from the `upd_<segment>` diagnostics).
    pub accel_reliability_pct: Option<f64>,
    /// AGR (001 Table 2, matricial global): % of samples in which a coupled
    /// (relative) accelerometer row updated the estimate.
    pub accel_global_reliability_pct: Option<f64>,
    /// % of samples with at least one missing input (empty or non-finite
    /// cell), from the segment filters' `missing_inputs` diagnostic: those
    /// samples were predicted without that input's update.
    pub missing_input_pct: Option<f64>,
    /// Whether the estimate file records this trial ([`crate::trial_check`]).
    pub trial_check: crate::trial_check::TrialCheck,
    /// Restarts of the estimator over the whole run (the `resets`
    /// diagnostic of `sdre` / `ekf`), `None` when there were none: the
    /// estimate after a restart is not a filter output (issue 16).
    pub resets: Option<Resets>,
    /// The warning when angle references look like degrees
    /// ([`crate::ReferenceUnitsWatch`]); in the JSON as `warnings`.
    pub reference_units: Option<String>,
    /// Per angle channel the estimate carries and the trial has a
    /// reference of (in the window): on how many rows it was scored (no
    /// lag) out of those with a reference; in the JSON as `rows_scored` /
    /// `rows_with_reference`.
    pub coverage: Vec<ChannelCoverage>,
    /// Last lines left out of the trial or the estimate file, cut off
    /// mid-row while they were written (their message,
    /// `limbfuse_io::table::CutLine`): `evaluate` warns of each, and the
    /// JSON lists them under `warnings`. Empty for an evaluation of data in
    /// memory.
    pub cut_lines: Vec<String>,
}

/// How many rows of one channel were scored out of those with a reference
/// ([`Evaluation::coverage`]): fewer when the estimate is empty on some of
/// them (before a filter starts, after a restart, a missing input).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChannelCoverage {
    /// The channel.
    pub channel: AngleChannel,
    /// Rows with both an estimate and a reference (without a lag shift).
    pub scored: u64,
    /// Rows with a reference.
    pub with_reference: u64,
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
    /// of the joint angles when no segment angle was evaluated. A channel
    /// whose estimate equals its reference on every sample (the fixed thigh
    /// of the knee-FES model, which the estimator copies from the trial) is
    /// not an estimate and is left out when another channel is estimated
    /// ([`Evaluation::exact_channels`]), so
    /// that it does not halve the mean (issue 17 item 6).
    pub fn mean_rmse(&self) -> Option<f64> {
        let all_exact = self
            .channels
            .iter()
            .all(|(c, s)| s.n() == 0 || self.is_exact(*c));
        let counted = |c: &AngleChannel| all_exact || !self.is_exact(*c);
        let mean_over = |segments_only: bool| -> Option<f64> {
            let vals: Vec<f64> = self
                .channels
                .iter()
                .map(|(c, _)| c)
                .filter(|c| !segments_only || matches!(c, AngleChannel::Segment(_)))
                .filter(|c| counted(c))
                .filter_map(|c| self.rmse(*c))
                .collect();
            (!vals.is_empty()).then(|| vals.iter().sum::<f64>() / vals.len() as f64)
        };
        mean_over(true).or_else(|| mean_over(false))
    }

    /// Whether the estimate of `c` equals its reference on every evaluated
    /// sample, to [`GIVEN_VALUE_TOLERANCE_RAD`]: a value the estimator was
    /// given, not one it estimated.
    fn is_exact(&self, c: AngleChannel) -> bool {
        self.channels
            .iter()
            .find(|(k, _)| *k == c)
            .and_then(|(_, s)| s.max_abs_error())
            .is_some_and(|m| m <= GIVEN_VALUE_TOLERANCE_RAD)
    }

    /// The channels left out of [`Evaluation::mean_rmse`] because their
    /// estimate equals the reference on every sample while another
    /// channel's does not.
    pub fn exact_channels(&self) -> Vec<AngleChannel> {
        let exact: Vec<AngleChannel> = self
            .channels
            .iter()
            .map(|(c, _)| *c)
            .filter(|c| self.is_exact(*c))
            .collect();
        let any_estimated = self
            .channels
            .iter()
            .any(|(c, s)| s.n() > 0 && !self.is_exact(*c));
        if any_estimated {
            exact
        } else {
            Vec::new()
        }
    }
}

/// Largest error (rad) on every sample at which an estimated channel is
/// taken for a value the estimator was given (a fixed thigh, a fixed-hip
/// trunk) and left out of [`Evaluation::mean_rmse`]: 1e-6 rad. Text files
/// round a given value (an independent simulator writes the fixed thigh as
/// 1.57079633, the estimate file holds 1.570796327: 3e-9 rad, which made the
/// mean count the thigh as a perfect estimate and halve the knee-FES mean),
/// while no estimate of a measured angle stays this close on every sample:
/// a 14-bit encoder's step is 3.8e-4 rad.
pub const GIVEN_VALUE_TOLERANCE_RAD: f64 = 1e-6;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_rmse_leaves_out_a_channel_equal_to_its_reference() {
        // Knee-FES shape: thigh given (error 0 everywhere, or the 3e-9 rad
        // of a reference written to 8 decimals), shank estimated.
        let mut m = AngleMetrics::new("sdre", EvalOptions::default());
        for k in 0..4 {
            let mut r = Record::default();
            r.reference.segment[1] = Some(if k == 3 { 1.500000003 } else { 1.5 });
            r.reference.segment[2] = Some(0.1 * k as f64);
            let mut e = Estimate::empty(0.0);
            e.segment[1] = Some(1.5);
            e.segment[2] = Some(0.1 * k as f64 + if k % 2 == 0 { 0.02 } else { -0.02 });
            m.push(&r, &e);
        }
        let ev = m.evaluation();
        let thigh = ev.rmse(AngleChannel::Segment(limbfuse_core::Segment::Thigh));
        assert!(thigh.is_some_and(|e| e > 0.0 && e < 2e-9), "{thigh:?}");
        let mean = ev.mean_rmse().unwrap();
        assert!((mean - 0.02).abs() < 1e-12, "{mean}");
        // With a nonzero thigh error, both count.
        let mut r = Record::default();
        r.reference.segment[1] = Some(1.5);
        let mut e = Estimate::empty(0.0);
        e.segment[1] = Some(1.6);
        m.push(&r, &e);
        assert!(m.evaluation().mean_rmse().unwrap() > 0.03);
        // Every channel exact: the mean is 0, not absent.
        let mut x = AngleMetrics::new("accel-inclination", EvalOptions::default());
        let mut r = Record::default();
        r.reference.segment[1] = Some(0.2);
        let mut e = Estimate::empty(0.0);
        e.segment[1] = Some(0.2);
        x.push(&r, &e);
        assert_eq!(x.evaluation().mean_rmse(), Some(0.0));
    }

    #[test]
    fn reliability_percentages_count_samples_with_an_update() {
        let mut m = AngleMetrics::new("global", EvalOptions::default());
        m.set_diagnostic_names(["psi", "upd_trunk", "upd_thigh", "upd_hip", "upd_knee"]);
        let r = Record::default();
        // 4 samples: (segment rows, coupled rows) updated = (yes, no), (no, no), (yes, yes), (no, yes)
        for (seg, cpl) in [(1.0, 0.0), (0.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            let mut e = Estimate::empty(0.0);
            e.diag[1] = Some(0.0);
            e.diag[2] = Some(seg);
            e.diag[4] = Some(cpl);
            m.push(&r, &e);
        }
        let ev = m.evaluation();
        assert_eq!(ev.accel_reliability_pct, Some(50.0));
        assert_eq!(ev.accel_global_reliability_pct, Some(50.0));
        let mut l = AngleMetrics::new("local", EvalOptions::default());
        l.set_diagnostic_names(["upd_trunk", "upd_hip"]);
        assert_eq!(l.evaluation().accel_global_reliability_pct, None);
        let mut b = AngleMetrics::new("gyro-integration", EvalOptions::default());
        b.set_diagnostic_names(Vec::<String>::new());
        b.push(&r, &Estimate::empty(0.0));
        assert_eq!(b.evaluation().accel_reliability_pct, None);
        assert_eq!(b.evaluation().missing_input_pct, None);
    }

    #[test]
    fn missing_inputs_are_counted_per_sample() {
        let mut m = AngleMetrics::new("mjls", EvalOptions::default());
        m.set_diagnostic_names(["mode", "missing_inputs"]);
        let r = Record::default();
        for miss in [0.0, 3.0, 0.0, 1.0, 0.0] {
            let mut e = Estimate::empty(0.0);
            e.diag[1] = Some(miss);
            m.push(&r, &e);
        }
        let ev = m.evaluation();
        assert_eq!(ev.missing_input_pct, Some(40.0));
        assert!(ev
            .to_text()
            .contains("missing input (predicted without its update): 40.0 %"));
    }
}
