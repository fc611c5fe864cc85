//! Paper 004 studies on simulated trials; prints Markdown tables (pasted
//! into docs/RESULTS.md). `cargo run --release -p limbfuse-studies --example fes_studies [-- --hip-only]`.

use clap::Parser;
use limbfuse_core::Record;
use limbfuse_models::FixedHipParams;
use limbfuse_sim::fixed_hip::FixedHipConfig;
use limbfuse_sim::knee_fes::KneeFesConfig;
use limbfuse_studies::example_args::FesStudiesArgs;
use limbfuse_studies::fes_study::{fixed_hip_run, single_joint_study, tune_fixed_hip, HipResult};

fn p(t: &Option<limbfuse_eval::stats::TestResult>) -> String {
    t.map_or("-".into(), |t| {
        format!("W = {:.3}, p = {:.4}", t.statistic, t.p_value)
    })
}

fn hip_row(name: &str, r: &HipResult, gyro: bool) {
    let g = if gyro {
        format!(" | {:.2} / {:.2}", r.gyro[0], r.gyro[1])
    } else {
        String::new()
    };
    println!(
        "| {name} | {:.3} / {:.3} | {:.3} / {:.3}{g} |",
        r.sdre[0], r.sdre[1], r.ekf[0], r.ekf[1]
    );
}

const SINGLE: [(&str, bool, bool); 3] = [
    (
        "with muscle activation dynamics in the truth (default), each method tuned",
        true,
        false,
    ),
    (
        "with activation dynamics, EKF with the SDRE's Q and S",
        true,
        true,
    ),
    (
        "truth without activation dynamics (a = u, the estimators' model), each method tuned",
        false,
        false,
    ),
];

