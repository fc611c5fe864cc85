//! Golden reference outputs of the three segment filters: a seeded 10 s
//! walking trial at 1.0 m/s (default sensors) through `local`, `mjls` and
//! `global` with default parameters; every 25th estimate's four segment
//! angles are compared with `tests/golden/segment_kf_walk_seed2026.csv`.
//!
//! The tolerance, 1e-9 rad, admits only floating-point reassociation (a
//! rewritten but equivalent Kalman step); any change of behaviour (a
//! criterion, a default, the simulator) fails the test. After a deliberate
//! change, regenerate the file with
//! `LIMBFUSE_BLESS=1 cargo test -p limbfuse-estimators --test integration -- segment_kf_golden::`
//! and say why in the commit.

use std::fmt::Write as _;
use std::path::PathBuf;

use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::segment_kf::{GlobalKf, LocalKf, MarkovJumpKf};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

const EVERY: usize = 25;
const TOL: f64 = 1e-9;

fn golden_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden/segment_kf_walk_seed2026.csv")
}

/// `method,t,trunk,thigh,shank,foot` rows (angles in rad, empty when not
/// estimated), shortest round-trip formatting.
fn current_output() -> String {
    let records: Vec<Record> = WalkingSimulator::new(WalkingConfig {
        seed: 2026,
        speed_mps: 1.0,
        duration_s: 10.0,
        ..WalkingConfig::default()
    })
    .expect("valid config")
    .collect();
    let filters: [Box<dyn Estimator>; 3] = [
        Box::new(LocalKf::default()),
        Box::new(MarkovJumpKf::default()),
        Box::new(GlobalKf::default()),
    ];
    let mut out = String::from("method,t,trunk,thigh,shank,foot\n");
    for mut f in filters {
        for (k, r) in records.iter().enumerate() {
            let e = f.step(&r.sample).expect("valid sample");
            if k % EVERY == 0 {
                write!(out, "{},{}", f.name(), e.t).unwrap();
                for s in e.segment {
                    match s {
                        Some(v) => write!(out, ",{v:?}").unwrap(),
                        None => out.push(','),
                    }
                }
                out.push('\n');
            }
        }
    }
    out
}

fn parse(line: &str) -> (String, Vec<Option<f64>>) {
    let mut cells = line.split(',');
    let method = cells.next().unwrap_or_default().to_string();
    let values = cells
        .map(|c| {
            (!c.is_empty()).then(|| {
                c.parse::<f64>()
                    .unwrap_or_else(|e| panic!("golden cell {c:?}: {e}"))
            })
        })
        .collect();
    (method, values)
}

#[test]
fn segment_filters_reproduce_their_golden_output() {
    let now = current_output();
    let path = golden_path();
    if std::env::var_os("LIMBFUSE_BLESS").is_some() {
        std::fs::write(&path, &now).expect("write golden file");
        eprintln!("wrote {}", path.display());
        return;
    }
    let golden = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e}; generate it with LIMBFUSE_BLESS=1 (see the module doc)",
            path.display()
        )
    });
    let (g, n): (Vec<&str>, Vec<&str>) = (golden.lines().collect(), now.lines().collect());
    assert_eq!(g.len(), n.len(), "row count differs from the golden file");
    assert_eq!(g[0], n[0], "header");
    let mut worst = 0.0f64;
    for (row, (gl, nl)) in g.iter().zip(&n).enumerate().skip(1) {
        let (gm, gv) = parse(gl);
        let (nm, nv) = parse(nl);
        assert_eq!(gm, nm, "row {row}: method");
        assert_eq!(gv.len(), nv.len(), "row {row}: cell count");
        for (col, (a, b)) in gv.iter().zip(&nv).enumerate() {
            match (a, b) {
                (Some(a), Some(b)) => {
                    let d = (a - b).abs();
                    worst = worst.max(if col == 0 { 0.0 } else { d });
                    assert!(
                        d <= TOL,
                        "row {row} ({gm}), column {col}: golden {a}, now {b} (|diff| {d:e} > {TOL:e})"
                    );
                }
                (None, None) => {}
                _ => panic!("row {row} ({gm}), column {col}: golden {a:?}, now {b:?}"),
            }
        }
    }
    eprintln!("largest difference from the golden file: {worst:e} rad");
}
