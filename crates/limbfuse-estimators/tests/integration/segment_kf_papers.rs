//! The segment filters against the papers' worked examples and equations:
//! 000's mode-selection example (section 3), 000/001's output matrices,
//! 001's first-iteration gains of the local and global two-segment models.
#![allow(clippy::needless_range_loop, non_snake_case)]

use crate::segment_kf_support::G;
use limbfuse_core::kalman::{update_rows, CovarianceUpdate};
use limbfuse_core::{Estimator, Sample, Segment};
use limbfuse_estimators::segment_kf::params::CommonParams;
use limbfuse_estimators::segment_kf::{
    global_output_matrix, local_output_matrix, mjls_output_matrix, mjls_select, GlobalKf,
    GlobalKfParams, LocalKf, LocalKfParams, MarkovJumpKf, MarkovJumpKfParams, MjlsDiag,
};
use nalgebra::{SMatrix, SVector, Vector3};

// Paper 000 section 3, the ten samples of ||a_i|| - g, printed in the order
// B, T, F, S (foot before shank).
const EX_B: [f64; 10] = [0.8, 0.9, 0.6, 0.5, 0.4, 0.1, 0.2, 0.4, 0.3, 0.1];
const EX_T: [f64; 10] = [0.7, 0.7, 0.4, 0.2, 0.6, 0.2, 0.2, 0.3, 0.6, 0.2];
const EX_F: [f64; 10] = [0.3, 0.4, 0.3, 0.3, 0.3, 0.4, 0.3, 0.4, 0.9, 0.8];
const EX_S: [f64; 10] = [0.1, 0.2, 0.7, 0.6, 0.5, 0.5, 0.1, 0.5, 0.1, 0.7];
// Printed results: rho(k), Xi(k), and updates at k = 1, 2, 4, 6, 7, 9, 10.
const EX_RHO: [f64; 10] = [0.1, 0.2, 0.3, 0.2, 0.3, 0.1, 0.1, 0.3, 0.1, 0.1];
const EX_XI: [char; 10] = ['S', 'S', 'F', 'T', 'F', 'B', 'S', 'T', 'S', 'B'];
const EX_UPDATES: [usize; 7] = [1, 2, 4, 6, 7, 9, 10];

fn seg_letter(s: Segment) -> char {
    match s {
        Segment::Trunk => 'B',
        Segment::Thigh => 'T',
        Segment::Shank => 'S',
        Segment::Foot => 'F',
    }
}

#[test]
fn paper_000_worked_example_mode_selection() {
    for k in 0..10 {
        // limbfuse order: trunk (B), thigh (T), shank (S), foot (F).
        let rho = [Some(EX_B[k]), Some(EX_T[k]), Some(EX_S[k]), Some(EX_F[k])];
        let m = mjls_select(&rho, &[0.2; 4]);
        assert_eq!(m.rho_min, Some(EX_RHO[k]), "rho at k = {}", k + 1);
        assert_eq!(
            seg_letter(m.most_reliable.unwrap()),
            EX_XI[k],
            "Xi at k = {}",
            k + 1
        );
        assert_eq!(
            m.reliable,
            EX_UPDATES.contains(&(k + 1)),
            "update at k = {}",
            k + 1
        );
    }
}

