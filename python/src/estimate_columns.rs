//! Estimates as columns, in the estimate file's order (SPEC section 3): `t`,
//! the angles the method outputs, `phase`, `speed`, `com_*`, `diag_*`.
//! [`EstimateColumns`] collects a run; [`EstimateView`] reads columns handed
//! in from Python back into [`Estimate`]s.

use limbfuse_core::estimator::Outputs;
use limbfuse_core::runner::{BoxError, Observer};
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Estimate, Estimator, GaitPhase, Record, MAX_DIAG};
use limbfuse_io::estimate_file::COM_COLUMNS;
use nalgebra::Vector3;

use crate::column_block::ColumnBlock;

/// The column of the estimated gait phase (text cells).
pub const PHASE: &str = "phase";

fn has(o: &Outputs, c: AngleChannel) -> bool {
    match c {
        AngleChannel::Segment(s) => o.segment[s.index()],
        AngleChannel::Joint(j) => o.joint[j.index()],
    }
}

/// Estimates staged row by row before they are written to the columns: a
/// block of rows (row-major, in cache) is transposed into the columns at
/// once, so that each column is written sequentially rather than one
/// value per column per sample.
const STAGED_ROWS: usize = 256;

/// A run's estimates as columns (NaN = missing or non-finite, written as
/// an empty cell by the estimate writer too).
///
/// [`EstimateColumns::push`] stages each estimate; the columns hold every
/// estimate after [`EstimateColumns::flush`] (which the runner's
/// [`Observer::finish`] calls).
#[derive(Debug, Default)]
pub struct EstimateColumns {
    format: RowFormat,
    /// Staged rows, `names.len()` values each.
    stage: Vec<f64>,
    staged: usize,
    /// Numeric column names (without `phase`), in file order.
    pub names: Vec<String>,
    /// One column per name.
    pub values: ColumnBlock,
    /// The `phase` cells, when the method estimates the phase.
    pub phase: Option<Vec<Option<&'static str>>>,
    /// `# key: value` lines of the file header (without `# `).
    pub header: Vec<String>,
}

impl EstimateColumns {
    /// Empty columns for `est`'s outputs and diagnostics, with room for
    /// `n` samples (a run grows no vector).
    pub fn for_estimator(est: &dyn Estimator, n: usize) -> Result<Self, std::fmt::Error> {
        let outputs = est.outputs();
        let diag = est.diagnostic_names();
        let n_diag = diag.len().min(MAX_DIAG);
        let angles: Vec<AngleChannel> = AngleChannel::ALL
            .into_iter()
            .filter(|c| has(&outputs, *c))
            .collect();
        let mut names = vec!["t".to_string()];
        names.extend(angles.iter().map(|c| c.name().to_string()));
        if outputs.speed {
            names.push("speed".into());
        }
        if outputs.com {
            names.extend(COM_COLUMNS.iter().map(|c| c.to_string()));
        }
        if outputs.contact {
            names.extend(CONTACT.iter().map(|c| c.to_string()));
        }
        names.extend(diag[..n_diag].iter().map(|n| format!("diag_{n}")));
        let mut header = vec![format!("method: {}", est.name())];
        let mut params = String::new();
        est.describe_parameters(&mut params)?;
        header.extend(
            params
                .lines()
                .filter(|l| !l.trim().is_empty())
                .map(str::to_string),
        );
        Ok(EstimateColumns {
            format: RowFormat {
                outputs,
                n_diag,
                angles,
            },
            stage: vec![0.0; STAGED_ROWS.min(n.max(1)) * names.len()],
            staged: 0,
            values: ColumnBlock::new(names.len(), n),
            names,
            phase: outputs.phase.then(|| Vec::with_capacity(n)),
            header,
        })
    }

    /// Appends one estimate (staged: see [`EstimateColumns::flush`]).
    pub fn push(&mut self, e: &Estimate) {
        let width = self.names.len();
        if (self.staged + 1) * width > self.stage.len() {
            self.flush();
        }
        let at = self.staged * width;
        if let Some(row) = self.stage.get_mut(at..at + width) {
            self.format.write(e, row);
            self.staged += 1;
        }
        if let Some(p) = &mut self.phase {
            p.push(e.phase.map(GaitPhase::label));
        }
    }

