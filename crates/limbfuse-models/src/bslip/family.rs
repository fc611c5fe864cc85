//! The continuous gait family: a library's gaits (one body, ordered by
//! speed) read as samples of a family of gaits parameterised by the mean
//! walking speed `v`, linearly interpolated between the two neighbouring
//! gaits (docs/GAIT_IMM.md, "Continuous gait family").
//!
//! Between two periodic gaits of the same body, every parameter of
//! [`GaitTemplate`] (the gait parameters `xi`, step length, width and time,
//! touchdown and lift-off times) is interpolated with the weight
//! `a = (v - v_i) / (v_{i+1} - v_i)`. The interpolated gait is periodic only
//! to first order in the library spacing (the IMM's filters correct the
//! remainder from the measurements); outside the library's range the end
//! gait is returned with its own speed label.

use super::gait::{BslipParams, GaitParameters};
use super::template::GaitTemplate;

fn lerp(a: f64, b: f64, w: f64) -> f64 {
    a + w * (b - a)
}

/// The template between `a` and `b` with weight `w` in `[0, 1]` (0: `a`).
pub fn interpolate(a: &GaitTemplate, b: &GaitTemplate, w: f64) -> GaitTemplate {
    let l = |x: f64, y: f64| lerp(x, y, w);
    let gait = GaitParameters::from_array(core::array::from_fn(|i| {
        l(a.gait.to_array()[i], b.gait.to_array()[i])
    }));
    GaitTemplate {
        speed: l(a.speed, b.speed),
        // One body in a library; interpolated too, so that gaits rescaled
        // to other heights (sec IV-B) still form a family.
        body: BslipParams {
            mass: l(a.body.mass, b.body.mass),
            rest_length: l(a.body.rest_length, b.body.rest_length),
            gravity: l(a.body.gravity, b.body.gravity),
            stiffness: gait.stiffness,
        },
        gait,
        step_length: l(a.step_length, b.step_length),
        step_width: l(a.step_width, b.step_width),
        step_time: l(a.step_time, b.step_time),
        t_touchdown: l(a.t_touchdown, b.t_touchdown),
        t_lift_off: l(a.t_lift_off, b.t_lift_off),
    }
}

/// The family's gait at mean speed `speed` (m/s): interpolated between the
/// neighbouring gaits of `family` (ascending speeds), the end gait outside
/// the range. `None` for an empty family or a non-finite speed.
pub fn gait_at_speed(family: &[GaitTemplate], speed: f64) -> Option<GaitTemplate> {
    let (first, last) = (family.first()?, family.last()?);
    if !speed.is_finite() {
        return None;
    }
    if speed <= first.speed {
        return Some(*first);
    }
    if speed >= last.speed {
        return Some(*last);
    }
    family.windows(2).find_map(|p| {
        let (a, b) = (&p[0], &p[1]);
        (speed >= a.speed && speed <= b.speed && b.speed > a.speed)
            .then(|| interpolate(a, b, (speed - a.speed) / (b.speed - a.speed)))
    })
}

/// The family's mean speed whose forward CoM velocity at mid-stance is
/// `vx` (m/s): the inverse of `v -> xdot0(v)` on the interpolated family
/// (first bracketing pair; clamped to the end gaits). `None` for an empty
/// family or a non-finite `vx`.
pub fn speed_at_mid_stance_velocity(family: &[GaitTemplate], vx: f64) -> Option<f64> {
    let (first, last) = (family.first()?, family.last()?);
    if !vx.is_finite() {
        return None;
    }
    let found = family.windows(2).find_map(|p| {
        let (a, b) = (p[0].gait.forward_speed, p[1].gait.forward_speed);
        let inside = (vx - a) * (vx - b) <= 0.0 && a != b;
        inside.then(|| lerp(p[0].speed, p[1].speed, (vx - a) / (b - a)))
    });
    Some(found.unwrap_or(if vx < first.gait.forward_speed {
        first.speed
    } else {
        last.speed
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gait(speed: f64, k: f64, vx: f64) -> GaitTemplate {
        let gait = GaitParameters {
            phi: 1.2,
            theta: 0.06,
            stiffness: k,
            height: 0.97,
            lateral: 0.04,
            forward_speed: vx,
        };
        GaitTemplate {
            speed,
            body: gait.model(&BslipParams::default()),
            gait,
            step_length: speed,
            step_width: 0.11,
            step_time: 1.0,
            t_touchdown: 0.3,
            t_lift_off: 0.5,
        }
    }

    #[test]
    fn interpolation_hits_the_neighbours_and_the_midpoint() {
        let f = [gait(0.6, 20_000.0, 0.5), gait(0.8, 16_000.0, 0.7)];
        let m = gait_at_speed(&f, 0.7).unwrap();
        assert!((m.speed - 0.7).abs() < 1e-12);
        assert!((m.gait.stiffness - 18_000.0).abs() < 1e-9);
        assert_eq!(m.body.stiffness, m.gait.stiffness);
        assert!((m.step_length - 0.7).abs() < 1e-12);
        assert_eq!(gait_at_speed(&f, 0.6).unwrap(), f[0]);
        assert_eq!(gait_at_speed(&f, 0.3).unwrap(), f[0]);
        assert_eq!(gait_at_speed(&f, 1.3).unwrap(), f[1]);
        assert!(gait_at_speed(&f, f64::NAN).is_none());
        assert!(gait_at_speed(&[], 0.7).is_none());
    }

    #[test]
    fn mid_stance_velocity_inverts_the_family() {
        let f = [
            gait(0.6, 20_000.0, 0.5),
            gait(0.8, 16_000.0, 0.7),
            gait(1.0, 16_000.0, 0.8),
        ];
        for v in [0.65, 0.8, 0.93] {
            let vx = gait_at_speed(&f, v).unwrap().gait.forward_speed;
            let back = speed_at_mid_stance_velocity(&f, vx).unwrap();
            assert!((back - v).abs() < 1e-12, "{v} -> {vx} -> {back}");
        }
        assert_eq!(speed_at_mid_stance_velocity(&f, 0.1), Some(0.6));
        assert_eq!(speed_at_mid_stance_velocity(&f, 2.0), Some(1.0));
    }
}
