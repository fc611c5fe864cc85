//! The time axis of the report's plots: seconds since the trial's first
//! sample, and the gaps in the trial's time stamps.
//!
//! Plots use time relative to the first sample (audit 2026-12-05): a trial
//! whose `t` starts at 100000 s or at a Unix time was drawn with
//! coordinates (1e8 ms, 1.7e12 ms) beyond what a browser holds exactly,
//! giving squeezed or blank plots. A step longer than
//! [`limbfuse_eval::trial_summary::GAP_STEPS`] median steps (the rule of
//! `limbfuse inspect`) is a gap: the page states the gaps and the lines
//! break there.

use limbfuse_eval::trial_summary::GAP_STEPS;

use crate::decimate::Points;

/// A gap in the time stamps: the samples before and after it (relative s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeGap {
    /// Time of the last sample before the gap.
    pub start: f64,
    /// Time of the first sample after it.
    pub end: f64,
}

impl TimeGap {
    /// Its length (s).
    pub fn length(&self) -> f64 {
        self.end - self.start
    }
}

/// The plots' time axis for one trial.
#[derive(Debug, Clone, PartialEq)]
pub struct TimeBase {
    /// The trial time of the first sample (s): plot time 0.
    pub origin: f64,
    /// Every sample's time minus `origin` (s).
    pub relative: Vec<f64>,
    /// The gaps, in relative time, in order.
    pub gaps: Vec<TimeGap>,
}

impl TimeBase {
    /// The time base of samples at `t` (trial seconds).
    pub fn new(t: &[f64]) -> Self {
        let origin = t.first().copied().unwrap_or(0.0);
        let relative: Vec<f64> = t.iter().map(|t| t - origin).collect();
        let gaps = find_gaps(&relative);
        TimeBase {
            origin,
            relative,
            gaps,
        }
    }

    /// The longest gap, if any.
    pub fn longest_gap(&self) -> Option<TimeGap> {
        self.gaps
            .iter()
            .copied()
            .max_by(|a, b| a.length().total_cmp(&b.length()))
    }
}

/// The steps of `t` longer than [`GAP_STEPS`] median steps.
fn find_gaps(t: &[f64]) -> Vec<TimeGap> {
    let mut steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    if steps.is_empty() {
        return Vec::new();
    }
    steps.sort_by(f64::total_cmp);
    let median = steps[steps.len() / 2];
    t.windows(2)
        .filter(|w| w[1] - w[0] > GAP_STEPS * median)
        .map(|w| TimeGap {
            start: w[0],
            end: w[1],
        })
        .collect()
}

/// `points` (in time order) with a break (`None`) between any two
/// consecutive points that have a gap between them: no segment is drawn
/// across a gap.
pub fn break_at_gaps(points: Points, gaps: &[TimeGap]) -> Points {
    if gaps.is_empty() {
        return points;
    }
    let mut out = Vec::with_capacity(points.len() + gaps.len());
    let mut next_gap = 0;
    let mut previous: Option<f64> = None;
    for (t, v) in points {
        while next_gap < gaps.len() && gaps[next_gap].end <= t {
            let gap = gaps[next_gap];
            if previous.is_some_and(|p| p <= gap.start) {
                out.push((gap.start, None));
            }
            next_gap += 1;
        }
        previous = Some(t);
        out.push((t, v));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_are_relative_to_the_first_sample_and_gaps_are_found() {
        let mut t: Vec<f64> = (0..100).map(|k| 1.7e9 + k as f64 * 0.01).collect();
        t.drain(40..70); // 0.31 s gap after 0.39 s
        let base = TimeBase::new(&t);
        assert_eq!(base.origin, 1.7e9);
        assert_eq!(base.relative[0], 0.0);
        assert!((base.relative[1] - 0.01).abs() < 1e-6);
        assert_eq!(base.gaps.len(), 1);
        let gap = base.longest_gap().unwrap();
        assert!((gap.start - 0.39).abs() < 1e-6 && (gap.length() - 0.31).abs() < 1e-6);
        assert!(TimeBase::new(&[0.0, 0.01, 0.02, 0.031]).gaps.is_empty());
    }

    #[test]
    fn lines_break_at_a_gap_and_nowhere_else() {
        let gaps = [TimeGap {
            start: 1.0,
            end: 4.0,
        }];
        let pts: Points = vec![
            (0.0, Some(1.0)),
            (1.0, Some(2.0)),
            (4.0, Some(3.0)),
            (5.0, Some(4.0)),
        ];
        let out = break_at_gaps(pts, &gaps);
        assert_eq!(
            out,
            vec![
                (0.0, Some(1.0)),
                (1.0, Some(2.0)),
                (1.0, None),
                (4.0, Some(3.0)),
                (5.0, Some(4.0)),
            ]
        );
        // a series that starts after the gap gets no break
        let late = break_at_gaps(vec![(4.0, Some(1.0)), (5.0, Some(1.0))], &gaps);
        assert_eq!(late.len(), 2);
    }
}
