//! Studies of the self-aligning knee estimator (paper 002) for
//! `docs/RESULTS.md`: accuracy over seeds, the order x window table (002
//! Table 1), and the recovery after a thigh-sensor re-mounting (002
//! section 3.6). Run by `examples/knee_study.rs`.

use std::time::Instant;

use limbfuse_core::{Estimator, Joint, Record};
use limbfuse_estimators::knee_selfalign::{Fusion, Geometry, KneeSelfAlign, KneeSelfAlignParams};
pub use limbfuse_eval::knee_errors::{pearson, KneeRun};
use limbfuse_sim::{KneeScenario, KneeSimulator, Remount, SimError, WalkingConfig};

/// Simulates the paper-002 scenario: walking, random IMU orientations and
/// positions, optional re-mounting.
pub fn simulate(
    seed: u64,
    duration_s: f64,
    ap_offset_sd_m: f64,
    remount: Option<Remount>,
) -> Result<Vec<Record>, SimError> {
    let d = KneeScenario::default();
    let sc = KneeScenario {
        walking: WalkingConfig {
            seed,
            duration_s,
            ..d.walking
        },
        ap_offset_sd_m,
        remount,
        ..d
    };
    Ok(KneeSimulator::new(sc)?.collect())
}

/// Like [`simulate`], also returning the true geometry (segment z axes and
/// sensor positions in the sensor frames, moved along the axes as the
/// estimator does) at the start of the trial.
pub fn simulate_with_truth(
    seed: u64,
    duration_s: f64,
    ap_offset_sd_m: f64,
) -> Result<(Vec<Record>, Geometry), SimError> {
    simulate_with_truth_and(seed, duration_s, ap_offset_sd_m, |_| {})
}

/// [`simulate_with_truth`] with the walking configuration (sensor error
/// models, ...) adjusted by `adjust` after seed and duration are set.
pub fn simulate_with_truth_and(
    seed: u64,
    duration_s: f64,
    ap_offset_sd_m: f64,
    adjust: impl FnOnce(&mut WalkingConfig),
) -> Result<(Vec<Record>, Geometry), SimError> {
    let d = KneeScenario::default();
    let mut walking = WalkingConfig {
        seed,
        duration_s,
        ..d.walking
    };
    adjust(&mut walking);
    let sim = KneeSimulator::new(KneeScenario {
        walking,
        ap_offset_sd_m,
        ..d
    })?;
    let (axis, position) = sim.sensor_frame_geometry();
    let (pt, ps) = limbfuse_estimators::knee_selfalign::position::correct_along_axes(
        &position[0],
        &position[1],
        &axis[0],
        &axis[1],
    );
    let g = Geometry {
        axis,
        position: [pt, ps],
        acc_scale: 1.0,
    };
    Ok((sim.collect(), g))
}

/// Runs a fresh estimator over `records` and compares its knee angle with
/// the reference.
pub fn run(records: &[Record], params: KneeSelfAlignParams) -> Result<KneeRun, String> {
    let mut est = KneeSelfAlign::new(params).map_err(|e| e.to_string())?;
    let k = Joint::Knee.index();
    let start = Instant::now();
    let mut out = Vec::with_capacity(records.len());
    for r in records {
        out.push(est.step(&r.sample).map_err(|e| e.to_string())?.joint[k]);
    }
    let seconds = start.elapsed().as_secs_f64();
    Ok(KneeRun::from_estimates(
        records,
        &out,
        &[(0, records.len())],
        seconds,
    ))
}

/// Identifies the joint geometry from `records` as one window (offline,
/// like `limbfuse align --joint-axis`); `None` when not identified.
pub fn identify_offline(records: &[Record], order: usize) -> Option<Geometry> {
    let mut est = KneeSelfAlign::new(KneeSelfAlignParams {
        window: records.len(),
        order,
        ..KneeSelfAlignParams::default()
    })
    .ok()?;
    for r in records {
        est.step(&r.sample).ok()?;
    }
    est.geometry().copied()
}

