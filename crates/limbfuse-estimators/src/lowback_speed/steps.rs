//! One sampling period of `lowback-speed` after its vertical acceleration
//! (steps 2-4 of the module doc): the history rings, the walking RMS, the
//! smoothed signal's maxima (initial contacts), the step's pendulum length
//! and the stride's speed.

use limbfuse_core::DiagnosticWriter;

use super::{
    pendulum_step_length, sides, step_excursion, LowbackDiag, LowbackSpeed, HISTORY,
    WALKING_RMS_TIME_CONSTANT_S,
};

impl LowbackSpeed {
    /// Adds the vertical acceleration `a_v` (m/s^2) and heading `psi` (rad)
    /// of the sample at `t` (s), one sampling period `dt` (s) after the
    /// previous one, and writes what it decides to `d`.
    pub(super) fn push_vertical(
        &mut self,
        a_v: f64,
        psi: f64,
        t: f64,
        dt: f64,
        d: &mut DiagnosticWriter<'_, LowbackDiag>,
    ) {
        let slot = (self.n % HISTORY as u64) as usize;
        self.history[slot] = a_v;
        self.heading[slot] = psi;
        let alpha = (dt / WALKING_RMS_TIME_CONSTANT_S).min(1.0);
        self.rms_sq += (a_v * a_v - self.rms_sq) * alpha;
        self.n += 1;
        self.decide_sides(dt, d);
        let span = 2 * self.half as u64 + 1;
        if self.n >= span {
            // Smoothed value centred `half` samples back.
            let start = self.n - span;
            let s: f64 = (0..span)
                .map(|j| self.kernel[j as usize] * self.at(start + j))
                .sum();
            self.smoothed = [self.smoothed[1], self.smoothed[2], s];
            let centre = self.n - 1 - self.half as u64;
            let walking = libm::sqrt(self.rms_sq) > self.params.walking_rms;
            let [s0, s1, s2] = self.smoothed;
            if self.n > span + 1 && walking && s1 > 0.0 && s1 > s0 && s1 >= s2 {
                // A maximum at `centre - 1`.
                let index = centre - 1;
                let t_ic = t - (self.half + 1) as f64 * dt;
                let p = &self.params;
                let mut accept = true;
                if let Some((i0, t0, s_prev)) = self.last_ic {
                    let step_time = t_ic - t0;
                    if step_time < p.min_step_time {
                        // Too close: keep the larger maximum.
                        accept = s1 > s_prev;
                        if accept {
                            self.last_ic = None;
                        }
                    } else if step_time <= p.max_step_time && index - i0 < HISTORY as u64 {
                        let h = step_excursion((i0..index).map(|i| self.at(i)), dt);
                        let sl = pendulum_step_length(h, p.leg_length, p.correction);
                        d.value(LowbackDiag::StepLength, sl);
                        d.value(LowbackDiag::Excursion, h);
                        // The previous valid step ended at `t0`: the two make a stride.
                        let mut turned = false;
                        if let Some((sl_prev, t_start, i_start)) = self.last_step {
                            let stride_time = t_ic - t_start;
                            if stride_time <= 2.0 * p.max_step_time
                                && index - i_start < HISTORY as u64
                            {
                                let turn_rate = (self.heading_at(index) - self.heading_at(i_start))
                                    / stride_time;
                                d.value(LowbackDiag::StrideTurnRate, turn_rate);
                                turned = turn_rate.abs() > p.turn_rate;
                                let after_turn = p.withhold_after_turn && self.last_stride_turned;
                                if turned || after_turn {
                                    let why = if turned { 1.0 } else { 2.0 };
                                    d.value(LowbackDiag::StrideWithheld, why);
                                    self.speed = None;
                                } else {
                                    d.value(LowbackDiag::StrideLength, sl_prev + sl);
                                    d.value(LowbackDiag::StrideTime, stride_time);
                                    self.speed = Some(((sl_prev + sl) / stride_time, t));
                                }
                            }
                        }
                        self.last_stride_turned = turned;
                        self.last_step = Some((sl, t0, i0));
                    } else {
                        self.last_step = None;
                        self.last_stride_turned = false;
                    }
                }
                if accept {
                    d.value(LowbackDiag::Ic, t_ic);
                    self.pending_sides.push(index, t_ic);
                    if self.last_ic.is_none() {
                        self.last_step = None;
                        self.last_stride_turned = false;
                    }
                    self.last_ic = Some((index, t_ic, s1));
                }
            }
        }
    }

    /// Writes the side of every waiting contact whose filter window has
    /// arrived ([`sides`]): the rate about the vertical is the heading's
    /// difference per sample, band-passed around the contact.
    fn decide_sides(&mut self, dt: f64, d: &mut DiagnosticWriter<'_, LowbackDiag>) {
        let m = self.side_half as u64;
        while let Some((index, t_ic)) = self.pending_sides.front() {
            let newest = self.n - 1;
            if index + m > newest {
                break;
            }
            self.pending_sides.pop();
            // The window's first rate needs the heading one sample before it.
            if index < m + 1 || newest - (index - m - 1) >= HISTORY as u64 {
                continue;
            }
            let start = index - m;
            let rate: f64 = self
                .side_taps
                .iter()
                .enumerate()
                .map(|(j, h)| {
                    let i = start + j as u64;
                    h * (self.heading_at(i) - self.heading_at(i - 1))
                })
                .sum::<f64>()
                / dt;
            match sides::contact_side(rate, self.params.side_min_rate) {
                Some(true) => d.value(LowbackDiag::IcRight, t_ic),
                Some(false) => d.value(LowbackDiag::IcLeft, t_ic),
                None => {}
            }
        }
    }
}
