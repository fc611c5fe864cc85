//! A trial's time column made usable (`limbfuse repair-time`): SPEC section 2
//! asks for `t` strictly increasing, and every reader stops at the first row
//! that breaks it (the line and column of the row). Real recordings break it
//! in three ways, which this module tells apart and repairs by dropping rows
//! (or, on request, by sorting them), never by inventing a time stamp:
//!
//! * an **exact duplicate**: a row whose `t` and every other cell repeat the
//!   row before it (a logger that wrote a packet twice): dropped (a copy
//!   written further on breaks the order, and goes as out of order);
//! * **the same time, other values**: a row whose `t` repeats the row
//!   before it but whose cells differ. Which of the two readings belongs to
//!   that instant cannot be told from the file: the first is kept, the later
//!   one dropped. (Only the row before: a stamp 0.5 s late can equal, bit
//!   for bit, the stamp of the row 0.5 s on, and that row is the one to
//!   keep; the late one goes as out of order);
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
//! Two passes over the input: the first keeps each row's time, line and
//! number (20 bytes a row; about 36 at the peak, with a longest run's
//! links) and the text of one row; the second writes the
//! rows kept (with [`TimeOrder::Sort`], a row read before its turn waits in
//! memory). The cells are copied as written (no number is re-read or re-formatted;
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

    /// How the report names `count` such rows.
    pub const fn said(self, count: usize) -> &'static str {
        match (self, count == 1) {
            (DropReason::Duplicate, true) => "exact duplicate of the row before",
            (DropReason::Duplicate, false) => "exact duplicates of the row before",
            (DropReason::SameTimeOtherValues, true) => {
                "row with the time of the row before and other values (that one kept)"
            }
            (DropReason::SameTimeOtherValues, false) => {
                "rows with the time of the row before and other values (that one kept)"
            }
            (DropReason::OutOfOrder, true) => "time stamp out of order",
            (DropReason::OutOfOrder, false) => "time stamps out of order",
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
    /// The input's last line, left out: cut off while it was written
    /// (docs/ROBUST_INPUT.md 2o).
    pub cut_last_line: Option<crate::table::CutLine>,
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
                    r.said(self.count(r)),
                    self.line_ranges(r, max_ranges)
                )
            })
            .collect()
    }

    /// `` `{command}` would drop N of its M rows: ...`` ([`Self::dropped_lines`]
    /// joined): what `inspect` adds to a time-order error.
    pub fn would_drop(&self, command: &str, max_ranges: usize) -> String {
        format!(
            "`{command}` would drop {} of its {} rows: {}",
            self.dropped.len(),
            self.rows_read,
            self.dropped_lines(max_ranges).join("; ")
        )
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
                parts.push(format!("{n} dropped: {}", reason.said(n)));
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

/// What the first pass keeps: per row that may be written (a *candidate*:
/// not a repeat of the row before), its time, line and row number; the
/// repeats already dropped; the time steps. Memory is 20 bytes per row and
/// the text of one row, whatever the file's length (a week of lower-back
/// recording at 100 Hz is 60 million rows).
struct Scan {
    rows_read: usize,
    t: Vec<f64>,
    line: Vec<u64>,
    row: Vec<u32>,
    dropped: Vec<DroppedRow>,
    largest_step_back_s: f64,
    median_step_s: f64,
    cut_last_line: Option<crate::table::CutLine>,
}

/// The first pass: every row's time; a row with the time of the candidate
/// before it is dropped there (an exact duplicate, or the same time with
/// other values: the first is kept). Only the row before is compared: a
/// stamp 0.5 s late can equal, bit for bit, the stamp of the row 0.5 s on,
/// which is the one to keep (the late one goes as out of order), and a copy
/// written further on is out of order too.
fn scan(table: &mut TableReader) -> Result<Scan, FileError> {
    let t_col = table.time_column()?;
    let columns = table.header().len();
    let mut s = Scan {
        rows_read: 0,
        t: Vec::new(),
        line: Vec::new(),
        row: Vec::new(),
        dropped: Vec::new(),
        largest_step_back_s: 0.0,
        median_step_s: 0.0,
        cut_last_line: None,
    };
    let mut buf = zmij::Buffer::new();
    // the last candidate's text, and the row being compared with it
    let (mut last, mut text) = (Vec::new(), Vec::new());
    let mut forward = Vec::new();
    let mut previous: Option<f64> = None;
    while let Some(row) = table.next_row()? {
        // (present and finite; its order is this module's business)
        let t = row.time(t_col, None)?;
        if let Some(p) = previous {
            s.largest_step_back_s = s.largest_step_back_s.max(p - t);
            if t > p {
                forward.push(t - p);
            }
        }
        previous = Some(t);
        // (row numbers as u32: 4 bytes a row; 2^32 rows would be a file of
        // hundreds of gigabytes)
        let n = u32::try_from(s.rows_read)
            .map_err(|_| FileError::at(row.path(), row.line(), "at most 4294967295 data rows"))?;
        s.rows_read += 1;
        if s.t.last() == Some(&t) {
            text.clear();
            push_row(&mut text, &row, columns, &mut buf);
            s.dropped.push(DroppedRow {
                line: row.line(),
                t,
                reason: if text == last {
                    DropReason::Duplicate
                } else {
                    DropReason::SameTimeOtherValues
                },
                kept_line: s.line.last().copied(),
            });
            continue;
        }
        last.clear();
        push_row(&mut last, &row, columns, &mut buf);
        s.t.push(t);
        s.line.push(row.line());
        s.row.push(n);
    }
    if !forward.is_empty() {
        let mid = forward.len() / 2;
        s.median_step_s = *forward.select_nth_unstable_by(mid, f64::total_cmp).1;
    }
    s.cut_last_line = table.cut_last_line();
    Ok(s)
}

/// Positions (into `t`) of one longest strictly increasing subsequence, in
/// order (patience sorting with predecessor links, O(n log n); positions as
/// u32, `t` shorter than 2^32: [`scan`]).
fn longest_increasing(t: &[f64]) -> Vec<u32> {
    const NONE: u32 = u32::MAX;
    // tails[k]: position of the smallest last value of an increasing run of
    // length k + 1 found so far
    let mut tails: Vec<u32> = Vec::new();
    let mut prev: Vec<u32> = vec![NONE; t.len()];
    for (p, &v) in t.iter().enumerate() {
        let k = tails.partition_point(|&q| t[q as usize] < v);
        prev[p] = k.checked_sub(1).map_or(NONE, |j| tails[j]);
        if k == tails.len() {
            tails.push(p as u32);
        } else {
            tails[k] = p as u32;
        }
    }
    let mut out = Vec::with_capacity(tails.len());
    let mut at = tails.last().copied().unwrap_or(NONE);
    while at != NONE {
        out.push(at);
        at = prev[at as usize];
    }
    out.reverse();
    out
}

/// The report and the rows to write (row numbers in output order).
fn plan(s: Scan, order: TimeOrder) -> (TimeRepairReport, Vec<u32>) {
    let mut report = TimeRepairReport {
        rows_read: s.rows_read,
        dropped: s.dropped,
        largest_step_back_s: s.largest_step_back_s,
        median_step_s: s.median_step_s,
        cut_last_line: s.cut_last_line,
        ..TimeRepairReport::default()
    };
    let in_order = longest_increasing(&s.t);
    let out: Vec<u32> = match order {
        TimeOrder::Drop => {
            let mut next = in_order.iter().peekable();
            for p in 0..s.t.len() {
                if next.peek().is_some_and(|&&q| q as usize == p) {
                    next.next();
                } else {
                    report.dropped.push(DroppedRow {
                        line: s.line[p],
                        t: s.t[p],
                        reason: DropReason::OutOfOrder,
                        kept_line: None,
                    });
                }
            }
            in_order.iter().map(|&p| s.row[p as usize]).collect()
        }
        TimeOrder::Sort => {
            // the fewest rows that have to move: all but a longest run in order
            report.moved = s.t.len() - in_order.len();
            let mut sorted: Vec<u32> = (0..s.t.len() as u32).collect();
            sorted.sort_by(|&a, &b| s.t[a as usize].total_cmp(&s.t[b as usize]));
            // equal times brought together: the first in file order is kept
            let mut kept: Vec<u32> = Vec::with_capacity(sorted.len());
            for p in sorted {
                let (p, last) = (p as usize, kept.last().map(|&q| q as usize));
                match last {
                    Some(q) if s.t[q] == s.t[p] => {
                        report.dropped.push(DroppedRow {
                            line: s.line[p],
                            t: s.t[p],
                            reason: DropReason::SameTimeOtherValues,
                            kept_line: Some(s.line[q]),
                        });
                        report.sorted_onto_a_taken_time += 1;
                    }
                    _ => kept.push(p as u32),
                }
            }
            kept.iter().map(|&p| s.row[p as usize]).collect()
        }
    };
    report.dropped.sort_by_key(|d| d.line);
    report.rows_kept = out.len();
    (report, out)
}

/// Reads the trial (CSV or Arrow) at `input`, repairs its time column as the
/// module docs say, and writes a CSV trial file to `output` (atomically):
/// two passes over the input, the second writing the rows kept.
pub fn repair_time(
    input: &Path,
    output: &Path,
    order: TimeOrder,
) -> Result<TimeRepairReport, FileError> {
    let (report, out) = plan(scan(&mut TableReader::open(input)?)?, order);
    write_rows(
        input,
        output,
        &out,
        report.rows_read,
        &report.metadata_value(order),
    )?;
    Ok(report)
}

/// What [`repair_time`] with [`TimeOrder::Drop`] would drop from the trial
/// at `input`, without writing anything (`limbfuse inspect` on a file whose
/// time does not increase).
pub fn time_problems(input: &Path) -> Result<TimeRepairReport, FileError> {
    Ok(plan(scan(&mut TableReader::open(input)?)?, TimeOrder::Drop).0)
}

/// The second pass: the metadata, `# time_repaired: repaired`, the header
/// and the rows `out` (row numbers, in output order) of the `rows` rows. A
/// row is written when its turn comes; a row read before its turn (sorted
/// later) waits in memory, so that only [`TimeOrder::Sort`] holds rows.
fn write_rows(
    input: &Path,
    output: &Path,
    out: &[u32],
    rows: usize,
    repaired: &str,
) -> Result<(), FileError> {
    let mut table = TableReader::open(input)?;
    let columns = table.header().len();
    let io = |e: io::Error| FileError::io(output, e);
    let mut file = crate::AtomicFile::create(output).map_err(io)?;
    {
        let mut w = io::BufWriter::new(&mut file);
        // the input's metadata (an earlier repair's line replaced) and this one's
        let kept = table.meta().entries().iter();
        let kept = kept.filter(|(k, _)| k != TIME_REPAIRED_KEY);
        crate::cell_format::write_comments(
            &mut w,
            kept.map(|(k, v)| (k.as_str(), v.as_str()))
                .chain([(TIME_REPAIRED_KEY, repaired)]),
        )
        .map_err(io)?;
        let mut line = Vec::new();
        for (c, name) in table.header().iter().enumerate() {
            if c > 0 {
                line.push(b',');
            }
            push_csv_cell(&mut line, name.as_bytes());
        }
        line.push(b'\n');
        w.write_all(&line).map_err(io)?;
        let mut wanted = vec![false; rows];
        for &r in out {
            wanted[r as usize] = true;
        }
        let mut waiting: HashMap<u32, Vec<u8>> = HashMap::new();
        let mut buf = zmij::Buffer::new();
        let (mut next, mut n, mut at) = (0usize, 0usize, 0u64);
        while let Some(row) = table.next_row()? {
            let r = n as u32;
            n += 1;
            at = row.line();
            if !wanted.get(n - 1).copied().unwrap_or(false) {
                continue;
            }
            line.clear();
            push_row(&mut line, &row, columns, &mut buf);
            line.push(b'\n');
            if out[next] != r {
                waiting.insert(r, line.clone());
                continue;
            }
            w.write_all(&line).map_err(io)?;
            next += 1;
            while let Some(text) = out.get(next).and_then(|r| waiting.remove(r)) {
                w.write_all(&text).map_err(io)?;
                next += 1;
            }
        }
        if n != rows || next != out.len() {
            return Err(FileError::at(
                input,
                at,
                format!(
                    "the {rows} rows read a moment before (the file changed while it was repaired)"
                ),
            ));
        }
        w.flush().map_err(io)?;
    }
    file.commit().map_err(io)
}

/// The metadata key [`repair_time`] adds.
pub const TIME_REPAIRED_KEY: &str = "time_repaired";

#[cfg(test)]
mod tests;