/// Knee-angle errors of a run with a fixed geometry on the samples whose
/// index is in one of `ranges` (half-open).
pub fn run_fixed(
    records: &[Record],
    geometry: Geometry,
    ranges: &[(usize, usize)],
    fusion: Fusion,
) -> Result<KneeRun, String> {
    let mut est = KneeSelfAlign::new(KneeSelfAlignParams {
        fusion,
        ..KneeSelfAlignParams::default()
    })
    .map_err(|e| e.to_string())?;
    est.fix_geometry(geometry)
        .ok_or("the geometry gives no joint-plane basis")?;
    let k = Joint::Knee.index();
    let start = Instant::now();
    let mut out = Vec::with_capacity(records.len());
    for r in records {
        out.push(est.step(&r.sample).map_err(|e| e.to_string())?.joint[k]);
    }
    let seconds = start.elapsed().as_secs_f64();
    Ok(KneeRun::from_estimates(records, &out, ranges, seconds))
}

/// Like [`run`], evaluated on the samples in `ranges` only.
pub fn run_on(
    records: &[Record],
    params: KneeSelfAlignParams,
    ranges: &[(usize, usize)],
) -> Result<KneeRun, String> {
    let mut est = KneeSelfAlign::new(params).map_err(|e| e.to_string())?;
    let k = Joint::Knee.index();
    let start = Instant::now();
    let mut out = Vec::with_capacity(records.len());
    for r in records {
        out.push(est.step(&r.sample).map_err(|e| e.to_string())?.joint[k]);
    }
    let seconds = start.elapsed().as_secs_f64();
    Ok(KneeRun::from_estimates(records, &out, ranges, seconds))
}

/// Sliding RMSE over the `width_s` seconds ending at each error sample, of
/// the errors minus `offset`.
pub fn sliding_rmse(errors: &[(f64, f64)], width_s: f64, offset: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(errors.len());
    let mut lo = 0;
    let mut sum = 0.0;
    for (hi, &(t, e)) in errors.iter().enumerate() {
        sum += (e - offset).powi(2);
        while errors[lo].0 <= t - width_s {
            sum -= (errors[lo].1 - offset).powi(2);
            lo += 1;
        }
        let n = (hi + 1 - lo) as f64;
        out.push((t, (sum.max(0.0) / n).sqrt()));
    }
    out
}

/// Recovery after an event at `t_event`: the time (s after the event) from
/// which the sliding RMSE stays at or below `threshold` to the end of the
/// trial; `None` if it never settles. Only windows that start at or after
/// the event count (the first is complete `width_s` after it).
pub fn recovery_time(
    sliding: &[(f64, f64)],
    t_event: f64,
    width_s: f64,
    threshold: f64,
) -> Option<f64> {
    let after: Vec<&(f64, f64)> = sliding
        .iter()
        .filter(|(t, _)| *t >= t_event + width_s)
        .collect();
    let last_bad = after.iter().rposition(|(_, r)| *r > threshold);
    match last_bad {
        None => after.first().map(|(t, _)| t - t_event),
        Some(i) if i + 1 < after.len() => Some(after[i + 1].0 - t_event),
        Some(_) => None,
    }
}

/// Mean error over `[t0, t1)`.
pub fn mean_error(errors: &[(f64, f64)], t0: f64, t1: f64) -> f64 {
    let sel: Vec<f64> = errors
        .iter()
        .filter(|(t, _)| *t >= t0 && *t < t1)
        .map(|x| x.1)
        .collect();
    sel.iter().sum::<f64>() / sel.len().max(1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sliding_rmse_and_recovery_by_hand() {
        // 1 Hz samples: error 0 until t = 10, 5 deg for t in [10, 13), then 0.
        let e: Vec<(f64, f64)> = (0..30)
            .map(|k| {
                let t = k as f64;
                (t, if (10.0..13.0).contains(&t) { 5.0 } else { 0.0 })
            })
            .collect();
        let s = sliding_rmse(&e, 2.0, 0.0);
        // Window (t-2, t]: at t = 11 holds t = 10, 11 -> 5.
        assert!((s[11].1 - 5.0).abs() < 1e-12);
        // At t = 13: 12 (5), 13 (0) -> sqrt(12.5).
        assert!((s[13].1 - 12.5f64.sqrt()).abs() < 1e-12);
        assert_eq!(s[14].1, 0.0);
        assert_eq!(recovery_time(&s, 10.0, 2.0, 1.0), Some(4.0));
        assert_eq!(recovery_time(&s, 20.0, 2.0, 1.0), Some(2.0));
    }
}