    /// Moves the staged estimates into the columns.
    pub fn flush(&mut self) {
        self.values.append_rows(&self.stage, self.staged);
        self.staged = 0;
    }

    /// One estimate as (name, value) pairs, `phase` in its file position.
    pub fn row(&self, e: &Estimate) -> Vec<(String, Option<f64>)> {
        let mut row = vec![f64::NAN; self.names.len()];
        self.format.write(e, &mut row);
        self.names
            .iter()
            .cloned()
            .zip(row)
            .map(|(n, v)| (n, Some(v).filter(|x| !x.is_nan())))
            .collect()
    }
}

/// Which values of an estimate a row holds, in file order.
#[derive(Debug, Default)]
struct RowFormat {
    outputs: Outputs,
    n_diag: usize,
    /// The angle channels the method outputs, in file order.
    angles: Vec<AngleChannel>,
}

impl RowFormat {
    /// Writes `e`'s values into `row` (one per column, in order).
    fn write(&self, e: &Estimate, row: &mut [f64]) {
        let n_diag = self.n_diag.min(row.len());
        let (row, diag) = row.split_at_mut(row.len() - n_diag);
        for (cell, d) in diag.iter_mut().zip(&e.diag) {
            *cell = match d {
                Some(x) if x.is_finite() => *x,
                _ => f64::NAN,
            };
        }
        let mut cells = row.iter_mut();
        let mut put = |v: Option<f64>| {
            if let Some(c) = cells.next() {
                *c = v.filter(|x| x.is_finite()).unwrap_or(f64::NAN);
            }
        };
        put(Some(e.t));
        for c in &self.angles {
            put(e.angle(*c));
        }
        if self.outputs.speed {
            put(e.speed);
        }
        if self.outputs.com {
            for k in 0..3 {
                put(e.com_pos.map(|v| v[k]));
            }
            for k in 0..3 {
                put(e.com_vel.map(|v| v[k]));
            }
        }
        if self.outputs.contact {
            for c in e.contact {
                put(c.map(|c| if c { 1.0 } else { 0.0 }));
            }
        }
    }
}

impl Observer for EstimateColumns {
    fn observe(&mut self, _record: &Record, estimate: &Estimate) -> Result<(), BoxError> {
        self.push(estimate);
        Ok(())
    }

    fn finish(&mut self) -> Result<(), BoxError> {
        self.flush();
        Ok(())
    }
}

