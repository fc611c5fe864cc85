//! The declared diagnostic sets (issue 13): names unique per estimator, the
//! estimator reports exactly its set's names, keys address their own
//! column, and on a nominal simulated run every declared diagnostic is
//! written at least once and no column outside the set ever is.

use std::collections::HashSet;

use limbfuse_core::{DiagnosticSet, Estimator, Record, MAX_DIAG};
use limbfuse_estimators::fes::{
    FixedHipDiag, FixedHipFilter, KneeFesDiag, KneeFesFilter, RmxDiag, RotationMatrixKnee,
};
use limbfuse_estimators::knee_selfalign::{Fusion, KneeDiag, KneeSelfAlign, KneeSelfAlignParams};
use limbfuse_estimators::segment_kf::{
    GlobalDiag, GlobalKf, LocalDiag, LocalKf, MarkovJumpKf, MjlsDiag, SegmentDiag,
};
use limbfuse_models::{FixedHipModel, FixedHipParams, KneeFesModel, KneeFesParams, KneeSubject};
use limbfuse_sim::fixed_hip::{simulate_fixed_hip, FixedHipConfig};
use limbfuse_sim::knee_fes::{simulate_knee_fes, KneeFesConfig};
use limbfuse_sim::{Motion, Mounting, WalkingConfig, WalkingSimulator};

/// Checks a declared set: unique names, `ALL[i]` is column `i` and has name
/// `NAMES[i]`, at most [`MAX_DIAG`] columns.
fn check_set<K: DiagnosticSet + core::fmt::Debug>(
    all: &[K],
    names: &[&str],
    name_of: fn(K) -> &'static str,
) {
    assert_eq!(all.len(), names.len());
    assert_eq!(K::NAMES, names);
    assert!(names.len() <= MAX_DIAG);
    let unique: HashSet<&str> = names.iter().copied().collect();
    assert_eq!(unique.len(), names.len(), "duplicate name in {names:?}");
    for (i, k) in all.iter().enumerate() {
        assert_eq!(k.index(), i, "{k:?}");
        assert_eq!(name_of(*k), names[i], "{k:?}");
        assert!(!names[i].is_empty() && !names[i].starts_with("diag_"));
    }
}

#[test]
fn every_declared_set_has_unique_names_and_keys_address_their_own_column() {
    check_set(&SegmentDiag::ALL, &SegmentDiag::NAMES, SegmentDiag::name);
    check_set(&LocalDiag::ALL, &LocalDiag::NAMES, LocalDiag::name);
    check_set(&MjlsDiag::ALL, &MjlsDiag::NAMES, MjlsDiag::name);
    check_set(&GlobalDiag::ALL, &GlobalDiag::NAMES, GlobalDiag::name);
    check_set(&KneeDiag::ALL, &KneeDiag::NAMES, KneeDiag::name);
    check_set(&KneeFesDiag::ALL, &KneeFesDiag::NAMES, KneeFesDiag::name);
    check_set(&FixedHipDiag::ALL, &FixedHipDiag::NAMES, FixedHipDiag::name);
    check_set(&RmxDiag::ALL, &RmxDiag::NAMES, RmxDiag::name);
}

/// Runs `est` over `records`; asserts it reports `names`, writes every one
/// of them at least once and never writes a column past them.
fn check_run(est: &mut dyn Estimator, records: &[Record], names: &[&str]) {
    assert_eq!(est.diagnostic_names(), names, "{}", est.name());
    let mut written = vec![false; names.len()];
    for r in records {
        let e = est.step(&r.sample).unwrap();
        for (w, d) in written.iter_mut().zip(&e.diag) {
            *w |= d.is_some();
        }
        if let Some(i) = e.diag[names.len()..].iter().position(Option::is_some) {
            panic!(
                "{}: column {} past the declared set written at t = {}",
                est.name(),
                names.len() + i,
                r.sample.t
            );
        }
    }
    let never: Vec<&str> = names
        .iter()
        .zip(&written)
        .filter(|(_, w)| !**w)
        .map(|(n, _)| *n)
        .collect();
    assert!(never.is_empty(), "{}: never written: {never:?}", est.name());
}

#[test]
fn segment_filters_write_every_declared_diagnostic_on_simulated_walking() {
    let records: Vec<Record> = WalkingSimulator::new(WalkingConfig {
        duration_s: 6.0,
        seed: 5,
        ..WalkingConfig::default()
    })
    .unwrap()
    .collect();
    check_run(&mut LocalKf::default(), &records, &LocalDiag::NAMES);
    check_run(&mut MarkovJumpKf::default(), &records, &MjlsDiag::NAMES);
    check_run(&mut GlobalKf::default(), &records, &GlobalDiag::NAMES);
}

#[test]
fn knee_selfalign_writes_every_declared_diagnostic_with_the_rate_bias_fusion() {
    // `kf_rate_bias` exists only with the rate-bias fusion; `rest_norm_error`
    // only after a rest: 1 s of standing, then the walk.
    let sim = |motion, duration_s| {
        WalkingSimulator::new(WalkingConfig {
            duration_s,
            seed: 11,
            mounting: Mounting::Random,
            motion,
            ..WalkingConfig::default()
        })
        .unwrap()
    };
    let mut records: Vec<Record> = sim(Motion::Stand, 1.0).collect();
    let start = records.last().unwrap().sample.t + 0.01;
    records.extend(sim(Motion::Walk, 8.0).map(|mut r| {
        r.sample.t += start;
        r
    }));
    let params = KneeSelfAlignParams {
        window: 300,
        fusion: Fusion::RATE_BIAS,
        ..KneeSelfAlignParams::default()
    };
    check_run(
        &mut KneeSelfAlign::new(params).unwrap(),
        &records,
        &KneeDiag::NAMES,
    );
}

#[test]
fn fes_estimators_write_every_declared_diagnostic_on_simulated_trials() {
    let knee = simulate_knee_fes(&KneeFesConfig {
        subject: KneeSubject::P2R,
        seed: 3,
        duration_s: 4.0,
        ..KneeFesConfig::default()
    })
    .unwrap();
    let m = KneeFesModel::new(KneeFesParams::subject(KneeSubject::P2R)).unwrap();
    check_run(
        &mut KneeFesFilter::sdre(m),
        &knee.records,
        &KneeFesDiag::NAMES,
    );
    check_run(
        &mut KneeFesFilter::ekf(m),
        &knee.records,
        &KneeFesDiag::NAMES,
    );
    check_run(
        &mut RotationMatrixKnee::new(),
        &knee.records,
        &RmxDiag::NAMES,
    );
    let hip = simulate_fixed_hip(&FixedHipConfig {
        seed: 1,
        duration_s: 3.0,
        ..FixedHipConfig::default()
    })
    .unwrap();
    let m = FixedHipModel::new(FixedHipParams::default()).unwrap();
    check_run(
        &mut FixedHipFilter::sdre(m),
        &hip.records,
        &FixedHipDiag::NAMES,
    );
}
