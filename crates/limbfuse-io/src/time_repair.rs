//! A trial's time column made usable (`limbfuse repair-time`): SPEC section 2
//! asks for `t` strictly increasing, and every reader stops at the first row
//! that breaks it (the line and column of the row). Real recordings break it
//! in three ways, which this module tells apart and repairs by dropping rows
//! (or, on request, by sorting them), never by inventing a time stamp:
//!
//! * an **exact duplicate**: a row whose `t` and every other cell repeat an
//!   earlier row (a logger that wrote a packet twice): dropped;
//! * **the same time, other values**: a row whose `t` repeats the row
//!   before it but whose cells differ. Which of the two readings belongs to
//!   that instant cannot be told from the file: the first is kept, the later
//!   one dropped. (Only the row before: a stamp 0.5 s late can equal, bit
//!   for bit, the stamp of the row 0.5 s on, and that row is the one to
//!   keep; the late one goes as out of order.);
//! * **out of order**: a row whose time stamp goes back. With
//!   [`TimeOrder::Drop`] (the default) the rows kept are one of the longest
//!   runs of rows, in file order, whose time increases (a longest strictly
//!   increasing subsequence of `t`), so one wrong time stamp (a clock read
//!   glitch: one row 0.5 s late) costs that row only and a swapped pair costs
//!   one of its two rows; the estimators treat the dropped rows as a gap.
//!   With [`TimeOrder::Sort`] the rows are put in time order instead (stable),
//!   which is right when the rows are packets that arrived out of order but
//!   carry their sensor's time stamps, and wrong when a time stamp is wrong.
//!
//! The cells are copied as written (no number is re-read or re-formatted;
//! an Arrow input's numbers are written as the trial writer writes them),
//! unknown columns included; the metadata lines are kept and one is added,
//! `# time_repaired:`, saying what was dropped.
//!
//! A recording whose clock was reset, or two recordings joined, also breaks
//! the order, and no repair is right for it: the report gives the dropped
//! rows as line ranges and their share, so that a long block is seen
//! ([`TimeRepairReport::dropped_share`]).

use std::collections::HashMap;
use std::io::{self, Write};
use std::path::Path;

use crate::cell_format::push_value;
use crate::error::FileError;
use crate::table::{Row, TableReader};

/// What [`repair_time`] does with rows whose time stamp goes back.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TimeOrder {
    /// Keep one of the longest runs of rows, in file order, whose time
    /// increases; drop the others (module docs).
    #[default]
    Drop,
    /// Sort the rows by time (stable).
    Sort,
}

/// Why a row was dropped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DropReason {
    /// Every cell repeats the row at `kept_line`.
    Duplicate,
    /// `t` repeats the row at `kept_line` (the row before it, or with
    /// [`TimeOrder::Sort`] the row sorted before it), other cells differ.
    SameTimeOtherValues,
    /// Its time stamp breaks the order of the rows kept ([`TimeOrder::Drop`]).
    OutOfOrder,
}

impl DropReason {
    /// Every reason, in the order the reports list them.
    pub const ALL: [DropReason; 3] = [
        DropReason::Duplicate,
        DropReason::SameTimeOtherValues,
        DropReason::OutOfOrder,
    ];

    /// Its name in Python's `limbfuse.repair_time` report.
    pub const fn name(self) -> &'static str {
        match self {
            DropReason::Duplicate => "duplicate",
            DropReason::SameTimeOtherValues => "same_time_other_values",
            DropReason::OutOfOrder => "out_of_order",
        }
    }

    /// How the report names it.
    pub const fn said(self) -> &'static str {
        match self {
            DropReason::Duplicate => "exact duplicates of an earlier row",
            DropReason::SameTimeOtherValues => {
                "rows with the time of the row before and other values (that one kept)"
            }
            DropReason::OutOfOrder => "time stamps out of order",
        }
    }
}

/// One dropped row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DroppedRow {
    /// 1-based line (an Arrow file: 1-based row number).
    pub line: u64,
    /// Its time (s).
    pub t: f64,
    /// Why.
    pub reason: DropReason,
    /// The earlier row it repeats (duplicates and same-time rows).
    pub kept_line: Option<u64>,
}

