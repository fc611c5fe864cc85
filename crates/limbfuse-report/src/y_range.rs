//! The y range of a whole-trial angle plot when an estimate's start
//! transient (a filter's first seconds, a 90 deg start error) would squash
//! the rest of the trial into a flat line: the range of the reference over
//! the whole trial and of the estimates after [`settle_s`], with the
//! clipped start marked on the plot and stated under it (docs/REPORT.md,
//! "Start transients"). Deterministic: computed from every sample, never
//! from the decimated display points.

use crate::data::Column;

/// The clipped y range of a plot and what it leaves out.
#[derive(Debug, Clone, PartialEq)]
pub struct YClip {
    /// The range shown (data units, before the plot's 5 % padding).
    pub lo: f64,
    /// Its top.
    pub hi: f64,
    /// The range of every value of the plot (what the clip leaves out).
    pub all: [f64; 2],
    /// Time (s since the first sample) of the last estimate sample outside
    /// `lo..=hi`: the clipped start is `0..=until_s`.
    pub until_s: f64,
    /// The estimates (indices into the plot's estimate list) that leave the range.
    pub exceeding: Vec<usize>,
}

/// The leading part of the trial whose estimates are left out of the y
/// range: a fifth of the trial, at most 5 s (a filter's start transient
/// is shorter; when it is longer, the range still holds what remains).
pub fn settle_s(duration_s: f64) -> f64 {
    (0.2 * duration_s).min(5.0)
}

/// The clipping of a plot over times `t` (s since the first sample) of the
/// reference (kept whole) and the estimates; `None` when the values after
/// the start fill at least two thirds of the whole-trial range (nothing
/// squashed: the range is every value, as before).
pub fn start_clip(t: &[f64], reference: Option<&Column>, estimates: &[&Column]) -> Option<YClip> {
    let duration = t.last().copied().unwrap_or(0.0) - t.first().copied().unwrap_or(0.0);
    let settle = t.first().copied().unwrap_or(0.0) + settle_s(duration);
    let mut bulk = [f64::INFINITY, f64::NEG_INFINITY];
    let mut all = bulk;
    let see = |r: &mut [f64; 2], v: f64| {
        if v.is_finite() {
            *r = [r[0].min(v), r[1].max(v)];
        }
    };
    for v in reference.into_iter().flatten().flatten() {
        see(&mut bulk, *v);
        see(&mut all, *v);
    }
    for col in estimates {
        for (k, v) in col.iter().enumerate() {
            let Some(v) = v else { continue };
            see(&mut all, *v);
            if t.get(k).is_some_and(|tk| *tk >= settle) {
                see(&mut bulk, *v);
            }
        }
    }
    if !bulk[0].is_finite() || !all[0].is_finite() {
        return None;
    }
    // (a bulk constant to rounding is plotted +-0.5 around it, svg.rs)
    let span = (bulk[1] - bulk[0]).max(1.0);
    if all[1] - all[0] <= 1.5 * span {
        return None;
    }
    let mut until_s = f64::NEG_INFINITY;
    let mut exceeding = Vec::new();
    for (i, col) in estimates.iter().enumerate() {
        let last_out = col
            .iter()
            .zip(t)
            .rev()
            .find(|(v, _)| v.is_some_and(|v| v.is_finite() && (v < bulk[0] || v > bulk[1])))
            .map(|(_, tk)| *tk);
        if let Some(tk) = last_out {
            until_s = until_s.max(tk);
            exceeding.push(i);
        }
    }
    Some(YClip {
        lo: bulk[0],
        hi: bulk[1],
        all,
        until_s: until_s - t.first().copied().unwrap_or(0.0),
        exceeding,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn walk(n: usize, start_error: f64, transient: usize) -> (Vec<f64>, Column, Column) {
        let t: Vec<f64> = (0..n).map(|k| k as f64 * 0.01).collect();
        let r: Column = t.iter().map(|t| Some(10.0 * (6.0 * t).sin())).collect();
        let e: Column = t
            .iter()
            .enumerate()
            .map(|(k, t)| {
                let decay = if k < transient {
                    start_error * (1.0 - k as f64 / transient as f64)
                } else {
                    0.0
                };
                Some(10.0 * (6.0 * t).sin() + 1.0 + decay)
            })
            .collect();
        (t, r, e)
    }

    /// A 90 deg start error decaying over 1 s of a 30 s walk (+-10 deg):
    /// the range is the walk's, and the first second is named as clipped.
    #[test]
    fn a_start_transient_is_clipped_and_named() {
        let (t, r, e) = walk(3000, 90.0, 100);
        let c = start_clip(&t, Some(&r), &[&e]).expect("clipped");
        assert!(
            (c.lo + 10.0).abs() < 0.01 && (c.hi - 11.0).abs() < 0.01,
            "{c:?}"
        );
        assert!(c.all[1] > 90.0);
        assert_eq!(c.exceeding, vec![0]);
        assert!(c.until_s > 0.5 && c.until_s < 1.0, "{}", c.until_s);
        // the same input, the same answer
        assert_eq!(start_clip(&t, Some(&r), &[&e]), Some(c));
    }

    /// Without a transient, or with one too small to squash the plot, the
    /// range is every value (nothing clipped).
    #[test]
    fn no_clip_without_a_squashing_transient() {
        let (t, r, e) = walk(3000, 0.0, 100);
        assert_eq!(start_clip(&t, Some(&r), &[&e]), None);
        let (t, r, e) = walk(3000, 8.0, 100);
        assert_eq!(start_clip(&t, Some(&r), &[&e]), None);
        // a reference that leaves the bulk is never clipped: it is kept whole
        let mut r2 = r.clone();
        r2[10] = Some(200.0);
        assert_eq!(start_clip(&t, Some(&r2), &[&e]), None);
    }
}
