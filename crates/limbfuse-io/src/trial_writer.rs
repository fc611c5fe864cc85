//! Streaming writer of trial files (SPEC section 2), as CSV or, for a path
//! ending in `.arrow`/`.feather`, as an Arrow IPC file (`crate::arrow_file`).

use std::io::{self, Write};
use std::path::Path;

use limbfuse_core::Record;

use crate::arrow_file::{self, ArrowSink};
use crate::cell_format::write_comments;
use crate::cell_sink::{CellSink, CsvLine};
use crate::layout::TrialLayout;
use crate::meta::TrialMeta;

/// Writes a trial file row by row: metadata comments, header, then records.
pub struct TrialWriter<W: Write> {
    layout: TrialLayout,
    out: Output<W>,
}

enum Output<W: Write> {
    Csv { out: W, line: CsvLine },
    Arrow(Box<ArrowSink<W>>),
}

impl<W: Write> TrialWriter<W> {
    /// Writes the metadata and header for `layout` (CSV).
    pub fn new(mut out: W, meta: &TrialMeta, layout: TrialLayout) -> io::Result<Self> {
        write_comments(
            &mut out,
            meta.entries().iter().map(|(k, v)| (k.as_str(), v.as_str())),
        )?;
        writeln!(out, "{}", layout.column_names().join(","))?;
        Ok(TrialWriter {
            layout,
            out: Output::Csv {
                out,
                line: CsvLine::with_capacity(1024),
            },
        })
    }

    /// Writes the schema of an Arrow IPC trial file for `layout`, with
    /// `meta` as its metadata (docs/ARROW.md).
    pub fn arrow(out: W, meta: &TrialMeta, layout: TrialLayout) -> io::Result<Self> {
        let sink = ArrowSink::new(out, layout.column_names(), "phase_ref", meta)?;
        Ok(TrialWriter {
            layout,
            out: Output::Arrow(Box::new(sink)),
        })
    }

    /// [`TrialWriter::arrow`] when `path` names an Arrow file
    /// ([`arrow_file::is_arrow_path`]), else [`TrialWriter::new`] (CSV).
    pub fn for_path(
        path: &Path,
        out: W,
        meta: &TrialMeta,
        layout: TrialLayout,
    ) -> io::Result<Self> {
        if arrow_file::is_arrow_path(path) {
            Self::arrow(out, meta, layout)
        } else {
            Self::new(out, meta, layout)
        }
    }

    /// Writes one record; channels absent from the layout are skipped, `None` values become empty cells.
    pub fn write(&mut self, r: &Record) -> io::Result<()> {
        match &mut self.out {
            Output::Csv { out, line } => {
                line.clear();
                write_record(line, &self.layout, r);
                out.write_all(line.finish())
            }
            Output::Arrow(sink) => {
                write_record(sink.as_mut(), &self.layout, r);
                sink.end_row()
            }
        }
    }

    /// Flushes (an Arrow file: writes its last batch and footer) and
    /// returns the underlying writer.
    pub fn finish(self) -> io::Result<W> {
        match self.out {
            Output::Csv { mut out, .. } => {
                out.flush()?;
                Ok(out)
            }
            Output::Arrow(sink) => sink.finish(),
        }
    }
}

/// The cells of `r` in the column order of `l` ([`TrialLayout::column_names`]).
fn write_record<S: CellSink + ?Sized>(line: &mut S, l: &TrialLayout, r: &Record) {
    let (s, re) = (&r.sample, &r.reference);
    line.number(Some(s.t));
    for i in 0..4 {
        let imu = &s.imu[i];
        if l.acc[i] {
            for k in 0..3 {
                line.number(imu.acc_axis(k));
            }
        }
        if l.gyr[i] {
            for k in 0..3 {
                line.number(imu.gyr_axis(k));
            }
        }
        if l.quat[i] {
            for k in 0..4 {
                line.number(imu.quat.map(|q| q[k]));
            }
        }
    }
    for i in 0..4 {
        let imu = &s.other_leg_imu[i];
        if l.other_acc[i] {
            for k in 0..3 {
                line.number(imu.acc_axis(k));
            }
        }
        if l.other_gyr[i] {
            for k in 0..3 {
                line.number(imu.gyr_axis(k));
            }
        }
    }
    for i in 0..3 {
        if l.encoder[i] {
            line.number(s.encoder[i]);
        }
    }
    for k in 0..4 {
        if l.stim[k] {
            line.number(s.inputs.stim[k]);
        }
    }
    for i in 0..3 {
        if l.motor_torque[i] {
            line.number(s.inputs.motor_torque[i]);
        }
    }
    for (present, v) in l.com_meas.iter().zip(s.com.values()) {
        if *present {
            line.number(v);
        }
    }
    for i in 0..4 {
        if l.segment_ref[i] {
            line.number(re.segment[i]);
        }
    }
    for i in 0..3 {
        if l.joint_ref[i] {
            line.number(re.joint[i]);
        }
    }
    if l.com_pos {
        for k in 0..3 {
            line.number(re.com_pos.map(|v| v[k]));
        }
    }
    if l.com_vel {
        for k in 0..3 {
            line.number(re.com_vel.map(|v| v[k]));
        }
    }
    if l.phase_ref {
        line.label(re.phase.map(|p| p.label()));
    }
    for side in 0..2 {
        if l.contact_ref[side] {
            line.number(re.contact[side].map(|c| if c { 1.0 } else { 0.0 }));
        }
    }
    if l.speed_ref {
        line.number(re.speed);
    }
}