/// What [`repair_time`] found and did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TimeRepairReport {
    /// Data rows read.
    pub rows_read: usize,
    /// Rows written.
    pub rows_kept: usize,
    /// Rows dropped, in file order.
    pub dropped: Vec<DroppedRow>,
    /// The fewest rows that had to move to put the rows in time order
    /// ([`TimeOrder::Sort`]: the rows but one of the longest runs already in
    /// order).
    pub moved: usize,
    /// Rows that sorting brought onto the time of another row (with other
    /// values; [`TimeOrder::Sort`]). Packets that merely arrived out of order
    /// each keep a time of their own, so these are stamps that are wrong:
    /// [`TimeOrder::Drop`] is the repair for them.
    pub sorted_onto_a_taken_time: usize,
    /// Largest step back in time between two consecutive rows of the input
    /// (s; 0 when `t` never goes back).
    pub largest_step_back_s: f64,
    /// Median of the input's forward time steps (s; 0 without any): with
    /// [`TimeRepairReport::largest_step_back_s`] it tells stamps that jitter
    /// (every step back under a sample period) from a clock that jumps.
    pub median_step_s: f64,
}

impl TimeRepairReport {
    /// Rows dropped for `reason`.
    pub fn count(&self, reason: DropReason) -> usize {
        self.dropped.iter().filter(|d| d.reason == reason).count()
    }

    /// Whether every step back is shorter than the median forward step: time
    /// stamps that jitter by about a sample period, not a clock that jumps
    /// (the rows are then likely in order, their stamps noisy).
    pub fn steps_back_are_jitter(&self) -> bool {
        self.largest_step_back_s > 0.0 && self.largest_step_back_s < self.median_step_s
    }

    /// Share of the rows read that were dropped (0-1).
    pub fn dropped_share(&self) -> f64 {
        if self.rows_read == 0 {
            0.0
        } else {
            self.dropped.len() as f64 / self.rows_read as f64
        }
    }

    /// Whether the input's time already increased strictly (nothing dropped
    /// or moved).
    pub fn was_clean(&self) -> bool {
        self.dropped.is_empty() && self.moved == 0
    }

    /// The lines of the rows dropped for `reason` as ranges of consecutive
    /// lines (`12`, `40-44`), at most `max` of them, then `...`.
    pub fn line_ranges(&self, reason: DropReason, max: usize) -> String {
        let lines: Vec<u64> = self
            .dropped
            .iter()
            .filter(|d| d.reason == reason)
            .map(|d| d.line)
            .collect();
        line_ranges(&lines, max)
    }

    /// One line per reason with rows dropped: how many, why, and their
    /// lines (at most `max_ranges` ranges): `10 exact duplicates of an
    /// earlier row (line 279, 305)`.
    pub fn dropped_lines(&self, max_ranges: usize) -> Vec<String> {
        DropReason::ALL
            .into_iter()
            .filter(|&r| self.count(r) > 0)
            .map(|r| {
                format!(
                    "{} {} (line {})",
                    self.count(r),
                    r.said(),
                    self.line_ranges(r, max_ranges)
                )
            })
            .collect()
    }

    /// The value of the `# time_repaired:` metadata line.
    pub fn metadata_value(&self, order: TimeOrder) -> String {
        let mut parts = vec![format!(
            "{} of {} rows kept",
            self.rows_kept, self.rows_read
        )];
        for reason in DropReason::ALL {
            let n = self.count(reason);
            if n > 0 {
                parts.push(format!("{n} dropped: {}", reason.said()));
            }
        }
        if order == TimeOrder::Sort && self.moved > 0 {
            parts.push(format!("{} rows moved into time order", self.moved));
        }
        parts.join("; ")
    }
}

/// Consecutive numbers as ranges, at most `max` ranges then `...`.
fn line_ranges(lines: &[u64], max: usize) -> String {
    let mut ranges: Vec<(u64, u64)> = Vec::new();
    for &l in lines {
        match ranges.last_mut() {
            Some((_, end)) if *end + 1 == l => *end = l,
            _ => ranges.push((l, l)),
        }
    }
    let mut out: Vec<String> = ranges
        .iter()
        .take(max)
        .map(|&(a, b)| {
            if a == b {
                a.to_string()
            } else {
                format!("{a}-{b}")
            }
        })
        .collect();
    if ranges.len() > max {
        out.push("...".into());
    }
    out.join(", ")
}

/// The rows of a table: each row's time, line and CSV text (cells joined by
/// commas, quoted where they must be), in one buffer.
struct Rows {
    t: Vec<f64>,
    line: Vec<u64>,
    span: Vec<(usize, usize)>,
    text: Vec<u8>,
}

