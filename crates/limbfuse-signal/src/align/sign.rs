//! Which way the medio-lateral axis points (to the subject's right).
//!
//! An axis from gyro data is known only up to sign, and flipping it (with
//! x, so that the frame stays a rotation) is invisible to the physics of a
//! rigid sensor. What breaks the symmetry is the gait itself:
//! * **Fast forward swing.** Thigh, shank and foot all rotate forward
//!   (positive) in swing, in about 40 % of the stride, and backward more
//!   slowly over stance: the positive peaks of `gyro_z` are larger than the
//!   negative ones. Score per segment: `(q_hi + q_lo) / (q_hi - q_lo)` of
//!   `gyro_z`, with `q_hi`/`q_lo` its 99th/1st percentiles.
//! * **Segments swing together.** Adjacent leg segments rotate forward in
//!   swing and backward in stance together, so their `gyro_z` correlate
//!   positively when both axes point the same way.
//!
//! * **The knee flexes one way.** The knee angle `thigh - shank` stays near
//!   extension for most of the stride and flexes to ~60 deg in a short
//!   swing peak: its skewness is strongly positive (+0.87..+0.91 on the
//!   simulator, +0.92..+1.06 on the gaittoolbox trial). The knee angle is
//!   the integral of `s_thigh gyro_thigh - s_shank gyro_shank`, high-passed
//!   by removing a centred 2 s moving average.
//!
//! The signs of the leg segments are chosen jointly: every combination of
//! signs is scored by the sum of the per-segment peak scores, the
//! adjacent-pair correlations and the knee skewness (clamped to +-1.5), and
//! the best combination wins.

use limbfuse_core::Segment;

use super::series::correlation;

/// Percentile `p` (0..1) of sorted data.
fn percentile(sorted: &[f64], p: f64) -> f64 {
    let i = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[i]
}

/// Peak-asymmetry score of a rate series: positive when the positive peaks
/// are the larger ones; in [-1, 1]. 0 for fewer than 10 samples.
pub(crate) fn peak_score(rates: &[f64]) -> f64 {
    if rates.len() < 10 {
        return 0.0;
    }
    let mut s = rates.to_vec();
    s.sort_by(f64::total_cmp);
    let (lo, hi) = (percentile(&s, 0.01), percentile(&s, 0.99));
    if hi - lo <= 0.0 {
        0.0
    } else {
        (hi + lo) / (hi - lo)
    }
}

/// Evidence for the sign of one segment (with its axis as found).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Evidence {
    /// Peak score of `gyro_z` along the axis as found.
    pub peak: f64,
}

