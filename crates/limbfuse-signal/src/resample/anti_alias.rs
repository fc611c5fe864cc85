//! Anti-alias low-pass filters used when decimating IMU channels: the
//! Blackman-windowed sinc evaluated at each output time over the input
//! samples within `+-W`, and the one-output-period boxcar mean it falls back
//! to (see the module docs of [`super`]).

use super::{Series, GAP_FACTOR, SINC_CUTOFF_FRACTION, SINC_HALF_WIDTH_PERIODS};

/// Blackman window on [-1, 1].
fn blackman(x: f64) -> f64 {
    use std::f64::consts::PI;
    if x.abs() >= 1.0 {
        return 0.0;
    }
    0.42 + 0.5 * (PI * x).cos() + 0.08 * (2.0 * PI * x).cos()
}

/// Normalised sinc, `sin(pi x) / (pi x)`.
fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-12 {
        1.0
    } else {
        let y = std::f64::consts::PI * x;
        y.sin() / y
    }
}

/// Mean over `[tg - T/2, tg + T/2]`, the end points weighted 1/2.
pub(super) fn boxcar_at(s: &Series, tg: f64, period_out: f64) -> Option<f64> {
    let half = 0.5 * period_out;
    let tol = 1e-9 * period_out;
    let lo = s.t.partition_point(|&x| x < tg - half - tol);
    let hi = s.t.partition_point(|&x| x <= tg + half + tol);
    let (mut sw, mut sv) = (0.0, 0.0);
    for k in lo..hi {
        let edge = (s.t[k] - tg).abs() >= half - tol;
        let w = if edge { 0.5 } else { 1.0 };
        sw += w;
        sv += w * s.v[k];
    }
    (sw > 0.0).then(|| sv / sw)
}

/// Windowed-sinc low-pass of `s` at every time of `grid` (output rate
/// `rate_hz`, input period `p_in`), with the boxcar fallback where the
/// kernel does not fit inside a gap-free run of the channel.
pub(super) fn windowed_sinc(s: &Series, grid: &[f64], rate_hz: f64, p_in: f64) -> Vec<Option<f64>> {
    let period_out = 1.0 / rate_hz;
    // Gap-free runs: run_end[k] = index of the last sample of k's run.
    let n = s.t.len();
    let mut run_start = vec![0usize; n];
    for k in 1..n {
        run_start[k] = if s.t[k] - s.t[k - 1] > GAP_FACTOR * p_in {
            k
        } else {
            run_start[k - 1]
        };
    }
    let mut run_end = vec![n - 1; n];
    for k in (0..n - 1).rev() {
        run_end[k] = if s.t[k + 1] - s.t[k] > GAP_FACTOR * p_in {
            k
        } else {
            run_end[k + 1]
        };
    }
    let half_width = SINC_HALF_WIDTH_PERIODS * period_out;
    let two_fc = 2.0 * SINC_CUTOFF_FRACTION * rate_hz;
    grid.iter()
        .map(|&tg| {
            let lo = s.t.partition_point(|&x| x <= tg - half_width);
            let hi = s.t.partition_point(|&x| x < tg + half_width);
            // The kernel must lie inside one gap-free run, within half an
            // input period of its ends.
            let inside = lo < hi
                && run_end[lo] >= hi - 1
                && s.t[run_start[lo]] <= tg - half_width + 0.5 * p_in
                && s.t[run_end[lo]] >= tg + half_width - 0.5 * p_in;
            if inside {
                let (mut sw, mut sv) = (0.0, 0.0);
                for k in lo..hi {
                    let tau = s.t[k] - tg;
                    let w = sinc(two_fc * tau) * blackman(tau / half_width);
                    sw += w;
                    sv += w * s.v[k];
                }
                // With the whole kernel covered the sum is about f_in / (2 fc)
                // > 1; anything tiny means something odd: fall back.
                if sw > 0.5 {
                    return Some(sv / sw);
                }
            }
            boxcar_at(s, tg, period_out)
        })
        .collect()
}