impl Rows {
    fn text(&self, i: usize) -> &[u8] {
        let (a, b) = self.span[i];
        &self.text[a..b]
    }
}

/// Appends `cell` as a CSV cell (quoted when it holds a comma, a quote or a
/// line break).
fn push_csv_cell(out: &mut Vec<u8>, cell: &[u8]) {
    if cell
        .iter()
        .any(|&c| matches!(c, b',' | b'"' | b'\n' | b'\r'))
    {
        out.push(b'"');
        for &c in cell {
            if c == b'"' {
                out.push(b'"');
            }
            out.push(c);
        }
        out.push(b'"');
    } else {
        out.extend_from_slice(cell);
    }
}

/// Appends the row's cells as CSV; an Arrow number (no text) is formatted.
fn push_row(out: &mut Vec<u8>, row: &Row<'_>, columns: usize, buf: &mut zmij::Buffer) {
    for col in 0..columns {
        if col > 0 {
            out.push(b',');
        }
        let text = row.text(col);
        if text.is_empty() {
            // (a CSV empty cell stays empty; an Arrow number has no text)
            if let Ok(Some(v)) = row.number(col) {
                push_value(out, buf, Some(v));
            }
        } else {
            push_csv_cell(out, text);
        }
    }
}

fn read_rows(table: &mut TableReader) -> Result<Rows, FileError> {
    let t_col = table.time_column()?;
    let columns = table.header().len();
    let mut rows = Rows {
        t: Vec::new(),
        line: Vec::new(),
        span: Vec::new(),
        text: Vec::new(),
    };
    let mut buf = zmij::Buffer::new();
    while let Some(row) = table.next_row()? {
        // (present and finite; its order is this module's business)
        let t = row.time(t_col, None)?;
        let start = rows.text.len();
        push_row(&mut rows.text, &row, columns, &mut buf);
        rows.t.push(t);
        rows.line.push(row.line());
        rows.span.push((start, rows.text.len()));
    }
    Ok(rows)
}

/// Row `i` dropped for repeating the time of row `kept` (kept).
fn same_time(rows: &Rows, i: usize, kept: usize) -> DroppedRow {
    DroppedRow {
        line: rows.line[i],
        t: rows.t[i],
        reason: DropReason::SameTimeOtherValues,
        kept_line: Some(rows.line[kept]),
    }
}

/// Indices (into `t`) of one longest strictly increasing subsequence, in
/// order (patience sorting with predecessor links, O(n log n)).
fn longest_increasing(t: &[f64], among: &[usize]) -> Vec<usize> {
    // tails[k]: position in `among` of the smallest last value of an
    // increasing run of length k + 1 found so far
    let mut tails: Vec<usize> = Vec::new();
    let mut prev: Vec<Option<usize>> = vec![None; among.len()];
    for (p, &i) in among.iter().enumerate() {
        let k = tails.partition_point(|&q| t[among[q]] < t[i]);
        prev[p] = k.checked_sub(1).map(|j| tails[j]);
        if k == tails.len() {
            tails.push(p);
        } else {
            tails[k] = p;
        }
    }
    let mut out = Vec::with_capacity(tails.len());
    let mut at = tails.last().copied();
    while let Some(p) = at {
        out.push(among[p]);
        at = prev[p];
    }
    out.reverse();
    out
}

/// Reads the trial (CSV or Arrow) at `input`, repairs its time column as the
/// module docs say, and writes a CSV trial file to `output` (atomically).
pub fn repair_time(
    input: &Path,
    output: &Path,
    order: TimeOrder,
) -> Result<TimeRepairReport, FileError> {
    let mut table = TableReader::open(input)?;
    let rows = read_rows(&mut table)?;
    let (report, kept) = plan(&rows, order);
    write_rows(&table, &rows, &kept, output, &report.metadata_value(order))
        .map_err(|e| FileError::io(output, e))?;
    Ok(report)
}

/// What [`repair_time`] with [`TimeOrder::Drop`] would drop from the trial
/// at `input`, without writing anything (`limbfuse inspect` on a file whose
/// time does not increase).
pub fn time_problems(input: &Path) -> Result<TimeRepairReport, FileError> {
    let mut table = TableReader::open(input)?;
    let rows = read_rows(&mut table)?;
    Ok(plan(&rows, TimeOrder::Drop).0)
}

