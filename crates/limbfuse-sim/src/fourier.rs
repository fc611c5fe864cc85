//! Truncated Fourier series in the gait phase `phi` (rad, one stride = 2 pi),
//! with analytic first and second derivatives, and their least-squares fit to
//! uniformly sampled periodic data.
//!
//! On a uniform grid of `N > 2K` samples the least-squares fit of a series of
//! order `K` is the truncated discrete Fourier transform, so fitting is exact
//! linear algebra with no tuning.

/// Largest number of harmonics a series may carry.
pub const KMAX: usize = 24;

/// `cos(k phi)` and `sin(k phi)` for `k = 0..=KMAX`, computed once per phase
/// and shared by every series evaluated at that phase.
#[derive(Debug, Clone, Copy)]
pub struct Harmonics {
    c: [f64; KMAX + 1],
    s: [f64; KMAX + 1],
}

impl Harmonics {
    /// Table at phase `phi` (angle-addition recurrence from `cos phi`, `sin phi`;
    /// the round-off after 24 steps is a few ulps).
    pub fn new(phi: f64) -> Self {
        Self::up_to(phi, KMAX)
    }

    /// Table filled up to harmonic `order` (at most `KMAX`); series of
    /// higher order must not be evaluated on it.
    pub fn up_to(phi: f64, order: usize) -> Self {
        let (s1, c1) = phi.sin_cos();
        let mut c = [0.0; KMAX + 1];
        let mut s = [0.0; KMAX + 1];
        c[0] = 1.0;
        for k in 1..=order.min(KMAX) {
            c[k] = c[k - 1] * c1 - s[k - 1] * s1;
            s[k] = s[k - 1] * c1 + c[k - 1] * s1;
        }
        Harmonics { c, s }
    }

    /// `cos(k phi)` (`k <= KMAX`, within the filled order).
    #[inline]
    pub fn cos(&self, k: usize) -> f64 {
        self.c[k]
    }

    /// `sin(k phi)` (`k <= KMAX`, within the filled order).
    #[inline]
    pub fn sin(&self, k: usize) -> f64 {
        self.s[k]
    }
}

/// `f(phi) = c0 + sum_k (a_k cos k phi + b_k sin k phi)`, `k = 1..=order`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fourier {
    /// Mean value.
    pub c0: f64,
    /// Cosine coefficients (`a[k-1]` multiplies `cos k phi`).
    pub a: [f64; KMAX],
    /// Sine coefficients.
    pub b: [f64; KMAX],
    /// Highest harmonic with a non-zero coefficient (evaluation stops there).
    pub order: usize,
}

/// Value and first two phase derivatives of a series at one phase.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct D2 {
    /// `f`.
    pub v: f64,
    /// `df/dphi`.
    pub d1: f64,
    /// `d2f/dphi2`.
    pub d2: f64,
}

impl D2 {
    /// A constant.
    pub const fn constant(v: f64) -> Self {
        D2 {
            v,
            d1: 0.0,
            d2: 0.0,
        }
    }
}

impl Default for Fourier {
    fn default() -> Self {
        Fourier {
            c0: 0.0,
            a: [0.0; KMAX],
            b: [0.0; KMAX],
            order: 0,
        }
    }
}

impl Fourier {
    /// The constant series `c0`.
    pub fn constant(c0: f64) -> Self {
        Fourier {
            c0,
            ..Default::default()
        }
    }

    /// Least-squares fit of order `order` (clamped to `KMAX` and to
    /// `(N - 1) / 2`) to samples `y[n] = f(2 pi n / N)`.
    pub fn fit(y: &[f64], order: usize) -> Self {
        let n = y.len();
        let mut f = Fourier::default();
        if n == 0 {
            return f;
        }
        let order = order.min(KMAX).min((n - 1) / 2);
        f.c0 = y.iter().sum::<f64>() / n as f64;
        let w = core::f64::consts::TAU / n as f64;
        for k in 1..=order {
            let (mut a, mut b) = (0.0, 0.0);
            for (i, yi) in y.iter().enumerate() {
                let (s, c) = (w * (k * i) as f64).sin_cos();
                a += yi * c;
                b += yi * s;
            }
            f.a[k - 1] = 2.0 * a / n as f64;
            f.b[k - 1] = 2.0 * b / n as f64;
        }
        f.trimmed()
    }

    /// Weighted least-squares fit of order `order` (clamped to `KMAX` and to
    /// `(N - 1) / 2`) to samples `y[n] = f(2 pi n / N)` with weights `w[n] >= 0`
    /// (normal equations, Cholesky). With equal weights it equals [`Fourier::fit`].
    pub fn fit_weighted(y: &[f64], w: &[f64], order: usize) -> Self {
        Self::fit_penalised(y, w, order, 0.0)
    }

