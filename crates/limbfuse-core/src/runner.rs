//! Drives an [`Estimator`] over a source of [`Record`]s and pushes each
//! estimate to [`Observer`]s (file writers, metrics, progress bars).
//!
//! The runner is the only place where estimation meets the outside world;
//! estimators stay free of I/O (the argmin executor/observer split).

use std::error::Error;

use crate::estimate::Estimate;
use std::collections::VecDeque;

use crate::estimator::{Estimator, EstimatorError, OfflineEstimator};
use crate::sample::Record;

/// A boxed error from a sample source or an observer.
pub type BoxError = Box<dyn Error + Send + Sync + 'static>;

/// Receives every (record, estimate) pair of a run.
pub trait Observer {
    /// Called once before the first sample, with the estimator that will run.
    fn start(&mut self, _estimator: &dyn Estimator) -> Result<(), BoxError> {
        Ok(())
    }
    /// Called for every processed sample.
    fn observe(&mut self, record: &Record, estimate: &Estimate) -> Result<(), BoxError>;
    /// Called once after the last sample.
    fn finish(&mut self) -> Result<(), BoxError> {
        Ok(())
    }
}

/// Why a run stopped.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The sample source failed (e.g. a malformed trial file row).
    #[error(transparent)]
    Source(BoxError),
    /// The estimator rejected sample number `index` (0-based).
    #[error("sample {index} (t = {t} s): {source}")]
    Estimator {
        /// 0-based sample index.
        index: u64,
        /// Sample time (s).
        t: f64,
        /// What went wrong.
        source: EstimatorError,
    },
    /// An observer failed (e.g. the output file could not be written).
    #[error(transparent)]
    Observer(BoxError),
}

/// Summary of a finished run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RunSummary {
    /// Number of samples processed.
    pub n_samples: u64,
}

/// A source of records that overwrites a caller-owned [`Record`] with each
/// new one, so that the runner moves no record per sample (a trial reader
/// parses straight into the runner's record).
pub trait RecordSource {
    /// Why a record could not be read.
    type Error: Into<BoxError>;
    /// Overwrites `record` with the next record; `Ok(false)` at the end
    /// (then `record` holds no meaningful value).
    fn read_into(&mut self, record: &mut Record) -> Result<bool, Self::Error>;
}

/// Any iterator of records as a [`RecordSource`] (each record is moved once).
struct RecordIter<I>(I);

impl<I, E> RecordSource for RecordIter<I>
where
    I: Iterator<Item = Result<Record, E>>,
    E: Into<BoxError>,
{
    type Error = E;

    fn read_into(&mut self, record: &mut Record) -> Result<bool, E> {
        match self.0.next() {
            None => Ok(false),
            Some(r) => {
                *record = r?;
                Ok(true)
            }
        }
    }
}

/// Runs `estimator` over `source`, streaming: memory use does not grow with the trial length.
pub fn run<I, E>(
    estimator: &mut dyn Estimator,
    source: I,
    observers: &mut [&mut dyn Observer],
) -> Result<RunSummary, RunError>
where
    I: IntoIterator<Item = Result<Record, E>>,
    E: Into<BoxError>,
{
    run_from(estimator, &mut RecordIter(source.into_iter()), observers)
}

/// [`run`] over a [`RecordSource`]: one record and one estimate are reused
/// for the whole run ([`Estimator::step_into`]), nothing is moved per sample.
pub fn run_from<S: RecordSource + ?Sized>(
    estimator: &mut dyn Estimator,
    source: &mut S,
    observers: &mut [&mut dyn Observer],
) -> Result<RunSummary, RunError> {
    for o in observers.iter_mut() {
        o.start(estimator).map_err(RunError::Observer)?;
    }
    let mut n = 0u64;
    let mut record = Record::default();
    let mut estimate = Estimate::empty(0.0);
    while source
        .read_into(&mut record)
        .map_err(|e| RunError::Source(e.into()))?
    {
        estimator
            .step_into(&record.sample, &mut estimate)
            .map_err(|source| RunError::Estimator {
                index: n,
                t: record.sample.t,
                source,
            })?;
        for o in observers.iter_mut() {
            o.observe(&record, &estimate).map_err(RunError::Observer)?;
        }
        n += 1;
    }
    for o in observers.iter_mut() {
        o.finish().map_err(RunError::Observer)?;
    }
    Ok(RunSummary { n_samples: n })
}

