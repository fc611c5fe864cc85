//! `gait-library build --mass 60` (or any body of about 60 kg or less) failed
//! before any speed: the search's start seed (20 kN/m at 1 m/s, chosen for
//! the 80 kg body) gave no step that reached mid-stance. The search now
//! falls back to the dynamically similar seed (`similar_start_seed`).

use limbfuse_models::bslip::BslipParams;
use limbfuse_sim::bslip::library::{
    build_library, similar_start_seed, start_gait, start_seed, START_SPEED,
};
use limbfuse_sim::bslip::search::{optimise_gait, SearchSettings};
use limbfuse_sim::bslip::step::StepSimulator;

fn body(mass: f64, rest_length: f64) -> BslipParams {
    BslipParams {
        mass,
        rest_length,
        ..BslipParams::default()
    }
}

/// The premise: from the 80 kg seed the 60 kg body's search fails; the
/// similar seed's stiffness is the 80 kg seed's x 60 / 80.
#[test]
fn the_80_kg_seed_finds_no_start_gait_for_a_60_kg_body() {
    let b = body(60.0, 1.0);
    let sim = StepSimulator::new(b);
    let s = SearchSettings::default();
    assert!(optimise_gait(&sim, &start_seed(1.0), START_SPEED, &s).is_err());
    let k = similar_start_seed(&b).stiffness;
    assert!((k - start_seed(1.0).stiffness * 0.75).abs() < 1e-9, "{k}");
}

/// Bodies of 40-60 kg get a periodic start gait at 1 m/s, and a library
/// over a walking range builds (failed at the start before: "gait at 1 m/s:
/// the mid-stance (leading leg unloaded) event did not occur within the
/// time limit").
#[test]
fn a_light_body_gets_a_library() {
    let s = SearchSettings::default();
    for (mass, l0) in [(60.0, 1.0), (55.0, 0.85), (40.0, 0.75)] {
        let sim = StepSimulator::new(body(mass, l0));
        let start = start_gait(&sim, &s).unwrap_or_else(|e| panic!("{mass} kg, {l0} m: {e}"));
        assert!(start.solution.residual <= s.periodic_tol, "{mass} kg");
        assert!((start.solution.outcome.mean_speed() - START_SPEED).abs() < 1e-6);
    }
    let lib = build_library(&body(60.0, 0.9), &[0.8, 1.0, 1.2], &s, |_, _| {})
        .expect("a 60 kg, 0.9 m library over 0.8-1.2 m/s");
    assert_eq!(lib.len(), 3);
}
