//! Per-segment views of a trial's IMU channels, quiet-period detection and
//! small signal helpers (moving-average high-pass, statistics).

use std::ops::Range;

use limbfuse_core::{Record, Segment};
use nalgebra::Vector3;

use super::AlignOptions;

/// Gyro reading of `seg` at record `k` (a non-finite reading counts as missing).
#[inline]
pub(crate) fn gyr(records: &[Record], seg: Segment, k: usize) -> Option<Vector3<f64>> {
    records[k].sample.imu[seg.index()]
        .gyr
        .filter(|v| v.iter().all(|x| x.is_finite()))
}

/// Accelerometer reading of `seg` at record `k` (non-finite counts as missing).
#[inline]
pub(crate) fn acc(records: &[Record], seg: Segment, k: usize) -> Option<Vector3<f64>> {
    records[k].sample.imu[seg.index()]
        .acc
        .filter(|v| v.iter().all(|x| x.is_finite()))
}

/// Median of a slice (NaN-free input); `None` when empty.
pub(crate) fn median(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    Some(v[v.len() / 2])
}

/// The longest run of records where every segment in `present` is still
/// (gyro norm below `quiet_gyro_max`, accelerometer norm within
/// `quiet_acc_dev` of that sensor's median norm over its low-rate samples),
/// if it lasts at least `quiet_min_s`.
pub(crate) fn quiet_window(
    records: &[Record],
    present: &[bool; 4],
    opts: &AlignOptions,
) -> Option<Range<usize>> {
    if !present.iter().any(|&p| p) {
        return None;
    }
    let mut norm_ref = [0.0; 4];
    for s in Segment::ALL {
        if !present[s.index()] {
            continue;
        }
        let mut n: Vec<f64> = (0..records.len())
            .filter_map(|k| match (gyr(records, s, k), acc(records, s, k)) {
                (Some(w), Some(a)) if w.norm() < opts.quiet_gyro_max => Some(a.norm()),
                _ => None,
            })
            .collect();
        norm_ref[s.index()] = median(&mut n)?;
    }
    let still = |k: usize| {
        Segment::ALL.iter().all(|&s| {
            !present[s.index()]
                || matches!((gyr(records, s, k), acc(records, s, k)),
                    (Some(w), Some(a)) if w.norm() < opts.quiet_gyro_max
                        && (a.norm() - norm_ref[s.index()]).abs() < opts.quiet_acc_dev)
        })
    };
    let mut best: Option<Range<usize>> = None;
    let mut k = 0;
    while k < records.len() {
        if !still(k) {
            k += 1;
            continue;
        }
        let start = k;
        while k < records.len() && still(k) {
            k += 1;
        }
        let dur = records[k - 1].sample.t - records[start].sample.t;
        let longer = match &best {
            Some(b) => k - start > b.len(),
            None => true,
        };
        if dur >= opts.quiet_min_s && longer {
            best = Some(start..k);
        }
    }
    best
}

/// Pearson correlation of two equally long series (0 when degenerate).
pub(crate) fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    if n < 2 {
        return 0.0;
    }
    let ma = a[..n].iter().sum::<f64>() / n as f64;
    let mb = b[..n].iter().sum::<f64>() / n as f64;
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (da, db) = (a[i] - ma, b[i] - mb);
        sab += da * db;
        saa += da * da;
        sbb += db * db;
    }
    if saa <= 0.0 || sbb <= 0.0 {
        0.0
    } else {
        sab / (saa * sbb).sqrt()
    }
}

/// Samples taken while the subject turns: the median over the sensors of
/// the rate about their mean-specific-force (vertical) direction, averaged
/// over a centred window of `2 half + 1` samples, exceeds `max_rate`
/// (rad/s); the mask is widened by `half` samples each side.
pub(crate) fn turning_mask(
    records: &[Record],
    present: &[bool; 4],
    half: usize,
    max_rate: f64,
) -> Vec<bool> {
    let n = records.len();
    let mut smoothed: Vec<Vec<f64>> = Vec::new();
    for s in Segment::ALL {
        if !present[s.index()] {
            continue;
        }
        let up: Vector3<f64> = (0..n).filter_map(|k| acc(records, s, k)).sum();
        let Some(up) = up.try_normalize(1e-9) else {
            continue;
        };
        let mut cum = vec![0.0; n + 1];
        for k in 0..n {
            cum[k + 1] = cum[k] + gyr(records, s, k).map_or(0.0, |w| w.dot(&up));
        }
        smoothed.push(
            (0..n)
                .map(|k| {
                    let (a, b) = (
                        k.saturating_sub(half),
                        k.saturating_add(half).saturating_add(1).min(n),
                    );
                    ((cum[b] - cum[a]) / (b - a) as f64).abs()
                })
                .collect(),
        );
    }
    let mut turn = vec![false; n];
    if smoothed.is_empty() {
        return turn;
    }
    for (k, t) in turn.iter_mut().enumerate() {
        let mut v: Vec<f64> = smoothed.iter().map(|s| s[k]).collect();
        v.sort_by(f64::total_cmp);
        let m = v.len();
        let med = if m % 2 == 1 {
            v[m / 2]
        } else {
            0.5 * (v[m / 2 - 1] + v[m / 2])
        };
        *t = med > max_rate;
    }
    let core = turn.clone();
    for (k, _) in core.iter().enumerate().filter(|(_, &c)| c) {
        for t in &mut turn[k.saturating_sub(half)..k.saturating_add(half).saturating_add(1).min(n)]
        {
            *t = true;
        }
    }
    turn
}
