use super::*;
use crate::TrialReader;
use proptest::prelude::*;

const HEAD: &str = "# format: limbfuse-trial/1\n# sample_rate_hz: 100\nt,knee_enc,note\n";

/// Writes `rows` (after [`HEAD`]) to a temporary file, repairs it and
/// returns the report and the output's text.
fn repaired(rows: &str, order: TimeOrder) -> (TimeRepairReport, String) {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.csv");
    let output = dir.path().join("out.csv");
    std::fs::write(&input, format!("{HEAD}{rows}")).unwrap();
    let report = repair_time(&input, &output, order).unwrap();
    (report, std::fs::read_to_string(&output).unwrap())
}

/// The data rows of an output (after its header).
fn data(text: &str) -> Vec<&str> {
    let mut lines = text.lines().skip_while(|l| l.starts_with('#'));
    lines.next(); // header
    lines.collect()
}

#[test]
fn a_clean_file_is_copied_cell_for_cell() {
    let rows = "0,0.1,a\n0.01,0.125000,\n0.02,,\"x, y\"\n";
    let (r, out) = repaired(rows, TimeOrder::Drop);
    assert!(r.was_clean());
    assert_eq!((r.rows_read, r.rows_kept), (3, 3));
    // the cells as written (`0.125000` is not re-formatted), quoting kept
    assert_eq!(data(&out), ["0,0.1,a", "0.01,0.125000,", "0.02,,\"x, y\""]);
    assert!(out.starts_with("# format: limbfuse-trial/1\n# sample_rate_hz: 100\n"));
    assert!(out.contains("# time_repaired: 3 of 3 rows kept\n"), "{out}");
}

#[test]
fn a_duplicate_row_is_dropped_and_a_same_time_row_keeps_the_first() {
    // line 4 is t = 0; line 6 repeats line 5 exactly; line 7 has line 5's time, another value
    let rows = "0,0.1,\n0.01,0.2,\n0.01,0.2,\n0.01,0.3,\n0.02,0.4,\n";
    let (r, out) = repaired(rows, TimeOrder::Drop);
    assert_eq!(data(&out), ["0,0.1,", "0.01,0.2,", "0.02,0.4,"]);
    assert_eq!(
        r.dropped,
        [
            DroppedRow {
                line: 6,
                t: 0.01,
                reason: DropReason::Duplicate,
                kept_line: Some(5)
            },
            DroppedRow {
                line: 7,
                t: 0.01,
                reason: DropReason::SameTimeOtherValues,
                kept_line: Some(5)
            },
        ]
    );
    assert_eq!(r.largest_step_back_s, 0.0);
}

#[test]
fn one_late_time_stamp_costs_its_row_only() {
    // 0.00 .. 0.09 with the row at 0.04 stamped 0.54 (a clock read glitch)
    let mut rows = String::new();
    for k in 0..10 {
        let t = if k == 4 { 0.54 } else { k as f64 / 100.0 };
        rows += &format!("{t},{k},\n");
    }
    let (r, out) = repaired(&rows, TimeOrder::Drop);
    assert_eq!(r.rows_kept, 9);
    assert_eq!(r.count(DropReason::OutOfOrder), 1);
    assert_eq!(r.dropped[0].line, 8); // data starts at line 4
    assert_eq!(r.dropped[0].t, 0.54);
    assert!((r.largest_step_back_s - 0.49).abs() < 1e-12);
    assert!(!data(&out).contains(&"0.54,4,"));
    // and an early one (0.04 stamped -0.5) the same way
    let rows = rows.replace("0.54,4,", "-0.5,4,");
    let (r, _) = repaired(&rows, TimeOrder::Drop);
    assert_eq!((r.rows_kept, r.dropped[0].line), (9, 8));
}

/// Found on the shared 1.2 m/s walk with 30 glitches: a stamp 0.5 s late
/// that equals the stamp of the row 0.5 s on (bit for bit) cost that row
/// too, as "the same time with other values", when every earlier row was
/// compared; now only the late row goes.
#[test]
fn a_late_stamp_equal_to_a_later_one_costs_the_late_row_only() {
    let mut rows = String::new();
    for k in 0..60 {
        // row 5 stamped 0.5 s late: 0.05 + 0.5 == 0.55 in binary floating point
        let t = if k == 5 { 0.05 + 0.5 } else { k as f64 / 100.0 };
        rows += &format!("{t},{k},\n");
    }
    assert_eq!(0.05 + 0.5, 55.0 / 100.0);
    let (r, out) = repaired(&rows, TimeOrder::Drop);
    assert_eq!(r.rows_kept, 59);
    assert_eq!(
        r.dropped,
        [DroppedRow {
            line: 9,
            t: 0.55,
            reason: DropReason::OutOfOrder,
            kept_line: None
        }]
    );
    assert!(data(&out).contains(&"0.55,55,"));
    // sorted instead, the late row lands on 0.55 s and is kept there (the
    // first in file order): the report counts it as a wrong stamp
    let (r, out) = repaired(&rows, TimeOrder::Sort);
    assert_eq!((r.moved, r.sorted_onto_a_taken_time), (1, 1));
    assert!(data(&out).contains(&"0.55,5,"));
}

