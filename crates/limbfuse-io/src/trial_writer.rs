//! Streaming writer of trial files (SPEC section 2).

use std::io::{self, Write};

use limbfuse_core::Record;

use crate::cell_format::{push_cell, push_value, write_comments};
use crate::layout::TrialLayout;
use crate::meta::TrialMeta;

/// Writes a trial file row by row: metadata comments, header, then records.
pub struct TrialWriter<W: Write> {
    out: W,
    layout: TrialLayout,
    line: Vec<u8>,
    buf: zmij::Buffer,
}

impl<W: Write> TrialWriter<W> {
    /// Writes the metadata and header for `layout`.
    pub fn new(mut out: W, meta: &TrialMeta, layout: TrialLayout) -> io::Result<Self> {
        write_comments(
            &mut out,
            meta.entries().iter().map(|(k, v)| (k.as_str(), v.as_str())),
        )?;
        writeln!(out, "{}", layout.column_names().join(","))?;
        Ok(TrialWriter {
            out,
            layout,
            line: Vec::with_capacity(1024),
            buf: zmij::Buffer::new(),
        })
    }

    /// Writes one record; channels absent from the layout are skipped, `None` values become empty cells.
    pub fn write(&mut self, r: &Record) -> io::Result<()> {
        let (l, s, re) = (&self.layout, &r.sample, &r.reference);
        let line = &mut self.line;
        let buf = &mut self.buf;
        line.clear();
        push_value(line, buf, Some(s.t));
        for i in 0..4 {
            let imu = &s.imu[i];
            if l.acc[i] {
                for k in 0..3 {
                    push_cell(line, buf, imu.acc.map(|v| v[k]));
                }
            }
            if l.gyr[i] {
                for k in 0..3 {
                    push_cell(line, buf, imu.gyr.map(|v| v[k]));
                }
            }
            if l.quat[i] {
                for k in 0..4 {
                    push_cell(line, buf, imu.quat.map(|q| q[k]));
                }
            }
        }
        for i in 0..4 {
            let imu = &s.other_leg_imu[i];
            if l.other_acc[i] {
                for k in 0..3 {
                    push_cell(line, buf, imu.acc.map(|v| v[k]));
                }
            }
            if l.other_gyr[i] {
                for k in 0..3 {
                    push_cell(line, buf, imu.gyr.map(|v| v[k]));
                }
            }
        }
        for i in 0..3 {
            if l.encoder[i] {
                push_cell(line, buf, s.encoder[i]);
            }
        }
        for k in 0..4 {
            if l.stim[k] {
                push_cell(line, buf, s.inputs.stim[k]);
            }
        }
        for i in 0..3 {
            if l.motor_torque[i] {
                push_cell(line, buf, s.inputs.motor_torque[i]);
            }
        }
        for (present, v) in l.com_meas.iter().zip(s.com.values()) {
            if *present {
                push_cell(line, buf, v);
            }
        }
        for i in 0..4 {
            if l.segment_ref[i] {
                push_cell(line, buf, re.segment[i]);
            }
        }
        for i in 0..3 {
            if l.joint_ref[i] {
                push_cell(line, buf, re.joint[i]);
            }
        }
        if l.com_pos {
            for k in 0..3 {
                push_cell(line, buf, re.com_pos.map(|v| v[k]));
            }
        }
        if l.com_vel {
            for k in 0..3 {
                push_cell(line, buf, re.com_vel.map(|v| v[k]));
            }
        }
        if l.phase_ref {
            line.push(b',');
            if let Some(p) = re.phase {
                line.extend_from_slice(p.label().as_bytes());
            }
        }
        for side in 0..2 {
            if l.contact_ref[side] {
                push_cell(
                    line,
                    buf,
                    re.contact[side].map(|c| if c { 1.0 } else { 0.0 }),
                );
            }
        }
        if l.speed_ref {
            push_cell(line, buf, re.speed);
        }
        line.push(b'\n');
        self.out.write_all(line)
    }

    /// Flushes and returns the underlying writer.
    pub fn finish(mut self) -> io::Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}
