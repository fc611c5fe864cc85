//! A fixed workload for counting the instructions of the segment filters
//! with callgrind (repeatable, unlike wall time on a shared machine):
//!
//! ```sh
//! cargo build --release -p limbfuse-methods --example segment_kf_callgrind
//! valgrind --tool=callgrind target/release/examples/segment_kf_callgrind mjls
//! ```
//!
//! Runs `mjls`, `global` or `local` (first argument) 20 times over the
//! seeded 60 s walking trial of the criterion bench (seed 42, 6 000 samples).

use limbfuse_core::{Estimator, Record};
use limbfuse_methods::segment_params::{FilterMethod, FilterParams, Preset};
use limbfuse_methods::MethodName;
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

fn main() {
    let records: Vec<Record> = WalkingSimulator::new(WalkingConfig {
        seed: 42,
        ..WalkingConfig::default()
    })
    .expect("valid config")
    .collect();
    let which = std::env::args()
        .nth(1)
        .map_or(Ok(MethodName::Mjls), |a| MethodName::parse(&a))
        .expect("a method name");
    let filter = FilterMethod::from_method(which).expect("local, mjls or global");
    let params = FilterParams::preset(filter, Preset::Default);
    let mut acc = 0.0;
    for _ in 0..20 {
        let mut e: Box<dyn Estimator + Send> = params.build().expect("valid preset");
        for r in &records {
            acc += e.step(&r.sample).expect("valid sample").segment[1].unwrap_or(0.0);
        }
    }
    println!("{acc}");
}