/// Runs an offline `estimator` (a smoother) over `source`: each record is
/// held until its estimate is final and then handed to the observers with
/// it, in order. Memory is the records and state the estimator holds back
/// (bounded by its own settings, e.g. a smoother's block and overlap).
pub fn run_offline<I, E>(
    estimator: &mut dyn OfflineEstimator,
    source: I,
    observers: &mut [&mut dyn Observer],
) -> Result<RunSummary, RunError>
where
    I: IntoIterator<Item = Result<Record, E>>,
    E: Into<BoxError>,
{
    for o in observers.iter_mut() {
        o.start(estimator.header()).map_err(RunError::Observer)?;
    }
    let mut held: VecDeque<Record> = VecDeque::new();
    let mut n = 0u64;
    let emit = |estimate: Estimate,
                held: &mut VecDeque<Record>,
                observers: &mut [&mut dyn Observer]|
     -> Result<(), RunError> {
        let record = held.pop_front().ok_or_else(|| {
            RunError::Observer("offline estimator: more estimates than samples".into())
        })?;
        for o in observers.iter_mut() {
            o.observe(&record, &estimate).map_err(RunError::Observer)?;
        }
        Ok(())
    };
    for item in source {
        let record = item.map_err(|e| RunError::Source(e.into()))?;
        estimator
            .push(&record.sample)
            .map_err(|source| RunError::Estimator {
                index: n,
                t: record.sample.t,
                source,
            })?;
        held.push_back(record);
        n += 1;
        while let Some(e) = estimator.pop() {
            emit(e, &mut held, observers)?;
        }
    }
    estimator.finish();
    while let Some(e) = estimator.pop() {
        emit(e, &mut held, observers)?;
    }
    for o in observers.iter_mut() {
        o.finish().map_err(RunError::Observer)?;
    }
    Ok(RunSummary { n_samples: n })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimator::Outputs;
    use crate::sample::{Reference, Sample};
    use core::fmt;

    /// Emits each sample's time as its thigh angle, three samples late.
    struct Delayed {
        held: VecDeque<f64>,
        ready: VecDeque<Estimate>,
    }

    impl Estimator for Delayed {
        fn name(&self) -> &'static str {
            "delayed"
        }
        fn outputs(&self) -> Outputs {
            Outputs::ALL_ANGLES
        }
        fn describe_parameters(&self, _: &mut dyn fmt::Write) -> fmt::Result {
            Ok(())
        }
        fn reset(&mut self) {}
        fn step(&mut self, s: &Sample) -> Result<Estimate, EstimatorError> {
            Ok(Estimate::empty(s.t))
        }
    }

    impl OfflineEstimator for Delayed {
        fn header(&self) -> &dyn Estimator {
            self
        }
        fn push(&mut self, s: &Sample) -> Result<(), EstimatorError> {
            self.held.push_back(s.t);
            if self.held.len() > 3 {
                self.finish_one();
            }
            Ok(())
        }
        fn pop(&mut self) -> Option<Estimate> {
            self.ready.pop_front()
        }
        fn finish(&mut self) {
            while !self.held.is_empty() {
                self.finish_one();
            }
        }
    }

    impl Delayed {
        fn finish_one(&mut self) {
            if let Some(t) = self.held.pop_front() {
                let mut e = Estimate::empty(t);
                e.segment[1] = Some(t);
                self.ready.push_back(e);
            }
        }
    }

    struct Pairs(Vec<(f64, f64)>);
    impl Observer for Pairs {
        fn observe(&mut self, r: &Record, e: &Estimate) -> Result<(), BoxError> {
            self.0.push((r.sample.t, e.segment[1].unwrap()));
            Ok(())
        }
    }

    #[test]
    fn offline_estimates_meet_their_own_records_in_order() {
        let records = (0..10).map(|k| {
            Ok::<_, BoxError>(Record {
                sample: Sample::empty(k as f64 * 0.01),
                reference: Reference::default(),
            })
        });
        let mut est = Delayed {
            held: VecDeque::new(),
            ready: VecDeque::new(),
        };
        let mut pairs = Pairs(Vec::new());
        let s = run_offline(&mut est, records, &mut [&mut pairs]).unwrap();
        assert_eq!(s.n_samples, 10);
        assert_eq!(pairs.0.len(), 10);
        for (k, (t, e)) in pairs.0.iter().enumerate() {
            assert_eq!(*t, k as f64 * 0.01);
            assert_eq!(t, e);
        }
    }
}