#[test]
fn a_swapped_pair_loses_one_row_or_is_sorted() {
    let rows = "0,0,\n0.01,1,\n0.03,3,\n0.02,2,\n0.04,4,\n";
    let (r, out) = repaired(rows, TimeOrder::Drop);
    assert_eq!(r.rows_kept, 4);
    assert_eq!(r.count(DropReason::OutOfOrder), 1);
    assert_eq!(r.moved, 0);
    let kept = data(&out);
    assert!(kept.windows(2).all(|w| {
        let t = |s: &str| s.split(',').next().unwrap().parse::<f64>().unwrap();
        t(w[0]) < t(w[1])
    }));
    let (r, out) = repaired(rows, TimeOrder::Sort);
    assert_eq!(
        (r.rows_kept, r.moved, r.sorted_onto_a_taken_time),
        (5, 1, 0)
    );
    assert!(r.dropped.is_empty());
    assert_eq!(
        data(&out),
        ["0,0,", "0.01,1,", "0.02,2,", "0.03,3,", "0.04,4,"]
    );
    assert!(out.contains("1 rows moved into time order"), "{out}");
}

#[test]
fn a_clock_reset_is_reported_as_a_block_of_lines() {
    // 0 .. 0.09 s, then the clock restarts at 0.05 s for ten rows
    let mut rows = String::new();
    for k in 0..10 {
        rows += &format!("{},{k},\n", k as f64 / 100.0);
    }
    for k in 0..10 {
        rows += &format!("{},{},\n", (k + 5) as f64 / 100.0, k + 10);
    }
    let (r, _) = repaired(&rows, TimeOrder::Drop);
    assert_eq!(r.rows_read, 20);
    // 15 rows keep their order (e.g. 0..0.04 then the second block's ten)
    assert_eq!(r.rows_kept, 15);
    assert_eq!(r.dropped.len(), 5);
    assert_eq!(r.dropped_share(), 0.25);
    // the five dropped rows are consecutive lines
    let ranges = r.line_ranges(DropReason::OutOfOrder, 3);
    assert!(!ranges.contains(','), "{ranges}");
    assert!((r.median_step_s - 0.01).abs() < 1e-12);
    assert!(!r.steps_back_are_jitter());
}

#[test]
fn stamps_that_jitter_by_more_than_half_a_period_are_told_from_a_jump() {
    // rows in order, stamps k / 100 + (0, +6, -6, 0) ms in turn: steps of
    // 16, -2, 16, 10 ms, so every step back (2 ms) is under the median
    // forward step (16 ms)
    let mut rows = String::new();
    for k in 0..40 {
        let jitter = if k % 4 == 1 {
            0.006
        } else if k % 4 == 2 {
            -0.006
        } else {
            0.0
        };
        rows += &format!("{},{k},\n", k as f64 / 100.0 + jitter);
    }
    let (r, _) = repaired(&rows, TimeOrder::Drop);
    assert!(r.count(DropReason::OutOfOrder) > 0);
    assert!(
        (r.largest_step_back_s - 0.002).abs() < 1e-9,
        "{}",
        r.largest_step_back_s
    );
    assert!(r.steps_back_are_jitter());
    let (r, out) = repaired(&rows, TimeOrder::Sort);
    assert_eq!(r.rows_kept, 40);
    assert_eq!(data(&out).len(), 40);
}

#[test]
fn the_repaired_file_reads_as_a_trial() {
    let rows = "0,0.1,\n0.02,0.3,\n0.01,0.2,\n0.02,0.3,\n0.03,0.4,\n";
    // the original stops the trial reader at line 6
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.csv");
    std::fs::write(&input, format!("{HEAD}{rows}")).unwrap();
    let mut reader = TrialReader::open(&input).unwrap();
    let err = loop {
        match reader.next_record() {
            Ok(Some(_)) => {}
            Ok(None) => panic!("read to the end"),
            Err(e) => break e.to_string(),
        }
    };
    assert!(err.contains("in.csv:6: column 1 (`t`)"), "{err}");
    let output = dir.path().join("out.csv");
    let r = repair_time(&input, &output, TimeOrder::Drop).unwrap();
    // line 7 repeats line 5 further on: 0, 0.01, 0.02 (line 7), 0.03 are in
    // order, and line 5 is the one out of order
    assert_eq!((r.rows_kept, r.dropped.len()), (4, 1));
    assert_eq!(
        (r.dropped[0].line, r.dropped[0].reason),
        (5, DropReason::OutOfOrder)
    );
    let mut reader = TrialReader::open(&output).unwrap();
    let mut n = 0;
    while let Some(rec) = reader.next_record().unwrap() {
        assert!(rec.sample.encoder[1].is_some());
        n += 1;
    }
    assert_eq!(n, 4);
}