/// The same example end to end through `MarkovJumpKf`: accelerometer
/// magnitudes g + rho_i, diagnostics `mode` and `upd_*` must show the
/// printed Xi and update instants. zeta is 0.2 + 1e-9 because (9.81 + 0.2)
/// - 9.81 is not exactly 0.2 in floating point.
#[test]
fn paper_000_worked_example_through_the_filter() {
    let mut p = MarkovJumpKfParams::default();
    // (the worked example starts on its first sample)
    p.common.first_sample_start = true;
    for s in p.common.segments.iter_mut() {
        s.zeta = 0.2 + 1e-9;
    }
    let mut f = MarkovJumpKf::new(p).unwrap();
    let sample = |k: usize, rho: [f64; 4]| {
        let mut s = Sample::empty(k as f64 * 0.01);
        for i in 0..4 {
            s.imu[i].acc = Some(Vector3::new(0.0, G + rho[i], 0.0));
            s.imu[i].gyr = Some(Vector3::zeros());
        }
        s.encoder = [Some(0.0); 3];
        s
    };
    // k = 0 initialises the segments.
    f.step(&sample(0, [0.0; 4])).unwrap();
    for k in 0..10 {
        let e = f
            .step(&sample(k + 1, [EX_B[k], EX_T[k], EX_S[k], EX_F[k]]))
            .unwrap();
        let updated = EX_UPDATES.contains(&(k + 1));
        let mode = e.diagnostic(MjlsDiag::Mode).unwrap();
        let expected_index = match EX_XI[k] {
            'B' => 0.0,
            'T' => 1.0,
            'S' => 2.0,
            _ => 3.0,
        };
        assert_eq!(
            mode,
            if updated { expected_index } else { -1.0 },
            "k = {}",
            k + 1
        );
        assert!((e.diagnostic(MjlsDiag::RhoMin).unwrap() - EX_RHO[k]).abs() < 1e-12);
        let upd_segments: Vec<f64> = MjlsDiag::UPDATED_SEGMENT
            .iter()
            .map(|k| e.diagnostic(*k).unwrap())
            .collect();
        assert_eq!(
            upd_segments.iter().sum::<f64>(),
            if updated { 1.0 } else { 0.0 }
        );
        if updated {
            assert_eq!(upd_segments[expected_index as usize], 1.0);
        }
        // Paper behaviour: no encoder rows either when unreliable.
        for n in MjlsDiag::UPDATED_JOINT {
            assert_eq!(
                e.diagnostic(n),
                Some(if updated { 1.0 } else { 0.0 }),
                "{} k = {}",
                n.name(),
                k + 1
            );
        }
    }
}

#[test]
fn output_matrices_match_the_papers() {
    // 000 eq 18 / 001 eq 10 with M from 000 Table 1, typed from the paper.
    #[rustfmt::skip]
    let c_enc = [
        [1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0],
    ];
    for (mode, col) in [
        (Some(Segment::Trunk), Some(0)),
        (Some(Segment::Thigh), Some(2)),
        (Some(Segment::Shank), Some(4)),
        (Some(Segment::Foot), Some(6)),
        (None, None),
    ] {
        let c = mjls_output_matrix(mode);
        for j in 0..8 {
            let m = if Some(j) == col { 1.0 } else { 0.0 };
            assert_eq!(c[(0, j)], m, "M row, mode {mode:?}, column {j}");
            for r in 0..3 {
                assert_eq!(c[(1 + r, j)], c_enc[r][j]);
            }
        }
    }
    // 001 eq 6.
    #[rustfmt::skip]
    let c_local = SMatrix::<f64, 4, 8>::from_row_slice(&[
        1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0,
        0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0,
    ]);
    assert_eq!(local_output_matrix(), c_local);
    // 001 eq 22.
    #[rustfmt::skip]
    let c_c = SMatrix::<f64, 7, 8>::from_row_slice(&[
        1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0,
        0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0,
        1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        0.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0,
        0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0,
    ]);
    assert_eq!(global_output_matrix(), c_c);
}

/// Closed forms of 001 (after eq 30) for P = I, H = [[1,0,0,0],[0,0,1,0],
/// [1,0,-1,0]], R = diag(sB, sT, sBT). D, k1, k3, k5, k7 as printed; k9 and
/// k11 as corrected in SPEC section 6 (re-derived: D = det(H H^T + R), and
/// K^T = (H H^T + R)^-1 H; the third column of K is adj(S) row 3 times H /
/// D, giving k9 = (S11' ...) = sB (1 + sT) / D, k11 = -sT (1 + sB) / D).
fn closed_forms(sB: f64, sT: f64, sBT: f64) -> ([f64; 12], f64) {
    let D = sB * (1.0 + 2.0 * sT + sBT + sT * sBT) + sT + sBT * (1.0 + sT);
    let k = [
        (sT + sBT + sT * sBT) / D,   // k1
        0.0,                         // k2
        sT / D,                      // k3
        0.0,                         // k4
        sB / D,                      // k5
        0.0,                         // k6
        (sB + sBT * (1.0 + sB)) / D, // k7
        0.0,                         // k8
        sB * (1.0 + sT) / D,         // k9
        0.0,                         // k10
        -sT * (1.0 + sB) / D,        // k11
        0.0,                         // k12
    ];
    (k, D)
}

