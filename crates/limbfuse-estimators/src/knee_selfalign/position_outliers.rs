//! Ours (2026-12-07, beyond paper 002): samples whose eq-3 residual is a
//! gross outlier, left out of the window's position fit and of the
//! accelerometer angle.
//!
//! Eq 3 needs the rate derivative (the five-point formula of
//! [`super::position`]), which turns one corrupted gyroscope reading into
//! four corrupted derivatives: a single-sample spike of 3 rad/s at 100 Hz
//! is a pair of 200 rad/s^2 errors, `Gamma` errors of tens of m/s^2 at a
//! sensor 0.2 m from the joint, against residuals of about 0.1 m/s^2. Three
//! such spikes in 50 s of walking moved the fitted positions far enough
//! that the accelerometer angle was no longer trusted (knee RMSE 1.1 -> 3.8
//! deg on the independent 1.2 m/s walk; 60 spikes: 20 deg, docs/RESULTS.md
//! "Single-sample gyroscope spikes"). The outliers are found by Hampel's
//! identifier (Hampel 1974; Pearson 2002, IEEE Trans. Control Syst.
//! Technol. 10:55-63): a residual more than [`HAMPEL_K`] robust standard
//! deviations (1.4826 median absolute deviations) from the window's median.
//! They are left out ([`Ring::exclude`]), the positions fitted again, and
//! a sample whose residual at the current geometry is beyond the last
//! window's bound gives no accelerometer angle ([`rejects`]).
//!
//! The threshold is not the Gaussian 3: eq 3's residuals are heavy-tailed
//! (impacts, soft tissue, a rig's belt), and leaving out every residual
//! beyond 3 robust SDs took 2-5 % of each window and moved the knee of
//! limbfuse's simulated walks by up to 0.5 deg. Measured over every window
//! of the shared recordings and simulations (docs/RESULTS.md), the largest
//! clean residual is 4-7 robust SDs on the simulated walks and 19 on the
//! knee rig, a 3 rad/s spike's 500-650: 25 leaves every clean window as it
//! was and still finds a spike of 0.3 rad/s.

use nalgebra::{Vector3, Vector6};

use super::acc_scale::scaled;
use super::position::{Kinematics, MIN_JOINT_ACCELERATION};
use super::ring::Ring;

/// Hampel's identifier's threshold, in robust standard deviations.
pub const HAMPEL_K: f64 = 25.0;

/// A normal distribution's standard deviation over its median absolute
/// deviation.
const MAD_TO_SD: f64 = 1.482_6;

/// Fewest residuals from which a median absolute deviation is taken.
const MIN_RESIDUALS: usize = 20;

/// The residual level of a window's position fit: a residual `e` is an
/// outlier when `|e - median| > bound`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResidualScreen {
    /// Median of the window's eq-3 residuals (m/s^2).
    pub median: f64,
    /// [`HAMPEL_K`] robust standard deviations (m/s^2).
    pub bound: f64,
}

impl ResidualScreen {
    /// Whether the residual `e` (m/s^2) is an outlier.
    pub fn is_outlier(&self, e: f64) -> bool {
        (e - self.median).abs() > self.bound
    }
}

/// Eq 3's residual of sample `i` at the positions `o` with the relative
/// accelerometer scale `r` (`None` where [`Ring::kinematics`] or the
/// residual has none).
pub fn residual_at(ring: &Ring, i: usize, o: &Vector6<f64>, r: f64) -> Option<f64> {
    residual_of(&ring.kinematics(i)?, o, r)
}

/// `e_o` of [`position_residual`] without its gradient (`None` where that
/// has none).
fn residual_of(kin: &[Kinematics; 2], o: &Vector6<f64>, r: f64) -> Option<f64> {
    let [t, s] = *kin;
    let s = if r == 1.0 { s } else { scaled(&s, r) };
    let n_t = t
        .joint_acceleration(&o.fixed_rows::<3>(0).into_owned())
        .norm();
    let n_s = s
        .joint_acceleration(&o.fixed_rows::<3>(3).into_owned())
        .norm();
    (n_t >= MIN_JOINT_ACCELERATION && n_s >= MIN_JOINT_ACCELERATION).then_some(n_t - n_s)
}

