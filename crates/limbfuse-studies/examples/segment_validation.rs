//! Every segment-angle method on data limbfuse did not generate and on its
//! own simulator, in one table (issue 14 item 4, for docs/RESULTS.md):
//! `cargo run --release -p limbfuse-studies --example segment_validation -- [--seeds N] [DATA_DIR]`
//!
//! Methods (default parameters, built through the method layer exactly as
//! `limbfuse estimate` builds them, sensor-range gate included):
//! gyro-integration, accel-inclination, local, mjls, global, chain.
//!
//! * Real: the shared gaittoolbox S02 right leg (Xsens + Vicon), imported
//!   and aligned as `limbfuse import` + `limbfuse align` do, scored
//!   offset-free on its two straight passes (0.45-3.55 s, 4.40-8.72 s),
//!   each channel synchronised within +-5 samples (the IMU streams lag the
//!   Vicon angles by about 2 samples, docs/RESULTS.md); mean of thigh,
//!   shank and foot (the trial has no trunk reference).
//! * The three shared independent-simulator walks, as they are: mean
//!   4-segment RMSE, absolute and offset-free.
//! * limbfuse's simulator, 60 s at 0.4-1.6 m/s with the default
//!   (uncalibrated) sensors, seeds 1..=N: mean 4-segment RMSE, absolute and
//!   offset-free, mean over seeds (worst seed in brackets).
//!
//! A dataset that is absent is reported as skipped.

use std::convert::Infallible;
use std::path::Path;

use clap::Parser;
use limbfuse_core::runner::{run, Observer};
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Record, Segment};
use limbfuse_eval::{AngleMetrics, EvalOptions, TimeWindow};
use limbfuse_io::{import::import_gaittoolbox, TrialLayout, TrialMeta, TrialReader};
use limbfuse_methods::{build, MethodName, MethodSpec};
use limbfuse_signal::align::{apply_alignment, estimate_alignment, AlignOptions};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};
use limbfuse_studies::example_args::SegmentValidationArgs;
use rayon::prelude::*;

const METHODS: [MethodName; 6] = [
    MethodName::GyroIntegration,
    MethodName::AccelInclination,
    MethodName::Local,
    MethodName::Mjls,
    MethodName::Global,
    MethodName::Chain,
];

/// A trial in memory.
struct Trial {
    meta: TrialMeta,
    layout: TrialLayout,
    records: Vec<Record>,
}

/// Runs `method` on the trial and scores it with every option set given;
/// `None` when the method does not apply to the trial (e.g. `mjls` needs
/// joint encoders).
fn score(method: MethodName, trial: &Trial, options: &[EvalOptions]) -> Option<Vec<AngleMetrics>> {
    let spec = MethodSpec::defaults(method).expect("defaults resolve");
    let mut est = build(&spec, &trial.meta, &trial.layout).ok()?;
    let mut metrics: Vec<AngleMetrics> = options
        .iter()
        .map(|o| AngleMetrics::new(method.name(), *o))
        .collect();
    let mut observers: Vec<&mut dyn Observer> =
        metrics.iter_mut().map(|m| m as &mut dyn Observer).collect();
    run(
        est.as_mut(),
        trial.records.iter().map(|r| Ok::<_, Infallible>(*r)),
        &mut observers,
    )
    .expect("runs");
    Some(metrics)
}

/// Mean RMSE (deg) over `segments`; `None` when one is not scored.
fn mean_rmse(m: &AngleMetrics, segments: &[Segment]) -> Option<f64> {
    let ev = m.evaluation();
    let mut sum = 0.0;
    for s in segments {
        sum += ev.rmse(AngleChannel::Segment(*s))?.to_degrees();
    }
    Some(sum / segments.len() as f64)
}

/// A table cell: `n/a` where the method does not apply.
fn cell(v: Option<f64>) -> String {
    v.map_or("n/a".into(), |v| format!("{v:.2}"))
}

fn offset_free(window: TimeWindow, max_lag: usize) -> EvalOptions {
    EvalOptions {
        window,
        offset_free: true,
        max_lag,
        ..EvalOptions::default()
    }
}

fn real_trial(dir: &Path) -> Option<Trial> {
    let imported = match import_gaittoolbox(dir) {
        Ok(t) => t,
        Err(e) => {
            println!("real trial skipped: {e}");
            return None;
        }
    };
    let mut meta = imported.meta;
    let alignment =
        estimate_alignment(&imported.records, &AlignOptions::default()).expect("S02 aligns");
    alignment.annotate(&mut meta);
    let records = imported
        .records
        .iter()
        .map(|r| apply_alignment(r, &alignment))
        .collect();
    Some(Trial {
        meta,
        layout: imported.layout,
        records,
    })
}

