//! A file-to-file `estimate` run on three threads (issue 18 item 6): the
//! trial is parsed on a reader thread, the estimator and the observers run
//! on the calling thread, and the estimate file is formatted and written on
//! a writer thread. Records and estimates cross in batches of [`BATCH`]
//! over bounded channels, so memory stays bounded whatever the trial's
//! length. The estimator sees the same records in the same order and the
//! writer writes the same bytes as in a single-threaded run; only the wall
//! time changes (docs/PERFORMANCE.md, "End to end").
//!
//! Not used when the estimate goes to standard output: a streamed estimate
//! must leave as soon as its row arrives (docs/STREAMING.md), which batching
//! would delay.

use std::sync::mpsc::{sync_channel, Receiver, SyncSender};

use limbfuse_core::runner::{self, BoxError, Observer, RunError, RunSummary};
use limbfuse_core::{Estimate, Estimator, Record};
use limbfuse_io::{EstimateWriter, FileError, TrialReader};

/// Records or estimates per hand-over between threads.
pub const BATCH: usize = 1024;

/// Batches in flight per channel (bounds the memory of a run).
const DEPTH: usize = 4;

/// Runs `est` over `reader` with `observers` on the calling thread,
/// `writer` on a writer thread and the parsing on a reader thread;
/// `prepare` is applied to every record before the estimator sees it (a
/// calibration). The writer is started here; the caller finishes it.
///
/// A malformed row ends the run with the same error, after the same
/// records, as [`runner::run`] over the reader; a failing writer ends it
/// with the writer's error.
pub fn run<W: std::io::Write + Send>(
    est: &mut dyn Estimator,
    reader: &mut TrialReader,
    writer: &mut EstimateWriter<W>,
    observers: &mut [&mut dyn Observer],
    prepare: &(dyn Fn(&mut Record) + Sync),
) -> Result<RunSummary, RunError> {
    writer.start(est).map_err(RunError::Observer)?;
    std::thread::scope(|s| {
        let (record_tx, record_rx) = sync_channel(DEPTH);
        s.spawn(move || read_batches(reader, record_tx, prepare));
        let (estimate_tx, estimate_rx) = sync_channel::<Vec<Estimate>>(DEPTH);
        let written = s.spawn(move || write_batches(writer, estimate_rx));
        let mut sink = BatchedSink {
            tx: Some(estimate_tx),
            batch: Vec::with_capacity(BATCH),
        };
        let source = BatchedRecords {
            rx: record_rx,
            current: Vec::new().into_iter(),
        };
        let summary = {
            let mut all: Vec<&mut dyn Observer> = Vec::with_capacity(observers.len() + 1);
            all.push(&mut sink);
            for o in observers.iter_mut() {
                all.push(&mut **o);
            }
            runner::run(est, source, &mut all)
        };
        // Whatever happened, let the writer thread end before reporting.
        drop(sink);
        let written = written
            .join()
            .unwrap_or_else(|_| Err("the estimate writer thread panicked".into()));
        match (summary, written) {
            (Ok(s), Ok(())) => Ok(s),
            // The writer's own error explains a refused hand-over.
            (Err(RunError::Observer(_)), Err(e)) | (Ok(_), Err(e)) => Err(RunError::Observer(e)),
            (Err(e), _) => Err(e),
        }
    })
}

/// The reader thread: every record of `reader`, prepared, in batches; a
/// malformed row is sent after the records before it and ends the thread,
/// as does a receiver that stopped listening.
fn read_batches(
    reader: &mut TrialReader,
    tx: SyncSender<Result<Vec<Record>, FileError>>,
    prepare: &(dyn Fn(&mut Record) + Sync),
) {
    let mut batch = Vec::with_capacity(BATCH);
    for item in reader.by_ref() {
        match item {
            Ok(mut record) => {
                prepare(&mut record);
                batch.push(record);
                if batch.len() == BATCH {
                    let full = std::mem::replace(&mut batch, Vec::with_capacity(BATCH));
                    if tx.send(Ok(full)).is_err() {
                        return;
                    }
                }
            }
            Err(e) => {
                if !batch.is_empty() && tx.send(Ok(batch)).is_err() {
                    return;
                }
                let _ = tx.send(Err(e));
                return;
            }
        }
    }
    if !batch.is_empty() {
        let _ = tx.send(Ok(batch));
    }
}

/// The writer thread: every estimate received, in order, into `writer`.
fn write_batches<W: std::io::Write>(
    writer: &mut EstimateWriter<W>,
    rx: Receiver<Vec<Estimate>>,
) -> Result<(), BoxError> {
    // The estimate writer reads nothing from the record it is shown.
    let record = Record::default();
    for batch in rx {
        for e in &batch {
            writer.observe(&record, e)?;
        }
    }
    writer.finish()
}

/// The records of the reader thread, one at a time.
struct BatchedRecords {
    rx: Receiver<Result<Vec<Record>, FileError>>,
    current: std::vec::IntoIter<Record>,
}

impl Iterator for BatchedRecords {
    type Item = Result<Record, FileError>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            if let Some(r) = self.current.next() {
                return Some(Ok(r));
            }
            match self.rx.recv() {
                Ok(Ok(batch)) => self.current = batch.into_iter(),
                Ok(Err(e)) => return Some(Err(e)),
                // The reader thread has sent everything.
                Err(_) => return None,
            }
        }
    }
}

/// An observer that hands the estimates to the writer thread in batches.
struct BatchedSink {
    tx: Option<SyncSender<Vec<Estimate>>>,
    batch: Vec<Estimate>,
}

impl BatchedSink {
    fn send(&mut self) -> Result<(), BoxError> {
        let full = std::mem::replace(&mut self.batch, Vec::with_capacity(BATCH));
        match &self.tx {
            Some(tx) if tx.send(full).is_ok() => Ok(()),
            _ => Err("the estimate writer stopped".into()),
        }
    }
}

impl Observer for BatchedSink {
    fn observe(&mut self, _record: &Record, estimate: &Estimate) -> Result<(), BoxError> {
        self.batch.push(*estimate);
        if self.batch.len() == BATCH {
            self.send()?;
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), BoxError> {
        if !self.batch.is_empty() {
            self.send()?;
        }
        self.tx = None;
        Ok(())
    }
}
