//! Stride speed and length compared like with like against a `speed_ref`
//! that blends overlapping strides (ours, issue 19; docs/GAIT_EVENTS.md
//! "Evaluation").
//!
//! The shared gait recordings (`gaitmap-foot-walk`, `mobgap-lowerback`)
//! hold in each row of `speed_ref` the mean speed of the reference strides
//! (left and right) that contain the row. The mean of that column over an
//! estimated stride is therefore half the stride itself and half the two
//! overlapping strides of the other foot, so stride-to-stride differences
//! between the feet count as error when one estimated stride is compared
//! with it. Here the estimate goes through the same operator first: in each
//! row, the mean speed of the estimated strides (every track) that contain
//! the row; per estimated stride, the mean of that blended estimate over
//! the stride's rows is compared with the mean of `speed_ref` over the same
//! rows. The blended length is that blended speed times the stride time
//! (the estimated time for the estimate, the paired reference time for the
//! reference), as in the per-stride length error.
//!
//! Undoing the reference's blend instead (solving for each reference stride)
//! is ill-conditioned: a constant added to every left stride and subtracted
//! from every right one leaves the blend unchanged except at the ends of a
//! walk, so only the blended comparison is well defined.

/// One estimated stride of one track, with the reference paired with it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackStride {
    /// Initial contact that starts the stride (s).
    pub start: f64,
    /// Initial contact that ends it (s).
    pub end: f64,
    /// Estimated length (m).
    pub length: f64,
    /// Reference stride time (s), when both initial contacts are paired.
    pub reference_time: Option<f64>,
}

/// Stride speed and length errors (each stride against the blended
/// reference, or blended as in this module).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StrideFigures {
    /// Strides compared (every row of the stride has a reference).
    pub n_strides: usize,
    /// Mean |speed error| (m/s).
    pub speed_mae_mps: Option<f64>,
    /// Mean speed error, estimate - reference (m/s).
    pub speed_bias_mps: Option<f64>,
    /// Strides with a reference length.
    pub n_lengths: usize,
    /// Mean |length error| / reference length (%).
    pub stride_length_error_pct: Option<f64>,
    /// Mean |length error| (m).
    pub stride_length_mae_m: Option<f64>,
}

impl StrideFigures {
    /// The figures of signed speed errors and `(signed length error, reference length)` pairs.
    pub fn from_errors(speed: &[f64], length: &[(f64, f64)]) -> Self {
        let mean =
            |v: &mut dyn Iterator<Item = f64>, n: usize| (n > 0).then(|| v.sum::<f64>() / n as f64);
        StrideFigures {
            n_strides: speed.len(),
            speed_mae_mps: mean(&mut speed.iter().map(|e| e.abs()), speed.len()),
            speed_bias_mps: mean(&mut speed.iter().copied(), speed.len()),
            n_lengths: length.len(),
            stride_length_error_pct: mean(
                &mut length.iter().map(|(e, l)| 100.0 * e.abs() / l),
                length.len(),
            ),
            stride_length_mae_m: mean(&mut length.iter().map(|(e, _)| e.abs()), length.len()),
        }
    }
}

/// How far (s) an event time may lie before a row and still count as on
/// it: 10 us. Events that fall on a row carry the rounding of the
/// arithmetic that produced them (a few 1e-13 s at a clock near 1000 s,
/// about 1e-7 s per operation at a Unix-time clock near 1.7e9 s, where one
/// ulp is 2.4e-7 s), so an exact comparison puts such an event on either
/// side of its row depending on the clock's origin. 10 us is 0.2 % of the
/// shortest sample period of the shared recordings (4.9 ms at 204.8 Hz).
pub const ROW_TOLERANCE_S: f64 = 1e-5;

/// First row at or after `x` (t sorted), an event within
/// [`ROW_TOLERANCE_S`] before a row counting as on it.
pub fn row_at(t: &[f64], x: f64) -> usize {
    t.partition_point(|&v| v < x - ROW_TOLERANCE_S)
}

