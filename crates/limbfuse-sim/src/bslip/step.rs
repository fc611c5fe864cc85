//! One B-SLIP step, MS -> TD -> LO -> MS, with its events located
//! (paper 003 sec II-B), and the step's Poincaré return map (eqs 3-4).

use limbfuse_core::GaitPhase;
use limbfuse_models::bslip::{
    derivative, leg_compression, lift_off_function, mid_stance_function, touchdown_function,
    BslipParams, GaitParameters, Side, Stance, State,
};

use super::integrator::{advance, Stop, Tolerances};

/// Why a step did not complete as a walking step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum StepFailure {
    /// The trailing leg reached its rest length before the leading leg touched down.
    #[error("the trailing leg lifted off before touchdown (no double support)")]
    LiftOffBeforeTouchdown,
    /// An event did not come within the time limit.
    #[error("the {0} event did not occur within the time limit")]
    NoEvent(&'static str),
    /// The CoM fell below half the leg length.
    #[error("the CoM fell")]
    Fell,
    /// A parameter is not finite or not positive.
    #[error("invalid gait parameters")]
    InvalidParameters,
    /// The simulator's cancellation hook asked to stop.
    #[error("cancelled")]
    Cancelled,
}

/// Outcome of one step starting at MS with the trailing foot at the origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepOutcome {
    /// Touchdown time (s from MS).
    pub t_touchdown: f64,
    /// Lift-off time (s).
    pub t_lift_off: f64,
    /// End (next MS) time (s).
    pub t_end: f64,
    /// State at touchdown.
    pub x_touchdown: State,
    /// State at lift-off.
    pub x_lift_off: State,
    /// State at the next MS.
    pub x_end: State,
    /// Leading foot `(x, z)`.
    pub leading_foot: [f64; 2],
    /// Lowest and highest CoM height over the step (m).
    pub height_range: (f64, f64),
}

impl StepOutcome {
    /// Step length: forward distance between the feet (m).
    pub fn step_length(&self) -> f64 {
        self.leading_foot[0]
    }

    /// Step width: lateral distance between the feet (m).
    pub fn step_width(&self) -> f64 {
        self.leading_foot[1].abs()
    }

    /// Mean forward speed over the step (m/s).
    pub fn mean_speed(&self) -> f64 {
        self.x_end[0] / self.t_end
    }

    /// Poincaré state at the end MS relative to the leading foot,
    /// `[lateral, height, vx, v_lateral]` (eq 4, this crate's axes).
    pub fn end_section(&self) -> [f64; 4] {
        [
            self.x_end[2] - self.leading_foot[1],
            self.x_end[1],
            self.x_end[3],
            self.x_end[5],
        ]
    }
}

/// Initial state of a step at MS: trailing foot at the origin.
pub fn initial_state(gait: &GaitParameters, side: Side) -> State {
    State::new(
        0.0,
        gait.height,
        side.sign() * gait.lateral,
        gait.forward_speed,
        0.0,
        0.0,
    )
}

/// Longest a step phase may last before it is declared failed (s).
const PHASE_TIME_LIMIT: f64 = 3.0;

/// Phase-resolved simulator of steps: used by the gait search and, with
/// [`phase_at`], by the trial simulator.
#[derive(Debug, Clone, Copy)]
pub struct StepSimulator {
    /// Body parameters (mass, rest length, gravity; stiffness from the gait).
    pub body: BslipParams,
    /// Integration tolerances.
    pub tol: Tolerances,
    /// Polled before every step: true fails it with
    /// [`StepFailure::Cancelled`] (`SearchSettings::cancel`).
    pub cancel: Option<fn() -> bool>,
}

impl StepSimulator {
    /// A simulator with default tolerances.
    pub fn new(body: BslipParams) -> Self {
        StepSimulator {
            body,
            tol: Tolerances::default(),
            cancel: None,
        }
    }

    /// This simulator with the search's cancellation hook.
    pub fn with_cancel(self, cancel: Option<fn() -> bool>) -> Self {
        StepSimulator { cancel, ..self }
    }

    /// Simulates one step of `gait` from its MS initial state (`Left` side).
    pub fn step(&self, gait: &GaitParameters) -> Result<StepOutcome, StepFailure> {
        self.step_from(gait, &initial_state(gait, Side::Left), Side::Left)
    }