/// The report and the rows to keep, in output order.
fn plan(rows: &Rows, order: TimeOrder) -> (TimeRepairReport, Vec<usize>) {
    let n = rows.t.len();
    let mut report = TimeRepairReport {
        rows_read: n,
        ..TimeRepairReport::default()
    };
    let mut forward = Vec::with_capacity(n);
    for w in rows.t.windows(2) {
        report.largest_step_back_s = report.largest_step_back_s.max(w[0] - w[1]);
        if w[1] > w[0] {
            forward.push(w[1] - w[0]);
        }
    }
    if !forward.is_empty() {
        let mid = forward.len() / 2;
        report.median_step_s = *forward.select_nth_unstable_by(mid, f64::total_cmp).1;
    }
    // Exact duplicates: every cell (so the time too) of an earlier row.
    let mut first_at: HashMap<u64, usize> = HashMap::with_capacity(n);
    let mut unique = Vec::with_capacity(n);
    for i in 0..n {
        let key = (rows.t[i] + 0.0).to_bits();
        match first_at.get(&key) {
            Some(&j) if rows.text(i) == rows.text(j) => report.dropped.push(DroppedRow {
                line: rows.line[i],
                t: rows.t[i],
                reason: DropReason::Duplicate,
                kept_line: Some(rows.line[j]),
            }),
            Some(_) => unique.push(i),
            None => {
                first_at.insert(key, i);
                unique.push(i);
            }
        }
    }
    // A row with the time of the row before it (other values): the first
    // is kept. (Not any earlier row: a stamp 0.5 s late can equal, bit for
    // bit, the stamp of the row 0.5 s on, which is the one to keep.)
    let mut candidates = Vec::with_capacity(unique.len());
    for &i in &unique {
        match candidates.last() {
            Some(&j) if rows.t[j] == rows.t[i] => {
                report.dropped.push(same_time(rows, i, j));
            }
            _ => candidates.push(i),
        }
    }
    let kept = match order {
        TimeOrder::Drop => {
            let kept = longest_increasing(&rows.t, &candidates);
            let mut in_kept = vec![false; n];
            for &i in &kept {
                in_kept[i] = true;
            }
            for &i in &candidates {
                if !in_kept[i] {
                    report.dropped.push(DroppedRow {
                        line: rows.line[i],
                        t: rows.t[i],
                        reason: DropReason::OutOfOrder,
                        kept_line: None,
                    });
                }
            }
            kept
        }
        TimeOrder::Sort => {
            // the fewest rows that have to move: all but a longest run in order
            report.moved = candidates.len() - longest_increasing(&rows.t, &candidates).len();
            let mut sorted = candidates;
            sorted.sort_by(|&a, &b| rows.t[a].total_cmp(&rows.t[b]));
            // equal times brought together: the first in file order is kept
            let mut kept: Vec<usize> = Vec::with_capacity(sorted.len());
            for i in sorted {
                match kept.last() {
                    Some(&j) if rows.t[j] == rows.t[i] => {
                        report.dropped.push(same_time(rows, i, j));
                        report.sorted_onto_a_taken_time += 1;
                    }
                    _ => kept.push(i),
                }
            }
            kept
        }
    };
    report.dropped.sort_by_key(|d| d.line);
    report.rows_kept = kept.len();
    (report, kept)
}

/// Writes the metadata, `# time_repaired: repaired`, the header and the
/// `kept` rows.
fn write_rows(
    table: &TableReader,
    rows: &Rows,
    kept: &[usize],
    output: &Path,
    repaired: &str,
) -> io::Result<()> {
    let mut file = crate::AtomicFile::create(output)?;
    {
        let mut out = io::BufWriter::new(&mut file);
        for (k, v) in table.meta().entries() {
            if k != TIME_REPAIRED_KEY {
                writeln!(out, "# {k}: {v}")?;
            }
        }
        writeln!(
            out,
            "# {TIME_REPAIRED_KEY}: {}",
            crate::provenance::one_line(repaired)
        )?;
        let mut header = Vec::new();
        for (c, name) in table.header().iter().enumerate() {
            if c > 0 {
                header.push(b',');
            }
            push_csv_cell(&mut header, name.as_bytes());
        }
        header.push(b'\n');
        out.write_all(&header)?;
        for &i in kept {
            out.write_all(rows.text(i))?;
            out.write_all(b"\n")?;
        }
        out.flush()?;
    }
    file.commit()
}

/// The metadata key [`repair_time`] adds.
pub const TIME_REPAIRED_KEY: &str = "time_repaired";

#[cfg(test)]
mod tests;
