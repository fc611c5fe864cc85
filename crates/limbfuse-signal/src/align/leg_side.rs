//! Which leg the sensors are on, from the aligned leg sensors.
//!
//! The aligned frame is the same for both legs (z to the subject's right), so
//! the sagittal motion cannot tell them apart: a left leg is the mirror image
//! of a right one, and mirroring flips the *frontal* rotation (about x,
//! forward): `S Rx(a) S = Rx(-a)`, `S = diag(1, 1, -1)`. The frontal pattern
//! of gait: the thigh and shank are adducted (knee medial of the hip) in
//! stance, when the pelvis drops on the swing side and the body sways over
//! the stance foot, and abduct toward toe-off and in swing (hip adduction
//! peak ~10 deg in loading response, abduction ~5 deg at toe-off: Perry &
//! Burnfield 2010 ch. 6, Kadaba et al. 1990). For the right leg adduction is
//! a rotation about +x (the segment's up axis tilts to the right), for the
//! left about -x.
//!
//! Score per thigh/shank sensor: the correlation of its frontal angle
//! (integrated aligned `gyro_x`, high-passed by removing a centred 2 s
//! moving average) with the stance indicator `c = -sign(sum gyro_z)` (thigh
//! and shank rotate backward over stance and forward in swing). Right leg:
//! positive; left leg: negative. The leg is decided from the sum of the
//! thigh and shank scores; below `leg_min_score` in magnitude it is left
//! undetermined (reported, the alignment does not depend on it).

use limbfuse_core::{Leg, Record, Segment};
use nalgebra::Matrix3;

use super::series::{correlation, gyr};

/// The leg found, with the evidence.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LegDetection {
    /// The leg, or `None` when the score is too small.
    pub leg: Option<Leg>,
    /// Sum of the thigh and shank scores (positive: right).
    pub score: f64,
    /// Score per segment (trunk, thigh, shank, foot); `None` where not computed.
    pub per_segment: [Option<f64>; 4],
}

/// Integral of `rate` (gaps over 3 intervals not integrated over), high-passed
/// by removing a centred moving average of `2 half + 1` samples.
fn high_passed_integral(rate: &[f64], times: &[f64], half: usize) -> Vec<f64> {
    let n = rate.len();
    let mut d: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    d.sort_by(f64::total_cmp);
    let dt = d.get(d.len() / 2).copied().unwrap_or(0.0);
    let mut psi = vec![0.0; n];
    for k in 1..n {
        let step = times[k] - times[k - 1];
        psi[k] = psi[k - 1]
            + if step <= 3.0 * dt {
                0.5 * step * (rate[k] + rate[k - 1])
            } else {
                0.0
            };
    }
    let mut cum = vec![0.0; n + 1];
    for k in 0..n {
        cum[k + 1] = cum[k] + psi[k];
    }
    (0..n)
        .map(|k| {
            let (a, b) = (
                k.saturating_sub(half),
                k.saturating_add(half).saturating_add(1).min(n),
            );
            psi[k] - (cum[b] - cum[a]) / (b - a) as f64
        })
        .collect()
}

/// Detects the leg from the aligned rotations `rot` (raw to aligned, per
/// segment) over the walking samples `moving`.
pub(crate) fn detect_leg(
    records: &[Record],
    moving: &[usize],
    rot: &[Option<Matrix3<f64>>; 4],
    min_score: f64,
) -> LegDetection {
    let mut none = LegDetection {
        leg: None,
        score: 0.0,
        per_segment: [None; 4],
    };
    let pair = [Segment::Thigh, Segment::Shank];
    // Samples where every used sensor has a gyro reading.
    let used: Vec<Segment> = pair
        .into_iter()
        .filter(|s| rot[s.index()].is_some())
        .collect();
    if used.is_empty() || moving.len() < 100 {
        return none;
    }
    // Aligned gyro of a used sensor; `None` where its rotation or its gyro
    // reading is missing (such samples are left out below, so no reading
    // is ever assumed).
    let aligned = |s: Segment, k: usize| Some(rot[s.index()]? * gyr(records, s, k)?);
    let idx: Vec<usize> = moving
        .iter()
        .copied()
        .filter(|&k| used.iter().all(|&s| aligned(s, k).is_some()))
        .collect();
    if idx.len() < 100 {
        return none;
    }
    let times: Vec<f64> = idx.iter().map(|&k| records[k].sample.t).collect();
    let dt = (times[times.len() - 1] - times[0]) / (times.len() - 1) as f64;
    let half = ((1.0 / dt).round() as usize).max(1);
    let stance: Vec<f64> = idx
        .iter()
        .map(|&k| {
            let sum: f64 = used
                .iter()
                .filter_map(|&s| aligned(s, k))
                .map(|w| w.z)
                .sum();
            -sum.signum()
        })
        .collect();
    for &s in &used {
        let roll: Vec<f64> = idx
            .iter()
            .filter_map(|&k| aligned(s, k))
            .map(|w| w.x)
            .collect();
        let frontal = high_passed_integral(&roll, &times, half);
        let c = correlation(&frontal, &stance);
        none.per_segment[s.index()] = Some(c);
        none.score += c;
    }
    none.leg = if none.score >= min_score {
        Some(Leg::Right)
    } else if none.score <= -min_score {
        Some(Leg::Left)
    } else {
        None
    };
    none
}