/// K = [k1..k4; k5..k8; k9..k12]^T: column c of K holds k(4c+1)..k(4c+4).
fn check_gain(K: &[[f64; 3]; 4], sB: f64, sT: f64, sBT: f64, tol: f64) {
    let (k, _) = closed_forms(sB, sT, sBT);
    for c in 0..3 {
        for r in 0..4 {
            let want = k[4 * c + r];
            assert!(
                (K[r][c] - want).abs() < tol,
                "k{} = {} vs {} (sB {sB}, sT {sT}, sBT {sBT})",
                4 * c + r + 1,
                K[r][c],
                want
            );
        }
    }
}

const VARIANCE_TRIPLES: [(f64, f64, f64); 4] = [
    (0.5, 2.0, 0.25),
    (1.0, 1.0, 1.0),
    (0.01, 3.7, 0.2),
    (46.562, 329.08, 12.0),
];

#[test]
fn paper_001_first_iteration_gains_of_the_global_model() {
    // The filter's own 7-row H restricted to rows B, T, hip through the
    // masked update the filter uses; P = I (8x8): the B and T blocks see
    // exactly the 4x4 problem of the paper.
    for (sB, sT, sBT) in VARIANCE_TRIPLES {
        let H = global_output_matrix();
        let R = SMatrix::<f64, 7, 7>::from_diagonal(&SVector::<f64, 7>::from_column_slice(&[
            sB, sT, 1.0, 1.0, sBT, 1.0, 1.0,
        ]));
        let active = [true, true, false, false, true, false, false];
        for form in [CovarianceUpdate::Joseph, CovarianceUpdate::Standard] {
            let u = update_rows(
                &SVector::<f64, 8>::zeros(),
                &SMatrix::<f64, 8, 8>::identity(),
                &SVector::<f64, 7>::zeros(),
                &H,
                &R,
                &active,
                form,
            )
            .unwrap();
            let mut K = [[0.0; 3]; 4];
            for (c, row) in [0usize, 1, 4].iter().enumerate() {
                for (r, k) in K.iter_mut().enumerate() {
                    k[c] = u.K[(r, *row)];
                }
            }
            check_gain(&K, sB, sT, sBT, 1e-12);
            // Shank and foot states are untouched.
            for r in 4..8 {
                assert_eq!(u.K.row(r).norm(), 0.0);
            }
        }
        // D is the determinant of S = H P H^T + R (checked independently).
        let S = nalgebra::Matrix3::new(
            sB + 1.0,
            0.0,
            1.0,
            0.0,
            sT + 1.0,
            -1.0,
            1.0,
            -1.0,
            sBT + 2.0,
        );
        let (_, D) = closed_forms(sB, sT, sBT);
        assert!((S.determinant() - D).abs() < 1e-12 * D.max(1.0));
    }
}

#[test]
fn paper_001_printed_k9_k11_are_wrong() {
    // The printed k9 = (sB (1 + sT) - 1) / D and k11 = -(sT (1 + sB) - 1) / D
    // differ from the gains actually computed (SPEC section 6 erratum).
    let (sB, sT, sBT) = (0.5, 2.0, 0.25);
    let (k, D) = closed_forms(sB, sT, sBT);
    let printed_k9 = (sB * (1.0 + sT) - 1.0) / D;
    let printed_k11 = -(sT * (1.0 + sB) - 1.0) / D;
    assert!((printed_k9 - k[8]).abs() > 0.1);
    assert!((printed_k11 - k[10]).abs() > 0.1);
}

/// Parameters that make the first predicted covariance equal to the
/// identity up to 1e-18: P0 = I, no process noise, Euler, dt = 1e-9.
fn identity_prior(mut c: CommonParams, sigmas: [f64; 4]) -> CommonParams {
    // (the gains are those of the filter started on the first sample)
    c.first_sample_start = true;
    c.p0_angle_sigma = 1.0;
    c.p0_bias_sigma = 1.0;
    c.discretization = limbfuse_core::discretize::Discretization::Euler;
    for (s, sigma) in c.segments.iter_mut().zip(sigmas) {
        s.gyro_noise = 0.0;
        s.bias_drive = 0.0;
        s.bias_tau = f64::INFINITY;
        s.accel_angle_sigma = sigma;
        s.zeta = 0.3;
    }
    c
}

