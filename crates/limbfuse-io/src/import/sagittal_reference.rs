//! Reference sagittal angles from motion-capture joint centres, in a
//! heading-following sagittal plane (used by the gaittoolbox importer).
//!
//! World frame of the input: z up, metres, any horizontal orientation.
//! - *Forward* at sample k is the horizontal direction of the pelvis velocity
//!   (central differences) averaged over a centred window (default 1 s, about
//!   one stride, which cancels the step-to-step lateral sway).
//! - A segment's angle is that of its proximal->distal vector `r` projected on
//!   the forward/up plane: `theta = atan2(r . forward, -r . up)`, so 0 is
//!   "distal end straight below", positive is "distal end forward/up"
//!   (counter-clockwise seen from the subject's right, SPEC section 1).
//! - The foot's ankle->toe vector is nearly horizontal when standing, so its
//!   zero is the median raw foot angle during foot-flat (toe and ankle both
//!   slower than `foot_flat_speed`) on the straight parts: the foot then lies
//!   on the level floor, as in upright standing.
//! - Straight parts: pelvis speed >= `min_speed` and |heading rate| <=
//!   `max_heading_rate`, kept when at least `min_straight_s` long. Angles are
//!   computed everywhere the markers exist, but only mean something there.

use core::f64::consts::PI;
use core::ops::Range;

use nalgebra::Vector3;

/// Joint-centre trajectories (z up, metres), one entry per sample, `None` where missing.
#[derive(Debug, Clone, Default)]
pub struct JointCentres {
    /// Mid-pelvis.
    pub pelvis: Vec<Option<Vector3<f64>>>,
    /// Hip joint centre.
    pub hip: Vec<Option<Vector3<f64>>>,
    /// Knee joint centre.
    pub knee: Vec<Option<Vector3<f64>>>,
    /// Ankle joint centre.
    pub ankle: Vec<Option<Vector3<f64>>>,
    /// Toe.
    pub toe: Vec<Option<Vector3<f64>>>,
}

/// Tuning of the reference derivation (defaults documented in `docs/IMPORTERS.md`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SagittalParams {
    /// Length (s) of the centred moving average applied to the pelvis velocity.
    pub heading_window_s: f64,
    /// Minimum smoothed pelvis speed (m/s) of a straight part.
    pub min_speed: f64,
    /// Maximum |heading rate| (rad/s) of a straight part.
    pub max_heading_rate: f64,
    /// Minimum duration (s) of a straight part.
    pub min_straight_s: f64,
    /// Toe and ankle speed (m/s) below which the foot counts as flat on the floor.
    pub foot_flat_speed: f64,
    /// Fewest foot-flat samples needed to fix the foot zero (else no foot reference).
    pub min_foot_flat_samples: usize,
}

impl Default for SagittalParams {
    fn default() -> Self {
        SagittalParams {
            heading_window_s: 1.0,
            min_speed: 0.5,
            max_heading_rate: 45f64.to_radians(),
            min_straight_s: 1.0,
            foot_flat_speed: 0.05,
            min_foot_flat_samples: 10,
        }
    }
}

/// The derived reference, one entry per sample.
#[derive(Debug, Clone, Default)]
pub struct SagittalReference {
    /// Heading (rad, about world z, from world x) of the smoothed pelvis velocity.
    pub heading: Vec<Option<f64>>,
    /// Smoothed horizontal pelvis speed (m/s).
    pub speed: Vec<Option<f64>>,
    /// Heading rate (rad/s).
    pub heading_rate: Vec<Option<f64>>,
    /// Straight parts as half-open sample ranges.
    pub straight: Vec<Range<usize>>,
    /// Walking speed on the straight parts (m/s; `None` elsewhere): the
    /// pelvis velocity (central difference, not smoothed) along the heading,
    /// so that its mean over a stride is the distance walked over it divided
    /// by its time, the lateral sway left out.
    pub walking_speed: Vec<Option<f64>>,
    /// Thigh angle (rad).
    pub thigh: Vec<Option<f64>>,
    /// Shank angle (rad).
    pub shank: Vec<Option<f64>>,
    /// Foot angle (rad), zero at foot-flat; all `None` when no zero was found.
    pub foot: Vec<Option<f64>>,
    /// Raw foot angle (rad) subtracted to get `foot`.
    pub foot_offset: Option<f64>,
    /// Number of foot-flat samples the offset is the median of.
    pub foot_flat_samples: usize,
}