    /// [`Fourier::fit_weighted`] with a penalty `lambda sum_k k^4 (a_k^2 +
    /// b_k^2)` on the mean square second derivative, `lambda` relative to the
    /// sum of the weights: suppresses ringing of high harmonics where the
    /// weights are small.
    pub fn fit_penalised(y: &[f64], w: &[f64], order: usize, lambda: f64) -> Self {
        let n = y.len();
        let order = order.min(KMAX).min(n.saturating_sub(1) / 2);
        let p = 2 * order + 1;
        let mut ata = nalgebra::DMatrix::<f64>::zeros(p, p);
        let mut aty = nalgebra::DVector::<f64>::zeros(p);
        let mut row = vec![0.0; p];
        for (i, (&yi, &wi)) in y.iter().zip(w).enumerate() {
            let h = Harmonics::up_to(core::f64::consts::TAU * i as f64 / n as f64, order);
            row[0] = 1.0;
            for k in 1..=order {
                row[2 * k - 1] = h.c[k];
                row[2 * k] = h.s[k];
            }
            for a in 0..p {
                let ra = wi * row[a];
                aty[a] += ra * yi;
                for b in a..p {
                    ata[(a, b)] += ra * row[b];
                }
            }
        }
        for a in 0..p {
            for b in 0..a {
                ata[(a, b)] = ata[(b, a)];
            }
        }
        let scale = lambda * w.iter().sum::<f64>();
        for k in 1..=order {
            let pen = scale * (k as f64).powi(4);
            ata[(2 * k - 1, 2 * k - 1)] += pen;
            ata[(2 * k, 2 * k)] += pen;
        }
        let mut f = Fourier::default();
        let Some(ch) = ata.cholesky() else {
            return Fourier::fit(y, order);
        };
        let c = ch.solve(&aty);
        f.c0 = c[0];
        for k in 1..=order {
            f.a[k - 1] = c[2 * k - 1];
            f.b[k - 1] = c[2 * k];
        }
        f.trimmed()
    }

    /// Recomputes [`Fourier::order`] from the coefficients.
    fn trimmed(mut self) -> Self {
        self.order = (1..=KMAX)
            .rev()
            .find(|&k| self.a[k - 1] != 0.0 || self.b[k - 1] != 0.0)
            .unwrap_or(0);
        self
    }

    /// Value and phase derivatives at the phase of `h`.
    #[inline]
    pub fn eval(&self, h: &Harmonics) -> D2 {
        let mut out = D2::constant(self.c0);
        for k in 1..=self.order {
            let (a, b) = (self.a[k - 1], self.b[k - 1]);
            let cs = a * h.c[k] + b * h.s[k];
            let kf = k as f64;
            out.v += cs;
            out.d1 += kf * (b * h.c[k] - a * h.s[k]);
            out.d2 -= kf * kf * cs;
        }
        out
    }

    /// Value only at phase `phi` (slow path for set-up code).
    pub fn value(&self, phi: f64) -> f64 {
        self.eval(&Harmonics::new(phi)).v
    }

    /// `sum_i w_i f_i`: series are linear in their coefficients.
    pub fn combine(terms: &[(f64, &Fourier)]) -> Self {
        let mut f = Fourier::default();
        for (w, t) in terms {
            f.c0 += w * t.c0;
            for k in 0..KMAX {
                f.a[k] += w * t.a[k];
                f.b[k] += w * t.b[k];
            }
        }
        f.trimmed()
    }

    /// The zero-mean antiderivative `F` with `F' = f - c0`.
    pub fn integral(&self) -> Self {
        let mut f = Fourier::default();
        for k in 1..=KMAX {
            let kf = k as f64;
            f.a[k - 1] = -self.b[k - 1] / kf;
            f.b[k - 1] = self.a[k - 1] / kf;
        }
        f.trimmed()
    }

    /// The series shifted by half a stride: `g(phi) = f(phi + pi)`.
    pub fn half_cycle_shift(&self) -> Self {
        let mut f = *self;
        for k in (1..=KMAX).step_by(2) {
            f.a[k - 1] = -f.a[k - 1];
            f.b[k - 1] = -f.b[k - 1];
        }
        f
    }
}

/// `n` uniformly spaced phases over one stride, `2 pi i / n`.
pub fn grid(n: usize) -> impl Iterator<Item = f64> {
    (0..n).map(move |i| core::f64::consts::TAU * i as f64 / n as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::TAU;

    #[test]
    fn fit_recovers_a_band_limited_series_and_derivatives() {
        let f = |p: f64| 1.5 + 0.3 * p.cos() - 0.2 * (3.0 * p).sin() + 0.05 * (7.0 * p).cos();
        let y: Vec<f64> = grid(64).map(f).collect();
        let s = Fourier::fit(&y, 10);
        for p in [0.1, 1.3, 4.0] {
            let d = s.eval(&Harmonics::new(p));
            assert!((d.v - f(p)).abs() < 1e-12);
            let d1 = -0.3 * p.sin() - 0.6 * (3.0 * p).cos() - 0.35 * (7.0 * p).sin();
            let d2 = -0.3 * p.cos() + 1.8 * (3.0 * p).sin() - 2.45 * (7.0 * p).cos();
            assert!((d.d1 - d1).abs() < 1e-11);
            assert!((d.d2 - d2).abs() < 1e-10);
        }
    }

    #[test]
    fn weighted_fit_with_equal_weights_is_the_plain_fit() {
        let y: Vec<f64> = grid(64).map(|p| (3.0 * p).sin().abs()).collect();
        let a = Fourier::fit(&y, 8);
        let b = Fourier::fit_weighted(&y, &[1.0; 64], 8);
        assert!((a.c0 - b.c0).abs() < 1e-12);
        for k in 0..8 {
            assert!((a.a[k] - b.a[k]).abs() < 1e-12 && (a.b[k] - b.b[k]).abs() < 1e-12);
        }
    }

    #[test]
    fn integral_and_shift() {
        let y: Vec<f64> = grid(64)
            .map(|p| 2.0 + p.sin() + 0.5 * (2.0 * p).cos())
            .collect();
        let s = Fourier::fit(&y, 8);
        let i = s.integral();
        let p = 0.7;
        // d/dphi of the integral equals the zero-mean series.
        assert!((i.eval(&Harmonics::new(p)).d1 - (s.value(p) - 2.0)).abs() < 1e-12);
        let sh = s.half_cycle_shift();
        assert!((sh.value(p) - s.value(p + TAU / 2.0)).abs() < 1e-12);
    }
}