/// Chooses signs (+1 keep, -1 flip) for the segments with evidence, given
/// the per-segment evidence and the rate series along each axis as found
/// (same time base, `None` for missing; used for the pair correlations).
/// Returns the signs and the margin of the best combination over the best
/// combination that flips any segment relative to it.
pub(crate) fn choose_signs(
    evidence: &[Option<Evidence>; 4],
    rates: &[Vec<Option<f64>>; 4],
    times: &[f64],
) -> ([f64; 4], [f64; 4]) {
    let leg = [Segment::Thigh, Segment::Shank, Segment::Foot];
    let mut pair_corr = Vec::new();
    for w in leg.windows(2) {
        let (a, b) = (w[0].index(), w[1].index());
        if evidence[a].is_none() || evidence[b].is_none() {
            continue;
        }
        let (x, y): (Vec<f64>, Vec<f64>) = rates[a]
            .iter()
            .zip(&rates[b])
            .filter_map(|(p, q)| Some(((*p)?, (*q)?)))
            .unzip();
        pair_corr.push((a, b, correlation(&x, &y)));
    }
    let (th, sh) = (Segment::Thigh.index(), Segment::Shank.index());
    // Knee skewness for (s_thigh, s_shank) = (+, +) and (+, -); the other
    // two combinations are their negatives.
    let knee = (evidence[th].is_some() && evidence[sh].is_some()).then(|| {
        [1.0, -1.0].map(|s2| knee_skew(&rates[th], &rates[sh], s2, times).clamp(-1.5, 1.5))
    });
    let score = |s: &[f64; 4]| -> f64 {
        let knee_term = knee.map_or(0.0, |k| {
            let rel = s[th] * s[sh];
            s[th] * if rel > 0.0 { k[0] } else { k[1] }
        });
        let own: f64 = leg
            .iter()
            .filter_map(|g| evidence[g.index()].map(|e| e.peak * s[g.index()]))
            .sum();
        own + knee_term
            + pair_corr
                .iter()
                .map(|&(a, b, c)| c * s[a] * s[b])
                .sum::<f64>()
    };
    let mut best = ([1.0; 4], f64::NEG_INFINITY);
    let mut all = Vec::new();
    for bits in 0..8u32 {
        let mut s = [1.0; 4];
        for (i, g) in leg.iter().enumerate() {
            if bits & (1 << i) != 0 {
                s[g.index()] = -1.0;
            }
        }
        // Combinations that flip a segment without evidence are duplicates.
        if leg
            .iter()
            .any(|g| evidence[g.index()].is_none() && s[g.index()] < 0.0)
        {
            continue;
        }
        let v = score(&s);
        all.push((s, v));
        if v > best.1 {
            best = (s, v);
        }
    }
    // Margin per segment: best score minus the best score with that segment flipped.
    let mut margin = [0.0; 4];
    for g in leg {
        let i = g.index();
        if evidence[i].is_none() {
            continue;
        }
        let alt = all
            .iter()
            .filter(|(s, _)| s[i] != best.0[i])
            .map(|(_, v)| *v)
            .fold(f64::NEG_INFINITY, f64::max);
        margin[i] = best.1 - alt;
    }
    (best.0, margin)
}

/// Skewness of the high-passed integral of `thigh - s2 * shank` (rates along
/// the axes as found, at `times`); gaps longer than 3 median intervals are
/// not integrated over, a missing rate holds the last one.
fn knee_skew(thigh: &[Option<f64>], shank: &[Option<f64>], s2: f64, times: &[f64]) -> f64 {
    let n = thigh.len().min(shank.len()).min(times.len());
    if n < 10 {
        return 0.0;
    }
    let mut d: Vec<f64> = times[..n].windows(2).map(|w| w[1] - w[0]).collect();
    d.sort_by(f64::total_cmp);
    let dt = d[d.len() / 2];
    let half = ((1.0 / dt).round() as usize).max(1);
    let mut psi = vec![0.0; n];
    let mut last = 0.0;
    let mut prev_rate = 0.0;
    for k in 0..n {
        let rate = match (thigh[k], shank[k]) {
            (Some(a), Some(b)) => a - s2 * b,
            _ => prev_rate,
        };
        if k > 0 {
            let step = times[k] - times[k - 1];
            if step <= 3.0 * dt {
                last += 0.5 * step * (rate + prev_rate);
            }
        }
        psi[k] = last;
        prev_rate = rate;
    }
    let mut cum = vec![0.0; n + 1];
    for k in 0..n {
        cum[k + 1] = cum[k] + psi[k];
    }
    let hp: Vec<f64> = (0..n)
        .map(|k| {
            let (a, b) = (
                k.saturating_sub(half),
                k.saturating_add(half).saturating_add(1).min(n),
            );
            psi[k] - (cum[b] - cum[a]) / (b - a) as f64
        })
        .collect();
    let m = hp.iter().sum::<f64>() / n as f64;
    let (mut m2, mut m3) = (0.0, 0.0);
    for x in &hp {
        m2 += (x - m).powi(2);
        m3 += (x - m).powi(3);
    }
    let (m2, m3) = (m2 / n as f64, m3 / n as f64);
    if m2 > 0.0 {
        m3 / m2.powf(1.5)
    } else {
        0.0
    }
}
