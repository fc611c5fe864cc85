//! A run of an estimator over a trial's columns into estimate columns:
//! the runner's loop (`limbfuse_core::runner::run_from`: one sample and
//! one estimate reused, [`Estimator::step_into`]) without its observer
//! calls, the trial's input columns read in place ([`SampleColumns`]) and
//! each estimate written straight into the output columns
//! ([`EstimateColumns::push`]).

use limbfuse_core::runner::RunError;
use limbfuse_core::{Estimate, Estimator, Sample};
use limbfuse_eval::ResetWatch;

use crate::column_samples::SampleColumns;
use crate::estimate_columns::EstimateColumns;

/// Runs `est` over every sample of `inputs`, pushing each estimate to
/// `out` and, when given, to the restart watch `resets` (restarted for
/// `est`'s diagnostics). Errors as `runner::run_from`'s.
pub fn run_columns(
    est: &mut dyn Estimator,
    inputs: &SampleColumns<'_>,
    out: &mut EstimateColumns,
    mut resets: Option<&mut ResetWatch>,
) -> Result<(), RunError> {
    if let Some(w) = resets.as_deref_mut() {
        *w = ResetWatch::new(est.diagnostic_names().iter());
    }
    let mut sample = Sample::default();
    let mut estimate = Estimate::empty(0.0);
    for i in 0..inputs.len() {
        inputs.fill(i, &mut sample);
        est.step_into(&sample, &mut estimate)
            .map_err(|source| RunError::Estimator {
                index: i as u64,
                t: sample.t,
                source,
            })?;
        out.push(&estimate);
        if let Some(w) = resets.as_deref_mut() {
            w.push(&estimate);
        }
    }
    Ok(())
}
