//! The SHOE zero-velocity (foot at rest) detector of Skog et al. 2010,
//! "Zero-velocity detection — an algorithm evaluation", IEEE TBME 57(11),
//! eq. 18 (the stance hypothesis optimal detector): over a window of `W`
//! samples,
//!
//! `T = 1/W sum_k ( ||a_k - g a_bar / ||a_bar|| ||^2 / sigma_a^2 + ||w_k||^2 / sigma_w^2 )`
//!
//! and the foot is at rest when `T < gamma`. The window is the trailing one
//! (the decision for sample `k` uses `k - W + 1 ..= k`), so the detector
//! adds no latency. Fixed capacity: no allocation.

use nalgebra::Vector3;

/// Largest window the detector holds.
pub const MAX_WINDOW: usize = 16;

/// SHOE parameters (defaults: the OpenShoe values of Skog et al. 2010 /
/// Nilsson et al. 2012: `W = 3`, `sigma_a = 0.01 m/s^2`,
/// `sigma_w = 0.1 deg/s`, `gamma = 0.3e5`). With them, a foot with zero
/// acceleration error is at rest below `sqrt(gamma) sigma_w = 0.30 rad/s`,
/// and a motionless foot below `sqrt(gamma) sigma_a = 1.7 m/s^2` of
/// specific-force deviation from gravity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShoeParams {
    /// Window length `W` (samples), 1..=[`MAX_WINDOW`].
    pub window: usize,
    /// Accelerometer noise `sigma_a` (m/s^2).
    pub sigma_acc: f64,
    /// Gyroscope noise `sigma_w` (rad/s).
    pub sigma_gyr: f64,
    /// Threshold `gamma`.
    pub gamma: f64,
}

impl Default for ShoeParams {
    fn default() -> Self {
        ShoeParams {
            window: 3,
            sigma_acc: 0.01,
            sigma_gyr: 0.1 * core::f64::consts::PI / 180.0,
            gamma: 0.3e5,
        }
    }
}

/// Streaming SHOE detector.
#[derive(Debug, Clone)]
pub struct Shoe {
    params: ShoeParams,
    acc: [Vector3<f64>; MAX_WINDOW],
    gyr: [Vector3<f64>; MAX_WINDOW],
    len: usize,
    next: usize,
}

impl Shoe {
    /// A detector with an empty window.
    pub fn new(params: ShoeParams) -> Self {
        let mut params = params;
        params.window = params.window.clamp(1, MAX_WINDOW);
        Shoe {
            params,
            acc: [Vector3::zeros(); MAX_WINDOW],
            gyr: [Vector3::zeros(); MAX_WINDOW],
            len: 0,
            next: 0,
        }
    }

    /// Forgets the window (after a dropout).
    pub fn reset(&mut self) {
        self.len = 0;
        self.next = 0;
    }

    /// The test statistic `T` of the current window, once it is full.
    pub fn statistic(&self, g: f64) -> Option<f64> {
        let w = self.params.window;
        if self.len < w {
            return None;
        }
        let mean: Vector3<f64> = self.acc[..w].iter().sum::<Vector3<f64>>() / w as f64;
        let n = mean.norm();
        if n <= 0.0 {
            return None;
        }
        let up = mean * (g / n);
        let (sa2, sw2) = (
            self.params.sigma_acc * self.params.sigma_acc,
            self.params.sigma_gyr * self.params.sigma_gyr,
        );
        let sum: f64 = (0..w)
            .map(|k| (self.acc[k] - up).norm_squared() / sa2 + self.gyr[k].norm_squared() / sw2)
            .sum();
        Some(sum / w as f64)
    }

    /// Adds one sample; true when the foot is at rest.
    pub fn update(&mut self, acc: &Vector3<f64>, gyr: &Vector3<f64>, g: f64) -> bool {
        let w = self.params.window;
        self.acc[self.next] = *acc;
        self.gyr[self.next] = *gyr;
        self.next = (self.next + 1) % w;
        self.len = (self.len + 1).min(w);
        self.statistic(g).is_some_and(|t| t < self.params.gamma)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistic_matches_the_formula_computed_by_hand() {
        let p = ShoeParams::default();
        let mut s = Shoe::new(p);
        let a = [
            Vector3::new(0.1, 9.8, 0.0),
            Vector3::new(0.0, 9.7, 0.2),
            Vector3::new(-0.1, 9.9, 0.0),
        ];
        let w = [
            Vector3::new(0.01, 0.0, 0.0),
            Vector3::new(0.0, 0.02, 0.0),
            Vector3::new(0.0, 0.0, -0.03),
        ];
        for k in 0..3 {
            s.update(&a[k], &w[k], 9.81);
        }
        // By hand: mean = (0, 9.8, 0.2/3); unit * g.
        let mean: Vector3<f64> = Vector3::new(0.0, 29.4 / 3.0, 0.2 / 3.0);
        let up = mean / mean.norm() * 9.81;
        let mut expected: f64 = 0.0;
        for k in 0..3 {
            expected += (a[k] - up).norm_squared() / 1e-4
                + w[k].norm_squared() / (p.sigma_gyr * p.sigma_gyr);
        }
        expected /= 3.0;
        let got = s.statistic(9.81).unwrap();
        assert!(
            (got - expected).abs() < 1e-9 * expected,
            "{got} vs {expected}"
        );
    }

    #[test]
    fn still_foot_is_at_rest_and_a_turning_foot_is_not() {
        let mut s = Shoe::new(ShoeParams::default());
        let a = Vector3::new(0.0, 0.0, 9.81);
        for _ in 0..5 {
            assert!(s.update(&a, &Vector3::new(0.0, 0.0, 0.05), 9.81) || s.len < 3);
        }
        // 0.5 rad/s is above sqrt(gamma) sigma_w = 0.30 rad/s.
        for _ in 0..3 {
            s.update(&a, &Vector3::new(0.0, 0.0, 0.5), 9.81);
        }
        assert!(!s.update(&a, &Vector3::new(0.0, 0.0, 0.5), 9.81));
    }
}
