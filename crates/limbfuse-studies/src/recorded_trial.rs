//! A trial file read whole into memory, and the estimates of one method
//! over it, for the study examples that compare runs sample by sample
//! (`time_base_study`, `gyro_shape_floor`).

use std::convert::Infallible;
use std::path::Path;

use limbfuse_core::runner::{run, BoxError, Observer};
use limbfuse_core::{Estimate, Record};
use limbfuse_io::FileError;
use limbfuse_io::{TrialLayout, TrialMeta, TrialReader};
use limbfuse_methods::{build, MethodName, MethodSpec};

/// A trial's metadata, column layout and every record.
pub struct RecordedTrial {
    /// The file's metadata.
    pub meta: TrialMeta,
    /// Which columns the file has.
    pub layout: TrialLayout,
    /// Every record, in order.
    pub records: Vec<Record>,
}

impl RecordedTrial {
    /// Reads `path` whole; the reader's error (naming the file, line and
    /// column) when it is not a valid trial.
    pub fn read(path: &Path) -> Result<RecordedTrial, FileError> {
        let reader = TrialReader::open(path)?;
        let meta = reader.meta().clone();
        let layout = *reader.layout();
        let records = reader.collect::<Result<Vec<_>, _>>()?;
        Ok(RecordedTrial {
            meta,
            layout,
            records,
        })
    }
}

/// Keeps every estimate of a run.
#[derive(Debug, Default)]
pub struct EstimateLog(pub Vec<Estimate>);

impl Observer for EstimateLog {
    fn observe(&mut self, _record: &Record, estimate: &Estimate) -> Result<(), BoxError> {
        self.0.push(*estimate);
        Ok(())
    }
}

/// Runs `method` with its defaults (as `limbfuse estimate` builds it) over
/// `records`, with `observers` beside the log of its estimates; the
/// method's build error (e.g. a channel the trial lacks) or the run's.
pub fn run_defaults(
    method: MethodName,
    meta: &TrialMeta,
    layout: &TrialLayout,
    records: &[Record],
    observers: &mut [&mut dyn Observer],
) -> Result<Vec<Estimate>, BoxError> {
    let spec = MethodSpec::defaults(method)?;
    let mut est = build(&spec, meta, layout)?;
    let mut log = EstimateLog(Vec::with_capacity(records.len()));
    let mut all: Vec<&mut dyn Observer> = Vec::with_capacity(observers.len() + 1);
    all.push(&mut log);
    for o in observers.iter_mut() {
        all.push(&mut **o);
    }
    run(
        est.as_mut(),
        records.iter().map(|r| Ok::<_, Infallible>(*r)),
        &mut all,
    )?;
    Ok(log.0)
}
