//! Model parameters and the gait parameters `xi` (paper 003 sec II-A).

/// Which foot carries the CoM in SS1 of a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// The left foot is the trailing (SS1) foot; the CoM lies to its right (+z).
    Left,
    /// The right foot is the trailing (SS1) foot; the CoM lies to its left (-z).
    Right,
}

impl Side {
    /// +1 for [`Side::Left`], -1 for [`Side::Right`]: the sign of the CoM's
    /// lateral offset from the trailing foot, and of the leading foot's
    /// lateral offset from the CoM at touchdown.
    pub const fn sign(self) -> f64 {
        match self {
            Side::Left => 1.0,
            Side::Right => -1.0,
        }
    }

    /// The other side (the next step's trailing foot).
    pub const fn other(self) -> Side {
        match self {
            Side::Left => Side::Right,
            Side::Right => Side::Left,
        }
    }
}

/// Body parameters of the B-SLIP model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BslipParams {
    /// Mass (kg).
    pub mass: f64,
    /// Leg rest length `l0` (m).
    pub rest_length: f64,
    /// Leg stiffness `k` (N/m).
    pub stiffness: f64,
    /// Gravity (m/s^2).
    pub gravity: f64,
}

impl Default for BslipParams {
    /// Geyer et al. 2006 (paper 003 ref \[19\]), walking: m = 80 kg, l0 = 1 m,
    /// k = 20 kN/m, g = 9.81 m/s^2.
    fn default() -> Self {
        BslipParams {
            mass: 80.0,
            rest_length: 1.0,
            stiffness: 20_000.0,
            gravity: limbfuse_core::STANDARD_GRAVITY,
        }
    }
}

/// The gait parameters `xi = [phi, theta, k, z0, y0, xdot0]` of paper 003
/// (sec II-A), in this crate's frame.
///
/// The step starts at MS with the trailing foot at the origin, the CoM at
/// `(0, height, side * lateral)` and velocity `(forward_speed, 0, 0)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaitParameters {
    /// Sagittal touchdown angle `phi` (rad): the leading leg's angle above the
    /// horizontal in the sagittal plane (Geyer's angle of attack).
    pub phi: f64,
    /// Lateral touchdown angle `theta` (rad): the leading leg's tilt out of the
    /// sagittal plane, towards the leading foot's side.
    pub theta: f64,
    /// Leg stiffness `k` (N/m).
    pub stiffness: f64,
    /// CoM height above the ground at MS (m) (the paper's `z0`).
    pub height: f64,
    /// Lateral distance of the CoM from the trailing foot at MS (m), positive
    /// towards the midline (the paper's `y0`).
    pub lateral: f64,
    /// Forward CoM velocity at MS (m/s) (the paper's `xdot0`).
    pub forward_speed: f64,
}

impl GaitParameters {
    /// The parameters as a vector `[phi, theta, k, height, lateral, forward_speed]`.
    pub const fn to_array(&self) -> [f64; 6] {
        [
            self.phi,
            self.theta,
            self.stiffness,
            self.height,
            self.lateral,
            self.forward_speed,
        ]
    }

    /// Parameters from `[phi, theta, k, height, lateral, forward_speed]`.
    pub const fn from_array(a: [f64; 6]) -> Self {
        GaitParameters {
            phi: a[0],
            theta: a[1],
            stiffness: a[2],
            height: a[3],
            lateral: a[4],
            forward_speed: a[5],
        }
    }

    /// CoM height at which the leading foot reaches the ground:
    /// `l0 sin(phi) cos(theta)`.
    pub fn touchdown_height(&self, rest_length: f64) -> f64 {
        rest_length * libm::sin(self.phi) * libm::cos(self.theta)
    }

    /// Leading-foot position relative to the CoM at touchdown, `(dx, dz)`:
    /// `l0 (cos(phi) cos(theta), side * sin(theta))` (its `dy` is
    /// `-touchdown_height`). `side` is the step's trailing side.
    pub fn touchdown_offset(&self, rest_length: f64, side: Side) -> (f64, f64) {
        (
            rest_length * libm::cos(self.phi) * libm::cos(self.theta),
            side.sign() * rest_length * libm::sin(self.theta),
        )
    }

    /// The model with this gait's stiffness.
    pub fn model(&self, body: &BslipParams) -> BslipParams {
        BslipParams {
            stiffness: self.stiffness,
            ..*body
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn touchdown_offset_is_a_leg_of_rest_length() {
        let g = GaitParameters {
            phi: 1.2,
            theta: 0.1,
            stiffness: 1.0,
            height: 0.97,
            lateral: 0.04,
            forward_speed: 0.7,
        };
        let (dx, dz) = g.touchdown_offset(0.9, Side::Right);
        let dy = g.touchdown_height(0.9);
        assert!(((dx * dx + dy * dy + dz * dz).sqrt() - 0.9).abs() < 1e-14);
        assert!(
            dz < 0.0,
            "right trailing foot: leading (left) foot lands at -z"
        );
        assert_eq!(GaitParameters::from_array(g.to_array()), g);
    }
}