fn still_sample(t: f64, rho: [f64; 4]) -> Sample {
    let mut s = Sample::empty(t);
    for i in 0..4 {
        s.imu[i].acc = Some(Vector3::new(0.0, G + rho[i], 0.0));
        s.imu[i].gyr = Some(Vector3::zeros());
    }
    s
}

#[test]
fn paper_001_global_gains_through_the_filter() {
    // Trunk and thigh reliable (Psi_2 and Upsilon_h hold), shank and foot not.
    for (sB, sT, sBT) in VARIANCE_TRIPLES {
        let mut p = GlobalKfParams {
            common: identity_prior(CommonParams::default(), [sB.sqrt(), sT.sqrt(), 1.0, 1.0]),
            ..GlobalKfParams::default()
        };
        p.relative_sigma[0] = Some(sBT.sqrt());
        let mut f = GlobalKf::new(p).unwrap();
        f.step(&still_sample(0.0, [0.0; 4])).unwrap();
        f.step(&still_sample(1e-9, [0.1, 0.1, 1.0, 1.0])).unwrap();
        let g = f.last_gain();
        let mut K = [[0.0; 3]; 4];
        for (c, row) in [0usize, 1, 4].iter().enumerate() {
            for (r, k) in K.iter_mut().enumerate() {
                k[c] = g[(r, *row)];
            }
        }
        check_gain(&K, sB, sT, sBT, 1e-8);
    }
}

#[test]
fn paper_001_local_gains_first_and_second_iteration() {
    // 001: K1 = diag(1/(sB + 1), 1/(sT + 1)) on the angle states, and eq 30
    // K2 = -(s + 1)(1/(s + 1) - 1) / (s (s + 2)) = 1/(s + 2); no coupling.
    let (sB, sT) = (0.7_f64, 2.5_f64);
    let p = LocalKfParams {
        common: identity_prior(CommonParams::default(), [sB.sqrt(), sT.sqrt(), 1.0, 1.0]),
        min_reliable: 2,
    };
    let mut f = LocalKf::new(p).unwrap();
    f.step(&still_sample(0.0, [0.0; 4])).unwrap();
    f.step(&still_sample(1e-9, [0.1, 0.1, 1.0, 1.0])).unwrap();
    let k = *f.last_gain();
    assert!((k[(0, 0)] - 1.0 / (sB + 1.0)).abs() < 1e-8);
    assert!((k[(2, 1)] - 1.0 / (sT + 1.0)).abs() < 1e-8);
    f.step(&still_sample(2e-9, [0.1, 0.1, 1.0, 1.0])).unwrap();
    let k2 = *f.last_gain();
    let eq30 = |s: f64| -(s + 1.0) * (1.0 / (s + 1.0) - 1.0) / (s * (s + 2.0));
    assert!((k2[(0, 0)] - eq30(sB)).abs() < 1e-8);
    assert!((k2[(2, 1)] - eq30(sT)).abs() < 1e-8);
    assert!((eq30(sB) - 1.0 / (sB + 2.0)).abs() < 1e-15);
    for (r, c) in [(2, 0), (3, 0), (0, 1), (1, 1)] {
        assert_eq!(k[(r, c)], 0.0);
        assert_eq!(k2[(r, c)], 0.0);
    }
}

#[test]
fn names_and_outputs() {
    assert_eq!(LocalKf::default().name(), "local");
    assert_eq!(MarkovJumpKf::default().name(), "mjls");
    assert_eq!(GlobalKf::default().name(), "global");
    for e in [
        &LocalKf::default() as &dyn Estimator,
        &MarkovJumpKf::default(),
        &GlobalKf::default(),
    ] {
        assert_eq!(e.outputs(), limbfuse_core::Outputs::ALL_ANGLES);
        let mut s = String::new();
        e.describe_parameters(&mut s).unwrap();
        assert!(
            s.contains("loop: closed") && s.contains("thigh.zeta: 0.4"),
            "{s}"
        );
        for line in s.lines() {
            assert!(line.contains(": "), "{line}");
        }
    }
}
