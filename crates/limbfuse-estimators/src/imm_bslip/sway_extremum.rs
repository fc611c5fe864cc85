//! Mid-stance and its side from the CoM's lateral sway (ours, not in paper
//! 003; docs/GAIT_IMM.md, "Restart after a gap or a mid-stride start").
//!
//! In walking the CoM sways over the stance foot: the lateral position `z`
//! (SPEC: z right) is furthest left at mid-stance (MS) on the left foot and
//! furthest right at MS on the right foot. B-SLIP gaits are symmetric in time
//! about MS, so the lateral velocity is zero there; a real pelvis sways the
//! same way (its extremes lie near MS).
//!
//! The extremum is found by a least-squares parabola
//! `z(tau) = c0 + c1 tau + c2 tau^2` over the last window of measured
//! positions (`tau` from the window's mid time), one step long
//! ([`window_for_step`]): from one lateral zero crossing to the next, so it
//! never spans two extremes, and as long as the step allows, because the
//! curvature of a slow walk's sway stands out of the noise only over a long
//! window (limbfuse's 0.5 m/s B-SLIP trial, paper 003 eq 15's 7 mm noise:
//! t statistic about 1 over 0.5 s at MS). The sway is symmetric about
//! its extremum, so the vertex `tau_v = -c1 / (2 c2)` of a fit centred on it
//! is unbiased even where the sway is not a parabola. An extremum is
//! reported when the curvature is significant (`|c2| / se(c2) >`
//! [`MIN_CURVATURE_T`], `se` from the fit's own residuals, so measurement
//! noise of any size is accounted for) and the vertex has reached the
//! window's middle: half a window after MS.

use limbfuse_models::bslip::Side;
use nalgebra::{Matrix3, Vector3};

/// Shortest and longest fitted window (s).
pub const WINDOW_RANGE_S: (f64, f64) = (0.4, 1.2);

/// The fitted window for a walk of step time `step_time` (s): one step,
/// within [`WINDOW_RANGE_S`].
pub fn window_for_step(step_time: f64) -> f64 {
    if step_time.is_finite() {
        step_time.clamp(WINDOW_RANGE_S.0, WINDOW_RANGE_S.1)
    } else {
        WINDOW_RANGE_S.0
    }
}

/// Minimum t statistic of the curvature `c2`: three standard errors.
pub const MIN_CURVATURE_T: f64 = 3.0;

/// Fewest samples in a window (three parameters and their residuals).
const MIN_SAMPLES: usize = 8;

/// An MS found in the sway.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwayMidStance {
    /// Time of the lateral extremum (s).
    pub t: f64,
    /// The stance foot's side: left at a minimum of `z`, right at a maximum.
    pub side: Side,
}

/// The window's fit: `(c, se(c2))`, `None` when it is singular.
fn fit(
    samples: impl Iterator<Item = (f64, f64)> + Clone,
    t_mid: f64,
) -> Option<(Vector3<f64>, f64)> {
    let mut xtx = Matrix3::zeros();
    let mut xtz = Vector3::zeros();
    let mut zz = 0.0;
    let mut n = 0usize;
    for (t, z) in samples {
        let tau = t - t_mid;
        let row = Vector3::new(1.0, tau, tau * tau);
        xtx += row * row.transpose();
        xtz += row * z;
        zz += z * z;
        n += 1;
    }
    if n < MIN_SAMPLES {
        return None;
    }
    let inv = xtx.try_inverse()?;
    let c = inv * xtz;
    // Residual sum of squares: z'z - c' X'z.
    let rss = (zz - c.dot(&xtz)).max(0.0);
    let s2 = rss / (n - 3) as f64;
    Some((c, libm::sqrt(s2 * inv[(2, 2)])))
}

