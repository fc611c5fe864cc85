//! Estimates as columns, in the estimate file's order (SPEC section 3): `t`,
//! the angles the method outputs, `phase`, `speed`, `com_*`, `diag_*`.
//! [`EstimateColumns`] collects a run; [`EstimateView`] reads columns handed
//! in from Python back into [`Estimate`]s.

use limbfuse_core::estimator::Outputs;
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Estimate, Estimator, GaitPhase, MAX_DIAG};
use limbfuse_io::estimate_file::COM_COLUMNS;
use nalgebra::Vector3;

use crate::column_block::{finite_or_nan, ColumnBlock};

/// The column of the estimated gait phase (text cells).
pub const PHASE: &str = "phase";

fn has(o: &Outputs, c: AngleChannel) -> bool {
    match c {
        AngleChannel::Segment(s) => o.segment[s.index()],
        AngleChannel::Joint(j) => o.joint[j.index()],
    }
}

/// A run's estimates as columns (NaN = missing or non-finite, written as
/// an empty cell by the estimate writer too), each estimate written
/// straight into the columns by [`EstimateColumns::push`].
#[derive(Debug, Default)]
pub struct EstimateColumns {
    format: RowFormat,
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
    /// Empty columns for `est`'s outputs and all its diagnostics, with
    /// room for `n` samples (a run grows no vector).
    pub fn for_estimator(est: &dyn Estimator, n: usize) -> Result<Self, std::fmt::Error> {
        let n_diag = est.diagnostic_names().len().min(MAX_DIAG);
        Self::with_diagnostics(est, n, &(0..n_diag).collect::<Vec<_>>())
    }

    /// [`EstimateColumns::for_estimator`] with only the diagnostics at
    /// `chosen` (ascending indices into `Estimate::diag`, as
    /// `DiagnosticColumns::resolve` gives them).
    pub fn with_diagnostics(
        est: &dyn Estimator,
        n: usize,
        chosen: &[usize],
    ) -> Result<Self, std::fmt::Error> {
        let outputs = est.outputs();
        let diag = est.diagnostic_names();
        let mut names = vec!["t".to_string()];
        let mut cells = vec![Cell::Time];
        for c in AngleChannel::ALL.into_iter().filter(|c| has(&outputs, *c)) {
            names.push(c.name().to_string());
            cells.push(match c {
                AngleChannel::Segment(s) => Cell::Segment(s.index()),
                AngleChannel::Joint(j) => Cell::Joint(j.index()),
            });
        }
        if outputs.speed {
            names.push("speed".into());
            cells.push(Cell::Speed);
        }
        if outputs.com {
            names.extend(COM_COLUMNS.iter().map(|c| c.to_string()));
            cells.extend((0..3).map(Cell::ComPos).chain((0..3).map(Cell::ComVel)));
        }
        if outputs.contact {
            names.extend(CONTACT.iter().map(|c| c.to_string()));
            cells.extend((0..2).map(Cell::Contact));
        }
        names.extend(chosen.iter().map(|&i| format!("diag_{}", diag[i])));
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
            format: RowFormat::new(cells, chosen),
            values: ColumnBlock::new(names.len(), n),
            names,
            phase: outputs.phase.then(|| Vec::with_capacity(n)),
            header,
        })
    }

    /// Appends one estimate.
    #[inline]
    pub fn push(&mut self, e: &Estimate) {
        let mut head = [0.0; MAX_HEAD];
        let n = self.format.head(e, &mut head);
        let mut picked = [None; MAX_DIAG];
        self.values
            .push_row(&head[..n], self.format.diag(e, &mut picked));
        if let Some(p) = &mut self.phase {
            p.push(e.phase.map(GaitPhase::label));
        }
    }

    /// One estimate as (name, value) pairs, `phase` in its file position.
    pub fn row(&self, e: &Estimate) -> Vec<(String, Option<f64>)> {
        let mut head = [0.0; MAX_HEAD];
        let n = self.format.head(e, &mut head);
        let mut picked = [None; MAX_DIAG];
        let diag = self
            .format
            .diag(e, &mut picked)
            .iter()
            .map(|d| finite_or_nan(*d));
        self.names
            .iter()
            .cloned()
            .zip(head[..n].iter().copied().chain(diag))
            .map(|(n, v)| (n, Some(v).filter(|x| !x.is_nan())))
            .collect()
    }
}