/// Wraps an angle into (-pi, pi].
pub fn wrap_angle(a: f64) -> f64 {
    let w = a.rem_euclid(2.0 * PI);
    if w > PI {
        w - 2.0 * PI
    } else {
        w
    }
}

/// Central-difference derivative (one-sided at gaps and ends).
fn derivative(p: &[Option<Vector3<f64>>], fs: f64) -> Vec<Option<Vector3<f64>>> {
    let n = p.len();
    (0..n)
        .map(|k| {
            let prev = if k > 0 { p[k - 1] } else { None };
            let next = p.get(k + 1).copied().flatten();
            match (prev, p[k], next) {
                (Some(a), _, Some(b)) => Some((b - a) * (fs / 2.0)),
                (_, Some(c), Some(b)) => Some((b - c) * fs),
                (Some(a), Some(c), _) => Some((c - a) * fs),
                _ => None,
            }
        })
        .collect()
}

/// Centred moving average of the horizontal (x, y) part over `2 * half + 1` samples, skipping gaps.
fn smooth_xy(v: &[Option<Vector3<f64>>], half: usize) -> Vec<Option<[f64; 2]>> {
    let n = v.len();
    let mut sum = vec![[0.0f64; 3]; n + 1];
    for (k, x) in v.iter().enumerate() {
        let (a, b, c) = x.map_or((0.0, 0.0, 0.0), |x| (x.x, x.y, 1.0));
        sum[k + 1] = [sum[k][0] + a, sum[k][1] + b, sum[k][2] + c];
    }
    (0..n)
        .map(|k| {
            let lo = k.saturating_sub(half);
            let hi = (k + half + 1).min(n);
            let count = sum[hi][2] - sum[lo][2];
            (count > 0.0).then(|| {
                [
                    (sum[hi][0] - sum[lo][0]) / count,
                    (sum[hi][1] - sum[lo][1]) / count,
                ]
            })
        })
        .collect()
}

/// Sagittal angle of the proximal->distal vector in the plane of `heading` and up.
pub fn segment_angle(proximal: Vector3<f64>, distal: Vector3<f64>, heading: f64) -> f64 {
    let r = distal - proximal;
    let forward = r.x * heading.cos() + r.y * heading.sin();
    forward.atan2(-r.z)
}

/// Runs of `mask` at least `min_len` long, as half-open ranges.
fn runs(mask: &[bool], min_len: usize) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut start = None;
    for (k, &m) in mask.iter().chain(core::iter::once(&false)).enumerate() {
        match (m, start) {
            (true, None) => start = Some(k),
            (false, Some(s)) => {
                if k - s >= min_len.max(1) {
                    out.push(s..k);
                }
                start = None;
            }
            _ => {}
        }
    }
    out
}