/// The MS at the middle of the last `window` s of `samples` (time, lateral
/// position; oldest first, ending now), if it holds a significant extremum
/// whose vertex has reached its middle.
pub fn mid_stance_in<I>(samples: I, window: f64) -> Option<SwayMidStance>
where
    I: DoubleEndedIterator<Item = (f64, f64)> + Clone,
{
    let (t_now, _) = samples.clone().next_back()?;
    let start = t_now - window;
    let last = samples.clone().skip_while(move |&(t, _)| t < start);
    let (t_first, _) = last.clone().next()?;
    if t_now - t_first < 0.9 * window {
        return None;
    }
    let t_mid = 0.5 * (t_first + t_now);
    let (c, se) = fit(last, t_mid)?;
    let c2 = c[2];
    // A NaN fit (it cannot be: the samples are finite) is not significant.
    let significant = c2.abs() > MIN_CURVATURE_T * se;
    if !significant {
        return None;
    }
    let tau_v = -c[1] / (2.0 * c2);
    let half = 0.5 * (t_now - t_first);
    if !(tau_v <= 0.0 && tau_v >= -0.5 * half) {
        return None;
    }
    // The window is centred on the vertex only when it is found at once; a
    // weak curvature (a slow walk) is significant only later, with the
    // vertex off the window's middle, where the sway's departure from a
    // parabola biases it towards the middle. Refit centred on the vertex.
    let mut t_v = t_mid + tau_v;
    for _ in 0..4 {
        let (a, b) = (t_v - 0.5 * window, t_v + 0.5 * window);
        let centred = samples.clone().filter(move |&(t, _)| a <= t && t <= b);
        let (Some((first, _)), Some((last, _))) =
            (centred.clone().next(), centred.clone().next_back())
        else {
            break;
        };
        if first > a + 0.05 * window || last < b - 0.05 * window {
            break;
        }
        let Some((c, _)) = fit(centred, t_v) else {
            break;
        };
        if c[2] * c2 <= 0.0 {
            break;
        }
        let step = -c[1] / (2.0 * c[2]);
        if step.abs() > 0.25 * window {
            break;
        }
        t_v += step;
        if step.abs() < 1e-4 {
            break;
        }
    }
    Some(SwayMidStance {
        t: t_v,
        side: if c2 > 0.0 { Side::Left } else { Side::Right },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The window of a fast walk's step.
    const WINDOW: f64 = 0.5;

    /// `z = a cos(w (t - t0))` sampled at `rate` from `t_start` to `t_end`,
    /// plus the deterministic "noise" `noise(k)`.
    fn sway(
        a: f64,
        w: f64,
        t0: f64,
        rate: f64,
        t_end: f64,
        noise: impl Fn(usize) -> f64,
    ) -> Vec<(f64, f64)> {
        let n = (t_end * rate) as usize;
        (0..=n)
            .map(|k| {
                let t = k as f64 / rate;
                (t, a * (w * (t - t0)).cos() + noise(k))
            })
            .collect()
    }

    /// The first window, sliding sample by sample, that reports an MS.
    fn first_detection(s: &[(f64, f64)]) -> Option<(usize, SwayMidStance)> {
        (1..=s.len())
            .find_map(|k| mid_stance_in(s[..k].iter().copied(), WINDOW).map(|m| (k - 1, m)))
    }

    #[test]
    fn a_maximum_is_mid_stance_on_the_right_found_half_a_window_later() {
        // Stride 1.2 s; maximum (right foot) at 0.4 s, minimum at 1.0 s.
        let w = 2.0 * core::f64::consts::PI / 1.2;
        let s = sway(0.02, w, 0.4, 100.0, 3.0, |_| 0.0);
        let (k, m) = first_detection(&s).unwrap();
        assert_eq!(m.side, Side::Right);
        // The cosine is not a parabola and the window is centred on the
        // vertex only to a sample: 1 ms.
        assert!((m.t - 0.4).abs() < 1e-3, "{}", m.t);
        // Reported when the window's middle reaches the vertex.
        assert!((s[k].0 - (0.4 + 0.5 * WINDOW)).abs() < 0.011, "{}", s[k].0);
        // The next report is the minimum.
        let (_, next) = first_detection(&s[k + 1..]).unwrap();
        assert_eq!(next.side, Side::Left);
        assert!((next.t - 1.0).abs() < 1e-3, "{}", next.t);
    }

    #[test]
    fn a_minimum_is_mid_stance_on_the_left() {
        // A slow walk (stride 2 s): minimum (left foot) at 0.4 s.
        let w = core::f64::consts::PI;
        let s = sway(-0.02, w, 0.4, 100.0, 3.0, |_| 0.0);
        let (_, m) = first_detection(&s).unwrap();
        assert_eq!(m.side, Side::Left);
        assert!((m.t - 0.4).abs() < 1e-3, "{}", m.t);
    }

    #[test]
    fn noise_moves_the_vertex_by_little_and_a_flat_walk_reports_nothing() {
        // 7 mm "noise" from a fixed pseudo-random sequence (paper 003 eq 15's
        // position variance 5e-5 m^2), 2.3 cm sway, 100 Hz.
        let noise = |k: usize| {
            let u = ((k as u64).wrapping_mul(2_654_435_761) % 1000) as f64 / 1000.0;
            0.007 * 1.732 * (2.0 * u - 1.0)
        };
        let w = 2.0 * core::f64::consts::PI / 1.38;
        let s = sway(0.023, w, 0.4, 100.0, 3.0, noise);
        let (_, m) = first_detection(&s).unwrap();
        assert_eq!(m.side, Side::Right);
        assert!((m.t - 0.4).abs() < 0.05, "{}", m.t);
        let flat = sway(0.0, w, 1.0, 100.0, 3.0, noise);
        assert_eq!(first_detection(&flat), None);
    }

    #[test]
    fn too_short_or_too_sparse_a_window_reports_nothing() {
        let w = 2.0 * core::f64::consts::PI / 1.2;
        let s = sway(0.02, w, 0.3, 100.0, 0.4, |_| 0.0);
        assert_eq!(first_detection(&s), None);
        let sparse = sway(0.02, w, 0.3, 10.0, 3.0, |_| 0.0);
        assert_eq!(first_detection(&sparse[..6]), None);
    }
}
