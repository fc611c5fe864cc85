//! `limbfuse repair-time TRIAL -o OUT [--out-of-order drop|sort]`: a copy of a
//! trial whose time increases strictly (`limbfuse_io::time_repair`).

use anyhow::{bail, Context, Result};
use limbfuse_io::time_repair::{repair_time, TimeOrder, TimeRepairReport};

use crate::cli::{RepairTimeArgs, TimeOrderArg};

/// Share of dropped rows beyond which the report warns that this is more
/// than a glitch: 1 % (at 100 Hz, one row in each second dropped).
const MANY_DROPPED: f64 = 0.01;

/// Line ranges shown per reason.
pub const RANGES_SHOWN: usize = 8;

/// Repairs the trial's time column and says what was dropped or moved.
pub fn run(a: &RepairTimeArgs) -> Result<()> {
    super::refuse_stdout(&a.output)?;
    super::refuse_input_as_output(&a.trial, &a.output)?;
    if limbfuse_io::arrow_file::is_arrow_path(&a.output) {
        bail!(
            "-o {}: `repair-time` writes a CSV trial file; name the output `.csv` (an Arrow input is \
             read, its rows written as CSV)",
            a.output.display()
        );
    }
    let order = match a.out_of_order {
        TimeOrderArg::Drop => TimeOrder::Drop,
        TimeOrderArg::Sort => TimeOrder::Sort,
    };
    let r = repair_time(&a.trial, &a.output, order)
        .with_context(|| format!("repairing the time of {}", a.trial.display()))?;
    eprint!("{}", said(a, &r));
    Ok(())
}

/// The report on stderr.
fn said(a: &RepairTimeArgs, r: &TimeRepairReport) -> String {
    let (input, output) = (a.trial.display(), a.output.display());
    // (a last line cut off while the file was written is left out, as every
    // reader leaves it out: docs/ROBUST_INPUT.md 2o)
    let cut = r.cut_last_line.map_or_else(String::new, |c| {
        format!("warning: {}\n", c.message(&a.trial))
    });
    if r.was_clean() {
        return format!(
            "{input}: the time already increases on every row; {} rows copied -> {output}\n{cut}",
            r.rows_read
        );
    }
    let mut out = format!(
        "repaired the time of {input}: {} of {} rows kept -> {output}\n",
        r.rows_kept, r.rows_read
    );
    for line in r.dropped_lines(RANGES_SHOWN) {
        out += &format!("  dropped: {line}\n");
    }
    if r.moved > 0 {
        out += &format!("  {} rows moved into time order\n", r.moved);
    }
    if r.largest_step_back_s > 0.0 {
        out += &format!(
            "  largest step back in time: {:.3} s (median step {:.3} s)\n",
            r.largest_step_back_s, r.median_step_s
        );
    }
    if r.sorted_onto_a_taken_time > 0 {
        out += &format!(
            "warning: {input}: {} rows sorted onto the time of another row: packets that only \
             arrived late keep a time of their own, so these time stamps are wrong \
             (`--out-of-order drop` drops them)\n",
            r.sorted_onto_a_taken_time
        );
    }
    if r.dropped_share() > MANY_DROPPED && r.steps_back_are_jitter() {
        out += &format!(
            "warning: {input}: {:.1} % of the rows dropped, every step back shorter than a sample \
             period: time stamps that jitter by that much, on rows likely in order; \
             `--out-of-order sort` keeps every row (docs/ROBUST_INPUT.md 2m)\n",
            100.0 * r.dropped_share()
        );
    } else if r.dropped_share() > MANY_DROPPED {
        out += &format!(
            "warning: {input}: {:.1} % of the rows dropped: more than a glitch (a clock reset or two \
             recordings joined look like this); check the recording before using the copy\n",
            100.0 * r.dropped_share()
        );
    }
    out + &cut
}
