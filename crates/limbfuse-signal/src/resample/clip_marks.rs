//! Clipped gyroscope readings carried through resampling.
//!
//! A gyroscope at its full scale reports the rail, not the rate. Left out
//! before resampling (until 2026-12-06), a swing clipped at a consumer
//! sensor's 250 deg/s became a gap and `gait-events` found no gait in the
//! resampled file; low-passed with the rest, the clipped run's edges fall
//! below the sensor gate's test and the angle methods integrate them
//! (`chain` 1.1 -> 3.3 deg, `knee-gyro-axis` 11 -> 77 deg on that walk at
//! 50 Hz, docs/RESULTS.md "Clipped accelerometers"). So a clipped cell is
//! left out of its axis's series (its vector's other axes stay), the axis
//! is resampled from the rest, and an output sample within half an input
//! period of a clipped reading is set to the nearest such reading, the
//! rail: the gate then rejects the vector for the angle methods, and
//! `gait-events`, which keeps clipped gyroscope readings, still sees the
//! swing. (Half an output period, marking every output next to a run,
//! measured worse: docs/RESULTS.md.)

/// Sets `out[k]` (a series resampled on `grid` without its clipped
/// readings) to the clipped reading of `clipped` (times increasing, values
/// at the rail) nearest to `grid[k]` within `half` (s). One pass.
pub(super) fn mark_clipped(
    clipped: &[(f64, f64)],
    grid: &[f64],
    half: f64,
    out: &mut [Option<f64>],
) {
    let mut j = 0;
    for (k, &tg) in grid.iter().enumerate() {
        while j < clipped.len() && clipped[j].0 < tg - half {
            j += 1;
        }
        let nearest = clipped[j..]
            .iter()
            .take_while(|(t, _)| *t <= tg + half)
            .min_by(|a, b| (a.0 - tg).abs().total_cmp(&(b.0 - tg).abs()));
        if let (Some(o), Some(&(_, v))) = (out.get_mut(k), nearest) {
            *o = Some(v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_near_a_clipped_reading_take_the_rail() {
        // 100 Hz input clipped at -4.3 rad/s from 0.10 to 0.15 s, resampled
        // to 50 Hz (output 7 missing: in the run, no other reading).
        let clipped: Vec<(f64, f64)> = (10..=15).map(|k| (k as f64 * 0.01, -4.3)).collect();
        let grid: Vec<f64> = (0..20).map(|k| k as f64 * 0.02).collect();
        let mut out: Vec<Option<f64>> = vec![Some(0.5); 20];
        out[6] = None;
        mark_clipped(&clipped, &grid, 0.01, &mut out);
        for (k, o) in out.iter().enumerate() {
            let tg = grid[k];
            let expect = if (0.09..=0.16 + 1e-9).contains(&tg) {
                Some(-4.3)
            } else {
                Some(0.5)
            };
            assert_eq!(*o, expect, "t = {tg}");
        }
    }
}