fn main() {
    let t0 = std::time::Instant::now();
    // --hip-only skips the single-joint study (a).
    let hip_only = FesStudiesArgs::parse().hip_only;
    let single: &[(&str, bool, bool)] = if hip_only { &[] } else { &SINGLE };
    for &(label, activation, shared) in single {
        let st = single_joint_study(
            &KneeFesConfig {
                activation_dynamics: activation,
                ..KneeFesConfig::default()
            },
            shared,
        );
        println!("### (a) Single joint, {label}\n");
        println!(
            "Tuned on the pre-trials (P1-L, seeds 1000-1002): sdre (S_gyro, S_acc, Q_rate) = {:?}, ekf = {:?}, rmx k_p = {}, k_i = {}.\n",
            st.tuning[0], st.tuning[1], st.rmx_gains.kp, st.rmx_gains.ki
        );
        println!("| leg | trial | SDRE | EKF | RMX |\n|---|---|---|---|---|");
        for r in &st.rows {
            println!(
                "| {} | {} | {:.2} | {:.2} | {:.2} |",
                r.subject.label(),
                r.trial,
                r.rmse_deg[0],
                r.rmse_deg[1],
                r.rmse_deg[2]
            );
        }
        let m = st.mean();
        println!(
            "| **mean** | | **{:.2}** | **{:.2}** | **{:.2}** |\n",
            m[0], m[1], m[2]
        );
        println!(
            "Shapiro-Wilk: SDRE {}, EKF {}, RMX {}. Wilcoxon signed-rank (two-sided): SDRE vs EKF {}, SDRE vs RMX {}.\n",
            p(&st.shapiro[0]),
            p(&st.shapiro[1]),
            p(&st.shapiro[2]),
            p(&st.wilcoxon[0]),
            p(&st.wilcoxon[1])
        );
    }
    let base = FixedHipConfig::default();
    let tuning = tune_fixed_hip(&base);
    let seeds: Vec<u64> = (1..=10).collect();
    let none = |_: &mut Record| {};
    println!("### (b) Fixed hip, default noise, 10 seeds\n");
    println!(
        "Tuned on the pre-trials (seeds 1000-1002): sdre {:?}, ekf {:?}.\n",
        tuning.sdre, tuning.ekf
    );
    println!("| case | SDRE hip / knee (deg) | EKF hip / knee (deg) |\n|---|---|---|");
    let r = fixed_hip_run(&base, base.params, &tuning, &seeds, &none);
    hip_row("each tuned", &r, false);
    let shared = limbfuse_studies::fes_study::HipTuning {
        sdre: tuning.sdre,
        ekf: tuning.sdre,
    };
    hip_row(
        "EKF with the SDRE's Q, S",
        &fixed_hip_run(&base, base.params, &shared, &seeds, &none),
        false,
    );
    for (sg, sa, q) in [(1e-6, 1.0, 0.1), (1e-4, 1.0, 0.1), (1e-6, 100.0, 0.01)] {
        let t = limbfuse_studies::fes_study::HipTuning {
            sdre: (sg, sa, q),
            ekf: (sg, sa, q),
        };
        hip_row(
            &format!("both with S_gyro {sg:e}, S_acc {sa}, Q_rate {q}"),
            &fixed_hip_run(&base, base.params, &t, &seeds, &none),
            false,
        );
    }
    println!("\n### (c) Gyro drift (constant added to both gyros), fixed hip\n");
    println!("| drift (deg/s) | SDRE hip / knee | EKF hip / knee | gyro integration hip / knee |\n|---|---|---|---|");
    for d in [0.0, 0.1, 0.5, 1.0, 3.0] {
        let cfg = FixedHipConfig {
            gyro_drift: f64::to_radians(d),
            ..base
        };
        let r = fixed_hip_run(&cfg, base.params, &tuning, &seeds, &none);
        hip_row(&format!("{d}"), &r, true);
    }
    println!("\n### (d) Inaccurate model parameters, fixed hip, ideal sensors\n");
    println!("| estimator model | SDRE hip / knee | EKF hip / knee |\n|---|---|---|");
    let ideal = FixedHipConfig {
        noise: false,
        ..base
    };
    let exact = fixed_hip_run(&ideal, base.params, &tuning, &seeds, &none);
    hip_row("exact", &exact, false);
    let bp = base.params;
    let perturbed = FixedHipParams {
        thigh_mass: bp.thigh_mass * 1.2,
        leg_mass: bp.leg_mass * 0.8,
        thigh_inertia: bp.thigh_inertia * 1.2,
        leg_inertia: bp.leg_inertia * 0.8,
        muscle_peak: bp.muscle_peak.map(|t| t * 0.8),
        hip_damping: bp.hip_damping * 1.5,
        ..bp
    };
    let r = fixed_hip_run(&ideal, perturbed, &tuning, &seeds, &none);
    hip_row(
        "masses/inertias +-20 %, muscle torques -20 %, hip damping +50 %",
        &r,
        false,
    );
    println!("\n### (e) Misalignment, fixed hip, default noise\n");
    println!("| case | SDRE hip / knee | EKF hip / knee |\n|---|---|---|");
    hip_row("aligned", &r_default(&base, &tuning, &seeds), false);
    let s1 = |r: &mut Record| {
        for seg in [1, 2] {
            if let Some(a) = r.sample.imu[seg].acc.as_mut() {
                a.x += 0.5;
            }
        }
    };
    hip_row(
        "S1: acc_x + 0.5 m/s^2",
        &fixed_hip_run(&base, base.params, &tuning, &seeds, &s1),
        false,
    );
    let s2 = |r: &mut Record| {
        for seg in [1, 2] {
            if let Some(a) = r.sample.imu[seg].acc.as_mut() {
                *a *= 0.8;
            }
        }
    };
    hip_row(
        "S2: acc x 0.8",
        &fixed_hip_run(&base, base.params, &tuning, &seeds, &s2),
        false,
    );
    let trusting = limbfuse_studies::fes_study::HipTuning {
        sdre: (1e-6, 1.0, 0.1),
        ekf: (1e-6, 1.0, 0.1),
    };
    println!("\nSame, both filters with the accelerometer-trusting tuning S_gyro 1e-6, S_acc 1, Q_rate 0.1:\n");
    println!("| case | SDRE hip / knee | EKF hip / knee |\n|---|---|---|");
    hip_row(
        "aligned",
        &fixed_hip_run(&base, base.params, &trusting, &seeds, &none),
        false,
    );
    hip_row(
        "S1: acc_x + 0.5 m/s^2",
        &fixed_hip_run(&base, base.params, &trusting, &seeds, &s1),
        false,
    );
    hip_row(
        "S2: acc x 0.8",
        &fixed_hip_run(&base, base.params, &trusting, &seeds, &s2),
        false,
    );
    eprintln!("done in {:.1} s", t0.elapsed().as_secs_f64());
}

fn r_default(
    base: &FixedHipConfig,
    tuning: &limbfuse_studies::fes_study::HipTuning,
    seeds: &[u64],
) -> HipResult {
    fixed_hip_run(base, base.params, tuning, seeds, &|_: &mut Record| {})
}
