//! `chain` allocates nothing per step (counting-allocator pattern of
//! `no_allocation.rs`, in its own binary so the counter sees no other test).

use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::chain_ekf::{ChainEkf, ChainGeometry, ChainParams};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

use crate::counting_alloc::allocations;

#[test]
fn chain_steps_without_allocating() {
    let cfg = WalkingConfig {
        duration_s: 5.0,
        ..Default::default()
    };
    let mut recs: Vec<Record> = WalkingSimulator::new(cfg).unwrap().collect();
    for (k, r) in recs.iter_mut().enumerate() {
        if k % 13 == 5 {
            r.sample.imu[2].acc = None;
            r.sample.imu[1].gyr = None;
            r.sample.encoder[0] = None;
        }
    }
    let mut ekf = ChainEkf::new(ChainParams::default(), ChainGeometry::default(), cfg.g).unwrap();
    let before = allocations();
    let mut sum = 0.0;
    for r in &recs {
        sum += ekf.step(&r.sample).unwrap().segment[1].unwrap_or(0.0);
    }
    let after = allocations();
    assert!(sum.is_finite());
    assert_eq!(
        after - before,
        0,
        "chain allocated {} times",
        after - before
    );
}
