//! Streaming error statistics of one channel: memory does not grow with the
//! number of samples.

/// `x` wrapped to `[-pi, pi)`.
fn wrap_angle(x: f64) -> f64 {
    use core::f64::consts::PI;
    if (-PI..PI).contains(&x) {
        x
    } else {
        (x + PI).rem_euclid(2.0 * PI) - PI
    }
}

/// Accumulates `(estimate, reference)` pairs of one channel.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ChannelError {
    n: u64,
    sum_e: f64,
    sum_e2: f64,
    max_abs: f64,
    sum_x: f64,
    sum_y: f64,
    sum_xx: f64,
    sum_yy: f64,
    sum_xy: f64,
}

impl ChannelError {
    /// Adds one pair (`estimate`, `reference`) of angles (rad). The error is
    /// taken on the circle, `estimate - reference` wrapped to `[-pi, pi)`:
    /// an estimate that is right but one turn away (a filter whose angle
    /// state ran past +-pi) has no error, and no error exceeds half a turn.
    pub fn push(&mut self, estimate: f64, reference: f64) {
        let e = wrap_angle(estimate - reference);
        self.n += 1;
        self.sum_e += e;
        self.sum_e2 += e * e;
        self.max_abs = self.max_abs.max(e.abs());
        self.sum_x += estimate;
        self.sum_y += reference;
        self.sum_xx += estimate * estimate;
        self.sum_yy += reference * reference;
        self.sum_xy += estimate * reference;
    }

    /// Number of pairs.
    pub fn n(&self) -> u64 {
        self.n
    }

    /// Root-mean-square error, `None` without pairs.
    pub fn rmse(&self) -> Option<f64> {
        (self.n > 0).then(|| (self.sum_e2 / self.n as f64).sqrt())
    }

    /// Mean error (estimate - reference).
    pub fn mean_error(&self) -> Option<f64> {
        (self.n > 0).then(|| self.sum_e / self.n as f64)
    }

    /// RMSE after removing the mean error: the standard deviation of the error.
    pub fn rmse_offset_free(&self) -> Option<f64> {
        let n = self.n as f64;
        (self.n > 0).then(|| (self.sum_e2 / n - (self.sum_e / n).powi(2)).max(0.0).sqrt())
    }

    /// Largest absolute error.
    pub fn max_abs_error(&self) -> Option<f64> {
        (self.n > 0).then_some(self.max_abs)
    }

    /// Pearson correlation of estimate and reference; `None` when either is constant.
    pub fn correlation(&self) -> Option<f64> {
        if self.n < 2 {
            return None;
        }
        let n = self.n as f64;
        let cov = self.sum_xy / n - self.sum_x / n * self.sum_y / n;
        let vx = self.sum_xx / n - (self.sum_x / n).powi(2);
        let vy = self.sum_yy / n - (self.sum_y / n).powi(2);
        if vx <= 0.0 || vy <= 0.0 {
            return None;
        }
        Some((cov / (vx * vy).sqrt()).clamp(-1.0, 1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_computed_statistics() {
        // errors: +1, -1, +3 -> rmse = sqrt(11/3), mean = 1, std = sqrt(11/3 - 1) = sqrt(8/3).
        let mut c = ChannelError::default();
        c.push(1.0, 0.0);
        c.push(0.0, 1.0);
        c.push(5.0, 2.0);
        assert!((c.rmse().unwrap() - (11.0f64 / 3.0).sqrt()).abs() < 1e-15);
        assert!((c.mean_error().unwrap() - 1.0).abs() < 1e-15);
        assert!((c.rmse_offset_free().unwrap() - (8.0f64 / 3.0).sqrt()).abs() < 1e-15);
        assert_eq!(c.max_abs_error(), Some(3.0));
        // x = (1, 0, 5), y = (0, 1, 2): mean x = 2, mean y = 1,
        // cov = (-1*-1 + -2*0 + 3*1)/3 = 4/3, var x = (1+4+9)/3 = 14/3, var y = 2/3.
        let r = (4.0 / 3.0) / ((14.0f64 / 3.0) * (2.0 / 3.0)).sqrt();
        assert!((c.correlation().unwrap() - r).abs() < 1e-14);
    }

    #[test]
    fn constant_offset_vanishes_offset_free() {
        let mut c = ChannelError::default();
        for k in 0..100 {
            let y = (k as f64 * 0.1).sin();
            c.push(y + 0.05, y);
        }
        assert!((c.rmse().unwrap() - 0.05).abs() < 1e-12);
        assert!(c.rmse_offset_free().unwrap() < 1e-7);
        assert!((c.correlation().unwrap() - 1.0).abs() < 1e-12);
        assert_eq!(ChannelError::default().rmse(), None);
    }

    #[test]
    fn errors_are_taken_on_the_circle() {
        use core::f64::consts::PI;
        let mut c = ChannelError::default();
        // One turn away: no error; across +-pi: the short way round.
        c.push(0.3 + 2.0 * PI, 0.3);
        c.push(PI - 0.01, -PI + 0.01);
        c.push(-0.1 - 4.0 * PI, 0.0);
        let e = [0.0, -0.02, -0.1];
        let rmse = (e.iter().map(|x| x * x).sum::<f64>() / 3.0).sqrt();
        assert!((c.rmse().unwrap() - rmse).abs() < 1e-12, "{:?}", c.rmse());
        assert!((c.max_abs_error().unwrap() - 0.1).abs() < 1e-12);
        // Small errors are untouched, bit for bit.
        let mut d = ChannelError::default();
        d.push(0.123, 0.1);
        assert_eq!(d.mean_error(), Some(0.123 - 0.1));
    }
}
