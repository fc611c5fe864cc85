//! How much the `chain` filter's geometry moves its error on one trial
//! (docs/RESULTS.md, "Real data: gaittoolbox S02, after `align`", issue 14,
//! "Geometry: the lever measured"). A sensitivity measurement, not a fit:
//! nothing here becomes a default.
//!
//! The geometry the chain would use on the trial (its metadata, else
//! Winter's proportions and typical placements, `resolve_geometry`) is the
//! base. Each quantity (an IMU's mount coordinate, a segment length) is
//! moved alone by -3..+3 cm, every other one held at the base (mid-segment
//! mounts do not follow a changed length), and the chain (default
//! parameters) is scored as `limbfuse evaluate --offset-free --max-lag N`
//! scores it, per window. Then a coordinate search over the leg's
//! sagittal mounts and both lengths, on a lattice of five points within
//! +-`--search-cm` (3) of the base, minimises the last window's thigh/shank/foot mean: the best
//! geometry found *on the scored data itself*, so it flatters the lever;
//! it is optimistic for what identifying the geometry could give (a local
//! coordinate search, not an exhaustive one).
//! The geometry keys of the trial's metadata (`imu_mounts_m`,
//! `segment_lengths_m`, `height_m`) are dropped so that the moved geometry
//! is the one used; the alignment metadata (frame offsets) is kept.
//! `cargo run --release -p limbfuse-studies --example chain_geometry_sensitivity -- TRIAL --window A:B [--window C:D] [--max-lag N] [--search-cm R]`

use std::path::Path;

use clap::Parser;
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::Segment;
use limbfuse_estimators::chain_ekf::{ChainGeometry, ChainParams};
use limbfuse_eval::{AngleMetrics, EvalOptions, TimeWindow};
use limbfuse_io::TrialMeta;
use limbfuse_methods::chain_method::{resolve_geometry, ChainSettings, GeometryFile};
use limbfuse_methods::{build, MethodSpec};
use limbfuse_studies::example_args::ChainGeometrySensitivityArgs;
use limbfuse_studies::recorded_trial::{EstimateLog, RecordedTrial};

/// Metadata keys holding the geometry (`limbfuse_io::body_meta`).
const GEOMETRY_KEYS: [&str; 3] = ["imu_mounts_m", "segment_lengths_m", "height_m"];
const SEGMENTS: [&str; 4] = ["trunk", "thigh", "shank", "foot"];
const AXES: [&str; 3] = ["x (front)", "y (up)", "z (right)"];

/// One geometric quantity.
#[derive(Debug, Clone, Copy)]
enum Quantity {
    /// IMU of segment `.0`, coordinate `.1` (0 x, 1 y, 2 z).
    Mount(usize, usize),
    /// Thigh (false) or shank (true) length.
    Length(bool),
}

impl Quantity {
    fn name(self) -> String {
        match self {
            Quantity::Mount(s, a) => format!("{} IMU {}", SEGMENTS[s], AXES[a]),
            Quantity::Length(false) => "thigh length".into(),
            Quantity::Length(true) => "shank length".into(),
        }
    }

    fn moved(self, g: &ChainGeometry, d: f64) -> ChainGeometry {
        let mut g = *g;
        match self {
            Quantity::Mount(s, a) => g.imu_position[s][a] += d,
            Quantity::Length(false) => g.thigh_length += d,
            Quantity::Length(true) => g.shank_length += d,
        }
        g
    }
}

/// The geometry as a parameter file's `[geometry]` with every quantity
/// explicit (frame offsets from the trial's alignment metadata).
fn file_of(g: &ChainGeometry) -> GeometryFile {
    GeometryFile {
        height_m: None,
        thigh_length: Some(g.thigh_length),
        shank_length: Some(g.shank_length),
        imu_trunk: Some(g.imu_position[0]),
        imu_thigh: Some(g.imu_position[1]),
        imu_shank: Some(g.imu_position[2]),
        imu_foot: Some(g.imu_position[3]),
        frame_offset_deg: None,
    }
}

/// Thigh, shank, foot offset-free RMSE (deg) and their mean, per window.
type Scores = Vec<[f64; 4]>;

fn score(
    trial: &RecordedTrial,
    meta: &TrialMeta,
    g: &ChainGeometry,
    windows: &[(f64, f64)],
    max_lag: usize,
) -> Scores {
    let spec = MethodSpec::Chain(ChainSettings {
        params: ChainParams::default(),
        geometry: file_of(g),
    });
    let mut est = build(&spec, meta, &trial.layout).unwrap_or_else(|e| panic!("chain: {e}"));
    let mut log = EstimateLog(Vec::with_capacity(trial.records.len()));
    limbfuse_core::runner::run(
        est.as_mut(),
        trial
            .records
            .iter()
            .map(|r| Ok::<_, std::convert::Infallible>(*r)),
        &mut [&mut log],
    )
    .unwrap_or_else(|e| panic!("chain run: {e}"));
    windows
        .iter()
        .map(|&(start, end)| {
            let options = EvalOptions {
                window: TimeWindow {
                    start: Some(start),
                    end: Some(end),
                },
                offset_free: true,
                max_lag,
                allow_trial_mismatch: false,
            };
            let mut m = AngleMetrics::new("chain", options);
            for (r, e) in trial.records.iter().zip(&log.0) {
                m.push(r, e);
            }
            let ev = m.evaluation();
            let mut row = [0.0; 4];
            for (v, s) in row
                .iter_mut()
                .zip([Segment::Thigh, Segment::Shank, Segment::Foot])
            {
                *v = ev
                    .rmse(AngleChannel::Segment(s))
                    .map_or(f64::NAN, f64::to_degrees);
            }
            row[3] = (row[0] + row[1] + row[2]) / 3.0;
            row
        })
        .collect()
}

