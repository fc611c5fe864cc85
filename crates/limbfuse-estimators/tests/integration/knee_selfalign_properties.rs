//! Invariants of the paper-002 building blocks over random inputs.

use limbfuse_estimators::hinge_axis::spherical::{
    axis_from_spherical, axis_residual, spherical_from_axis,
};
use limbfuse_estimators::knee_selfalign::angle::{accel_angle, wrap, PlaneBasis};
use limbfuse_estimators::knee_selfalign::position::{
    correct_along_axes, position_residual, Kinematics,
};
use nalgebra::{Vector3, Vector4, Vector6};
use proptest::prelude::*;

fn vec3(r: f64) -> impl Strategy<Value = Vector3<f64>> {
    (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| Vector3::new(x, y, z))
}

proptest! {
    #[test]
    fn spherical_round_trip(phi in -1.5f64..1.5, theta in 0.0f64..std::f64::consts::TAU) {
        let j = axis_from_spherical(phi, theta);
        prop_assert!((j.norm() - 1.0).abs() < 1e-12);
        let (p, t) = spherical_from_axis(&j);
        prop_assert!((axis_from_spherical(p, t) - j).norm() < 1e-12);
    }

    #[test]
    fn axis_residual_is_sign_blind_and_its_gradient_matches(
        gt in vec3(4.0), gs in vec3(4.0),
        p in (-1.4f64..1.4, 0.0f64..std::f64::consts::TAU, -1.4f64..1.4, 0.0f64..std::f64::consts::TAU),
    ) {
        let psi = Vector4::new(p.0, p.1, p.2, p.3);
        if let Some((e, h)) = axis_residual(&gt, &gs, &psi) {
            // Flipping an axis (phi -> -phi, theta -> theta + pi) leaves e_j.
            let flipped = Vector4::new(-p.0, p.1 + std::f64::consts::PI, p.2, p.3);
            if let Some((e2, _)) = axis_residual(&gt, &gs, &flipped) {
                prop_assert!((e - e2).abs() < 1e-9);
            }
            for i in 0..4 {
                let step = 1e-6;
                let (mut a, mut b) = (psi, psi);
                a[i] += step;
                b[i] -= step;
                if let (Some((ea, _)), Some((eb, _))) = (axis_residual(&gt, &gs, &a), axis_residual(&gt, &gs, &b)) {
                    let fd = (ea - eb) / (2.0 * step);
                    prop_assert!((fd - h[i]).abs() < 1e-5 * (1.0 + h[i].abs()), "{} vs {}", fd, h[i]);
                }
            }
        }
    }

    #[test]
    fn position_gradient_matches(
        at in vec3(20.0), gt in vec3(4.0), dt in vec3(30.0),
        as_ in vec3(20.0), gs in vec3(4.0), ds in vec3(30.0),
        o in (vec3(0.3), vec3(0.3)),
    ) {
        let t = Kinematics { acc: at, gyr: gt, gyr_dot: dt };
        let s = Kinematics { acc: as_, gyr: gs, gyr_dot: ds };
        let psi = Vector6::new(o.0.x, o.0.y, o.0.z, o.1.x, o.1.y, o.1.z);
        if let Some((_, h)) = position_residual(&t, &s, &psi) {
            for i in 0..6 {
                let step = 1e-7;
                let (mut a, mut b) = (psi, psi);
                a[i] += step;
                b[i] -= step;
                if let (Some((ea, _)), Some((eb, _))) = (position_residual(&t, &s, &a), position_residual(&t, &s, &b)) {
                    let fd = (ea - eb) / (2.0 * step);
                    prop_assert!((fd - h[i]).abs() < 1e-4 * (1.0 + h[i].abs()), "{} vs {}", fd, h[i]);
                }
            }
        }
    }

    #[test]
    fn accel_angle_is_antisymmetric_and_basis_orthonormal(
        j in vec3(1.0), r in vec3(1.0), a in vec3(10.0), b in vec3(10.0),
    ) {
        prop_assume!(j.norm() > 0.1);
        let j = j.normalize();
        if let Some(basis) = PlaneBasis::from_reference(&j, &r) {
            prop_assert!((basis.x.norm() - 1.0).abs() < 1e-12);
            prop_assert!((basis.y.norm() - 1.0).abs() < 1e-12);
            prop_assert!(basis.x.dot(&basis.y).abs() < 1e-12);
            prop_assert!(basis.x.dot(&j).abs() < 1e-12);
            prop_assert!((basis.x.cross(&basis.y) - j).norm() < 1e-12);
            if let (Some(ab), Some(ba)) = (accel_angle(&a, &b, &basis, &basis), accel_angle(&b, &a, &basis, &basis)) {
                prop_assert!(wrap(ab + ba).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn o_correction_only_moves_along_the_axes(
        ot in vec3(0.4), os in vec3(0.4), jt in vec3(1.0), js in vec3(1.0),
    ) {
        prop_assume!(jt.norm() > 0.1 && js.norm() > 0.1);
        let (jt, js) = (jt.normalize(), js.normalize());
        let (ct, cs) = correct_along_axes(&ot, &os, &jt, &js);
        prop_assert!((ct.dot(&jt) + cs.dot(&js)).abs() < 1e-12);
        prop_assert!(((ct - ot).cross(&jt)).norm() < 1e-12);
        prop_assert!(((cs - os).cross(&js)).norm() < 1e-12);
    }
}
