//! A fixed workload for counting the instructions of the segment filters
//! with callgrind (repeatable, unlike wall time on a shared machine):
//!
//! ```sh
//! cargo build --release -p limbfuse-estimators --example segment_kf_callgrind
//! valgrind --tool=callgrind target/release/examples/segment_kf_callgrind mjls
//! ```
//!
//! Runs `mjls`, `global` or `local` (first argument) 20 times over the
//! seeded 60 s walking trial of the criterion bench (seed 42, 6 000 samples).

use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::segment_kf::{GlobalKf, LocalKf, MarkovJumpKf};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

fn main() {
    let records: Vec<Record> = WalkingSimulator::new(WalkingConfig {
        seed: 42,
        ..WalkingConfig::default()
    })
    .expect("valid config")
    .collect();
    let which = std::env::args().nth(1).unwrap_or_else(|| "mjls".into());
    let mut acc = 0.0;
    for _ in 0..20 {
        let mut e: Box<dyn Estimator> = match which.as_str() {
            "global" => Box::new(GlobalKf::default()),
            "local" => Box::new(LocalKf::default()),
            _ => Box::new(MarkovJumpKf::default()),
        };
        for r in &records {
            acc += e.step(&r.sample).expect("valid sample").segment[1].unwrap_or(0.0);
        }
    }
    println!("{acc}");
}