fn cells(s: &Scores) -> String {
    s.iter()
        .map(|r| format!("{:.2} / {:.2} / {:.2} **{:.2}**", r[0], r[1], r[2], r[3]))
        .collect::<Vec<_>>()
        .join(" | ")
}

fn cm(g: &ChainGeometry, base: &ChainGeometry, q: Quantity) -> f64 {
    let (a, b) = match q {
        Quantity::Mount(s, i) => (g.imu_position[s][i], base.imu_position[s][i]),
        Quantity::Length(false) => (g.thigh_length, base.thigh_length),
        Quantity::Length(true) => (g.shank_length, base.shank_length),
    };
    100.0 * (a - b)
}

fn main() {
    let args = ChainGeometrySensitivityArgs::parse();
    let path = Path::new(&args.trial);
    let trial =
        RecordedTrial::read(path).unwrap_or_else(|e| panic!("{e} (run from the repository root)"));
    let base = resolve_geometry(&trial.meta, &GeometryFile::default())
        .unwrap_or_else(|e| panic!("{}: geometry: {e}", path.display()));
    let mut meta = TrialMeta::new();
    for (k, v) in trial.meta.entries() {
        if !GEOMETRY_KEYS.contains(&k.as_str()) {
            meta.set(k.clone(), v);
        }
    }
    let check = resolve_geometry(&meta, &file_of(&base)).expect("base geometry as a file");
    assert_eq!(check, base, "the base geometry round-trips through a file");
    let windows = &args.windows;
    let last = windows.len() - 1;
    let header: Vec<String> = windows
        .iter()
        .map(|(a, b)| format!("{a}-{b} s thigh / shank / foot **mean**"))
        .collect();
    println!(
        "{}: chain (default parameters), offset-free RMSE (deg), lag within +-{} samples",
        path.display(),
        args.max_lag
    );
    println!(
        "base geometry: thigh {:.4} m, shank {:.4} m, IMUs trunk {:?} thigh {:?} shank {:?} foot {:?} m",
        base.thigh_length,
        base.shank_length,
        base.imu_position[0],
        base.imu_position[1],
        base.imu_position[2],
        base.imu_position[3]
    );
    println!("| quantity | moved by (cm) | {} |", header.join(" | "));
    println!("|---|---|{}", "---|".repeat(windows.len()));
    let base_scores = score(&trial, &meta, &base, windows, args.max_lag);
    println!("| base | 0 | {} |", cells(&base_scores));
    let mut quantities: Vec<Quantity> = (0..4)
        .flat_map(|s| (0..3).map(move |a| Quantity::Mount(s, a)))
        .collect();
    quantities.push(Quantity::Length(false));
    quantities.push(Quantity::Length(true));
    let mut best_single = (f64::INFINITY, String::new());
    for &q in &quantities {
        for d in [-3.0, -2.0, -1.0, 1.0, 2.0, 3.0] {
            let s = score(
                &trial,
                &meta,
                &q.moved(&base, d / 100.0),
                windows,
                args.max_lag,
            );
            if s[last][3] < best_single.0 {
                best_single = (s[last][3], format!("{} {d:+} cm", q.name()));
            }
            println!("| {} | {d:+} | {} |", q.name(), cells(&s));
        }
    }
    println!(
        "best single move for the last window: {} ({:.2} deg)",
        best_single.1, best_single.0
    );
    // Coordinate search over the leg's sagittal mounts and the lengths.
    let searched: Vec<Quantity> = [1, 2, 3]
        .iter()
        .flat_map(|&s| [Quantity::Mount(s, 0), Quantity::Mount(s, 1)])
        .chain([Quantity::Length(false), Quantity::Length(true)])
        .collect();
    let r = args.search_cm / 100.0;
    let lattice = [-r, -0.5 * r, 0.0, 0.5 * r, r];
    let mut g = base;
    let mut best = base_scores;
    let mut runs = 0;
    for sweep in 1..=10 {
        let mut improved = false;
        for &q in &searched {
            for d in lattice {
                let step = d - cm(&g, &base, q) / 100.0;
                if step.abs() < 1e-9 {
                    continue;
                }
                let trial_g = q.moved(&g, step);
                let s = score(&trial, &meta, &trial_g, windows, args.max_lag);
                runs += 1;
                if s[last][3] < best[last][3] - 1e-9 {
                    g = trial_g;
                    best = s;
                    improved = true;
                }
            }
        }
        println!("search sweep {sweep}: {} ({runs} runs)", cells(&best));
        if !improved {
            break;
        }
    }
    let moved: Vec<String> = searched
        .iter()
        .map(|&q| format!("{} {:+.1}", q.name(), cm(&g, &base, q)))
        .collect();
    println!(
        "best geometry found on the last window (cm from base): {}",
        moved.join(", ")
    );
    println!("| searched on the last window | - | {} |", cells(&best));
}