/// Foot-contact columns (SPEC section 3 additions, docs/GAIT_EVENTS.md), in
/// `Estimate::contact` order.
const CONTACT: [&str; 2] = ["contact_left", "contact_right"];
/// Estimate columns borrowed from Python (the `Estimate` class).
#[derive(Debug)]
pub struct EstimateView<'a> {
    /// Time (s).
    pub t: &'a [f64],
    angle: [Option<&'a [f64]>; 7],
    speed: Option<&'a [f64]>,
    com: [Option<&'a [f64]>; 6],
    contact: [Option<&'a [f64]>; 2],
    /// Diagnostic names (without `diag_`) and values.
    pub diag: Vec<(String, &'a [f64])>,
    phase: Option<Vec<Option<GaitPhase>>>,
}

impl<'a> EstimateView<'a> {
    /// Reads the named columns; every name must be an estimate column.
    pub fn new(
        t: &'a [f64],
        named: Vec<(String, &'a [f64])>,
        phase: Option<Vec<Option<String>>>,
    ) -> Result<Self, String> {
        crate::columns::check_time(t)?;
        let mut v = EstimateView {
            t,
            angle: [None; 7],
            speed: None,
            com: [None; 6],
            contact: [None; 2],
            diag: Vec::new(),
            phase: None,
        };
        for (name, values) in named {
            if values.len() != t.len() {
                return Err(format!(
                    "estimate column `{name}` has {} samples but `t` has {}",
                    values.len(),
                    t.len()
                ));
            }
            if let Some(k) = AngleChannel::ALL.iter().position(|c| c.name() == name) {
                v.angle[k] = Some(values);
            } else if name == "speed" {
                v.speed = Some(values);
            } else if let Some(k) = COM_COLUMNS.iter().position(|c| *c == name) {
                v.com[k] = Some(values);
            } else if let Some(k) = CONTACT.iter().position(|c| *c == name) {
                v.contact[k] = Some(values);
            } else if let Some(d) = name.strip_prefix("diag_") {
                if v.diag.len() == MAX_DIAG {
                    return Err(format!("more than {MAX_DIAG} diagnostic columns"));
                }
                v.diag.push((d.to_string(), values));
            } else {
                return Err(format!(
                    "unknown estimate column `{name}` (expected trunk, thigh, shank, foot, hip, knee, ankle, phase, speed, com_x..com_vz, contact_left, contact_right or diag_NAME)"
                ));
            }
        }
        if let Some(cells) = phase {
            v.phase = Some(crate::columns::phase_cells(PHASE, &cells, t.len())?);
        }
        Ok(v)
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// The estimate of sample `i`.
    pub fn estimate(&self, i: usize) -> Estimate {
        let opt = |c: Option<&[f64]>| c.map(|v| v[i]).filter(|x| x.is_finite());
        let mut e = Estimate::empty(self.t[i]);
        for (k, c) in AngleChannel::ALL.iter().enumerate() {
            let v = opt(self.angle[k]);
            match c {
                AngleChannel::Segment(s) => e.segment[s.index()] = v,
                AngleChannel::Joint(j) => e.joint[j.index()] = v,
            }
        }
        e.speed = opt(self.speed);
        let com = self.com.map(opt);
        if let [Some(x), Some(y), Some(z), ..] = com {
            e.com_pos = Some(Vector3::new(x, y, z));
        }
        if let [.., Some(x), Some(y), Some(z)] = com {
            e.com_vel = Some(Vector3::new(x, y, z));
        }
        for (k, c) in self.contact.iter().enumerate() {
            e.contact[k] = opt(*c).map(|x| x >= 0.5);
        }
        for (k, (_, v)) in self.diag.iter().enumerate() {
            e.diag[k] = opt(Some(v));
        }
        e.phase = self.phase.as_ref().and_then(|p| p[i]);
        e
    }

    /// The numeric column names in file order, with `phase` where the file
    /// has it, and a getter of the text of cell (row, column).
    pub fn file_columns(&self) -> Vec<String> {
        let mut names = vec!["t".to_string()];
        for (k, c) in AngleChannel::ALL.iter().enumerate() {
            if self.angle[k].is_some() {
                names.push(c.name().into());
            }
        }
        if self.phase.is_some() {
            names.push(PHASE.into());
        }
        if self.speed.is_some() {
            names.push("speed".into());
        }
        for (k, c) in COM_COLUMNS.iter().enumerate() {
            if self.com[k].is_some() {
                names.push(c.to_string());
            }
        }
        for (k, c) in CONTACT.iter().enumerate() {
            if self.contact[k].is_some() {
                names.push(c.to_string());
            }
        }
        names.extend(self.diag.iter().map(|(n, _)| format!("diag_{n}")));
        names
    }

    /// Writes row `i` as CSV cells in [`EstimateView::file_columns`] order
    /// (shortest round-trip decimals, empty cell = missing).
    pub fn write_row(&self, i: usize, line: &mut Vec<u8>, buf: &mut ryu::Buffer) {
        let mut cell = |line: &mut Vec<u8>, v: f64, first: bool| {
            if !first {
                line.push(b',');
            }
            if v.is_finite() {
                line.extend_from_slice(buf.format_finite(v).as_bytes());
            }
        };
        cell(line, self.t[i], true);
        for c in self.angle.iter().flatten() {
            cell(line, c[i], false);
        }
        if let Some(p) = &self.phase {
            line.push(b',');
            if let Some(ph) = p[i] {
                line.extend_from_slice(ph.label().as_bytes());
            }
        }
        for c in self
            .speed
            .iter()
            .chain(self.com.iter().flatten())
            .chain(self.contact.iter().flatten())
        {
            cell(line, c[i], false);
        }
        for (_, c) in &self.diag {
            cell(line, c[i], false);
        }
        line.push(b'\n');
    }
}
