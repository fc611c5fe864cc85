//! Equations of motion of the B-SLIP model (paper 003 sec II-A).
//!
//! Each stance leg pushes the CoM along the leg with the linear spring force
//! `F = k (l0 - l) r / l`, `r = c - foot`, `l = |r|`; the CoM acceleration is
//! `sum F / m - g y`. The same force acts whether the leg is compressed or
//! stretched: a stretched leg pulling on the CoM is unphysical, which is what
//! the IMM's physical likelihood (eq 14) detects.

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

use super::gait::BslipParams;

/// CoM state `[x, y, z, vx, vy, vz]` (m, m/s), world frame.
pub type State = Vector6<f64>;

/// Which feet are on the ground, as ground points `(x, z)` (m).
///
/// SS1: `trailing` only; DS: both; SS2: `leading` only.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Stance {
    /// The trailing foot (stance in SS1 and DS).
    pub trailing: Option<[f64; 2]>,
    /// The leading foot (stance in DS and SS2).
    pub leading: Option<[f64; 2]>,
}

impl Stance {
    /// The feet on the ground, trailing first.
    pub fn feet(&self) -> impl Iterator<Item = [f64; 2]> {
        self.trailing.into_iter().chain(self.leading)
    }
}

fn leg_vector(state: &State, foot: [f64; 2]) -> Vector3<f64> {
    Vector3::new(state[0] - foot[0], state[1], state[2] - foot[1])
}

/// Length of the leg from `foot` to the CoM (m).
pub fn leg_length(state: &State, foot: [f64; 2]) -> f64 {
    leg_vector(state, foot).norm()
}

/// Leg compression `l0 - l` (m): positive when the spring is compressed
/// (pushing), negative when stretched beyond its rest length.
pub fn leg_compression(p: &BslipParams, state: &State, foot: [f64; 2]) -> f64 {
    p.rest_length - leg_length(state, foot)
}

/// Force of one leg on the CoM (N).
pub fn leg_force(p: &BslipParams, state: &State, foot: [f64; 2]) -> Vector3<f64> {
    let r = leg_vector(state, foot);
    let l = r.norm();
    if l <= 0.0 {
        return Vector3::zeros();
    }
    r * (p.stiffness * (p.rest_length - l) / l)
}

/// CoM acceleration (m/s^2).
pub fn acceleration(p: &BslipParams, state: &State, stance: &Stance) -> Vector3<f64> {
    let mut a = Vector3::new(0.0, -p.gravity, 0.0);
    for foot in stance.feet() {
        a += leg_force(p, state, foot) / p.mass;
    }
    a
}

/// State derivative `f(x) = [v; a(x)]`.
pub fn derivative(p: &BslipParams, state: &State, stance: &Stance) -> State {
    let a = acceleration(p, state, stance);
    Vector6::new(state[3], state[4], state[5], a[0], a[1], a[2])
}

/// Jacobian `F = df/dx` (Table I of paper 003): `[[0, I], [da/dc, 0]]` with,
/// per leg, `da/dc = k/m [ (l0/l - 1) I - l0/l^3 r r^T ]`.
pub fn jacobian(p: &BslipParams, state: &State, stance: &Stance) -> Matrix6<f64> {
    let mut f = Matrix6::zeros();
    f.fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&Matrix3::identity());
    let mut dadc = Matrix3::zeros();
    for foot in stance.feet() {
        let r = leg_vector(state, foot);
        let l = r.norm();
        if l <= 0.0 {
            continue;
        }
        let s = p.stiffness / p.mass;
        dadc += (Matrix3::identity() * (p.rest_length / l - 1.0)
            - r * r.transpose() * (p.rest_length / (l * l * l)))
            * s;
    }
    f.fixed_view_mut::<3, 3>(3, 0).copy_from(&dadc);
    f
}

/// Mechanical energy (J): kinetic + gravitational + spring energy of the
/// stance legs. Conserved within a phase.
pub fn energy(p: &BslipParams, state: &State, stance: &Stance) -> f64 {
    let v = Vector3::new(state[3], state[4], state[5]);
    let mut e = 0.5 * p.mass * v.norm_squared() + p.mass * p.gravity * state[1];
    for foot in stance.feet() {
        let d = p.rest_length - leg_length(state, foot);
        e += 0.5 * p.stiffness * d * d;
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> BslipParams {
        BslipParams::default()
    }

    #[test]
    fn compressed_vertical_leg_pushes_up_by_hooke() {
        let p = params();
        let s = State::new(0.0, 0.95, 0.0, 0.0, 0.0, 0.0);
        let st = Stance {
            trailing: Some([0.0, 0.0]),
            leading: None,
        };
        let a = acceleration(&p, &s, &st);
        // k (l0 - l) / m - g = 20000 * 0.05 / 80 - 9.81
        assert!((a[1] - (12.5 - 9.81)).abs() < 1e-12);
        assert!(a[0].abs() < 1e-15 && a[2].abs() < 1e-15);
    }

    #[test]
    fn jacobian_matches_central_differences() {
        let p = params();
        let s = State::new(0.1, 0.93, 0.04, 0.7, -0.1, 0.05);
        let st = Stance {
            trailing: Some([-0.2, -0.05]),
            leading: Some([0.35, 0.07]),
        };
        let f = jacobian(&p, &s, &st);
        let h = 1e-6;
        for j in 0..6 {
            let mut sp = s;
            let mut sm = s;
            sp[j] += h;
            sm[j] -= h;
            let col = (derivative(&p, &sp, &st) - derivative(&p, &sm, &st)) / (2.0 * h);
            for i in 0..6 {
                assert!(
                    (f[(i, j)] - col[i]).abs() < 1e-5 * (1.0 + col[i].abs()),
                    "F[{i},{j}] = {} vs {}",
                    f[(i, j)],
                    col[i]
                );
            }
        }
    }

    #[test]
    fn leg_force_vanishes_at_rest_length() {
        let p = params();
        let s = State::new(0.6, 0.8, 0.0, 0.0, 0.0, 0.0);
        let f = leg_force(&p, &s, [0.0, 0.0]);
        assert!(f.norm() < 1e-10);
        assert!(leg_compression(&p, &s, [0.0, 0.0]).abs() < 1e-15);
    }
}