#[test]
fn a_missing_time_stays_an_error_with_its_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.csv");
    std::fs::write(&input, format!("{HEAD}0,0.1,\n,0.2,\n")).unwrap();
    let e = repair_time(&input, &dir.path().join("o.csv"), TimeOrder::Drop).unwrap_err();
    let m = e.to_string();
    assert!(m.contains("in.csv:5: column 1 (`t`)"), "{m}");
    assert!(!dir.path().join("o.csv").exists());
}

#[test]
fn line_ranges_join_consecutive_lines() {
    assert_eq!(line_ranges(&[3, 4, 5, 9, 11, 12], 5), "3-5, 9, 11-12");
    assert_eq!(line_ranges(&[3, 5, 7], 2), "3, 5, ...");
    assert_eq!(line_ranges(&[], 2), "");
}

/// Length of a longest strictly increasing subsequence, O(n^2) dynamic
/// programming: the reference of [`longest_increasing`].
fn lis_length_quadratic(t: &[f64]) -> usize {
    let mut best = vec![1usize; t.len()];
    for i in 0..t.len() {
        for j in 0..i {
            if t[j] < t[i] {
                best[i] = best[i].max(best[j] + 1);
            }
        }
    }
    best.into_iter().max().unwrap_or(0)
}

proptest! {
    /// The rows kept are increasing, in file order, and as many as the
    /// longest increasing subsequence has.
    #[test]
    fn the_rows_kept_are_a_longest_increasing_run(t in prop::collection::vec(0u8..40, 0..60)) {
        let t: Vec<f64> = t.into_iter().map(f64::from).collect();
        let kept = longest_increasing(&t);
        prop_assert_eq!(kept.len(), lis_length_quadratic(&t));
        prop_assert!(kept.windows(2).all(|w| w[0] < w[1] && t[w[0] as usize] < t[w[1] as usize]));
    }
}

/// The rows [`repair_time`] keeps, computed the plain way on the rows in
/// memory: drop a row whose time equals the last kept candidate's, then the
/// rows outside a longest increasing run (drop) or sort them, keeping the
/// first of equal times (sort).
fn oracle(rows: &[(f64, u32)], order: TimeOrder) -> Vec<(f64, u32)> {
    let mut cand: Vec<(f64, u32)> = Vec::new();
    for &r in rows {
        if cand.last().map(|c| c.0) != Some(r.0) {
            cand.push(r);
        }
    }
    let t: Vec<f64> = cand.iter().map(|c| c.0).collect();
    match order {
        TimeOrder::Drop => longest_increasing(&t)
            .into_iter()
            .map(|p| cand[p as usize])
            .collect(),
        TimeOrder::Sort => {
            let mut sorted = cand.clone();
            sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
            sorted.dedup_by(|b, a| a.0 == b.0);
            sorted
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// The file written holds the oracle's rows, in its order, and its time
    /// increases; the report adds up.
    #[test]
    fn the_two_passes_write_the_rows_a_plain_repair_keeps(
        rows in prop::collection::vec((0u8..30, 0u32..3), 0..80),
        sort in any::<bool>(),
    ) {
        let rows: Vec<(f64, u32)> = rows.into_iter().map(|(t, v)| (f64::from(t) / 100.0, v)).collect();
        let text: String = rows.iter().map(|(t, v)| format!("{t},{v},\n")).collect();
        let order = if sort { TimeOrder::Sort } else { TimeOrder::Drop };
        let (r, out) = repaired(&text, order);
        let written: Vec<(f64, u32)> = data(&out)
            .iter()
            .map(|l| {
                let mut c = l.split(',');
                (c.next().unwrap().parse().unwrap(), c.next().unwrap().parse().unwrap())
            })
            .collect();
        prop_assert_eq!(&written, &oracle(&rows, order));
        prop_assert!(written.windows(2).all(|w| w[0].0 < w[1].0));
        prop_assert_eq!(r.rows_read, rows.len());
        prop_assert_eq!(r.rows_kept + r.dropped.len(), rows.len());
    }
}
