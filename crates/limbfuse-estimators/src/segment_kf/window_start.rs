//! Optional start-up window of the segment filters (`startup_s` > 0; ours,
//! issue 14 — papers 000/001 do not say how their filters start).
//!
//! By default each segment starts at the accelerometer inclination of its
//! first sample. Started mid-stride, that inclination carries the dynamic
//! acceleration of that instant (tens of degrees for a foot in swing), and
//! the filter spends its first second converging from it: under the
//! paper-001 protocol (fresh 10 s runs) this transient is most of the error
//! (docs/RESULTS.md, "Start-up of the 10 s runs").
//!
//! With a window the filter emits no estimate for `startup_s` seconds and
//! accumulates, per segment, the circular mean `m_i` of `theta_a,i - I_i`
//! (`I_i` the trapezoidal gyro integral since the first sample), exactly as
//! the `chain` estimator's start-up does ([`Startup`], docs/CHAIN.md): over
//! a stride the dynamic accelerations average out of the inclination far
//! better than at one instant, while the integral carries the shape of the
//! motion. When the window closes every segment starts at `m_i + I_i` with
//! the filter's usual prior `p0_angle_sigma` (the residual error of the
//! window mean, not of one dynamic sample).

use limbfuse_core::Sample;

use crate::chain_ekf::startup::Startup;

/// Running sums of the window.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct WindowStart {
    sums: Startup,
}

impl WindowStart {
    /// Adds `sample` (`dt` = `None` for the first); returns the four
    /// segment angles at this sample once `window_s` has elapsed and every
    /// segment has had an accelerometer reading.
    pub fn observe(&mut self, sample: &Sample, dt: Option<f64>, window_s: f64) -> Option<[f64; 4]> {
        self.sums.observe(sample, dt);
        // (a window of whole sample periods must close on its last sample
        // despite the rounding of `t`)
        if self.sums.elapsed(sample.t) < window_s - 1e-9 * window_s.max(1.0) {
            return None;
        }
        Some([
            self.sums.angle(0)?,
            self.sums.angle(1)?,
            self.sums.angle(2)?,
            self.sums.angle(3)?,
        ])
    }
}
