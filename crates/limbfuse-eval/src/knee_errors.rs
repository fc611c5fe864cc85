//! Knee-angle errors of one run of a knee estimator against the reference:
//! RMSE, mean error, offset-free RMSE and correlation over chosen sample
//! ranges (used by `limbfuse demo` and the paper-002 studies).

use limbfuse_core::{Joint, Record};

/// Knee-angle errors of one run against the reference.
#[derive(Debug, Clone, PartialEq)]
pub struct KneeRun {
    /// `(t, estimate - reference)` (rad) where both exist.
    pub errors: Vec<(f64, f64)>,
    /// RMSE (rad).
    pub rmse: f64,
    /// Mean error (rad).
    pub mean: f64,
    /// RMSE after removing the mean error (rad).
    pub rmse_offset_free: f64,
    /// Pearson correlation with the reference.
    pub corr: f64,
    /// Wall time of the estimator loop (s).
    pub seconds: f64,
    /// Samples in the trial.
    pub n_samples: usize,
}

impl KneeRun {
    /// Errors of the knee estimates `out` (one per record, rad) against the
    /// records' reference knee angle, counting only the samples whose index
    /// is in one of `ranges` (half-open); `seconds` is the wall time of the
    /// run that produced `out`.
    pub fn from_estimates(
        records: &[Record],
        out: &[Option<f64>],
        ranges: &[(usize, usize)],
        seconds: f64,
    ) -> KneeRun {
        let k = Joint::Knee.index();
        let mut errors = Vec::new();
        let (mut e_s, mut r_s) = (Vec::new(), Vec::new());
        for (i, (r, e)) in records.iter().zip(out).enumerate() {
            if !ranges.iter().any(|&(a, b)| i >= a && i < b) {
                continue;
            }
            if let (Some(e), Some(x)) = (e, r.reference.joint[k]) {
                errors.push((r.sample.t, e - x));
                e_s.push(*e);
                r_s.push(x);
            }
        }
        let n = errors.len().max(1) as f64;
        let mean = errors.iter().map(|x| x.1).sum::<f64>() / n;
        let rmse = (errors.iter().map(|x| x.1 * x.1).sum::<f64>() / n).sqrt();
        let rmse_offset_free =
            (errors.iter().map(|x| (x.1 - mean).powi(2)).sum::<f64>() / n).sqrt();
        KneeRun {
            rmse,
            mean,
            rmse_offset_free,
            corr: pearson(&e_s, &r_s),
            errors,
            seconds,
            n_samples: records.len(),
        }
    }
}

/// Pearson correlation (NaN for fewer than two points or no variance).
pub fn pearson(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut c, mut va, mut vb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        c += (x - ma) * (y - mb);
        va += (x - ma).powi(2);
        vb += (y - mb).powi(2);
    }
    c / (va * vb).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pearson_matches_numpy() {
        // numpy.corrcoef([1, 2, 3], [2, 4, 6.5]) = 0.9979487157886733
        assert!(
            (pearson(&[1.0, 2.0, 3.0], &[2.0, 4.0, 6.5]) - 0.997_948_715_788_673_3).abs() < 1e-12
        );
    }
}
