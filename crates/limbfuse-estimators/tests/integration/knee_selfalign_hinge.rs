//! The joint-axis and joint-position identification of paper 002 on an
//! ideal 3D hinge whose sensor signals are computed independently of the
//! estimator (orientation and position differentiated numerically): noise
//! free, the identified axes must be within 1 deg and the positions within
//! 1 cm of the truth, and the knee angle must follow the hinge angle.
#![allow(clippy::needless_range_loop)] // axis i of thigh (0) and shank (1) in parallel arrays

use crate::knee_hinge::{rot, Hinge, HingeMotion};
use limbfuse_core::{Estimator, ImuSample, Joint, Sample, Segment};
use limbfuse_estimators::knee_selfalign::position::correct_along_axes;
use limbfuse_estimators::knee_selfalign::{KneeSelfAlign, KneeSelfAlignParams};
use nalgebra::Vector3;

#[test]
fn noise_free_hinge_axes_within_1_deg_positions_within_1_cm() {
    let hinge = Hinge {
        mount: [
            rot(Vector3::new(0.3, -1.0, 0.6), 2.1),
            rot(Vector3::new(-0.8, 0.2, 0.5), -1.4),
        ],
        point: [
            Vector3::new(0.02, 0.2, 0.08),
            Vector3::new(-0.01, -0.22, 0.05),
        ],
        motion: HingeMotion::WalkLike,
        still: None,
    };
    let params = KneeSelfAlignParams {
        window: 500,
        order: 6,
        ..KneeSelfAlignParams::default()
    };
    let mut est = KneeSelfAlign::new(params).unwrap();
    let mut errs = Vec::new();
    let n = 1500;
    for k in 0..n {
        let t = k as f64 / 100.0;
        let mut s = Sample::empty(t);
        for (i, seg) in [Segment::Thigh, Segment::Shank].into_iter().enumerate() {
            let (w, f) = hinge.reading(i, t);
            s.imu[seg.index()] = ImuSample {
                acc: Some(f),
                gyr: Some(w),
                quat: None,
                ..Default::default()
            };
        }
        let e = est.step(&s).unwrap();
        if k >= 1200 {
            errs.push(e.joint[Joint::Knee.index()].unwrap() - hinge.kappa(t));
        }
    }
    let g = est.geometry().expect("identified");
    let axis = [
        hinge.mount[0].transpose() * Vector3::z(),
        hinge.mount[1].transpose() * Vector3::z(),
    ];
    let pos = [
        hinge.mount[0].transpose() * hinge.point[0],
        hinge.mount[1].transpose() * hinge.point[1],
    ];
    let (pt, ps) = correct_along_axes(&pos[0], &pos[1], &axis[0], &axis[1]);
    for i in 0..2 {
        let err = g.axis[i].angle(&axis[i]).to_degrees();
        assert!(err < 1.0, "axis {i}: {err} deg");
    }
    assert!(
        (g.position[0] - pt).norm() < 0.01,
        "{} vs {}",
        g.position[0],
        pt
    );
    assert!(
        (g.position[1] - ps).norm() < 0.01,
        "{} vs {}",
        g.position[1],
        ps
    );
    // The sensors sit off their segment lines (thigh 2 cm in front at 20 cm
    // above the knee, shank 1 cm behind at 22 cm below), so the
    // sensor-position zero turns the thigh line forward by atan(0.02 / 0.2)
    // and the shank line (knee to above) forward by atan(0.01 / 0.22): the
    // angle reads low by their difference, 3.11 deg.
    let offset = (0.02f64 / 0.2).atan() - (0.01f64 / 0.22).atan();
    let mean = errs.iter().sum::<f64>() / errs.len() as f64;
    assert!(
        (mean + offset).abs() < 0.05f64.to_radians(),
        "mean error {} deg",
        mean.to_degrees()
    );
    let sd = (errs.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / errs.len() as f64).sqrt();
    assert!(sd < 0.1f64.to_radians(), "sd {} deg", sd.to_degrees());
}
