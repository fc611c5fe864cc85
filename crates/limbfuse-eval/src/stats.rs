//! Statistical tests of the paper 004 study (section 4.1.4): the
//! Shapiro-Wilk normality test and the Wilcoxon signed-rank test.
//!
//! No maintained Rust crate offers both tests (`statrs` has distributions
//! only), so they are implemented here from their published algorithms and
//! tested against SciPy 1.17 (`scipy.stats.shapiro`, `scipy.stats.wilcoxon`)
//! on fixed data:
//! * Shapiro-Wilk: J. P. Royston, "Remark AS R94: A remark on algorithm
//!   AS 181: the W-test for normality", Applied Statistics 44(4), 1995
//!   (the algorithm SciPy and R use), for 3 <= n <= 5000.
//! * Wilcoxon signed-rank, two-sided: zero differences dropped (Wilcoxon's
//!   convention), average ranks for ties; exact null distribution of `W+`
//!   by dynamic programming when there are no ties and n <= 50, else the
//!   normal approximation with the tie-corrected variance (no continuity
//!   correction), as SciPy's `method="auto"`.

/// Standard normal CDF.
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / core::f64::consts::SQRT_2)
}

/// Standard normal quantile: Acklam's rational approximation refined by one
/// Halley step on `normal_cdf` (full double precision in practice).
#[allow(clippy::excessive_precision)] // published coefficients, kept as printed
pub fn normal_quantile(p: f64) -> f64 {
    if p <= 0.0 {
        return f64::NEG_INFINITY;
    }
    if p >= 1.0 {
        return f64::INFINITY;
    }
    const A: [f64; 6] = [
        -3.969683028665376e+01,
        2.209460984245205e+02,
        -2.759285104469687e+02,
        1.383577518672690e+02,
        -3.066479806614716e+01,
        2.506628277459239e+00,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e+01,
        1.615858368580409e+02,
        -1.556989798598866e+02,
        6.680131188771972e+01,
        -1.328068155288572e+01,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-03,
        -3.223964580411365e-01,
        -2.400758277161838e+00,
        -2.549732539343734e+00,
        4.374664141464968e+00,
        2.938163982698783e+00,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-03,
        3.224671290700398e-01,
        2.445134137142996e+00,
        3.754408661907416e+00,
    ];
    let plow = 0.02425;
    let x = if p < plow {
        let q = (-2.0 * p.ln()).sqrt();
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    } else if p <= 1.0 - plow {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        let q = (-2.0 * (1.0 - p).ln()).sqrt();
        -(((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    let e = normal_cdf(x) - p;
    let u = e * (2.0 * core::f64::consts::PI).sqrt() * (x * x / 2.0).exp();
    x - u / (1.0 + x * u / 2.0)
}

/// Result of a test: statistic and p-value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TestResult {
    /// The test statistic (`W` for Shapiro-Wilk, the smaller of `W+`, `W-` for Wilcoxon).
    pub statistic: f64,
    /// p-value.
    pub p_value: f64,
}

/// Shapiro-Wilk test (Royston 1995); `None` for n < 3, n > 5000 or constant data.
pub fn shapiro_wilk(data: &[f64]) -> Option<TestResult> {
    let n = data.len();
    if !(3..=5000).contains(&n) || data.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let mut x = data.to_vec();
    x.sort_by(|a, b| a.total_cmp(b));
    let nf = n as f64;
    let mean = x.iter().sum::<f64>() / nf;
    let ss: f64 = x.iter().map(|v| (v - mean) * (v - mean)).sum();
    if ss <= 0.0 {
        return None;
    }
    let mut a = vec![0.0; n];
    if n == 3 {
        a[0] = -core::f64::consts::FRAC_1_SQRT_2;
        a[2] = core::f64::consts::FRAC_1_SQRT_2;
    } else {
        let m: Vec<f64> = (1..=n)
            .map(|i| normal_quantile((i as f64 - 0.375) / (nf + 0.25)))
            .collect();
        let mm: f64 = m.iter().map(|v| v * v).sum();
        let u = 1.0 / nf.sqrt();
        let poly =
            |c: [f64; 6]| c[0] + u * (c[1] + u * (c[2] + u * (c[3] + u * (c[4] + u * c[5]))));
        let an =
            poly([0.0, 0.221157, -0.147981, -2.071190, 4.434685, -2.706056]) + m[n - 1] / mm.sqrt();
        if n > 5 {
            let an1 = poly([0.0, 0.042981, -0.293762, -1.752461, 5.682633, -3.582633])
                + m[n - 2] / mm.sqrt();
            let phi = (mm - 2.0 * m[n - 1] * m[n - 1] - 2.0 * m[n - 2] * m[n - 2])
                / (1.0 - 2.0 * an * an - 2.0 * an1 * an1);
            for i in 2..n - 2 {
                a[i] = m[i] / phi.sqrt();
            }
            a[n - 1] = an;
            a[0] = -an;
            a[n - 2] = an1;
            a[1] = -an1;
        } else {
            let phi = (mm - 2.0 * m[n - 1] * m[n - 1]) / (1.0 - 2.0 * an * an);
            for i in 1..n - 1 {
                a[i] = m[i] / phi.sqrt();
            }
            a[n - 1] = an;
            a[0] = -an;
        }
    }
    let num: f64 = a.iter().zip(&x).map(|(a, x)| a * x).sum();
    let w = (num * num / ss).min(1.0);
    let p = if n == 3 {
        let p = 6.0 / core::f64::consts::PI * (w.sqrt().asin() - 0.75f64.sqrt().asin());
        p.max(0.0)
    } else if n <= 11 {
        let gamma = 0.459 * nf - 2.273;
        let mu = 0.5440 - 0.39978 * nf + 0.025054 * nf * nf - 0.0006714 * nf.powi(3);
        let sigma = (1.3822 - 0.77857 * nf + 0.062767 * nf * nf - 0.0020322 * nf.powi(3)).exp();
        let z = (-(gamma - (1.0 - w).ln()).ln() - mu) / sigma;
        1.0 - normal_cdf(z)
    } else {
        let ln = nf.ln();
        let mu = 0.0038915 * ln.powi(3) - 0.083751 * ln * ln - 0.31082 * ln - 1.5861;
        let sigma = (0.0030302 * ln * ln - 0.082676 * ln - 0.4803).exp();
        let z = ((1.0 - w).ln() - mu) / sigma;
        1.0 - normal_cdf(z)
    };
    Some(TestResult {
        statistic: w,
        p_value: p,
    })
}

/// Two-sided Wilcoxon signed-rank test of paired samples `x`, `y`; `None`
/// when fewer than one non-zero difference remains.
pub fn wilcoxon_signed_rank(x: &[f64], y: &[f64]) -> Option<TestResult> {
    let d: Vec<f64> = x
        .iter()
        .zip(y)
        .map(|(a, b)| a - b)
        .filter(|d| *d != 0.0 && d.is_finite())
        .collect();
    let n = d.len();
    if n == 0 {
        return None;
    }
    let mut idx: Vec<usize> = (0..n).collect();
    idx.sort_by(|&i, &j| d[i].abs().total_cmp(&d[j].abs()));
    let mut ranks = vec![0.0; n];
    let mut ties = false;
    let mut tie_term = 0.0;
    let mut i = 0;
    while i < n {
        let mut j = i;
        while j + 1 < n && d[idx[j + 1]].abs() == d[idx[i]].abs() {
            j += 1;
        }
        let r = (i + j) as f64 / 2.0 + 1.0;
        for k in i..=j {
            ranks[idx[k]] = r;
        }
        let t = (j - i + 1) as f64;
        if t > 1.0 {
            ties = true;
            tie_term += t * t * t - t;
        }
        i = j + 1;
    }
    // `+ 0.0`: an empty f64 sum is -0.0.
    let w_plus: f64 = (0..n)
        .filter(|&k| d[k] > 0.0)
        .map(|k| ranks[k])
        .sum::<f64>()
        + 0.0;
    let total = (n * (n + 1)) as f64 / 2.0;
    let w_minus = total - w_plus;
    let stat = w_plus.min(w_minus);
    let p = if !ties && n <= 50 {
        // Exact: number of subsets of {1..n} with rank sum s.
        let max = n * (n + 1) / 2;
        let mut count = vec![0.0f64; max + 1];
        count[0] = 1.0;
        for r in 1..=n {
            for s in (r..=max).rev() {
                count[s] += count[s - r];
            }
        }
        let all = 2f64.powi(n as i32);
        let k = stat.round() as usize;
        let tail: f64 = count[..=k].iter().sum::<f64>() / all;
        (2.0 * tail).min(1.0)
    } else {
        let nf = n as f64;
        let var = nf * (nf + 1.0) * (2.0 * nf + 1.0) / 24.0 - tie_term / 48.0;
        let z = (stat - total / 2.0) / var.sqrt();
        (2.0 * normal_cdf(z)).min(1.0)
    };
    Some(TestResult {
        statistic: stat,
        p_value: p,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Table 2 of paper 004: SDC and EKF RMSE (deg) of the 18 trials.
    const SDC: [f64; 18] = [
        1.10, 1.77, 1.19, 1.78, 1.64, 1.55, 1.25, 0.77, 1.05, 2.01, 2.07, 2.10, 2.01, 2.79, 2.0,
        2.45, 2.49, 2.40,
    ];
    const EKF: [f64; 18] = [
        1.28, 3.00, 1.06, 1.90, 1.62, 1.67, 1.29, 0.92, 1.07, 2.11, 2.80, 2.57, 2.20, 2.86, 1.73,
        2.95, 2.86, 2.82,
    ];

    #[test]
    fn wilcoxon_reproduces_the_thesis_and_scipy() {
        // The thesis reports p = 0.005 for SDRE vs EKF (Fig. 13); SciPy 1.17:
        // statistic 21, p = 0.00496445799767541.
        let r = wilcoxon_signed_rank(&SDC, &EKF).unwrap();
        assert_eq!(r.statistic, 21.0);
        assert!((r.p_value - 0.00496445799767541).abs() < 1e-12, "{r:?}");
        // scipy.stats.wilcoxon(x) (one sample = paired with zeros): W = 5, p = 0.01953125.
        let x = [0.3, 1.1, -0.4, 2.2, 0.9, -0.1, 1.5, 0.7, 0.2, 1.9];
        let r = wilcoxon_signed_rank(&x, &[0.0; 10]).unwrap();
        assert_eq!(r.statistic, 5.0);
        assert!((r.p_value - 0.01953125).abs() < 1e-12);
    }

    #[test]
    fn shapiro_wilk_matches_scipy() {
        // (data, W, p) from scipy.stats.shapiro (SciPy 1.17).
        let cases: [(&[f64], f64, f64); 5] = [
            (&SDC, 0.9686745927739902, 0.7724264218874444),
            (&EKF, 0.8991551350434775, 0.055543920054372954),
            // Shapiro & Wilk (1965)'s example: weights of 11 men (lb).
            (
                &[
                    148.0, 154.0, 158.0, 160.0, 161.0, 162.0, 166.0, 170.0, 182.0, 195.0, 236.0,
                ],
                0.7888146948631716,
                0.006703814061898823,
            ),
            (
                &[2.1, 3.4, 1.9, 5.6, 2.2],
                0.8032970061274809,
                0.08618284052841964,
            ),
            (&[1.0, 2.0, 4.0], 0.9642857142857142, 0.6368868450289689),
        ];
        for (x, w, p) in cases {
            let r = shapiro_wilk(x).unwrap();
            // SciPy computes in single precision (swilk.c uses float), hence 1e-6.
            assert!((r.statistic - w).abs() < 1e-6, "W {} vs {w}", r.statistic);
            assert!((r.p_value - p).abs() < 1e-5, "p {} vs {p}", r.p_value);
        }
    }

    #[test]
    fn normal_quantile_matches_scipy_and_inverts_the_cdf() {
        for (p, x) in [
            (0.001, -3.090232306167813),
            (0.3, -0.5244005127080407),
            (0.975, 1.959963984540054),
        ] {
            assert!((normal_quantile(p) - x).abs() < 1e-9, "{p}");
        }
        for p in [1e-10, 0.01, 0.5, 0.9, 0.999999] {
            assert!((normal_cdf(normal_quantile(p)) - p).abs() < 1e-14 * p.max(1e-3) * 1e3);
        }
    }
}
