//! Min/max-preserving decimation for display.
//!
//! A plot has at most a few thousand pixels across, so a long trial is cut
//! into `buckets` runs of consecutive samples (the same cut for every series
//! of a trial) and each run is drawn by its smallest and its largest value,
//! each at the time it occurred, in time order. Every peak and trough of the
//! signal therefore stays on screen at its true time and value: the line
//! drawn through the kept points covers exactly the vertical range the
//! samples cover. What is lost is the order of the other samples inside a
//! run (the line goes straight from the minimum to the maximum) and gaps
//! shorter than a run. A run whose values are all missing becomes a break
//! in the line. Series of at most `2 * buckets` samples are kept whole.
//!
//! Tables never use the decimated values: they are computed on every sample
//! (`limbfuse-eval`).

/// The points of one series kept for display: `(t, value)`, `None` = break.
pub type Points = Vec<(f64, Option<f64>)>;

/// Decimates `y` (sampled at `t`) to at most two points per bucket.
///
/// # Panics
/// Never; `t` and `y` of different lengths use the shorter.
pub fn min_max(t: &[f64], y: &[Option<f64>], buckets: usize) -> Points {
    let n = t.len().min(y.len());
    let buckets = buckets.max(1);
    if n <= 2 * buckets {
        return t.iter().zip(y).map(|(t, v)| (*t, *v)).collect();
    }
    let mut out = Vec::with_capacity(2 * buckets);
    for b in 0..buckets {
        let (start, end) = (b * n / buckets, (b + 1) * n / buckets);
        let mut lo: Option<(usize, f64)> = None;
        let mut hi: Option<(usize, f64)> = None;
        for (i, v) in y.iter().enumerate().take(end).skip(start) {
            let Some(v) = *v else { continue };
            if lo.is_none_or(|(_, m)| v < m) {
                lo = Some((i, v));
            }
            if hi.is_none_or(|(_, m)| v > m) {
                hi = Some((i, v));
            }
        }
        match (lo, hi) {
            (Some(a), Some(b)) if a.0 == b.0 => out.push((t[a.0], Some(a.1))),
            (Some(a), Some(b)) => {
                let (first, second) = if a.0 < b.0 { (a, b) } else { (b, a) };
                out.push((t[first.0], Some(first.1)));
                out.push((t[second.0], Some(second.1)));
            }
            _ => out.push((t[start], None)),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_series_are_kept_whole() {
        let t = [0.0, 1.0, 2.0];
        let y = [Some(1.0), None, Some(3.0)];
        assert_eq!(
            min_max(&t, &y, 2),
            vec![(0.0, Some(1.0)), (1.0, None), (2.0, Some(3.0))]
        );
    }

    #[test]
    fn every_bucket_keeps_its_extremes_in_time_order() {
        let n = 10_000;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.01).collect();
        let y: Vec<Option<f64>> = (0..n)
            .map(|i| Some((i as f64 * 0.37).sin() * (1.0 + (i % 97) as f64)))
            .collect();
        let buckets = 100;
        let p = min_max(&t, &y, buckets);
        assert!(p.len() <= 2 * buckets);
        // Each bucket's true min and max appear, at their own times.
        for b in 0..buckets {
            let (s, e) = (b * n / buckets, (b + 1) * n / buckets);
            let vals: Vec<f64> = y[s..e].iter().map(|v| v.unwrap()).collect();
            let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let ilo = s + vals.iter().position(|v| *v == lo).unwrap();
            let ihi = s + vals.iter().position(|v| *v == hi).unwrap();
            assert!(p.contains(&(t[ilo], Some(lo))), "bucket {b} min");
            assert!(p.contains(&(t[ihi], Some(hi))), "bucket {b} max");
        }
        assert!(p.windows(2).all(|w| w[0].0 < w[1].0), "time order");
        // The global extremes survive.
        let all_max = y
            .iter()
            .map(|v| v.unwrap())
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(p.iter().any(|(_, v)| *v == Some(all_max)));
    }

    #[test]
    fn an_all_missing_bucket_is_a_break() {
        let n = 100;
        let t: Vec<f64> = (0..n).map(f64::from).collect();
        let y: Vec<Option<f64>> = (0..n).map(|i| (i >= 50).then_some(1.0)).collect();
        let p = min_max(&t, &y, 10);
        assert_eq!(p[0], (0.0, None));
        assert!(p.iter().filter(|(_, v)| v.is_none()).count() == 5);
    }

    proptest::proptest! {
        /// Kept points are samples of the series, in time order; each
        /// bucket's extremes (and so the series' global ones) are kept;
        /// never more than two points per bucket.
        #[test]
        fn kept_points_are_samples_and_keep_the_extremes(
            y in proptest::collection::vec(proptest::option::weighted(0.9, -1e3f64..1e3), 1..600),
            buckets in 1usize..100,
        ) {
            let t: Vec<f64> = (0..y.len()).map(|i| i as f64 * 0.01).collect();
            let p = min_max(&t, &y, buckets);
            proptest::prop_assert!(p.len() <= y.len().max(2 * buckets));
            proptest::prop_assert!(p.windows(2).all(|w| w[0].0 < w[1].0));
            for (pt, v) in &p {
                let i = (pt / 0.01).round() as usize;
                if let Some(v) = v {
                    proptest::prop_assert_eq!(y[i], Some(*v));
                }
            }
            let vals = || y.iter().flatten().copied();
            if let Some(hi) = vals().reduce(f64::max) {
                proptest::prop_assert!(p.iter().any(|(_, v)| *v == Some(hi)));
                let lo = vals().reduce(f64::min).unwrap();
                proptest::prop_assert!(p.iter().any(|(_, v)| *v == Some(lo)));
            }
        }
    }
}