/// Derives heading, straight parts and thigh/shank/foot angles at rate `fs` (Hz).
pub fn sagittal_reference(c: &JointCentres, fs: f64, p: &SagittalParams) -> SagittalReference {
    let n = c.pelvis.len();
    let half = (p.heading_window_s * fs / 2.0).round().clamp(0.0, n as f64) as usize;
    let velocity = smooth_xy(&derivative(&c.pelvis, fs), half);
    let speed: Vec<Option<f64>> = velocity
        .iter()
        .map(|v| v.map(|[x, y]| x.hypot(y)))
        .collect();
    let heading: Vec<Option<f64>> = velocity
        .iter()
        .map(|v| {
            v.filter(|[x, y]| x.hypot(*y) > 1e-9)
                .map(|[x, y]| y.atan2(x))
        })
        .collect();
    let heading_rate: Vec<Option<f64>> = (0..n)
        .map(|k| {
            let (a, b, span) = match (
                k.checked_sub(1).and_then(|i| heading[i]),
                heading.get(k + 1).copied().flatten(),
            ) {
                (Some(a), Some(b)) => (a, b, 2.0),
                (None, Some(b)) => (heading[k]?, b, 1.0),
                (Some(a), None) => (a, heading[k]?, 1.0),
                (None, None) => return None,
            };
            Some(wrap_angle(b - a) * fs / span)
        })
        .collect();
    let mask: Vec<bool> = (0..n)
        .map(|k| {
            speed[k].is_some_and(|s| s >= p.min_speed)
                && heading_rate[k].is_some_and(|r| r.abs() <= p.max_heading_rate)
        })
        .collect();
    let straight = runs(&mask, (p.min_straight_s * fs).round() as usize);
    let pelvis_velocity = derivative(&c.pelvis, fs);
    let mut walking_speed = vec![None; n];
    for k in straight.iter().flat_map(|r| r.clone()) {
        walking_speed[k] = match (pelvis_velocity[k], heading[k]) {
            (Some(v), Some(h)) => Some(v.x * h.cos() + v.y * h.sin()),
            _ => None,
        };
    }

    let angle =
        |prox: &[Option<Vector3<f64>>], dist: &[Option<Vector3<f64>>]| -> Vec<Option<f64>> {
            (0..n)
                .map(|k| {
                    Some(segment_angle(
                        prox.get(k).copied()??,
                        dist.get(k).copied()??,
                        heading[k]?,
                    ))
                })
                .collect()
        };
    let thigh = angle(&c.hip, &c.knee);
    let shank = angle(&c.knee, &c.ankle);
    let foot_raw = angle(&c.ankle, &c.toe);

    let toe_speed = derivative(&c.toe, fs);
    let ankle_speed = derivative(&c.ankle, fs);
    let flat: Vec<f64> = straight
        .iter()
        .flat_map(|r| r.clone())
        .filter(|&k| {
            let slow = |v: Option<Vector3<f64>>| v.is_some_and(|v| v.norm() < p.foot_flat_speed);
            slow(toe_speed[k]) && slow(ankle_speed[k])
        })
        .filter_map(|k| foot_raw[k])
        .collect();
    let foot_offset = if flat.len() >= p.min_foot_flat_samples.max(1) {
        super::median(&flat)
    } else {
        None
    };
    let foot = match foot_offset {
        Some(off) => foot_raw
            .iter()
            .map(|f| f.map(|f| wrap_angle(f - off)))
            .collect(),
        None => vec![None; n],
    };
    SagittalReference {
        heading,
        speed,
        heading_rate,
        straight,
        walking_speed,
        thigh,
        shank,
        foot,
        foot_offset,
        foot_flat_samples: flat.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_signs_follow_spec() {
        // Walking along +y (heading pi/2): a knee in front of the hip is a positive thigh angle.
        let hip = Vector3::new(0.0, 0.0, 1.0);
        let knee = Vector3::new(0.0, 0.2, 0.6);
        assert!(segment_angle(hip, knee, PI / 2.0) > 0.4);
        // The same posture walking along -y is a negative angle.
        assert!(segment_angle(hip, knee, -PI / 2.0) < -0.4);
        assert!(segment_angle(hip, Vector3::new(0.0, 0.0, 0.5), 0.3).abs() < 1e-12);
    }

    #[test]
    fn straight_walk_then_turn() {
        // 4 s straight along +x at 1 m/s, then 2 s turning in place, then 4 s back along -x.
        let fs = 100.0;
        let mut c = JointCentres::default();
        for k in 0..1000 {
            let t = k as f64 / fs;
            let pel = if t < 4.0 {
                Vector3::new(t, 0.0, 1.0)
            } else if t < 6.0 {
                let a = (t - 4.0) / 2.0 * PI;
                Vector3::new(4.0 + 0.05 * a.sin(), 0.05 - 0.05 * a.cos(), 1.0)
            } else {
                Vector3::new(4.0 - (t - 6.0), 0.1, 1.0)
            };
            let hip = pel - Vector3::new(0.0, 0.0, 0.1);
            let knee = hip + Vector3::new(0.0, 0.0, -0.45);
            let ankle = knee + Vector3::new(0.0, 0.0, -0.45);
            let toe = ankle + Vector3::new(if t < 5.0 { 0.15 } else { -0.15 }, 0.0, -0.05);
            c.pelvis.push(Some(pel));
            c.hip.push(Some(hip));
            c.knee.push(Some(knee));
            c.ankle.push(Some(ankle));
            c.toe.push(Some(toe));
        }
        // Feet never stand still in this synthetic walk: allow any speed for foot-flat.
        let p = SagittalParams {
            foot_flat_speed: 10.0,
            ..Default::default()
        };
        let r = sagittal_reference(&c, fs, &p);
        assert_eq!(r.straight.len(), 2, "{:?}", r.straight);
        assert!(
            r.straight[0].start == 0 && (380..430).contains(&r.straight[0].end),
            "{:?}",
            r.straight
        );
        assert!((570..620).contains(&r.straight[1].start) && r.straight[1].end == 1000);
        assert!(r.thigh[100].unwrap().abs() < 1e-9 && r.shank[900].unwrap().abs() < 1e-9);
        assert!(r.foot[100].unwrap().abs() < 1e-9 && r.foot[900].unwrap().abs() < 1e-9);
    }
}
