//! Continuous B-SLIP walking on a library gait, phase by phase with located
//! events, for trial simulation and for sampling a gait's trajectories.
//!
//! Each step ends at MS on the leading foot; the next step starts from the
//! gait's exact periodic MS state mirrored to the other side (the jump is
//! the periodicity residual, <= 1e-8 m), so a long trial does not drift off
//! the periodic orbit of an open-loop-unstable gait.

use limbfuse_core::GaitPhase;
use limbfuse_models::bslip::{
    derivative, lift_off_function, mid_stance_function, touchdown_function, GaitTemplate, Side,
    Stance, State,
};

use super::integrator::{advance, Stop, Tolerances};
use super::step::initial_state;

/// A walker on one gait.
#[derive(Debug, Clone)]
pub struct Walker {
    template: GaitTemplate,
    tol: Tolerances,
    t: f64,
    x: State,
    phase: GaitPhase,
    side: Side,
    trailing: [f64; 2],
    leading: [f64; 2],
    h: f64,
    steps: usize,
}

impl Walker {
    /// Starts at MS of SS1 at time 0, trailing foot (`side`) at `(0, foot_z)`.
    pub fn new(template: GaitTemplate, side: Side, foot_z: f64) -> Self {
        let mut x = initial_state(&template.gait, side);
        x[2] += foot_z;
        Walker {
            template,
            tol: Tolerances::default(),
            t: 0.0,
            x,
            phase: GaitPhase::Ss1,
            side,
            trailing: [0.0, foot_z],
            leading: [0.0, foot_z],
            h: 0.0,
            steps: 0,
        }
    }

    /// Current time (s).
    pub fn time(&self) -> f64 {
        self.t
    }

    /// Current CoM state.
    pub fn state(&self) -> State {
        self.x
    }

    /// Current phase.
    pub fn phase(&self) -> GaitPhase {
        self.phase
    }

    /// Completed steps.
    pub fn steps(&self) -> usize {
        self.steps
    }

    /// The feet on the ground now.
    pub fn stance(&self) -> Stance {
        match self.phase {
            GaitPhase::Ss1 => Stance {
                trailing: Some(self.trailing),
                leading: None,
            },
            GaitPhase::Ds => Stance {
                trailing: Some(self.trailing),
                leading: Some(self.leading),
            },
            GaitPhase::Ss2 => Stance {
                trailing: None,
                leading: Some(self.leading),
            },
        }
    }

    /// Advances to time `t_end`, handling every event on the way. An event
    /// exactly at `t_end` is handled, so the phase reported at a sample time
    /// is the phase that starts there.
    pub fn advance_to(&mut self, t_end: f64) {
        while self.advance_to_next_event(t_end).is_some() {}
    }

    /// Advances to time `t_end` or to the first event before it, whichever
    /// comes first (an event exactly at `t_end` included), and handles that
    /// event. Returns the event's time and the CoM state at its instant,
    /// before the event is handled (the same state after a touchdown or a
    /// lift-off; at the end MS the walker restarts from the next step's
    /// mirrored MS state). `None` when `t_end` was reached without one.
    /// [`Walker::advance_to`] is this in a loop: the same integration.
    pub fn advance_to_next_event(&mut self, t_end: f64) -> Option<(f64, State)> {
        let p = self.template.body;
        let gait = self.template.gait;
        while self.t < t_end {
            let stance = self.stance();
            let f = |s: &State| derivative(&p, s, &stance);
            let trailing = self.trailing;
            let td = |s: &State| touchdown_function(&p, &gait, s);
            let lo = |s: &State| lift_off_function(&p, s, trailing);
            let ms = |s: &State| mid_stance_function(s);
            let event: &dyn Fn(&State) -> f64 = match self.phase {
                GaitPhase::Ss1 => &td,
                GaitPhase::Ds => &lo,
                GaitPhase::Ss2 => &ms,
            };
            let stop = advance(
                &f,
                Some(event),
                &self.tol,
                &mut self.t,
                &mut self.x,
                t_end,
                &mut self.h,
            );
            if stop == Stop::Event {
                let at = (self.t, self.x);
                self.on_event();
                return Some(at);
            }
        }
        None
    }