/// The blended comparison of `strides` (all tracks) with `speed_ref` on rows `t`.
pub fn blended_stride_speed(
    t: &[f64],
    speed_ref: &[Option<f64>],
    strides: &[TrackStride],
) -> StrideFigures {
    let n = t.len();
    let (mut sum, mut count) = (vec![0.0; n], vec![0u32; n]);
    for s in strides {
        let time = s.end - s.start;
        if time <= 0.0 {
            continue;
        }
        for k in row_at(t, s.start)..row_at(t, s.end) {
            sum[k] += s.length / time;
            count[k] += 1;
        }
    }
    let (mut speed, mut length) = (Vec::new(), Vec::new());
    for s in strides {
        let (k0, k1) = (row_at(t, s.start), row_at(t, s.end));
        if k1 <= k0 {
            continue;
        }
        let mut both = (0.0, 0.0);
        let mut complete = true;
        for k in k0..k1 {
            match speed_ref[k] {
                Some(v) if count[k] > 0 => {
                    both.0 += sum[k] / f64::from(count[k]);
                    both.1 += v;
                }
                _ => {
                    complete = false;
                    break;
                }
            }
        }
        if !complete {
            continue;
        }
        let rows = (k1 - k0) as f64;
        let (v_est, v_ref) = (both.0 / rows, both.1 / rows);
        speed.push(v_est - v_ref);
        if let Some(tr) = s.reference_time.filter(|&x| x > 0.0) {
            let (l_est, l_ref) = (v_est * (s.end - s.start), v_ref * tr);
            length.push((l_est - l_ref, l_ref));
        }
    }
    StrideFigures::from_errors(&speed, &length)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An event a rounding below a row counts as on it (issue 19, clock
    /// origin), on either side; one 2 ms before the row or 20 us after it does not.
    #[test]
    fn row_at_counts_an_event_within_the_tolerance_as_on_its_row() {
        for t0 in [0.0, 1000.0, 1.7e9] {
            let t: Vec<f64> = (0..200).map(|k| t0 + 0.01 * k as f64).collect();
            assert_eq!(row_at(&t, t[123] - 3e-7), 123, "t0 = {t0}");
            assert_eq!(row_at(&t, t[123]), 123, "t0 = {t0}");
            assert_eq!(row_at(&t, t[123] - 0.002), 123, "t0 = {t0}");
            assert_eq!(row_at(&t, t[122] + 0.002), 123, "t0 = {t0}");
            assert_eq!(row_at(&t, t[123] + 1e-6), 123, "t0 = {t0}");
            assert_eq!(row_at(&t, t[123] + 2e-5), 124, "t0 = {t0}");
        }
    }

    /// Left strides at 1.1 m/s, right at 1.3 m/s, overlapping by half; the
    /// reference blends them (1.2 m/s everywhere). An estimate that is
    /// exactly right per stride is 0.1 m/s off per stride against the blend,
    /// and exact blended; an estimate 0.05 m/s too fast on every stride is
    /// 0.05 m/s off blended.
    #[test]
    fn a_correct_estimate_is_exact_once_blended() {
        let t: Vec<f64> = (0..600).map(|k| f64::from(k) * 0.01).collect();
        let stride = |start: f64, v: f64, dv: f64| TrackStride {
            start,
            end: start + 1.0,
            length: (v + dv) * 1.0,
            reference_time: Some(1.0),
        };
        let make = |dv: f64| -> Vec<TrackStride> {
            (0..5)
                .map(|i| stride(f64::from(i), 1.1, dv))
                .chain((0..4).map(|i| stride(0.5 + f64::from(i), 1.3, dv)))
                .collect()
        };
        // Reference: rows covered by one left and one right stride.
        let speed_ref: Vec<Option<f64>> = t
            .iter()
            .map(|&x| (0.5..4.5).contains(&x).then_some(1.2))
            .collect();
        let b = blended_stride_speed(&t, &speed_ref, &make(0.0));
        assert_eq!(b.n_strides, 7, "{b:?}");
        assert!(b.speed_mae_mps.unwrap() < 1e-9, "{b:?}");
        assert!(b.stride_length_error_pct.unwrap() < 1e-7, "{b:?}");
        let b = blended_stride_speed(&t, &speed_ref, &make(0.05));
        assert!((b.speed_mae_mps.unwrap() - 0.05).abs() < 1e-9, "{b:?}");
        assert!((b.speed_bias_mps.unwrap() - 0.05).abs() < 1e-9, "{b:?}");
    }
}