/// Whether a sample whose joint-centre accelerations (eq 7, both sensors,
/// at the current geometry) are `joint` is an outlier of `screen`: its
/// accelerometer angle is then not used. Its eq-3 residual is the
/// difference of their norms, so the accelerometer angle's own
/// accelerations serve. `false` without a screen or a residual.
pub fn rejects(screen: Option<&ResidualScreen>, joint: &[Vector3<f64>; 2]) -> bool {
    let [n_t, n_s] = joint.map(|a| a.norm());
    screen.is_some_and(|s| {
        n_t >= MIN_JOINT_ACCELERATION && n_s >= MIN_JOINT_ACCELERATION && s.is_outlier(n_t - n_s)
    })
}

/// Leaves the window's outliers at `o` (scale `r`) out of
/// [`Ring::kinematics`]: the screen, and how many samples it left out
/// (`None` with fewer than 20 residuals or all equal). No allocation.
pub fn mark_outliers(ring: &mut Ring, o: &Vector6<f64>, r: f64) -> Option<(ResidualScreen, usize)> {
    let (mut indexed, mut values) = ring.take_scratch();
    indexed.extend((0..ring.len()).filter_map(|i| Some((i, residual_at(ring, i, o, r)?))));
    values.extend(indexed.iter().map(|&(_, e)| e));
    let screen = screen_of(&mut values);
    let mut marked = 0;
    if let Some(s) = screen {
        for &(i, e) in &indexed {
            if s.is_outlier(e) {
                ring.exclude(i);
                marked += 1;
            }
        }
    }
    ring.put_scratch((indexed, values));
    Some((screen?, marked))
}

/// Threshold of [`mark_rate_spikes`], in robust scales of the window's
/// rate departures. Clean windows reach 3.3 on the independent walks, 9.4 on
/// limbfuse's simulated ones, 30 on the gaittoolbox walk and 58 on the knee
/// rig; a 1 rad/s spike 52-61, a 3 rad/s spike 160-185 (docs/RESULTS.md,
/// "Single-sample gyroscope spikes"). A pre-screen only: its marks give the
/// robust start of [`super::position_fit::fit_positions_screened`] and are
/// then dropped, so a real sample it marks costs one more fit, not an
/// output.
pub const RATE_SPIKE_K: f64 = 25.0;

/// Fit-free pre-screen (ours): marks the samples around a gyroscope reading
/// that departs from the mean of its two neighbours (`|g_i - (g_i-1 +
/// g_i+1) / 2|`, the larger of the thigh's and the shank's) by more than
/// [`RATE_SPIKE_K`] times the window's robust scale of that departure
/// (1.4826 x its median): the reading and the two on each side, whose
/// five-point derivatives take it in. Returns how many it marked. No
/// allocation.
pub fn mark_rate_spikes(ring: &mut Ring) -> usize {
    let departure = |ring: &Ring, i: usize| -> Option<f64> {
        let [a, b, c] = [ring.get(i - 1), ring.get(i), ring.get(i + 1)];
        (a.gyr_ok && b.gyr_ok && c.gyr_ok).then(|| {
            (0..2)
                .map(|seg| (b.gyr[seg] - (a.gyr[seg] + c.gyr[seg]) * 0.5).norm())
                .fold(0.0, f64::max)
        })
    };
    let n = ring.len();
    if n < 3 {
        return 0;
    }
    let (mut indexed, mut values) = ring.take_scratch();
    indexed.extend((1..n - 1).filter_map(|i| Some((i, departure(ring, i)?))));
    values.extend(indexed.iter().map(|&(_, d)| d));
    let mut marked = 0;
    if values.len() >= MIN_RESIDUALS {
        let scale = MAD_TO_SD * median(&mut values);
        if scale > 0.0 && scale.is_finite() {
            for &(i, d) in &indexed {
                if d > RATE_SPIKE_K * scale {
                    for k in i.saturating_sub(2)..(i + 3).min(n) {
                        ring.exclude(k);
                    }
                    marked += 1;
                }
            }
        }
    }
    ring.put_scratch((indexed, values));
    marked
}

