//! Issue 16 item 3: how much should a knee-FES filter trust its model?
//! Chosen per leg by leave-one-pulse-out cross-validation on a pre-trial
//! with a reference (`limbfuse-studies::fes_pulse_cv`), then applied to the
//! leg's three test trials of study (a) (seeds `10 (leg + 1) + trial`),
//! which the choice never sees. The knob is the relative torque error `e`
//! of the extended filter's tuning (default 0.1; grid 0.01-3).
//!
//! Two cases: the estimator's model exact (Table 1 preset of the leg), and
//! every model parameter perturbed by +-30 % (one seeded draw per leg, the
//! same model for pre-trial and test trials: the user's identified model).
//! Pre-trial: seed `2000 + leg`, 30 s, activation dynamics and sensor
//! errors as the test trials. Filters: `sdre` / `ekf` with activation +
//! biases + lever arm (0.2 m), `ekf` with every state.
//! `cargo run --release -p limbfuse-studies --example fes_tune_cv`.

use clap::Parser;
use limbfuse_core::Record;
use limbfuse_estimators::fes::knee_extended::extended_knee_tuning;
use limbfuse_estimators::fes::{ExtendedKneePlant, FesFilter, Linearisation};
use limbfuse_models::{
    ExtendedKneeModel, KneeFesModel, KneeFesParams, KneeStateOptions, KneeSubject,
};
use limbfuse_sim::knee_fes::{simulate_knee_fes, KneeFesConfig};
use limbfuse_studies::example_args::NoArgs;
use limbfuse_studies::fes_pulse_cv::{
    leave_one_pulse_out, perturbed, pulse_windows, window_errors, WindowErrors,
};
use rayon::prelude::*;

const R: f64 = 0.2;
const GRID: [f64; 7] = [0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0];
const DEFAULT_E: f64 = 0.1;

fn opts(dist: bool) -> KneeStateOptions {
    KneeStateOptions {
        activation: true,
        disturbance: dist,
        gyro_bias: true,
        acc_bias: true,
    }
}

/// Window errors of configuration `cfg` (0: sdre+act+bias+r, 1:
/// ekf+act+bias+r, 2: ekf+all+r) with torque error `e`.
fn run(cfg: usize, m: KneeFesModel, e: f64, recs: &[Record], starts: &[f64]) -> WindowErrors {
    fn go<const N: usize>(
        m: KneeFesModel,
        o: KneeStateOptions,
        lin: Linearisation,
        e: f64,
        recs: &[Record],
        starts: &[f64],
    ) -> WindowErrors {
        let model = ExtendedKneeModel::<N>::new(m, o, R).expect("options match N");
        let mut f = FesFilter::new(
            ExtendedKneePlant::new(model),
            lin,
            extended_knee_tuning(&model, lin, e),
        );
        window_errors(&mut f, recs, starts)
    }
    match cfg {
        0 => go::<5>(m, opts(false), Linearisation::Sdc, e, recs, starts),
        1 => go::<5>(m, opts(false), Linearisation::Jacobian, e, recs, starts),
        _ => go::<6>(m, opts(true), Linearisation::Jacobian, e, recs, starts),
    }
}

fn rmse(w: &WindowErrors) -> f64 {
    (w.sse.iter().sum::<f64>() / w.n.iter().sum::<usize>().max(1) as f64)
        .sqrt()
        .to_degrees()
}

const NAMES: [&str; 3] = ["sdre+act+bias+r", "ekf+act+bias+r", "ekf+all+r"];

/// One leg and filter: leg, filter index, chosen `e`, CV RMSE, test RMSE
/// with the chosen `e`, test RMSE with the default.
type Row = (KneeSubject, usize, f64, f64, f64, f64);

fn main() {
    let _ = NoArgs::parse();
    for (case, spread) in [("exact model", 0.0), ("parameters +-30 %", 0.3)] {
        println!("\n{case}: e chosen by leave-one-pulse-out CV on the pre-trial; test = mean knee RMSE (deg) of the leg's 3 trials after 1 s");
        println!(
            "{:<6} {:<16} {:>7} {:>8} {:>10} {:>12}",
            "leg", "filter", "e", "CV RMSE", "test (e)", "test (e=0.1)"
        );
        let rows: Vec<Row> = KneeSubject::ALL
            .par_iter()
            .flat_map(|&subject| {
                let leg = subject.index() as u64;
                let p = perturbed(KneeFesParams::subject(subject), spread, 900 + leg);
                let m = KneeFesModel::new(p).expect("perturbed model");
                let base = KneeFesConfig::default();
                let pre = simulate_knee_fes(&KneeFesConfig {
                    subject,
                    seed: 2000 + leg,
                    ..base
                })
                .expect("pre-trial")
                .records;
                let starts = pulse_windows(&pre);
                let tests: Vec<Vec<Record>> = (1..=3)
                    .map(|k| {
                        simulate_knee_fes(&KneeFesConfig {
                            subject,
                            seed: 10 * (leg + 1) + k,
                            ..base
                        })
                        .expect("trial")
                        .records
                    })
                    .collect();
                (0..NAMES.len())
                    .map(|cfg| {
                        let errs: Vec<WindowErrors> = GRID
                            .iter()
                            .map(|e| run(cfg, m, *e, &pre, &starts))
                            .collect();
                        let cv = leave_one_pulse_out(&errs).expect("pulses");
                        let e = GRID[cv.chosen];
                        let test = |e: f64| {
                            tests
                                .iter()
                                .map(|t| rmse(&run(cfg, m, e, t, &[1.0])))
                                .sum::<f64>()
                                / tests.len() as f64
                        };
                        (subject, cfg, e, cv.cv_rmse_deg, test(e), test(DEFAULT_E))
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        for (s, cfg, e, cv, t, d) in &rows {
            println!(
                "{:<6} {:<16} {e:>7} {cv:>8.3} {t:>10.3} {d:>12.3}",
                s.label(),
                NAMES[*cfg]
            );
        }
        for (cfg, name) in NAMES.iter().enumerate() {
            let r: Vec<_> = rows.iter().filter(|r| r.1 == cfg).collect();
            let mean = |f: fn(&&Row) -> f64| r.iter().map(f).sum::<f64>() / r.len() as f64;
            println!(
                "{case}, {name}: mean test RMSE {:.3} deg with the CV choice, {:.3} deg with e = 0.1 (mean CV RMSE {:.3})",
                mean(|r| r.4),
                mean(|r| r.5),
                mean(|r| r.3)
            );
        }
    }
}
