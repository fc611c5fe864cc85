//! Which samples are walking: the leg sensors move periodically with the
//! stride. A trial may hold standing, sitting, fidgeting, turning on the
//! spot; only periodic gait supports the axis and sign rules.
//!
//! Test (per window of `walk_window_s`, centres every 0.25 s): the
//! normalised autocorrelation of the gyro norm `|w|` (independent of the
//! mounting) at lags of one stride, `T` in 0.7..2.2 s (cadence 55-170
//! steps/min, the range of adult walking from very slow to fast, Perry &
//! Burnfield 2010 ch. 2), is at least `walk_min_autocorr` for at least one leg
//! sensor (a sensor that does not move is then reported by name), and the window's gyro-norm standard deviation is at least
//! `quiet_gyro_max` (above sensor noise). Autocorrelation of a stride-periodic
//! signal is ~1 at the stride lag; noise and non-periodic motion give ~0.
//! This is the usual autocorrelation gait detector (e.g. Moe-Nilssen &
//! Helbostad 2004, J Biomech 37:121).

use limbfuse_core::{Record, Segment};

use super::series::gyr;
use super::AlignOptions;

/// Shortest and longest stride period (s) searched.
const STRIDE_S: (f64, f64) = (0.7, 2.2);
/// Spacing (s) of the window centres.
const STEP_S: f64 = 0.25;

/// Best normalised autocorrelation of `x[a..b]` over lags `lags`; `None`
/// when the window is too short or (nearly) constant.
fn best_autocorr(x: &[f64], lags: std::ops::RangeInclusive<usize>, min_sd: f64) -> Option<f64> {
    let n = x.len();
    let m = x.iter().sum::<f64>() / n as f64;
    let var = x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / n as f64;
    if var.sqrt() < min_sd {
        return Some(0.0);
    }
    let mut best = f64::NEG_INFINITY;
    for lag in lags {
        // (a lag of usize::MAX, from a time step of 1e-20 s, overflowed here)
        if lag.saturating_add(10) > n {
            break;
        }
        let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
        for k in 0..n - lag {
            let (a, b) = (x[k] - m, x[k + lag] - m);
            sab += a * b;
            saa += a * a;
            sbb += b * b;
        }
        if saa > 0.0 && sbb > 0.0 {
            best = best.max(sab / (saa * sbb).sqrt());
        }
    }
    best.is_finite().then_some(best)
}

/// Per record: does it lie in periodic (walking) motion? `dt` is the
/// median sample interval (s). Uses the leg sensors present (else the trunk).
pub(crate) fn walking_mask(
    records: &[Record],
    present: &[bool; 4],
    dt: f64,
    opts: &AlignOptions,
) -> Vec<bool> {
    let n = records.len();
    let leg: Vec<Segment> = [Segment::Thigh, Segment::Shank, Segment::Foot]
        .into_iter()
        .filter(|s| present[s.index()])
        .collect();
    let sensors = if leg.is_empty() {
        vec![Segment::Trunk]
    } else {
        leg
    };
    let norms: Vec<Vec<f64>> = sensors
        .iter()
        .map(|&s| {
            let mut last = 0.0;
            (0..n)
                .map(|k| {
                    if let Some(w) = gyr(records, s, k) {
                        last = w.norm();
                    }
                    last
                })
                .collect()
        })
        .collect();
    let win = ((opts.walk_window_s / dt).round() as usize).clamp(20, n.max(20));
    let lags = (STRIDE_S.0 / dt).round().max(1.0) as usize..=(STRIDE_S.1 / dt).round() as usize;
    let step = ((STEP_S / dt).round() as usize).max(1);
    let mut centres = Vec::new();
    let mut c = 0;
    while c < n {
        centres.push(c);
        c = c.saturating_add(step);
    }
    // (cancelled: no window is walking; the caller then checks the hook)
    let mut cancelled = false;
    let verdict: Vec<bool> = centres
        .iter()
        .map(|&c| {
            cancelled = cancelled || opts.cancel.is_some_and(|f| f());
            if n < win || cancelled {
                return false;
            }
            let a = c.saturating_sub(win / 2).min(n - win);
            let mut r: Vec<f64> = norms
                .iter()
                .map(|x| {
                    best_autocorr(&x[a..a + win], lags.clone(), opts.quiet_gyro_max).unwrap_or(0.0)
                })
                .collect();
            r.sort_by(f64::total_cmp);
            r[r.len() - 1] >= opts.walk_min_autocorr
        })
        .collect();
    (0..n)
        .map(|k| verdict[(k.saturating_add(step / 2) / step).min(verdict.len() - 1)])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_periodic_signal_correlates_at_its_period_and_noise_does_not() {
        let dt = 0.01;
        let x: Vec<f64> = (0..400)
            .map(|k| (k as f64 * dt * std::f64::consts::TAU / 1.1).sin().abs() * 3.0)
            .collect();
        let lags = 70..=220;
        let r = best_autocorr(&x, lags.clone(), 0.1).unwrap();
        assert!(r > 0.95, "{r}");
        // Deterministic pseudo-noise.
        let mut s = 12345u64;
        let y: Vec<f64> = (0..400)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (s >> 11) as f64 / (1u64 << 53) as f64
            })
            .collect();
        let r = best_autocorr(&y, lags.clone(), 0.0).unwrap();
        assert!(r < 0.3, "{r}");
        // Still: below the noise floor.
        assert_eq!(best_autocorr(&[1.0; 400], lags, 0.1), Some(0.0));
    }

    /// An audit multiplied a walking trial's times by 1e-20: the stride lag
    /// (stride period / dt) saturated to `usize::MAX` and `lag + 10`
    /// overflowed into an index out of bounds. Such a trial has no
    /// walking: every sample is `false`, nothing panics.
    #[test]
    fn a_time_step_of_1e_minus_20_s_finds_no_walking_without_overflow() {
        let records: Vec<Record> = (0..500)
            .map(|k| {
                let mut r = Record::default();
                r.sample.t = k as f64 * 1e-20;
                for imu in &mut r.sample.imu {
                    imu.gyr = Some(nalgebra::Vector3::new(
                        0.0,
                        0.0,
                        (k as f64 * 0.3).sin() * 3.0,
                    ));
                }
                r
            })
            .collect();
        let opts = AlignOptions::default();
        for dt in [1e-20, 1e-300, f64::MIN_POSITIVE] {
            let mask = walking_mask(&records, &[true; 4], dt, &opts);
            assert_eq!(mask, vec![false; 500]);
        }
        assert_eq!(
            best_autocorr(&[0.0, 1.0, 0.0, 1.0], usize::MAX - 5..=usize::MAX, 0.0),
            None
        );
    }
}