    /// Simulates one step from the MS state `x0` (trailing foot at the origin).
    pub fn step_from(
        &self,
        gait: &GaitParameters,
        x0: &State,
        side: Side,
    ) -> Result<StepOutcome, StepFailure> {
        if self.cancel.is_some_and(|c| c()) {
            return Err(StepFailure::Cancelled);
        }
        let p = gait.model(&self.body);
        let a = gait.to_array();
        if a.iter().any(|v| !v.is_finite()) || p.stiffness <= 0.0 || gait.height <= 0.0 {
            return Err(StepFailure::InvalidParameters);
        }
        let trailing = [0.0, 0.0];
        let mut lo_h = x0[1];
        let mut hi_h = x0[1];
        let mut x = *x0;
        let mut t = 0.0;
        let mut h = 0.0;
        // SS1: until touchdown; the trailing leg must stay compressed.
        let ss1 = Stance {
            trailing: Some(trailing),
            leading: None,
        };
        let f1 = |s: &State| derivative(&p, s, &ss1);
        let td_only = |s: &State| touchdown_function(&p, gait, s);
        loop {
            let t_limit = t + 0.02;
            let stop = advance(
                &f1,
                Some(&td_only),
                &self.tol,
                &mut t,
                &mut x,
                t_limit,
                &mut h,
            );
            lo_h = lo_h.min(x[1]);
            hi_h = hi_h.max(x[1]);
            if leg_compression(&p, &x, trailing) < 0.0 {
                return Err(StepFailure::LiftOffBeforeTouchdown);
            }
            if stop == Stop::Event {
                break;
            }
            if t > PHASE_TIME_LIMIT {
                return Err(StepFailure::NoEvent("touchdown"));
            }
            if x[1] < 0.5 * p.rest_length {
                return Err(StepFailure::Fell);
            }
        }
        let t_touchdown = t;
        let x_touchdown = x;
        let (dx, dz) = gait.touchdown_offset(p.rest_length, side);
        let leading = [x[0] + dx, x[2] + dz];
        // DS: until the trailing leg is back at rest length.
        let ds = Stance {
            trailing: Some(trailing),
            leading: Some(leading),
        };
        let f2 = |s: &State| derivative(&p, s, &ds);
        let lo = |s: &State| lift_off_function(&p, s, trailing);
        loop {
            let t_limit = t + 0.02;
            let stop = advance(&f2, Some(&lo), &self.tol, &mut t, &mut x, t_limit, &mut h);
            lo_h = lo_h.min(x[1]);
            hi_h = hi_h.max(x[1]);
            if stop == Stop::Event {
                break;
            }
            if t - t_touchdown > PHASE_TIME_LIMIT {
                return Err(StepFailure::NoEvent("lift-off"));
            }
            if x[1] < 0.5 * p.rest_length {
                return Err(StepFailure::Fell);
            }
        }
        let t_lift_off = t;
        let x_lift_off = x;
        // SS2: until MS (vy = 0 downwards) over the leading leg.
        let ss2 = Stance {
            trailing: None,
            leading: Some(leading),
        };
        let f3 = |s: &State| derivative(&p, s, &ss2);
        let ms = |s: &State| mid_stance_function(s);
        // If the CoM still falls at lift-off, MS is the next apex: the
        // event fires on the downward crossing only.
        loop {
            let t_limit = t + 0.02;
            let stop = advance(&f3, Some(&ms), &self.tol, &mut t, &mut x, t_limit, &mut h);
            lo_h = lo_h.min(x[1]);
            hi_h = hi_h.max(x[1]);
            if leg_compression(&p, &x, leading) < -1e-9 {
                return Err(StepFailure::NoEvent("mid-stance (leading leg unloaded)"));
            }
            if stop == Stop::Event {
                break;
            }
            if t - t_lift_off > PHASE_TIME_LIMIT {
                return Err(StepFailure::NoEvent("mid-stance"));
            }
            if x[1] < 0.5 * p.rest_length {
                return Err(StepFailure::Fell);
            }
        }
        Ok(StepOutcome {
            t_touchdown,
            t_lift_off,
            t_end: t,
            x_touchdown,
            x_lift_off,
            x_end: x,
            leading_foot: leading,
            height_range: (lo_h, hi_h),
        })
    }
}

/// The phase a time within a step falls in.
pub fn phase_at(outcome: &StepOutcome, t: f64) -> GaitPhase {
    if t < outcome.t_touchdown {
        GaitPhase::Ss1
    } else if t < outcome.t_lift_off {
        GaitPhase::Ds
    } else {
        GaitPhase::Ss2
    }
}
