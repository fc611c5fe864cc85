//! `limbfuse mirror TRIAL -o OTHER_LEG [--remount-seed N]`: the recording as
//! the mirror-image leg's sensors read it (docs/ALIGNMENT.md, "Both legs").

use anyhow::{Context, Result};
use limbfuse_core::Record;
use limbfuse_io::{TrialReader, TrialWriter};
use limbfuse_signal::align::mirror_trial::{mirror_trial, mirrored_leg};

use crate::cli::MirrorArgs;

/// Reads the trial, mirrors (and re-mounts) every sensor, writes the result.
pub fn run(a: &MirrorArgs) -> Result<()> {
    super::refuse_input_as_output(&a.trial, &a.output)?;
    let mut reader = TrialReader::open(&a.trial)?;
    let (meta, layout) = (reader.meta().clone(), *reader.layout());
    let source = a.trial.display().to_string();
    // (the channels checked before the whole file is read)
    mirrored_leg(&meta, &layout, &source)?;
    let records: Vec<Record> = super::read_records(&mut reader)?;
    let m = mirror_trial(&records, &meta, layout, &source, a.remount_seed)?;
    if !m.dropped_meta.is_empty() {
        eprintln!(
            "warning: {}: left out metadata lines that could not be mirrored: {}",
            a.trial.display(),
            m.dropped_meta.join(", ")
        );
    }
    let mut out = super::create_file(&a.output)?;
    let mut w = TrialWriter::for_path(&a.output, &mut out, &m.meta, m.layout)
        .with_context(|| format!("{}: cannot write", a.output.display()))?;
    for r in &m.records {
        w.write(r)
            .with_context(|| format!("{}: cannot write", a.output.display()))?;
    }
    w.finish()
        .with_context(|| format!("{}: cannot write", a.output.display()))?;
    super::commit(out)?;
    eprintln!(
        "mirrored {} samples ({} leg -> {} leg) -> {}",
        m.records.len(),
        m.from.name(),
        m.to.name(),
        a.output.display()
    );
    Ok(())
}