    fn on_event(&mut self) {
        match self.phase {
            GaitPhase::Ss1 => {
                let (dx, dz) = self
                    .template
                    .gait
                    .touchdown_offset(self.template.body.rest_length, self.side);
                self.leading = [self.x[0] + dx, self.x[2] + dz];
                self.phase = GaitPhase::Ds;
            }
            GaitPhase::Ds => self.phase = GaitPhase::Ss2,
            GaitPhase::Ss2 => {
                self.steps += 1;
                self.side = self.side.other();
                self.trailing = self.leading;
                let mut x = initial_state(&self.template.gait, self.side);
                x[0] += self.trailing[0];
                x[2] += self.trailing[1];
                self.x = x;
                self.phase = GaitPhase::Ss1;
            }
        }
    }
}

/// One step's trajectory sampled every `dt` plus the event instants, as
/// rows `[t, x, y, z, vx, vy, vz]` per phase (SS1, DS, SS2). A phase starts
/// and ends with the rows of its events (MS, touchdown, lift-off, MS: a
/// boundary row belongs to both phases), so every phase has at least two
/// rows however short it is. (Before 2026-12-06 a boundary row was the
/// first sample after the event: a lift-off less than `dt` before the end
/// MS left SS2 one row, which the library reader refused.)
pub fn sample_step(template: &GaitTemplate, dt: f64) -> [Vec<[f64; 7]>; 3] {
    let mut out: [Vec<[f64; 7]>; 3] = Default::default();
    let mut w = Walker::new(*template, Side::Left, 0.0);
    let row = |t: f64, x: &State| [t, x[0], x[1], x[2], x[3], x[4], x[5]];
    let index = |p: GaitPhase| match p {
        GaitPhase::Ss1 => 0,
        GaitPhase::Ds => 1,
        GaitPhase::Ss2 => 2,
    };
    out[0].push(row(w.time(), &w.state()));
    let mut k = 1;
    loop {
        let t = (k as f64 * dt).min(template.step_time);
        loop {
            let before = w.phase();
            let Some((te, xe)) = w.advance_to_next_event(t) else {
                break;
            };
            out[index(before)].push(row(te, &xe));
            if w.steps() > 0 {
                // The end MS: the last row of SS2.
                return out;
            }
            out[index(w.phase())].push(row(te, &xe));
        }
        // (a sample on an event's instant is that event's row)
        let phase = &mut out[index(w.phase())];
        if phase.last().is_none_or(|r| r[0] < w.time()) {
            phase.push(row(w.time(), &w.state()));
        }
        if t >= template.step_time {
            return out;
        }
        k += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_models::bslip::{BslipParams, GaitParameters};

    /// The 0.45 m/s gait that `gait-library build --speeds 0.45:0.85:0.1
    /// --leg-length 0.95 --mass 70` continues to (99 % double support: the
    /// lift-off 4 ms before the end MS, the touchdown 4 ms after the start).
    fn short_single_support() -> GaitTemplate {
        let stiffness = 5204.971841236786;
        GaitTemplate {
            speed: 0.45,
            body: BslipParams {
                mass: 70.0,
                rest_length: 0.95,
                stiffness,
                gravity: 9.81,
            },
            gait: GaitParameters {
                phi: 1.099869923189541,
                theta: 0.0751817763478072,
                stiffness,
                height: 0.8442157955068942,
                lateral: 0.03419755291075319,
                forward_speed: 0.5117284057873384,
            },
            step_length: 0.4318757537311837,
            step_width: 0.10555555555555554,
            step_time: 0.959723897139858,
            t_touchdown: 0.004038924716825274,
            t_lift_off: 0.9556849725434228,
        }
    }

    /// Every phase of a sampled step starts and ends at its events, however
    /// much shorter than `dt` it is. Before the fix SS2 was one row (the
    /// sample after the lift-off was the end MS) and SS1 ended at 10 ms, not
    /// at the touchdown; a library holding that step was refused.
    #[test]
    fn a_phase_shorter_than_the_sampling_step_keeps_its_event_rows() {
        let t = short_single_support();
        let [ss1, ds, ss2] = sample_step(&t, 0.01);
        let events = [0.0, t.t_touchdown, t.t_lift_off, t.step_time];
        for (k, rows) in [ss1, ds, ss2].iter().enumerate() {
            assert!(rows.len() >= 2, "phase {k}: {} row(s)", rows.len());
            let (first, last) = (rows[0][0], rows[rows.len() - 1][0]);
            assert!(
                (first - events[k]).abs() < 1e-6,
                "phase {k} starts at {first}"
            );
            assert!(
                (last - events[k + 1]).abs() < 1e-6,
                "phase {k} ends at {last}"
            );
            assert!(rows.windows(2).all(|w| w[1][0] > w[0][0]), "phase {k}");
        }
    }
}
