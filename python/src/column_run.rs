//! A run of an estimator over a trial's columns into estimate columns:
//! the runner's loop (`limbfuse_core::runner::run_from`: one sample and
//! one estimate reused, [`Estimator::step_into`]) without its observer
//! calls, the trial's input columns read in place ([`SampleColumns`]) and
//! each estimate written straight into the output columns
//! ([`EstimateColumns::push`]).

use limbfuse_core::runner::RunError;
use limbfuse_core::{Estimate, Estimator, OfflineEstimator, Sample};
use limbfuse_eval::output_watch::AnyOutputWatch;
use limbfuse_eval::{ClippedSwingWatch, GaitWatch, KneeWatch, RejectionWatch, ResetWatch};
use limbfuse_io::Calibration;

use crate::column_samples::SampleColumns;
use crate::estimate_columns::EstimateColumns;
use crate::interrupt::Interrupt;

/// What a run watches besides writing the estimates: restarts, whether a
/// gait method found gait, whether a knee-axis method identified the axis
/// (as `limbfuse estimate` does; `limbfuse_eval`).
#[derive(Debug, Default)]
pub struct RunWatches {
    /// Restart counts.
    pub resets: ResetWatch,
    /// Contacts or speeds seen.
    pub gait: GaitWatch,
    /// The knee-axis verdict, for a knee-axis method.
    pub knee: Option<KneeWatch>,
    /// Any value at all.
    pub any_output: AnyOutputWatch,
    /// Readings the sensor-range gate rejected (the CLI's warning).
    pub rejections: RejectionWatch,
    /// Strides whose foot accelerometer clipped past an impact (the CLI's warning).
    pub clipped_swings: ClippedSwingWatch,
}

/// Runs `est` over every sample of `inputs`, pushing each estimate to
/// `out` and, when given, to `watches` (restarted for `est`'s
/// diagnostics). Errors as `runner::run_from`'s. Stops early, with `out`
/// part-filled, when a signal handler raised (`interrupt`: Ctrl-C).
pub fn run_columns(
    est: &mut dyn Estimator,
    inputs: &SampleColumns<'_>,
    out: &mut EstimateColumns,
    mut watches: Option<&mut RunWatches>,
    calibration: Option<&Calibration>,
    interrupt: &mut Interrupt,
) -> Result<(), RunError> {
    if let Some(w) = watches.as_deref_mut() {
        // (a `Filter` continues its estimator's rejection counts)
        let carried = w.rejections.counts();
        *w = RunWatches::for_estimator(est);
        w.rejections.carry(carried);
    }
    let mut sample = Sample::default();
    let mut estimate = Estimate::empty(0.0);
    for i in 0..inputs.len() {
        inputs.fill(i, &mut sample);
        if let Some(c) = calibration {
            c.apply_sample(&mut sample);
        }
        est.step_into(&sample, &mut estimate)
            .map_err(|source| RunError::Estimator {
                index: i as u64,
                t: sample.t,
                source,
            })?;
        out.push(&estimate);
        if let Some(w) = watches.as_deref_mut() {
            w.push(&sample, &estimate);
        }
        if interrupt.poll() {
            break;
        }
    }
    Ok(())
}

/// As [`run_columns`] for an offline estimator (`estimate(..., backfill=True)`):
/// each estimate is written when the estimator releases it, and watched
/// with its own sample; stopped early as [`run_columns`].
pub fn run_columns_offline(
    est: &mut dyn OfflineEstimator,
    inputs: &SampleColumns<'_>,
    out: &mut EstimateColumns,
    watches: &mut RunWatches,
    calibration: Option<&Calibration>,
    interrupt: &mut Interrupt,
) -> Result<(), RunError> {
    *watches = RunWatches::for_estimator(est.header());
    let mut sample = Sample::default();
    let mut own = Sample::default();
    let mut written = 0;
    let mut release = |est: &mut dyn OfflineEstimator, own: &mut Sample| {
        while let Some(e) = est.pop() {
            out.push(&e);
            inputs.fill(written, own);
            watches.push(own, &e);
            written += 1;
        }
    };
    for i in 0..inputs.len() {
        inputs.fill(i, &mut sample);
        if let Some(c) = calibration {
            c.apply_sample(&mut sample);
        }
        est.push(&sample).map_err(|source| RunError::Estimator {
            index: i as u64,
            t: sample.t,
            source,
        })?;
        release(est, &mut own);
        if interrupt.poll() {
            return Ok(());
        }
    }
    est.finish();
    release(est, &mut own);
    Ok(())
}

impl RunWatches {
    /// Fresh watches for `est`'s diagnostics.
    pub fn for_estimator(est: &dyn Estimator) -> Self {
        RunWatches {
            resets: ResetWatch::new(est.diagnostic_names().iter()),
            gait: GaitWatch::for_diagnostics(est.diagnostic_names()),
            knee: KneeWatch::for_diagnostics(est.diagnostic_names()),
            any_output: AnyOutputWatch::default(),
            rejections: RejectionWatch::new(est.diagnostic_names()),
            clipped_swings: ClippedSwingWatch::new(est.diagnostic_names()),
        }
    }

    /// Watches one estimate and its sample.
    fn push(&mut self, sample: &Sample, estimate: &Estimate) {
        self.resets.push(estimate);
        self.gait.push(estimate);
        self.any_output.push(estimate);
        self.rejections.push(estimate);
        self.clipped_swings.push(estimate);
        if let Some(k) = self.knee.as_mut() {
            k.push(sample, estimate);
        }
    }
}
