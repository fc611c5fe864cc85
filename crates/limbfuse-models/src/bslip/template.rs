//! A library gait as the IMM uses it, and its rescaling by dynamic
//! similarity: to a CoM height (paper 003 sec IV-B) or to another body
//! (Froude scaling, docs/GAIT_IMM.md "Continuous gait family").

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

    /// The template for another body by Froude (dynamic) similarity
    /// (Alexander & Jayes 1983, J. Zool. 201:135): with `s = l0' / l0`,
    /// `gamma = g' / g`, `mu = m' / m`, lengths scale by `s`, times by
    /// `sqrt(s / gamma)`, velocities by `sqrt(s gamma)` and the stiffness by
    /// `mu gamma / s`, so the dimensionless groups (Froude number
    /// `v^2 / (g l0)`, relative stiffness `k l0 / (m g)`, lengths over `l0`,
    /// times times `sqrt(g / l0)`, the angles) are unchanged and the gait
    /// is a periodic gait of the other body's dynamics (`x'' = k/m (l0 - l)
    /// r/l - g` scales as a whole). `body.stiffness` is ignored. `None`
    /// unless every body parameter is positive and finite.
    pub fn rescaled_to_body(&self, body: &BslipParams) -> Option<GaitTemplate> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !(ok(body.mass) && ok(body.rest_length) && ok(body.gravity)) {
            return None;
        }
        let s = body.rest_length / self.body.rest_length;
        let gamma = body.gravity / self.body.gravity;
        let mu = body.mass / self.body.mass;
        let time = libm::sqrt(s / gamma);
        let velocity = libm::sqrt(s * gamma);
        let stiffness = self.gait.stiffness * mu * gamma / s;
        let gait = GaitParameters {
            phi: self.gait.phi,
            theta: self.gait.theta,
            stiffness,
            height: self.gait.height * s,
            lateral: self.gait.lateral * s,
            forward_speed: self.gait.forward_speed * velocity,
        };
        Some(GaitTemplate {
            speed: self.speed * velocity,
            body: BslipParams { stiffness, ..*body },
            gait,
            step_length: self.step_length * s,
            step_width: self.step_width * s,
            step_time: self.step_time * time,
            t_touchdown: self.t_touchdown * time,
            t_lift_off: self.t_lift_off * time,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn template() -> GaitTemplate {
        let gait = GaitParameters {
            phi: 1.2,
            theta: 0.06,
            stiffness: 15_000.0,
            height: 0.97,
            lateral: 0.04,
            forward_speed: 0.6,
        };
        GaitTemplate {
            speed: 0.7,
            body: gait.model(&BslipParams::default()),
            gait,
            step_length: 0.57,
            step_width: 0.11,
            step_time: 0.81,
            t_touchdown: 0.3,
            t_lift_off: 0.47,
        }
    }

    /// The dimensionless groups of docs/GAIT_IMM.md, computed independently.
    fn groups(t: &GaitTemplate) -> [f64; 6] {
        let (l0, g, m) = (t.body.rest_length, t.body.gravity, t.body.mass);
        [
            t.speed * t.speed / (g * l0),
            t.gait.stiffness * l0 / (m * g),
            t.gait.height / l0,
            t.step_length / l0,
            t.step_time * libm::sqrt(g / l0),
            t.t_touchdown / t.step_time,
        ]
    }

    #[test]
    fn froude_rescaling_keeps_every_dimensionless_group() {
        let t = template();
        let other = BslipParams {
            mass: 70.0,
            rest_length: 0.95,
            stiffness: 1.0,
            gravity: 3.71,
        };
        let r = t.rescaled_to_body(&other).unwrap();
        for (a, b) in groups(&t).iter().zip(groups(&r)) {
            assert!((a - b).abs() < 1e-12 * a.abs().max(1.0), "{a} vs {b}");
        }
        assert_eq!(r.body.mass, 70.0);
        assert_eq!(r.body.stiffness, r.gait.stiffness);
        assert_eq!((r.gait.phi, r.gait.theta), (t.gait.phi, t.gait.theta));
        // Back again: the identity.
        let back = r.rescaled_to_body(&t.body).unwrap();
        assert!((back.gait.stiffness - t.gait.stiffness).abs() < 1e-9);
        assert!((back.speed - t.speed).abs() < 1e-14);
        assert!(t
            .rescaled_to_body(&BslipParams {
                rest_length: 0.0,
                ..other
            })
            .is_none());
    }
}
