//! Nearest-sample resampling that keeps every run of equal values (the
//! contact references: 1 while a foot is on the ground, 0 in swing).
//!
//! A run shorter than the output period can fall between two output
//! samples and vanish with it: an audit resampled the shared HA001 walks
//! to 60 Hz and lost a reference initial contact (7 -> 6), a contact that
//! the file marks on one row at the end of a bout. Here a run that no output
//! sample stands for takes the output sample nearest its first row, from a
//! run that keeps another one: the event moves by at most half an output
//! period, and no other run disappears for it.

use super::interpolation::{bracket, nominal_period, Bracket};
use super::GAP_FACTOR;

/// The value of the nearest present sample at each time of `grid` (as
/// [`super::interpolation::nearest`]), with every run of equal values in
/// `v` represented by at least one output sample where that takes nothing
/// from another run.
pub(super) fn nearest_keeping_runs(
    t: &[f64],
    v: &[f64],
    grid: &[f64],
    period_out: f64,
) -> Vec<Option<f64>> {
    let p = nominal_period(t);
    let mut src: Vec<Option<usize>> = grid
        .iter()
        .map(|&tg| match bracket(t, tg, p, period_out) {
            Bracket::Pair(a, b, w) => Some(if w <= 0.5 { a } else { b }),
            Bracket::One(k) => Some(k),
            Bracket::Nothing => None,
        })
        .collect();
    // Runs: equal consecutive values with no gap between them.
    let gap = GAP_FACTOR * p.unwrap_or(period_out);
    let mut run = vec![0usize; t.len()];
    let mut starts = Vec::new();
    for i in 0..t.len() {
        let same = i > 0 && v[i] == v[i - 1] && t[i] - t[i - 1] <= gap;
        run[i] = match (i, same) {
            (0, _) => 0,
            (_, true) => run[i - 1],
            (_, false) => run[i - 1] + 1,
        };
        if !same {
            starts.push(i);
        }
    }
    let mut count = vec![0usize; starts.len()];
    for s in src.iter().flatten() {
        count[run[*s]] += 1;
    }
    for (r, &first) in starts.iter().enumerate() {
        if count[r] > 0 {
            continue;
        }
        let j = grid.partition_point(|&x| x < t[first]);
        let mut near: Vec<usize> = [j.checked_sub(1), (j < grid.len()).then_some(j)]
            .into_iter()
            .flatten()
            .filter(|&k| (grid[k] - t[first]).abs() <= period_out)
            .collect();
        near.sort_by(|&a, &b| {
            (grid[a] - t[first])
                .abs()
                .total_cmp(&(grid[b] - t[first]).abs())
        });
        for k in near {
            if let Some(s) = src[k] {
                if count[run[s]] > 1 {
                    count[run[s]] -= 1;
                    src[k] = Some(first);
                    count[r] += 1;
                    break;
                }
            }
        }
    }
    src.iter().map(|s| s.map(|i| v[i])).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A one-row contact at a bout's end (then nothing), resampled from 100
    /// to 60 Hz: plain nearest drops it, this keeps it on the output sample
    /// nearest its row.
    #[test]
    fn a_one_row_run_keeps_an_output_sample() {
        let t: Vec<f64> = (0..60).map(|k| k as f64 * 0.01).collect();
        let mut v = vec![0.0; 60];
        v[59] = 1.0; // the last row: a contact marked on one row
        let grid: Vec<f64> = (0..36).map(|k| k as f64 / 60.0).collect();
        let plain = super::super::interpolation::nearest(&t, &v, &grid, 1.0 / 60.0);
        assert!(!plain.contains(&Some(1.0)), "the case the audit found");
        let kept = nearest_keeping_runs(&t, &v, &grid, 1.0 / 60.0);
        let ones: Vec<usize> = (0..kept.len()).filter(|&k| kept[k] == Some(1.0)).collect();
        assert_eq!(ones.len(), 1);
        assert!((grid[ones[0]] - 0.59).abs() <= 0.5 / 60.0 + 1e-12);
        // every other output sample as plain nearest gives it
        for k in 0..grid.len() {
            if k != ones[0] {
                assert_eq!(kept[k], plain[k]);
            }
        }
    }

    /// Runs longer than the output period come out as plain nearest.
    #[test]
    fn long_runs_are_plain_nearest() {
        let t: Vec<f64> = (0..500).map(|k| k as f64 * 0.01).collect();
        let v: Vec<f64> = (0..500).map(|k| f64::from((k / 60) % 2 == 0)).collect();
        let grid: Vec<f64> = (0..250).map(|k| k as f64 / 50.0).collect();
        let plain = super::super::interpolation::nearest(&t, &v, &grid, 0.02);
        assert_eq!(nearest_keeping_runs(&t, &v, &grid, 0.02), plain);
    }
}
