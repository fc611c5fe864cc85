use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::segment_kf::{GlobalKf, MarkovJumpKf};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};
fn main() {
    let records: Vec<Record> = WalkingSimulator::new(WalkingConfig {
        seed: 42,
        ..WalkingConfig::default()
    })
    .unwrap()
    .collect();
    let which = std::env::args().nth(1).unwrap_or("mjls".into());
    let mut acc = 0.0;
    for _ in 0..20 {
        let mut e: Box<dyn Estimator> = if which == "mjls" {
            Box::new(MarkovJumpKf::default())
        } else {
            Box::new(GlobalKf::default())
        };
        for r in &records {
            acc += e.step(&r.sample).unwrap().segment[1].unwrap_or(0.0);
        }
    }
    println!("{acc}");
}
