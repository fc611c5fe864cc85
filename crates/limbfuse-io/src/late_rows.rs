//! Rows whose time does not follow the rows before them, in a stream
//! (`limbfuse estimate --late-rows drop`, docs/STREAMING.md "Rows out of
//! time order").
//!
//! SPEC asks for `t` strictly increasing and every reader stops at the
//! first row that breaks it. A file can be repaired first (`limbfuse
//! repair-time`, which sees the whole file: [`crate::time_repair`]); a live
//! stream cannot, and one bad packet from a logger would end it. With
//! [`LateRows::Drop`] the trial reader passes only rows in time order:
//!
//! - a row whose time is not after the last row passed (a packet written
//!   twice, one that arrived after later ones) is dropped;
//! - a row whose time jumps ahead of the last row passed by more than
//!   [`JUMP_STEPS`] typical steps is held until the next row arrives: if
//!   that row's time is after it, the jump was a gap in the data and both
//!   pass (the held one one read late); if that row falls between the last
//!   row passed and the held one, the held row's stamp was wrong (a stamp
//!   far ahead, which would otherwise have made every row until time caught
//!   up with it "late") and it is dropped instead.
//!
//! The typical step is an exponential mean of the steps passed (weight
//! [`STEP_WEIGHT`]); nothing is allocated per row (a [`Record`] is `Copy`).

use limbfuse_core::Record;

/// What a trial reader does with a row whose time does not follow the row
/// before it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LateRows {
    /// Stop with [`crate::FileError::TimeNotIncreasing`] (SPEC's rule).
    #[default]
    Refuse,
    /// Drop it (module docs) and count it.
    Drop,
}

/// A row more than this many typical steps after the last row passed is
/// held until the next row says whether it was a gap or a wrong stamp: 4
/// (stamp jitter of a third of a period never reaches it; a gap of four
/// lost samples is held one row, which costs only that row's latency).
pub const JUMP_STEPS: f64 = 4.0;

/// Weight of the newest step in the typical step: 0.1 (about the last ten).
pub const STEP_WEIGHT: f64 = 0.1;

/// How many dropped rows' lines are kept for the message.
pub const LINES_KEPT: usize = 5;

/// The rows dropped so far.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LateRowLog {
    /// Rows whose time was not after the row passed before them.
    pub behind: u64,
    /// The first of their lines (1-based, up to [`LINES_KEPT`]).
    pub behind_lines: [u64; LINES_KEPT],
    /// The largest step back (s): the row passed before minus the row's time.
    pub largest_back_s: f64,
    /// Rows held for a jump ahead and dropped: the row after them came
    /// before their time.
    pub ahead: u64,
    /// The first of their lines.
    pub ahead_lines: [u64; LINES_KEPT],
    /// The largest jump ahead dropped (s, from the row passed before it).
    pub largest_ahead_s: f64,
}

impl LateRowLog {
    /// Rows dropped, both kinds.
    pub fn dropped(&self) -> u64 {
        self.behind + self.ahead
    }

    fn note(count: &mut u64, lines: &mut [u64; LINES_KEPT], largest: &mut f64, line: u64, by: f64) {
        if let Some(slot) = lines.get_mut(*count as usize) {
            *slot = line;
        }
        *count += 1;
        *largest = largest.max(by);
    }

    /// The warning `estimate` prints; `None` when nothing was dropped.
    pub fn message(&self) -> Option<String> {
        let lines = |count: u64, lines: &[u64; LINES_KEPT]| {
            let shown = (count as usize).min(LINES_KEPT);
            let mut s = lines[..shown]
                .iter()
                .map(u64::to_string)
                .collect::<Vec<_>>()
                .join(", ");
            if count as usize > shown {
                s += ", ...";
            }
            s
        };
        let mut parts = Vec::new();
        if self.behind > 0 {
            parts.push(format!(
                "{} rows whose time was not after the row before them (line {}; up to {:.6} s back: \
                 written twice or arrived late)",
                self.behind,
                lines(self.behind, &self.behind_lines),
                self.largest_back_s
            ));
        }
        if self.ahead > 0 {
            parts.push(format!(
                "{} rows whose time jumped ahead of the rows after them (line {}; up to {:.6} s \
                 ahead: a wrong stamp)",
                self.ahead,
                lines(self.ahead, &self.ahead_lines),
                self.largest_ahead_s
            ));
        }
        (!parts.is_empty()).then(|| {
            format!(
                "--late-rows drop dropped {}; their samples are not in the estimate, which has that \
                 many rows fewer than the trial (to evaluate, estimate the file `limbfuse \
                 repair-time` makes of the recording: its rule sees the whole file)",
                parts.join(" and ")
            )
        })
    }
}

