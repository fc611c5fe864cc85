//! A library gait as the IMM uses it, and leg-length rescaling (paper 003
//! sec IV-B).

use super::gait::{BslipParams, GaitParameters};

/// One periodic gait of a library: body (with the gait's stiffness), gait
/// parameters and the step's event times.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaitTemplate {
    /// Mean forward speed (m/s): the gait's label.
    pub speed: f64,
    /// Body parameters; `stiffness` equals `gait.stiffness`.
    pub body: BslipParams,
    /// Gait parameters `xi`.
    pub gait: GaitParameters,
    /// Step length (m).
    pub step_length: f64,
    /// Step width (m).
    pub step_width: f64,
    /// Step duration MS to MS (s).
    pub step_time: f64,
    /// Touchdown time after MS (s).
    pub t_touchdown: f64,
    /// Lift-off time after MS (s).
    pub t_lift_off: f64,
}

impl GaitTemplate {
    /// The template scaled by dynamic similarity so that its CoM height at MS
    /// is `height` (m): lengths by `s = height / gait.height`, times and
    /// velocities by `sqrt(s)`, stiffness by `1 / s` (mass and gravity kept),
    /// so `k l0 / (m g)` and the Froude number are unchanged and the scaled
    /// gait is exactly periodic. The speed label scales by `sqrt(s)` too.
    /// `None` if `height` is not a positive finite number.
    pub fn rescaled_to_height(&self, height: f64) -> Option<GaitTemplate> {
        if !(height.is_finite() && height > 0.0) {
            return None;
        }
        let s = height / self.gait.height;
        let r = libm::sqrt(s);
        let gait = GaitParameters {
            phi: self.gait.phi,
            theta: self.gait.theta,
            stiffness: self.gait.stiffness / s,
            height,
            lateral: self.gait.lateral * s,
            forward_speed: self.gait.forward_speed * r,
        };
        Some(GaitTemplate {
            speed: self.speed * r,
            body: BslipParams {
                rest_length: self.body.rest_length * s,
                stiffness: gait.stiffness,
                ..self.body
            },
            gait,
            step_length: self.step_length * s,
            step_width: self.step_width * s,
            step_time: self.step_time * r,
            t_touchdown: self.t_touchdown * r,
            t_lift_off: self.t_lift_off * r,
        })
    }
}