/// At most as many columns before the diagnostics: `t`, 7 angles,
/// `speed`, 6 CoM values, 2 contacts.
const MAX_HEAD: usize = 17;

/// Where the value of a (non-diagnostic) column comes from in an estimate.
#[derive(Debug, Clone, Copy)]
enum Cell {
    Time,
    Segment(usize),
    Joint(usize),
    Speed,
    ComPos(usize),
    ComVel(usize),
    Contact(usize),
}

impl Cell {
    #[inline]
    fn value(self, e: &Estimate) -> f64 {
        finite_or_nan(match self {
            Cell::Time => Some(e.t),
            Cell::Segment(k) => e.segment[k],
            Cell::Joint(k) => e.joint[k],
            Cell::Speed => e.speed,
            Cell::ComPos(k) => e.com_pos.map(|v| v[k]),
            Cell::ComVel(k) => e.com_vel.map(|v| v[k]),
            Cell::Contact(k) => e.contact[k].map(|c| if c { 1.0 } else { 0.0 }),
        })
    }
}

/// Which values of an estimate a row holds, in file order: the cells the
/// method outputs (resolved once), then the chosen diagnostics.
#[derive(Debug, Default)]
struct RowFormat {
    cells: Vec<Cell>,
    /// Indices into `Estimate::diag` of the diagnostic columns.
    chosen: Vec<usize>,
    /// `Some(k)` when the chosen diagnostics are the first `k` (all of
    /// them, or none): the row takes them as one slice, without picking.
    leading: Option<usize>,
}

impl RowFormat {
    fn new(cells: Vec<Cell>, chosen: &[usize]) -> Self {
        let leading = chosen
            .iter()
            .enumerate()
            .all(|(k, &i)| k == i)
            .then_some(chosen.len());
        RowFormat {
            cells,
            chosen: chosen.iter().copied().filter(|&i| i < MAX_DIAG).collect(),
            leading,
        }
    }

    /// Writes `e`'s values before its diagnostics into `head`, one per
    /// column in order; returns how many.
    #[inline]
    fn head(&self, e: &Estimate, head: &mut [f64; MAX_HEAD]) -> usize {
        for (h, c) in head.iter_mut().zip(&self.cells) {
            *h = c.value(e);
        }
        self.cells.len().min(MAX_HEAD)
    }

    /// `e`'s chosen diagnostics, one per column in order (picked into
    /// `picked` unless they lead `e.diag`).
    #[inline]
    fn diag<'a>(
        &self,
        e: &'a Estimate,
        picked: &'a mut [Option<f64>; MAX_DIAG],
    ) -> &'a [Option<f64>] {
        if let Some(k) = self.leading {
            return e.diag.get(..k).unwrap_or(&e.diag);
        }
        for (p, &i) in picked.iter_mut().zip(&self.chosen) {
            *p = e.diag.get(i).copied().flatten();
        }
        &picked[..self.chosen.len()]
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

    /// What the estimate carries, for choosing its evaluation.
    pub fn content(&self) -> limbfuse_eval::EstimateContent {
        limbfuse_eval::EstimateContent {
            events_or_speed: self.speed.is_some() || self.contact.iter().any(Option::is_some),
            angles: self.angle.iter().any(Option::is_some),
        }
    }

    /// Which angle channels (in `AngleChannel::ALL` order) the estimate
    /// has a column of (`AngleMetrics::set_carried_channels`).
    pub fn carried_angles(&self) -> [bool; 7] {
        core::array::from_fn(|k| self.angle[k].is_some())
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