/// A held row: its record, line and time.
#[derive(Debug, Clone, Copy)]
struct Held {
    record: Record,
    line: u64,
}

/// The [`LateRows::Drop`] rule over a stream of rows (module docs).
#[derive(Debug, Clone, Default)]
pub struct LateRowFilter {
    last_t: Option<f64>,
    typical_step: Option<f64>,
    held: Option<Held>,
    /// A row that passes at the next read (a held row passed before it).
    pending: Option<Record>,
    log: LateRowLog,
}

impl LateRowFilter {
    /// What was dropped so far.
    pub fn log(&self) -> &LateRowLog {
        &self.log
    }

    /// The row `record` read from `line`: `true` when `record` (now) holds
    /// a row to pass, `false` when the next row must be read. After a held
    /// row passes in its place, [`LateRowFilter::take_pending`] gives this
    /// one.
    pub fn offer(&mut self, record: &mut Record, line: u64) -> bool {
        let t = record.sample.t;
        if let Some(h) = self.held {
            let held_t = h.record.sample.t;
            if t > held_t {
                // A gap, not a wrong stamp: both pass, the held one first.
                self.held = None;
                self.last_t = Some(t);
                self.pending = Some(core::mem::replace(record, h.record));
                return true;
            }
            if self.last_t.is_none_or(|last| t > last) {
                // The row falls before the held one's time: that stamp was wrong.
                let by = held_t - self.last_t.unwrap_or(held_t);
                let log = &mut self.log;
                LateRowLog::note(
                    &mut log.ahead,
                    &mut log.ahead_lines,
                    &mut log.largest_ahead_s,
                    h.line,
                    by,
                );
                self.held = None;
                self.pass(t);
                return true;
            }
            self.drop_behind(t, line);
            return false;
        }
        match self.last_t {
            Some(last) if t <= last => {
                self.drop_behind(t, line);
                false
            }
            Some(last) if self.typical_step.is_some_and(|s| t - last > JUMP_STEPS * s) => {
                self.held = Some(Held {
                    record: *record,
                    line,
                });
                false
            }
            _ => {
                self.pass(t);
                true
            }
        }
    }

    /// The row to pass before reading the next (after
    /// [`LateRowFilter::offer`] passed a held row in its place).
    pub fn take_pending(&mut self) -> Option<Record> {
        self.pending.take()
    }

    /// The end of the stream: a row still held passes (nothing came to
    /// contradict it).
    pub fn finish(&mut self) -> Option<Record> {
        self.held.take().map(|h| {
            self.last_t = Some(h.record.sample.t);
            h.record
        })
    }

    fn pass(&mut self, t: f64) {
        if let Some(last) = self.last_t {
            let step = t - last;
            self.typical_step = Some(match self.typical_step {
                Some(s) => s + STEP_WEIGHT * (step - s),
                None => step,
            });
        }
        self.last_t = Some(t);
    }

