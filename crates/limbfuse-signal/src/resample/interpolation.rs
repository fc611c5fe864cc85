//! Interpolation between present samples: the time bracket of an output
//! time (with the gap and edge rules of the module docs), linear
//! interpolation of scalars, normalised linear interpolation of
//! quaternions and nearest-sample gait-phase labels.

use limbfuse_core::sample::GaitPhase;

use super::{Series, GAP_FACTOR};

/// Nominal input period of a channel: the median spacing of its present
/// samples (`None` with fewer than two).
pub(super) fn nominal_period(t: &[f64]) -> Option<f64> {
    if t.len() < 2 {
        return None;
    }
    let mut d: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    let mid = d.len() / 2;
    let (_, m, _) = d.select_nth_unstable_by(mid, f64::total_cmp);
    Some(*m)
}

/// Where `tg` falls among the samples `t`: the bracketing pair (both
/// indices, not separated by a gap) or the single nearby sample at an edge.
pub(super) enum Bracket {
    /// The samples before and after `tg` and the weight of the later one.
    Pair(usize, usize, f64),
    /// One sample stands for `tg` (exact hit, or an edge within half a period).
    One(usize),
    /// No sample near `tg`.
    Nothing,
}

pub(super) fn bracket(t: &[f64], tg: f64, period: Option<f64>, period_out: f64) -> Bracket {
    if t.is_empty() {
        return Bracket::Nothing;
    }
    let tol = 1e-9 * tg.abs().max(1.0);
    let j = t.partition_point(|&x| x <= tg);
    // Exact hit.
    if j > 0 && (tg - t[j - 1]).abs() <= tol {
        return Bracket::One(j - 1);
    }
    if j < t.len() && (t[j] - tg).abs() <= tol {
        return Bracket::One(j);
    }
    // A lone sample stands for half an output period each side.
    let p = period.unwrap_or(period_out);
    if j > 0 && j < t.len() {
        let (a, b) = (j - 1, j);
        if t[b] - t[a] <= GAP_FACTOR * p {
            return Bracket::Pair(a, b, (tg - t[a]) / (t[b] - t[a]));
        }
    }
    // Edge of the data or of a gap: the nearest sample within half a period
    // (the longer of the input and output periods).
    let near = [j.checked_sub(1), (j < t.len()).then_some(j)]
        .into_iter()
        .flatten()
        .min_by(|&a, &b| (t[a] - tg).abs().total_cmp(&(t[b] - tg).abs()));
    match near {
        Some(k) if (t[k] - tg).abs() <= 0.5 * p.max(period_out) + tol => Bracket::One(k),
        _ => Bracket::Nothing,
    }
}

/// Linear interpolation of a scalar channel onto `grid`.
pub(super) fn linear(s: &Series, grid: &[f64], period_out: f64) -> Vec<Option<f64>> {
    let p = nominal_period(&s.t);
    grid.iter()
        .map(|&tg| match bracket(&s.t, tg, p, period_out) {
            Bracket::Pair(a, b, w) => Some(s.v[a] + w * (s.v[b] - s.v[a])),
            Bracket::One(k) => Some(s.v[k]),
            Bracket::Nothing => None,
        })
        .collect()
}

/// Quaternion series (sign-aligned normalised linear interpolation).
pub(super) fn resample_quat(
    t: &[f64],
    q: &[[f64; 4]],
    grid: &[f64],
    period_out: f64,
) -> Vec<Option<[f64; 4]>> {
    let p = nominal_period(t);
    grid.iter()
        .map(|&tg| match bracket(t, tg, p, period_out) {
            Bracket::Pair(a, b, w) => {
                let (qa, mut qb) = (q[a], q[b]);
                let dot: f64 = (0..4).map(|i| qa[i] * qb[i]).sum();
                if dot < 0.0 {
                    qb = qb.map(|x| -x);
                }
                let mut r = [0.0; 4];
                for i in 0..4 {
                    r[i] = qa[i] + w * (qb[i] - qa[i]);
                }
                let norm = r.iter().map(|x| x * x).sum::<f64>().sqrt();
                (norm > 1e-12).then(|| r.map(|x| x / norm))
            }
            Bracket::One(k) => Some(q[k]),
            Bracket::Nothing => None,
        })
        .collect()
}

/// Gait-phase labels: the nearest present sample.
pub(super) fn resample_phase(
    t: &[f64],
    ph: &[GaitPhase],
    grid: &[f64],
    period_out: f64,
) -> Vec<Option<GaitPhase>> {
    nearest(t, ph, grid, period_out)
}

/// Any channel: the nearest present sample (no value between two samples).
pub(super) fn nearest<T: Copy>(
    t: &[f64],
    ph: &[T],
    grid: &[f64],
    period_out: f64,
) -> Vec<Option<T>> {
    let p = nominal_period(t);
    grid.iter()
        .map(|&tg| match bracket(t, tg, p, period_out) {
            Bracket::Pair(a, b, w) => Some(if w <= 0.5 { ph[a] } else { ph[b] }),
            Bracket::One(k) => Some(ph[k]),
            Bracket::Nothing => None,
        })
        .collect()
}