fn file_trial(path: &Path) -> Option<Trial> {
    let mut reader = match TrialReader::open(path) {
        Ok(r) => r,
        Err(e) => {
            println!("{} skipped: {e}", path.display());
            return None;
        }
    };
    let mut records = Vec::new();
    while let Some(r) = reader.next_record().expect("readable trial") {
        records.push(r);
    }
    Some(Trial {
        meta: reader.meta().clone(),
        layout: *reader.layout(),
        records,
    })
}

fn simulated_trial(speed: f64, seed: u64) -> Trial {
    let cfg = WalkingConfig {
        speed_mps: speed,
        seed,
        ..WalkingConfig::default()
    };
    let sim = WalkingSimulator::new(cfg).expect("valid config");
    let mut meta = TrialMeta::new();
    for (k, v) in sim.metadata() {
        meta.set(k, v);
    }
    let layout = TrialLayout::walking();
    Trial {
        meta,
        layout,
        records: sim.collect(),
    }
}

fn main() {
    let args = SegmentValidationArgs::parse();
    let data = Path::new(&args.data_dir);
    let legs = [Segment::Thigh, Segment::Shank, Segment::Foot];
    println!(
        "| data | scored | {} |",
        METHODS.map(|m| m.name()).join(" | ")
    );
    println!("|---|---|{}", "---|".repeat(METHODS.len()));

    if let Some(trial) = real_trial(&data.join("gaittoolbox-s02-walk")) {
        let parts = [(0.45, 3.55), (4.40, 8.72)];
        let opts: Vec<EvalOptions> = parts
            .iter()
            .map(|&(a, b)| {
                offset_free(
                    TimeWindow {
                        start: Some(a),
                        end: Some(b),
                    },
                    5,
                )
            })
            .collect();
        let rows: Vec<Vec<Option<f64>>> = METHODS
            .par_iter()
            .map(|m| match score(*m, &trial, &opts) {
                Some(s) => s.iter().map(|s| mean_rmse(s, &legs)).collect(),
                None => vec![None; opts.len()],
            })
            .collect();
        for (k, (a, b)) in parts.iter().enumerate() {
            let cells: Vec<String> = rows.iter().map(|r| cell(r[k])).collect();
            println!(
                "| real S02 right, {a:.2}-{b:.2} s | offset-free, lag <= 5, thigh/shank/foot | {} |",
                cells.join(" | ")
            );
        }
    }

    for name in ["walk-v0.7-s300", "walk-v1.2-s301", "walk-v1.6-s302"] {
        let path = data.join("independent-sim").join(format!("{name}.csv"));
        let Some(trial) = file_trial(&path) else {
            continue;
        };
        let opts = [
            EvalOptions::default(),
            offset_free(TimeWindow::default(), 0),
        ];
        let rows: Vec<[Option<f64>; 2]> = METHODS
            .par_iter()
            .map(|m| match score(*m, &trial, &opts) {
                Some(s) => [
                    mean_rmse(&s[0], &Segment::ALL),
                    mean_rmse(&s[1], &Segment::ALL),
                ],
                None => [None, None],
            })
            .collect();
        let cells: Vec<String> = rows
            .iter()
            .map(|r| format!("{} / {}", cell(r[0]), cell(r[1])))
            .collect();
        println!(
            "| independent {name} | absolute / offset-free, 4 segments | {} |",
            cells.join(" | ")
        );
    }

    let n = args.seeds;
    for speed in [0.4, 0.7, 1.0, 1.3, 1.6] {
        // Per seed and method: [absolute, offset-free].
        let runs: Vec<Vec<[f64; 2]>> = (1..=n)
            .into_par_iter()
            .map(|seed| {
                let trial = simulated_trial(speed, seed);
                let opts = [
                    EvalOptions::default(),
                    offset_free(TimeWindow::default(), 0),
                ];
                METHODS
                    .iter()
                    .map(|m| {
                        let s =
                            score(*m, &trial, &opts).expect("simulated trials have every channel");
                        [0, 1].map(|k| mean_rmse(&s[k], &Segment::ALL).expect("scored"))
                    })
                    .collect()
            })
            .collect();
        let cells: Vec<String> = (0..METHODS.len())
            .map(|j| {
                let stat = |k: usize| {
                    let v: Vec<f64> = runs.iter().map(|r| r[j][k]).collect();
                    let mean = v.iter().sum::<f64>() / v.len() as f64;
                    let worst = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                    format!("{mean:.2} ({worst:.2})")
                };
                format!("{} / {}", stat(0), stat(1))
            })
            .collect();
        println!(
            "| limbfuse sim {speed} m/s, {n} seeds | absolute / offset-free, mean (worst) | {} |",
            cells.join(" | ")
        );
    }
}