/// The median (the upper one of an even count) of `v`, which it reorders.
fn median(v: &mut [f64]) -> f64 {
    let m = v.len() / 2;
    *v.select_nth_unstable_by(m, f64::total_cmp).1
}

/// Hampel's screen of the residuals `e` (reordered and overwritten).
fn screen_of(e: &mut [f64]) -> Option<ResidualScreen> {
    if e.len() < MIN_RESIDUALS {
        return None;
    }
    let med = median(e);
    e.iter_mut().for_each(|v| *v = (*v - med).abs());
    let mad = median(e);
    (mad > 0.0 && mad.is_finite()).then_some(ResidualScreen {
        median: med,
        bound: HAMPEL_K * MAD_TO_SD * mad,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hampel_screen_of_known_values() {
        // 1..=21: median 11, absolute deviations 0,1,1,...,10,10: MAD 5
        // (the upper median of 21 values is the 11th smallest: 5).
        let mut e: Vec<f64> = (1..=21).map(f64::from).collect();
        let s = screen_of(&mut e).unwrap();
        assert_eq!(s.median, 11.0);
        // bound 25 x 1.4826 x 5 = 185.325
        assert_eq!(s.bound, 25.0 * 1.4826 * 5.0);
        assert!(!s.is_outlier(11.0 + 185.3));
        assert!(s.is_outlier(11.0 + 185.4));
        assert!(s.is_outlier(11.0 - 185.4));
    }

    /// 100 Hz walking-like rates (two sines) with white noise of 0.005
    /// rad/s from a seeded generator, one reading of the shank's z axis
    /// off by `spike` rad/s at sample 100.
    fn rates(spike: f64) -> Ring {
        let mut ring = Ring::new(300);
        let mut u = 0x2545_f491_4f6c_dd1d_u64;
        let mut noise = || {
            u ^= u << 13;
            u ^= u >> 7;
            u ^= u << 17;
            0.005 * ((u >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 12f64.sqrt()
        };
        for k in 0..300 {
            let t = k as f64 * 0.01;
            let w = 4.0 * (2.0 * core::f64::consts::PI * t).sin();
            let mut shank = nalgebra::Vector3::new(noise(), noise(), -1.2 * w + noise());
            if k == 100 {
                shank.z += spike;
            }
            ring.push(crate::knee_selfalign::ring::Slot {
                t,
                gyr: [nalgebra::Vector3::new(noise(), noise(), w + noise()), shank],
                acc: [nalgebra::Vector3::new(0.0, 9.81, 0.0); 2],
                gyr_ok: true,
                acc_ok: true,
            });
        }
        ring
    }

    #[test]
    fn a_rate_spike_and_its_stencil_are_marked_and_nothing_else() {
        // Smooth rates: the largest departure is the noise's, a few robust
        // scales; a 1 rad/s reading departs by ~1 rad/s, hundreds of them.
        let mut clean = rates(0.0);
        assert_eq!(mark_rate_spikes(&mut clean), 0);
        assert!((0..300).all(|i| !clean.is_excluded(i)));
        // The spike departs by 1 rad/s, its neighbours by half of it (it is
        // in their neighbours' mean): three readings, each with the two
        // samples on either side.
        let mut spiked = rates(1.0);
        assert_eq!(mark_rate_spikes(&mut spiked), 3);
        let marked: Vec<usize> = (0..300).filter(|&i| spiked.is_excluded(i)).collect();
        assert_eq!(marked, (97..=103).collect::<Vec<_>>());
    }

    #[test]
    fn too_few_or_constant_residuals_give_no_screen() {
        let mut few: Vec<f64> = (0..19).map(f64::from).collect();
        assert_eq!(screen_of(&mut few), None);
        let mut flat = vec![0.5; 40];
        assert_eq!(screen_of(&mut flat), None);
    }
}