    fn drop_behind(&mut self, t: f64, line: u64) {
        let by = self.last_t.map_or(0.0, |last| last - t);
        let log = &mut self.log;
        LateRowLog::note(
            &mut log.behind,
            &mut log.behind_lines,
            &mut log.largest_back_s,
            line,
            by,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The times a filter passes from rows at `times` (lines 1, 2, ...),
    /// and its log.
    fn passed(times: &[f64]) -> (Vec<f64>, LateRowLog) {
        let mut f = LateRowFilter::default();
        let mut out = Vec::new();
        for (k, &t) in times.iter().enumerate() {
            let mut r = Record::default();
            r.sample.t = t;
            if f.offer(&mut r, k as u64 + 1) {
                out.push(r.sample.t);
            }
            out.extend(f.take_pending().map(|p| p.sample.t));
        }
        out.extend(f.finish().map(|r| r.sample.t));
        (out, *f.log())
    }

    fn grid(n: usize) -> Vec<f64> {
        (0..n).map(|k| k as f64 * 0.01).collect()
    }

    #[test]
    fn rows_in_order_pass_unchanged() {
        let t = grid(50);
        let (out, log) = passed(&t);
        assert_eq!(out, t);
        assert_eq!(log.dropped(), 0);
        assert_eq!(log.message(), None);
    }

    /// A row written twice and a swapped pair: the repeat and the late row
    /// of the pair go (one row each).
    #[test]
    fn a_repeat_and_a_swapped_pair_lose_one_row_each() {
        let mut t = grid(40);
        t.insert(10, t[9]); // line 11 repeats line 10
        t.swap(25, 26); // line 27 is before line 26
        let (out, log) = passed(&t);
        assert!(out.windows(2).all(|w| w[1] > w[0]), "{out:?}");
        assert_eq!(out.len(), t.len() - 2);
        assert_eq!((log.behind, log.ahead), (2, 0));
        assert_eq!(log.behind_lines[..2], [11, 27]);
        let m = log.message().unwrap();
        assert!(
            m.contains("2 rows whose time was not after") && m.contains("line 11, 27"),
            "{m}"
        );
    }

    /// A stamp 0.5 s ahead: that row goes, not the fifty after it (which a
    /// rule that only compares with the row before would drop).
    #[test]
    fn a_stamp_far_ahead_is_dropped_not_the_rows_after_it() {
        let mut t = grid(200);
        t[100] += 0.5;
        let (out, log) = passed(&t);
        let mut expected = grid(200);
        expected.remove(100);
        assert_eq!(out, expected);
        assert_eq!((log.behind, log.ahead), (0, 1));
        assert_eq!(log.ahead_lines[0], 101);
        assert!(
            (log.largest_ahead_s - 0.51).abs() < 1e-9,
            "{}",
            log.largest_ahead_s
        );
    }

    /// A gap of lost rows (0.3 s) is held one row and passes, the rows
    /// after it too; so does a jump on the last row of the stream.
    #[test]
    fn a_gap_passes_one_row_late() {
        let mut t: Vec<f64> = grid(100);
        t.retain(|&x| !(0.40..0.70).contains(&x));
        t.push(5.0);
        let (out, log) = passed(&t);
        assert_eq!(out, t);
        assert_eq!(log.dropped(), 0);
    }

    /// Stamps jittered by up to a third of the period are never held.
    #[test]
    fn jittered_stamps_pass() {
        let t: Vec<f64> = (0..500)
            .map(|k| k as f64 * 0.01 + 0.0033 * ((k * 7919 % 13) as f64 / 6.0 - 1.0))
            .collect();
        assert!(t.windows(2).all(|w| w[1] > w[0]));
        let (out, log) = passed(&t);
        assert_eq!(out, t);
        assert_eq!(log.dropped(), 0);
    }

    proptest::proptest! {
        /// Whatever the stamps, the rows passed are in strictly increasing
        /// time, in the order read, each read once; a stream already in
        /// order passes whole; every row is passed or counted as dropped.
        #[test]
        fn rows_passed_increase_and_come_from_the_stream(
            steps in proptest::collection::vec(-0.05f64..0.08, 1..300),
        ) {
            let mut t = vec![0.0];
            for s in &steps {
                t.push(t[t.len() - 1] + s);
            }
            let (out, log) = passed(&t);
            proptest::prop_assert!(out.windows(2).all(|w| w[1] > w[0]));
            let mut k = 0;
            for x in &out {
                while k < t.len() && t[k].to_bits() != x.to_bits() {
                    k += 1;
                }
                proptest::prop_assert!(k < t.len(), "{} is not read after the rows before it", x);
                k += 1;
            }
            proptest::prop_assert_eq!(out.len() as u64 + log.dropped(), t.len() as u64);
            if steps.iter().all(|&s| s > 0.0) {
                proptest::prop_assert_eq!(&out, &t);
            }
        }
    }
}
